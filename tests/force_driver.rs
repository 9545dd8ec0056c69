//! Drivers that prescribe a force (`fx`, `fy`: the set's resultant, in
//! equal shares or on a set that moves as one) instead of a displacement:
//! the scene keys, a bar against F L / (E A), the elastica of
//! scenes/verification/cantilever_tip_load.toml loaded through a force
//! driver, the same state reached by the displacement the force produced,
//! and a frictional block brought by a force input to the state its
//! displacement-driven twin reaches.

mod common;

use contact2d::newton::Solver;
use contact2d::results::NodeState;
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

/// `distribution = "rigid"`: the bar of the test above, four elements
/// through its height and nu = 0.3, pulled at its right end by fx = F on a
/// set that moves as one (a plane end). A uniform stress F / A with a free
/// lateral contraction is the exact solution (the wall is a roller, so the
/// end may stay plane), and the bilinear element holds it exactly: every
/// end node moves by F L / (E A) to round-off. Equal shares on the same
/// five nodes are not the consistent loads of a uniform traction (1/8, 1/4,
/// 1/4, 1/4, 1/8), so there the end does not stay plane.
#[test]
fn a_rigid_force_set_moves_as_one() {
    let end = |distribution: &str| {
        let load = format!(
            "[[driver]]\nname = \"pull\"\nset = \"bar.right\"\nfx = 40.0\ndistribution = \"{distribution}\""
        );
        let text = common::bar_scene("q4", [8, 4], &load, 1.0).replace("nu = 0.0", "nu = 0.3");
        let problem = contact2d::scene::parse(&text, Path::new("scenes/bar.toml")).unwrap();
        let mut solver = Solver::new(problem).unwrap();
        let step = run(&mut solver);
        let nodes = solver.problem().mesh.node_sets["bar.right"].clone();
        let ux: Vec<f64> = nodes.iter().map(|&n| solver.state().u[2 * n]).collect();
        (step.drivers[2].1.clone(), ux)
    };
    let expected = 40.0 * 10.0 / (1000.0 * 1.0 * 2.0);
    let (pull, ux) = end("rigid");
    assert_eq!(ux.len(), 5);
    for &u in &ux {
        assert!(
            (u - expected).abs() <= 1e-12 * expected,
            "ux {ux:?} vs {expected}"
        );
    }
    let mean = pull.ux.unwrap();
    assert!(
        (mean - expected).abs() <= 1e-12 * expected,
        "reported {mean}"
    );
    assert_eq!(pull.rx, 40.0);
    let (_, ux) = end("equal");
    let spread =
        ux.iter().fold(f64::MIN, |a, &b| a.max(b)) - ux.iter().fold(f64::MAX, |a, &b| a.min(b));
    assert!(
        spread > 1e-3 * expected,
        "equal shares keep the end plane: {ux:?}"
    );
}

/// The check of a force input: the sliding block of
/// scenes/verification/sliding_block.toml pressed and dragged sideways in
/// one increment, its top moved by a displacement, and the same scene with
/// the top pulled by the force that displacement needed, on a rigid set
/// (what a displacement driver does to a set: it moves as one). One
/// increment from the same start is the same discrete problem, friction
/// included, so the force reaches the displacement's state in one step, in
/// partial slip (the edges slide, the middle sticks). (In full slip a
/// force-driven block has no equilibrium beyond mu N: its drag is a limit
/// load.)
/// Tolerance: both runs stop at the force tolerance (1e-8 of the force
/// scale); the block's compliance turns that into well under 1e-6 of the
/// drag.
#[test]
fn a_force_input_reaches_the_displacement_driven_state() {
    let scene =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/verification/sliding_block.toml");
    let text = std::fs::read_to_string(&scene).unwrap();
    let solve = |top: &str| {
        let text = text
            .replace(
                "ux = { function = \"drag\", scale = 0.2 }\nuy = { function = \"press\", scale = -0.01 }",
                &format!("uy = -0.01\n\n[[driver]]\nname = \"drag\"\nset = \"block.top\"\n{top}"),
            )
            .replace("times = [0.5, 1.0, 1.02,", "times = [1.0]\nold = [1.02,")
            // Held sideways by a force alone, the block has no stiffness
            // until it touches: it starts in touch (docs/scenes.md).
            .replace("points = [[10.0, 0.0], [-10.0, 0.0]]", "points = [[10.0, 1e-8], [-10.0, 1e-8]]");
        let text = text.split("\nold = ").next().unwrap().to_string();
        let problem = contact2d::scene::parse(&text, &scene).unwrap();
        let mut solver = Solver::new(problem).unwrap();
        let step = run(&mut solver);
        (step, solver.state().u.clone())
    };
    for drag in [0.002, 0.004] {
        let (moved, u_moved) = solve(&format!("ux = {drag:e}"));
        let force = moved.drivers.iter().find(|d| d.0 == "drag").unwrap().1.rx;
        let (pulled, u_pulled) = solve(&format!("fx = {force:e}\ndistribution = \"rigid\""));
        let by_force = &pulled.drivers.iter().find(|d| d.0 == "drag").unwrap().1;
        let ux = by_force.ux.unwrap();
        assert!((ux - drag).abs() <= 1e-6 * drag, "ux {ux} vs {drag}");
        let u_max = u_moved.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        let diff = (u_moved.iter().zip(&u_pulled))
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(
            diff <= 1e-6 * u_max,
            "drag {drag}: states differ by {diff} (max |u| {u_max})"
        );
        let (a, b) = (&moved.pairs[0].1, &pulled.pairs[0].1);
        assert_eq!(
            a.nodes.state, b.nodes.state,
            "drag {drag}: stick/slip states"
        );
        let sliding = a
            .nodes
            .state
            .iter()
            .filter(|&&s| s == NodeState::Slip)
            .count();
        eprintln!(
            "drag {drag}: Fx {force:.4}, {sliding} of {} nodes slide, {} / {} iterations",
            a.nodes.state.len(),
            moved.iterations,
            pulled.iterations
        );
        assert!(sliding > 0, "drag {drag}: the edges slide");
        assert!(pulled.iterations <= 15, "{} iterations", pulled.iterations);
    }
}

