//! The inner solves of the winding machine's capstan (a frictional strip on
//! a rigid drum, the FMU's scene), drawn as the machine draws it: each is
//! factored by the unpivoted LDU (`linsolve::ldu`, `Augmented::try_ldu`);
//! and the drawn state keeps the contact conditions.

mod common;

use contact2d::newton::Solver;

/// Three steps of 0.05 mm, as `benches/scale.rs` draws the FMU: the slip
/// front crosses the wrap one node per inner solve, and every one of them
/// is factored by the LDU (the systems are unsymmetric), none on a
/// trailing block.
#[test]
fn drawn_capstan_factors_its_inner_solves_by_the_ldu() {
    use common::stress::{Frame, check_contact_conditions};
    let (text, path) = common::scene_text(
        "capstan_drum_frame.toml",
        &[
            ("uy = 0.0", "uy = { function = \"draw\", scale = -0.15 }"),
            (
                "times = [0.05]",
                "times = [0.05, 0.1, 0.15]\n\n[[function]]\nname = \"draw\"\npoints = [[0.0, 0.0], [0.15, 1.0]]",
            ),
        ],
    );
    let problem = contact2d::scene::parse(&text, &path).unwrap();
    let mut solver = Solver::new(problem).unwrap();
    let mut before = Frame::at_rest(&solver);
    let mut steps = Vec::new();
    for t in [0.05, 0.1, 0.15] {
        let step = solver.advance(t, &mut |_, _| {}).unwrap();
        assert!(step.converged, "t = {t}");
        steps.push(step.iterations);
        assert_eq!(step.substeps, 0, "t = {t}");
        let now = Frame::now(&solver, step);
        check_contact_conditions(solver.problem(), &before, &now).unwrap();
        before = now;
    }
    let p = solver.phases();
    println!("{}", p.summary());
    // More LDU solves than iterations: the inner solves are factored (the
    // one factorization beside them is an LDLT attempt that failed its
    // checks, counted too).
    let iterations: usize = steps.iter().sum();
    assert!(p.ldu >= iterations + 10, "{}", p.summary());
    assert_eq!((p.ldlt, p.lu), (0, 0), "{}", p.summary());
    assert_eq!(p.trailing, 0, "{}", p.summary());
}

/// The capstan at 128 strip elements drawn ten steps of 0.05 mm (the FMU
/// benchmark's scene, `benches/scale.rs`). Past the first step (which also
/// applies the back tension) the slack side's nodes slide at their capacity
/// with next to no slip (5e-8 mm), and the predictor's linearisation moves
/// them back (1e-4 mm): the inner solves stick them, then release them as
/// their forces pass the capacity. They release them as the iterate's
/// decisions do (`nodal::decide`: beyond the capacity by any amount), so the
/// next iterates keep the states and every drawn step takes Newton's 3
/// iterations. With a force tolerance in the inner solves' rule alone they
/// settled on stick zones the next iterates released by the dozen: 3 to 6
/// iterations and 10 to 71 solves per step.
#[test]
fn drawn_capstan_steps_take_three_iterations() {
    use common::stress::{Frame, check_contact_conditions};
    let times: Vec<String> = (1..=10)
        .map(|i| format!("{:.2}", 0.05 * i as f64))
        .collect();
    let (text, path) = common::scene_text(
        "capstan_drum_frame.toml",
        &[
            ("divisions = [1, 64]", "divisions = [1, 128]"),
            ("uy = 0.0", "uy = { function = \"draw\", scale = -0.5 }"),
            (
                "times = [0.05]",
                &format!(
                    "times = [{}]\n\n[[function]]\nname = \"draw\"\npoints = [[0.0, 0.0], [0.5, 1.0]]",
                    times.join(", ")
                ),
            ),
        ],
    );
    let problem = contact2d::scene::parse(&text, &path).unwrap();
    let mut solver = Solver::new(problem).unwrap();
    let mut before = Frame::at_rest(&solver);
    let mut iterations = Vec::new();
    for t in &times {
        let t: f64 = t.parse().unwrap();
        let step = solver.advance(t, &mut |_, _| {}).unwrap();
        assert!(step.converged, "t = {t}");
        assert_eq!(step.substeps, 0, "t = {t}");
        iterations.push(step.iterations);
        let now = Frame::now(&solver, step);
        check_contact_conditions(solver.problem(), &before, &now).unwrap();
        before = now;
    }
    println!(
        "iterations per step: {iterations:?}; {}",
        solver.phases().summary()
    );
    assert!(
        iterations[1..].iter().all(|&i| i <= 3),
        "iterations per step: {iterations:?}"
    );
}
