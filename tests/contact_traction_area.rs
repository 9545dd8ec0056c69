//! Reported contact tractions: force per unit reference area under
//! small-strain kinematics (the element stresses' measure, and Hertz's),
//! per unit current area under total Lagrangian kinematics (Cauchy).

mod common;

use contact2d::mesh::ElementKind;
use contact2d::newton::Solver;
use contact2d::problem::*;
use contact2d::results::NodeState;

const E: f64 = 1000.0;
const NU: f64 = 0.3;
const GAP: f64 = 1e-3;
/// Press displacement beyond the gap: 5 % nominal strain of the 1-high block.
const SQUEEZE: f64 = 0.05;

/// A 2 x 1 block (plane strain) squeezed by its top onto a frictionless rigid
/// flat GAP below it, x = 0 a symmetry line. Returns (reference width,
/// current width of the bottom, |Fy| of the pair, reported tn of the bottom).
fn squeeze(kind: ElementKind, kinematics: Kinematics) -> (f64, f64, f64, Vec<f64>) {
    let mesh = common::grid(kind, [0.0, 0.0], [2.0, 1.0], 4, 2, |x, y| [x, y]);
    let mut p = common::problem(
        mesh,
        AnalysisKind::PlaneStrain { thickness: 1.0 },
        kinematics,
        E,
        NU,
    );
    common::bottom_on_flat(&mut p, -GAP);
    p.drivers.push(Driver {
        name: "symmetry".into(),
        nodes: p.mesh.node_sets["left"].clone(),
        ux: Some(Scaled::constant(0.0)),
        uy: None,
        fx: None,
        fy: None,
        distribution: Default::default(),
    });
    p.drivers.push(Driver {
        name: "press".into(),
        nodes: p.mesh.node_sets["top"].clone(),
        ux: None,
        uy: Some(Scaled {
            scale: -(GAP + SQUEEZE),
            function: Some(0),
        }),
        fx: None,
        fy: None,
        distribution: Default::default(),
    });
    p.times = vec![0.5, 1.0];
    let mut s = Solver::new(p).unwrap();
    for t in [0.5, 1.0] {
        let r = s.advance(t, &mut |_, _| {}).unwrap();
        assert!(r.converged);
    }
    let pairs = s.last_pairs().unwrap();
    let pair = &pairs[0].1;
    let n = &pair.nodes;
    assert!(n.state.iter().all(|&st| st == NodeState::Slip), "{n:?}");
    let width = n.x.iter().cloned().fold(f64::MIN, f64::max) - n.x[0];
    (2.0, width, pair.fy.abs(), n.tn.clone())
}

#[test]
fn small_strain_tractions_are_per_reference_area() {
    // Uniaxial plane-strain compression: sigma_yy = E eps / (1 - nu^2) on the
    // reference section; the bottom widens by nu / (1 - nu) eps (2.1 %).
    let p = E / (1.0 - NU * NU) * SQUEEZE;
    for kind in [ElementKind::Q4, ElementKind::Q8] {
        let (w0, w, fy, tn) = squeeze(kind, Kinematics::SmallStrain);
        assert!((fy / w0 - p).abs() < 1e-9 * p, "{kind:?}: Fy {fy}");
        assert!((w / w0 - 1.0 - NU / (1.0 - NU) * SQUEEZE).abs() < 1e-9);
        for t in &tn {
            assert!((t - p).abs() < 1e-9 * p, "{kind:?}: tn {tn:?}, p {p}");
        }
    }
}

#[test]
fn total_lagrangian_tractions_are_per_current_area() {
    let (w0, w, fy, tn) = squeeze(ElementKind::Q8, Kinematics::TotalLagrangian);
    assert!(w / w0 > 1.01, "the bottom widens: {w}");
    // Uniform Cauchy traction: the load over the current width.
    for t in &tn {
        assert!(
            (t * w / fy - 1.0).abs() < 1e-9,
            "tn {tn:?}, Fy / w {}",
            fy / w
        );
    }
}
