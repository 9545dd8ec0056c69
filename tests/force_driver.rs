//! Drivers that prescribe a force (`fx`, `fy`: the set's resultant, shared
//! equally by its nodes) instead of a displacement: the scene keys, a bar
//! against F L / (E A), the elastica of scenes/verification/
//! cantilever_tip_load.toml loaded through a force driver, and the same
//! state reached by the displacement the force produced.

mod common;

use contact2d::newton::Solver;
use contact2d::scene::SceneErrorKind;
use std::path::Path;

const CANTILEVER: &str = "verification/cantilever_tip_load.toml";
/// The scene's tip load as a [[force]] ...
const TIP_FORCE: &str =
    "[[force]]\nset = \"beam.tip\"\nfy = { function = \"ramp\", scale = -80.0 }";
/// ... and as a driver prescribing the force.
const TIP_DRIVER: &str =
    "[[driver]]\nname = \"tip\"\nset = \"beam.tip\"\nfy = { function = \"ramp\", scale = -80.0 }";

fn run(solver: &mut Solver) -> contact2d::results::StepResult {
    let times = solver.problem().times.clone();
    let mut last = None;
    for t in times {
        last = Some(solver.advance(t, &mut |_, _| {}).unwrap());
    }
    last.unwrap()
}

/// A bar in plane stress, nu = 0, one element through its height (so that
/// equal shares on the end's two nodes are the consistent nodal forces of a
/// uniform traction): clamped in x at the left, pulled by fx = F at the
/// right. Exact for the bilinear element: u = F L / (E h t) at the end.
#[test]
fn bar_pulled_by_a_force_stretches_by_f_l_over_e_a() {
    let text = common::bar_scene(
        "q4",
        [8, 1],
        "[[driver]]\nname = \"pull\"\nset = \"bar.right\"\nfx = 40.0",
        1.0,
    );
    let problem = contact2d::scene::parse(&text, Path::new("scenes/bar.toml")).unwrap();
    let mut solver = Solver::new(problem).unwrap();
    let step = run(&mut solver);
    let pull = &step.drivers[2].1;
    let expected = 40.0 * 10.0 / (1000.0 * 1.0 * 2.0);
    let ux = pull.ux.unwrap();
    assert!(
        (ux - expected).abs() <= 1e-12 * expected,
        "ux {ux} vs {expected}"
    );
    // The applied force is reported as the driver's Rx; the wall holds it.
    assert_eq!(pull.rx, 40.0);
    assert!(
        (step.drivers[0].1.rx + 40.0).abs() <= 1e-10,
        "{:?}",
        step.drivers[0]
    );
    assert_eq!(pull.uy, None);
}

/// The tip load of the cantilever as a force driver: every increment the
/// same state as with the scene's [[force]] (the same load on the same
/// node), so the elastica check of tests/scenes.rs holds as well; the tip
/// driver reports the displacement.
#[test]
fn cantilever_tip_force_through_a_driver() {
    let mut by_force = Solver::new(common::shipped_scene(CANTILEVER, &[])).unwrap();
    let mut by_driver = Solver::new(common::shipped_scene(
        CANTILEVER,
        &[(TIP_FORCE, TIP_DRIVER)],
    ))
    .unwrap();
    let times = by_force.problem().times.clone();
    for t in times {
        let a = by_force.advance(t, &mut |_, _| {}).unwrap();
        let b = by_driver.advance(t, &mut |_, _| {}).unwrap();
        assert_eq!(a.iterations, b.iterations, "t = {t}");
        let diff = (by_force.state().u.iter().zip(&by_driver.state().u))
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(diff <= 1e-12, "t = {t}: {diff}");
        let tip = &b.drivers[1].1;
        assert_eq!(tip.ry, -80.0 * t);
        let node = by_driver.problem().mesh.node_sets["beam.tip"][0];
        assert_eq!(tip.uy, Some(by_driver.state().u[2 * node + 1]));
    }
    // Mattiasson (1981), k = 1: v/L = 0.30172 (tests/scenes.rs, 0.2 %).
    let node = by_driver.problem().mesh.node_sets["beam.tip"][0];
    let v = -by_driver.state().u[2 * node + 1] / 10.0;
    assert!((v / 0.30172 - 1.0).abs() < 2e-3, "v/L = {v}");
}

/// The displacement the force produced, prescribed instead (one increment:
/// the elastic state does not depend on the path), needs the force back as
/// its reaction: the two kinds of driver describe the same equilibrium.
#[test]
fn the_displacement_a_force_produced_needs_that_force() {
    let mut by_driver = Solver::new(common::shipped_scene(
        CANTILEVER,
        &[(TIP_FORCE, TIP_DRIVER)],
    ))
    .unwrap();
    let step = run(&mut by_driver);
    let tip = &step.drivers[1].1;
    let (ux, uy) = {
        let node = by_driver.problem().mesh.node_sets["beam.tip"][0];
        (by_driver.state().u[2 * node], tip.uy.unwrap())
    };
    let held = format!(
        "[[driver]]\nname = \"tip\"\nset = \"beam.tip\"\nux = {{ function = \"ramp\", scale = {ux:e} }}\nuy = {{ function = \"ramp\", scale = {uy:e} }}"
    );
    let mut by_motion = Solver::new(common::shipped_scene(
        CANTILEVER,
        &[(TIP_FORCE, held.as_str()), ("dt = 0.25", "dt = 1.0")],
    ))
    .unwrap();
    let step = run(&mut by_motion);
    let r = &step.drivers[1].1;
    // The scene's force tolerance (1e-8 of the force scale) bounds both
    // runs' residuals; 1e-6 of the load leaves room for both.
    assert!((r.ry + 80.0).abs() <= 1e-6 * 80.0, "Ry {}", r.ry);
    assert!(r.rx.abs() <= 1e-6 * 80.0, "Rx {}", r.rx);
}

#[test]
fn a_component_is_a_displacement_or_a_force() {
    let both = "[[driver]]\nname = \"tip\"\nset = \"beam.tip\"\nuy = 0.0\nfy = 1.0";
    let (text, path) = common::scene_text(CANTILEVER, &[(TIP_FORCE, both)]);
    let e = contact2d::scene::parse(&text, &path).unwrap_err();
    assert_eq!(e.kind, SceneErrorKind::InvalidValue);
    assert!(
        e.to_string().contains("driver[1].fy") && e.message.contains("uy and fy both given"),
        "{e}"
    );
    let none = "[[driver]]\nname = \"tip\"\nset = \"beam.tip\"";
    let (text, path) = common::scene_text(CANTILEVER, &[(TIP_FORCE, none)]);
    let e = contact2d::scene::parse(&text, &path).unwrap_err();
    assert!(
        e.message
            .contains("at least one component: ux or fx, uy or fy"),
        "{e}"
    );
}