#[test]
fn a_distribution_needs_a_force_and_a_rigid_set_its_own_nodes() {
    let bar = |load: &str| {
        let text = common::bar_scene("q4", [8, 1], load, 1.0);
        contact2d::scene::parse(&text, Path::new("scenes/bar.toml")).unwrap_err()
    };
    let e =
        bar("[[driver]]\nname = \"pull\"\nset = \"bar.right\"\nux = 1.0\ndistribution = \"rigid\"");
    assert!(
        e.to_string().contains("driver[2].distribution")
            && e.message.contains("prescribes no force"),
        "{e}"
    );
    let e = bar(
        "[[driver]]\nname = \"pull\"\nset = \"bar.right\"\nfx = 1.0\ndistribution = \"clamped\"",
    );
    assert!(e.to_string().contains("clamped"), "{e}");
    // bar.left is held in x by the wall: a rigid fx on it would have to
    // move it.
    let e =
        bar("[[driver]]\nname = \"pull\"\nset = \"bar.left\"\nfx = 1.0\ndistribution = \"rigid\"");
    assert!(
        e.to_string().contains("driver[2].set")
            && e.message.contains("rigid force fx")
            && e.message.contains("`wall`"),
        "{e}"
    );
    // Equal shares on a held node are a load the wall takes: allowed.
    let text = common::bar_scene(
        "q4",
        [8, 1],
        "[[driver]]\nname = \"pull\"\nset = \"bar.left\"\nfx = 1.0",
        1.0,
    );
    contact2d::scene::parse(&text, Path::new("scenes/bar.toml")).unwrap();
}

/// The winding machine's capstan with both strip ends pulled by forces
/// (T1 = 10 N on the slack end, T2 = 12 N on the tight end, at once): the
/// strip is held along the drum by its tension and friction alone. The
/// default inner solves (opening and closing on the linearised problem)
/// fail it; `advance` then solves the increment again with opening and
/// closing decided on the iterate (`StepResult::fallbacks`), without
/// halving it. The converged state: the drum holds both forces, the
/// contact conditions hold, and as T2 / T1 = 1.2 < exp(mu pi) = 2.19 part
/// of the wrap sticks, the friction's moment balances the ends', and
/// |Ft| <= mu Fn.
#[test]
fn capstan_held_by_two_forces_converges_through_the_fallback() {
    use common::stress::{Frame, check_contact_conditions};
    let (text, path) = common::scene_text("capstan_drum_frame.toml", &[("uy = 0.0", "fy = -12.0")]);
    let problem = contact2d::scene::parse(&text, &path).unwrap();
    let mut solver = Solver::new(problem).unwrap();
    let before = Frame::at_rest(&solver);
    let step = solver.advance(1.0, &mut |_, _| {}).unwrap();
    assert_eq!(step.substeps, 0);
    assert_eq!(
        step.fallbacks, 1,
        "the inner solves alone now converge it: drop the note in README"
    );
    assert!(step.iterations <= 15, "{} iterations", step.iterations);
    let drum = &step.drivers.iter().find(|d| d.0 == "drum").unwrap().1;
    assert!((drum.ry + 22.0).abs() <= 1e-9 * 22.0, "{drum:?}");
    let wrap = &step.pairs[0].1;
    assert!(wrap.n_stick > 0, "{wrap:?}");
    // The drum's moment balances the ends' forces, T2 - T1 = 2 N along
    // lines between R = 100 and R + 1 (the strip's thickness); it is the
    // friction's, Ft R, but for the normal forces' arms: a chord's normal
    // passes through the centre at its midpoint only, up to half a chord
    // (225 degrees in 5120 chords) from the contact point.
    let r = 100.000001;
    let mz = drum.mz.unwrap();
    assert!((200.0..=202.0).contains(&mz.abs()), "Mz {mz}");
    let half_chord = 0.5 * r * 225f64.to_radians() / 5120.0;
    assert!(
        (mz - wrap.ft * r).abs() <= wrap.fn_ * half_chord,
        "Mz {mz} Ft {} Fn {}",
        wrap.ft,
        wrap.fn_
    );
    assert!(
        wrap.ft.abs() <= 0.25 * wrap.fn_,
        "Ft {} Fn {}",
        wrap.ft,
        wrap.fn_
    );
    let now = Frame::now(&solver, step);
    check_contact_conditions(solver.problem(), &before, &now).unwrap();
}

