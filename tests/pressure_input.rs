//! A named edge pressure is an input: `Solver::set_pressure_input` (the
//! FMU's `<name>.p`) overrides the scene's value at the end of a step,
//! reached linearly from the converged one. Checked on a bar pulled by a
//! uniform traction on its end against F L / (E A), with its name rules.

mod common;

use contact2d::newton::Solver;
use contact2d::scene::SceneErrorKind;
use std::path::Path;

/// The bar of `common::bar_scene` (Q8) with a named pressure on its right
/// edge, zero in the scene, over two increments.
fn bar_text() -> String {
    common::bar_scene(
        "q8",
        [8, 2],
        "[[pressure]]\nname = \"pull\"\nset = \"bar.right\"\nvalue = 0.0\nfollower = false",
        2.0,
    )
}

fn bar(text: &str) -> Solver {
    Solver::new(contact2d::scene::parse(text, Path::new("scenes/bar.toml")).unwrap()).unwrap()
}

#[test]
fn pressure_input_pulls_the_bar_by_f_l_over_e_a() {
    let mut s = bar(&bar_text());
    let right: Vec<usize> = s.problem().mesh.node_sets["bar.right"].clone();
    // p = -20 (a pull) on the end of height 1 and thickness 2: F = 40,
    // u = F L / (E A) = 40 * 10 / (1000 * 2) = 0.2 at every node of the
    // end (uniform stress: exact for the 8-node element).
    s.set_pressure_input(0, Some(-20.0));
    let step = s.advance(1.0, &mut |_, _| {}).unwrap();
    for &n in &right {
        let ux = s.state().u[2 * n];
        assert!((ux - 0.2).abs() <= 1e-12, "node {n}: {ux}");
    }
    // The wall holds the bar back: -40 on it.
    assert!(
        (step.drivers[0].1.rx + 40.0).abs() <= 1e-10,
        "{:?}",
        step.drivers[0]
    );
    // Held: no iteration, the same state.
    let step = s.advance(2.0, &mut |_, _| {}).unwrap();
    assert_eq!(step.iterations, 0);
    // Back to the scene's value (0): unloaded.
    s.set_pressure_input(0, None);
    let mut again = bar(&bar_text().replace("t_end = 2.0", "t_end = 3.0"));
    again.set_pressure_input(0, Some(-20.0));
    again.advance(1.0, &mut |_, _| {}).unwrap();
    again.set_pressure_input(0, None);
    again.advance(2.0, &mut |_, _| {}).unwrap();
    let n = right[0];
    assert!(again.state().u[2 * n].abs() <= 1e-12);
}

/// Halfway through a step the pressure is halfway: a step bisected by
/// its own time (two increments of 0.5) ends where one does.
#[test]
fn pressure_input_runs_linearly_over_the_step() {
    let mut one = bar(&bar_text());
    one.set_pressure_input(0, Some(-20.0));
    one.advance(1.0, &mut |_, _| {}).unwrap();
    let mut two = bar(&bar_text());
    two.set_pressure_input(0, Some(-10.0));
    two.advance(0.5, &mut |_, _| {}).unwrap();
    two.set_pressure_input(0, Some(-20.0));
    two.advance(1.0, &mut |_, _| {}).unwrap();
    let diff = (one.state().u.iter().zip(&two.state().u))
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(diff <= 1e-12, "{diff}");
}

#[test]
fn pressure_names_follow_the_fmu_rules() {
    let parse = |t: &str| contact2d::scene::parse(t, Path::new("scenes/bar.toml"));
    let e = parse(&bar_text().replace("name = \"pull\"", "name = \"pull-1\"")).unwrap_err();
    assert_eq!(e.kind, SceneErrorKind::InvalidValue);
    assert!(
        e.to_string().contains("pressure[0].name = \"pull-1\""),
        "{e}"
    );
    let twice = bar_text().replace(
        "[steps]",
        "[[pressure]]\nname = \"pull\"\nset = \"bar.top\"\nvalue = 1.0\n\n[steps]",
    );
    let e = parse(&twice).unwrap_err();
    assert_eq!(e.kind, SceneErrorKind::Duplicate, "{e}");
    // Unnamed pressures stay as they were.
    assert!(parse(&bar_text().replace("name = \"pull\"\n", "")).is_ok());
}
