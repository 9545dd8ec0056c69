//! Patch tests: a homogeneous deformation prescribed on the boundary of a
//! distorted patch is reproduced at the interior nodes and in every element
//! stress to round-off, for Q4 and Q8, every analysis kind, small strain and
//! total Lagrangian kinematics.

mod common;

use contact2d::mesh::ElementKind;
use contact2d::newton::Solver;
use contact2d::problem::*;

/// A 3x3 patch on [1, 3] x [0, 2] with interior nodes moved off the lattice.
fn patch(kind: ElementKind) -> contact2d::mesh::Mesh {
    common::grid(kind, [1.0, 0.0], [2.0, 2.0], 3, 3, |x, y| {
        let bump = (x - 1.0) * (3.0 - x) * y * (2.0 - y);
        [
            x + 0.12 * bump * (3.0 * y).sin(),
            y + 0.1 * bump * (2.0 * x).cos(),
        ]
    })
}

/// Displacement gradient of the field: u = H X (planar), and for the
/// axisymmetric case u_r = a r, u_z = b z (H diagonal with H00 = a, which
/// keeps sigma_rr = sigma_theta so the field is in equilibrium).
fn check(kind: ElementKind, analysis: AnalysisKind, kinematics: Kinematics, h: [[f64; 2]; 2]) {
    let mesh = patch(kind);
    let mut p = common::problem(mesh, analysis, kinematics, 1000.0, 0.3);
    let boundary = common::nodes_where(&p.mesh, |x, y| {
        x.min(4.0 - x) < 1.0 + 1e-12 || y.min(2.0 - y) < 1e-12
    });
    for &n in &boundary {
        let [x, y] = p.mesh.nodes[n];
        p.drivers.push(Driver {
            name: format!("n{n}"),
            nodes: vec![n],
            ux: Some(Scaled {
                scale: h[0][0] * x + h[0][1] * y,
                function: Some(0),
            }),
            uy: Some(Scaled {
                scale: h[1][0] * x + h[1][1] * y,
                function: Some(0),
            }),
            fx: None,
            fy: None,
            distribution: Default::default(),
        });
    }
    let mut s = Solver::new(p).unwrap();
    s.advance(1.0, &mut common::silent()).unwrap();
    let p = s.problem();
    let interior = p.mesh.nodes.len() - boundary.len();
    assert!(interior >= if kind == ElementKind::Q4 { 4 } else { 16 });
    let u = &s.state().u;
    for (n, &[x, y]) in p.mesh.nodes.iter().enumerate() {
        let exact = [h[0][0] * x + h[0][1] * y, h[1][0] * x + h[1][1] * y];
        for c in 0..2 {
            assert!(
                (u[2 * n + c] - exact[c]).abs() < 1e-12,
                "{kind:?} {analysis:?} {kinematics:?}: node {n} comp {c}: {} vs {}",
                u[2 * n + c],
                exact[c]
            );
        }
    }
    // Every element carries the same stress (to round-off of the stress scale).
    let stresses = s.element_stresses();
    let scale = stresses[0].iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(scale > 1.0);
    for st in &stresses {
        for i in 0..4 {
            assert!(
                (st[i] - stresses[0][i]).abs() < 1e-11 * scale,
                "{kind:?} {analysis:?} {kinematics:?}: {st:?} vs {:?}",
                stresses[0]
            );
        }
    }
    // And it is the analytic stress in the small strain case.
    if kinematics == Kinematics::SmallStrain {
        let (e, nu) = (1000.0, 0.3);
        let eps = [
            h[0][0],
            h[1][1],
            if analysis == AnalysisKind::Axisymmetric {
                h[0][0]
            } else {
                0.0
            },
            h[0][1] + h[1][0],
        ];
        let g = e / (2.0 * (1.0 + nu));
        let exact = match analysis {
            AnalysisKind::PlaneStress { .. } => {
                let c = e / (1.0 - nu * nu);
                [
                    c * (eps[0] + nu * eps[1]),
                    c * (eps[1] + nu * eps[0]),
                    0.0,
                    g * eps[3],
                ]
            }
            _ => {
                let l = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
                let tr = eps[0] + eps[1] + eps[2];
                [
                    l * tr + 2.0 * g * eps[0],
                    l * tr + 2.0 * g * eps[1],
                    l * tr + 2.0 * g * eps[2],
                    g * eps[3],
                ]
            }
        };
        for i in 0..4 {
            assert!(
                (stresses[0][i] - exact[i]).abs() < 1e-11 * scale,
                "{kind:?} {analysis:?}: {:?} vs {exact:?}",
                stresses[0]
            );
        }
    }
}

#[test]
fn constant_strain_patches() {
    for kind in [ElementKind::Q4, ElementKind::Q8] {
        for kinematics in [Kinematics::SmallStrain, Kinematics::TotalLagrangian] {
            // General in-plane gradient (TL: a 0.35 rad rotation with stretch).
            let (c, s) = (0.35f64.cos(), 0.35f64.sin());
            let hp = if kinematics == Kinematics::TotalLagrangian {
                [[1.08 * c - 1.0, -0.95 * s], [1.08 * s, 0.95 * c - 1.0]]
            } else {
                [[2e-3, 1e-3], [-5e-4, -1.5e-3]]
            };
            check(
                kind,
                AnalysisKind::PlaneStrain { thickness: 1.0 },
                kinematics,
                hp,
            );
            check(
                kind,
                AnalysisKind::PlaneStress { thickness: 0.5 },
                kinematics,
                hp,
            );
            let ha = if kinematics == Kinematics::TotalLagrangian {
                [[0.06, 0.0], [0.0, -0.04]]
            } else {
                [[2e-3, 0.0], [0.0, -1e-3]]
            };
            check(kind, AnalysisKind::Axisymmetric, kinematics, ha);
        }
    }
}