/// A block resting on a rigid plane at gap 0 (the verification scene
/// scenes/verification/sliding_block.toml, its bottom nodes on the plane)
/// with its top pressed by fy = -N and pushed by fx = Q, a rigid force set,
/// instead of moved: forces alone, so at its first solve the contact is all
/// that could hold it, but touching nodes have not penetrated and stay
/// open, and the solve finds the body free. `advance` then tries the
/// increment again with the touching nodes closed
/// (`StepResult::fallbacks`). With Q < mu_s N the block holds (its middle
/// sticks): Fn = N, |Ft| = Q, the plane holds both, the contact conditions
/// hold. With Q > mu_s N nothing can hold it: the increment fails, and the
/// state stays where it was.
#[test]
fn a_block_resting_at_gap_0_is_held_by_its_contact() {
    use common::stress::{Frame, check_contact_conditions};
    let scene = |q: &str| {
        let fx = format!("fx = {{ function = \"press\", scale = {q} }}");
        let (text, path) = common::scene_text(
            "verification/sliding_block.toml",
            &[
                ("ux = { function = \"drag\", scale = 0.2 }", &fx),
                (
                    "uy = { function = \"press\", scale = -0.01 }",
                    "fy = { function = \"press\", scale = -10.0 }\ndistribution = \"rigid\"",
                ),
            ],
        );
        contact2d::scene::parse(&text, &path).unwrap()
    };
    let mut solver = Solver::new(scene("1.0")).unwrap();
    let mut prev = Frame::at_rest(&solver);
    for t in [0.5, 1.0] {
        let step = solver.advance(t, &mut |_, _| {}).unwrap();
        assert_eq!(step.substeps, 0);
        // Only the first increment starts free.
        assert_eq!(step.fallbacks, usize::from(t == 0.5));
        assert!(step.iterations <= 4, "{} iterations", step.iterations);
        let base = &step.pairs[0].1;
        // All in contact; the corners may slide (the shear peaks there).
        assert!(base.n_open == 0 && base.n_stick >= 1, "{base:?}");
        assert!((base.fn_ - 10.0 * t).abs() <= 1e-10, "Fn {}", base.fn_);
        assert!((base.ft.abs() - t).abs() <= 1e-10, "Ft {}", base.ft);
        let plane = &step.drivers.iter().find(|d| d.0 == "plane").unwrap().1;
        assert!(
            (plane.rx - t).abs() <= 1e-10 && (plane.ry + 10.0 * t).abs() <= 1e-10,
            "{plane:?}"
        );
        let cur = Frame::now(&solver, step);
        check_contact_conditions(solver.problem(), &prev, &cur).unwrap();
        prev = cur;
    }
    // Past friction's capacity (Q = 4 > 0.3 x 10, at every bisection too):
    // no equilibrium, the state kept.
    let mut solver = Solver::new(scene("4.0")).unwrap();
    solver.settings_mut().max_bisections = 1;
    let before = solver.state().clone();
    let err = solver.advance(1.0, &mut |_, _| {}).unwrap_err().to_string();
    // What it meets first depends on the path (a node alternating between
    // open and contact as the block starts to slide, or a correction
    // without equilibrium); either way it names the increment.
    assert!(err.contains("t = 1 failed"), "{err}");
    assert_eq!(solver.state(), &before);
}
