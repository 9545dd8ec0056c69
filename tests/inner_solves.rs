//! The inner solves of the winding machine's capstan (a frictional strip on
//! a rigid drum, the FMU's scene), drawn as the machine draws it: each
//! borders its Newton iteration's LU factor (`linsolve::bordering`) and
//! reads its system from the tangent and the entries beside it
//! (`bordering::Split`, the tangent counted by the solver) instead of
//! building it whole; and the drawn state keeps the contact conditions.

mod common;

use contact2d::newton::Solver;

/// Three steps of 0.05 mm, as `benches/scale.rs` draws the FMU: the slip
/// front crosses the wrap one node per inner solve, and every bordered
/// solve of them is a split one (none is on a trailing block: the system
/// is unsymmetric, and LU has none).
#[test]
fn drawn_capstan_borders_from_the_entries_beside_the_tangent() {
    use common::stress::{Frame, check_contact_conditions};
    let (text, path) = common::scene_text(
        "../examples/winding_machine/capstan.toml",
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
    for t in [0.05, 0.1, 0.15] {
        let step = solver.advance(t, &mut |_, _| {}).unwrap();
        assert!(step.converged, "t = {t}");
        assert_eq!(step.substeps, 0, "t = {t}");
        let now = Frame::now(&solver, step);
        check_contact_conditions(solver.problem(), &before, &now).unwrap();
        before = now;
    }
    let p = solver.phases();
    println!("{}", p.summary());
    assert!(p.bordered >= 10, "{}", p.summary());
    assert_eq!(p.trailing, 0, "{}", p.summary());
    assert_eq!(p.split_solves, p.bordered, "{}", p.summary());
}
