//! Scene parameters: a `[parameters]` table of named numbers, used wherever
//! a number stands as `"= expression"`; set to other values from outside
//! (`scene::parse_with`, the FMU's parameters), with the same checks and
//! file:line errors as a number written in the file.

mod common;

use contact2d::newton::Solver;
use contact2d::scene::{self, SceneErrorKind};
use std::path::Path;

const FILE: &str = "scenes/p.toml";

/// The bar of `common::bar_scene` (E = 1000, thickness 2, height 1: E A =
/// 2000) with its length, divisions and end force as parameters.
fn bar() -> String {
    let text = common::bar_scene(
        "q4",
        [8, 1],
        "[[driver]]\nname = \"pull\"\nset = \"bar.right\"\nfx = \"= force\"",
        1.0,
    );
    let text = text.replacen(
        "size = [10.0, 1.0], divisions = [8, 1]",
        "size = [\"= length\", 1.0], divisions = [\"= 2 * half\", 1]",
        1,
    );
    format!("[parameters]\nlength = 10.0\nhalf = 4\nforce = 40.0\n\n{text}")
}

fn stretch(problem: contact2d::problem::Problem) -> f64 {
    let mut solver = Solver::new(problem).unwrap();
    let step = solver.advance(1.0, &mut common::silent()).unwrap();
    step.drivers
        .iter()
        .find(|(n, _)| n == "pull")
        .unwrap()
        .1
        .ux
        .unwrap()
}

#[test]
fn expressions_take_the_parameters_values() {
    let p = scene::parse(&bar(), Path::new(FILE)).unwrap();
    assert_eq!(p.parameters.len(), 3);
    assert_eq!(p.parameters[0].name, "length");
    assert_eq!(p.parameters[0].value, 10.0);
    // 8 elements along (2 * half), 1 through: 18 nodes.
    assert_eq!(p.mesh.nodes.len(), 18);
    let right = p.mesh.nodes.iter().map(|x| x[0]).fold(f64::MIN, f64::max);
    assert_eq!(right, 10.0);
    // F L / (E A) = 40 * 10 / 2000, exact for a uniform stress.
    assert!((stretch(p) - 0.2).abs() < 1e-12);
}

#[test]
fn overrides_change_every_use() {
    let overrides = [("length".to_string(), 15.0), ("force".to_string(), 10.0)];
    let p = scene::parse_with(&bar(), Path::new(FILE), &overrides).unwrap();
    assert_eq!(p.parameters[0].value, 15.0);
    assert_eq!(p.parameters[0].default, 10.0);
    let right = p.mesh.nodes.iter().map(|x| x[0]).fold(f64::MIN, f64::max);
    assert_eq!(right, 15.0);
    assert!((stretch(p) - 10.0 * 15.0 / 2000.0).abs() < 1e-12);
    // An integer key takes an integral value.
    let p = scene::parse_with(&bar(), Path::new(FILE), &[("half".into(), 3.0)]).unwrap();
    assert_eq!(p.mesh.nodes.len(), 14);
}

#[test]
fn errors_name_the_line_and_the_expression() {
    // A value out of range where it is used: the check of that key, on
    // its line, with the expression that gave it.
    let e = scene::parse_with(&bar(), Path::new(FILE), &[("length".into(), -2.0)]).unwrap_err();
    assert_eq!(e.kind, SceneErrorKind::InvalidValue, "{e}");
    let line = bar().lines().position(|l| l.contains("= length")).unwrap() + 1;
    assert_eq!(e.line, line, "{e}");
    assert!(
        e.message
            .contains("(from \"length\" = -2, \"2 * half\" = 8)"),
        "{e}"
    );
    // Not an integer where one is wanted.
    let e = scene::parse_with(&bar(), Path::new(FILE), &[("half".into(), 2.25)]).unwrap_err();
    assert_eq!(e.line, line, "{e}");
    assert!(e.to_string().contains("\"2 * half\" = 4.5"), "{e}");
    // An unknown name in an expression.
    let text = bar().replacen("fx = \"= force\"", "fx = \"= forse * 2\"", 1);
    let e = scene::parse(&text, Path::new(FILE)).unwrap_err();
    assert_eq!(e.kind, SceneErrorKind::InvalidValue);
    assert_eq!(
        e.to_string(),
        format!(
            "{FILE}:{}: driver[2].fx = \"= forse * 2\": expression \"forse * 2\": no parameter named \"forse\" (at \"forse * 2\"); [parameters] defines the names",
            text.lines().position(|l| l.contains("forse")).unwrap() + 1
        )
    );
    // Setting a parameter the scene does not have.
    let e = scene::parse_with(&bar(), Path::new(FILE), &[("width".into(), 1.0)]).unwrap_err();
    assert_eq!(e.kind, SceneErrorKind::UnknownReference);
    assert!(e.to_string().contains("parameters.width"), "{e}");
    assert!(e.to_string().contains("length, half, force"), "{e}");
    // A parameter that is not a number, or badly named.
    let text = bar().replacen("length = 10.0", "length = \"ten\"", 1);
    let e = scene::parse(&text, Path::new(FILE)).unwrap_err();
    assert_eq!(e.line, 2, "{e}");
    assert!(
        e.message.contains("a parameter's value is a finite number"),
        "{e}"
    );
    let text = bar().replacen("half = 4", "2half = 4", 1);
    let e = scene::parse(&text, Path::new(FILE)).unwrap_err();
    assert_eq!(e.line, 3, "{e}");
    assert!(e.message.contains("a parameter's name is a letter"), "{e}");
    // A non-finite result.
    let text = bar().replacen("fx = \"= force\"", "fx = \"= force / (half - 4)\"", 1);
    let e = scene::parse(&text, Path::new(FILE)).unwrap_err();
    assert!(e.message.contains("gives inf, not a finite number"), "{e}");
}

#[test]
fn a_string_that_is_not_an_expression_stays_a_string() {
    // Names and set references are strings; only "=..." is evaluated.
    let p = scene::parse(&bar(), Path::new(FILE)).unwrap();
    assert_eq!(p.drivers[2].name, "pull");
}
