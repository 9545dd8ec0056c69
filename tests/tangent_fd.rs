//! The assembled tangent against central finite differences of the assembled
//! residual, for every analysis kind under small strain and total Lagrangian
//! kinematics, with dead and follower edge pressure and body force.

mod common;

use contact2d::assembly::{Model, PRESCRIBED, Workspace};
use contact2d::mesh::ElementKind;
use contact2d::problem::*;

fn residual(model: &Model, p: &Problem, u: &[f64]) -> Vec<f64> {
    let mut r = vec![0.0; u.len()];
    let mut h = vec![0.0; model.history_len];
    model
        .assemble(
            p,
            1.0,
            u,
            &mut h,
            &mut r,
            None,
            None,
            None,
            &mut Workspace::new(),
        )
        .unwrap();
    r
}

/// Max |K - K_fd| / max |K| over all free-free entries.
fn tangent_error(p: &Problem, u: &[f64]) -> f64 {
    let ndof = u.len();
    let model = Model::new(p, &vec![false; ndof]);
    let mut r = vec![0.0; ndof];
    let mut k = vec![0.0; model.pattern.row_idx.len()];
    let mut h = vec![0.0; model.history_len];
    model
        .assemble(
            p,
            1.0,
            u,
            &mut h,
            &mut r,
            Some(&mut k),
            None,
            None,
            &mut Workspace::new(),
        )
        .unwrap();
    let n = model.pattern.n;
    let mut dense = vec![0.0; n * n];
    for c in 0..n {
        for s in model.pattern.col_ptr[c]..model.pattern.col_ptr[c + 1] {
            dense[model.pattern.row_idx[s] * n + c] = k[s];
        }
    }
    let kmax = dense.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut err = 0.0f64;
    // Step relative to the element size (1): truncation ~ h^2, round-off ~ eps/h.
    let h = 1e-6;
    for j in 0..ndof {
        assert_ne!(model.eq[j], PRESCRIBED);
        let mut up = u.to_vec();
        up[j] += h;
        let mut um = u.to_vec();
        um[j] -= h;
        let (rp, rm) = (residual(&model, p, &up), residual(&model, p, &um));
        for i in 0..ndof {
            let fd = (rp[i] - rm[i]) / (2.0 * h);
            err = err.max((fd - dense[model.eq[i] as usize * n + model.eq[j] as usize]).abs());
        }
    }
    err / kmax
}

fn distorted(kind: ElementKind) -> contact2d::mesh::Mesh {
    // Two elements on [1, 3] x [0, 1.5] (x > 0 for the axisymmetric case), interior nodes moved.
    common::grid(kind, [1.0, 0.0], [2.0, 1.5], 2, 1, |x, y| {
        [
            x + 0.1 * (y * 2.0).sin() * (x - 1.0) * (3.0 - x),
            y + 0.07 * x * y,
        ]
    })
}

fn displacement(n: usize) -> Vec<f64> {
    // Large, smooth, non-symmetric displacement: rotations of ~0.3 rad, strains ~10%.
    (0..n)
        .map(|i| {
            let s = (i as f64 * 0.7).sin();
            if i % 2 == 0 {
                0.12 * s
            } else {
                -0.09 * s + 0.05
            }
        })
        .collect()
}

#[test]
fn tangent_matches_finite_differences() {
    let kinds = [
        AnalysisKind::PlaneStrain { thickness: 1.3 },
        AnalysisKind::PlaneStress { thickness: 0.7 },
        AnalysisKind::Axisymmetric,
    ];
    for kind in [ElementKind::Q4, ElementKind::Q8] {
        for analysis in kinds {
            for kinematics in [Kinematics::SmallStrain, Kinematics::TotalLagrangian] {
                for follower in [false, true] {
                    let mesh = distorted(kind);
                    let mut p = common::problem(mesh, analysis, kinematics, 1000.0, 0.3);
                    let edges = p.mesh.edge_sets["top"].clone();
                    p.pressures.push(Pressure {
                        edges,
                        value: Scaled::constant(35.0),
                        follower,
                        name: None,
                    });
                    let right = p.mesh.edge_sets["right"].clone();
                    p.pressures.push(Pressure {
                        edges: right,
                        value: Scaled::constant(-20.0),
                        follower,
                        name: None,
                    });
                    p.body_forces.push(BodyForce {
                        body: 0,
                        bx: Scaled::constant(3.0),
                        by: Scaled::constant(-5.0),
                    });
                    p.initial_stresses.push(InitialStress {
                        body: 0,
                        stress: [10.0, -4.0, 2.0, 3.0],
                    });
                    let u = displacement(2 * p.mesh.nodes.len());
                    let e = tangent_error(&p, &u);
                    // Central differences with h = 1e-6 on O(1) data: error ~1e-9 relative.
                    assert!(
                        e < 1e-7,
                        "{kind:?} {analysis:?} {kinematics:?} follower={follower}: relative error {e:e}"
                    );
                }
            }
        }
    }
}
