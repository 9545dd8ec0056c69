//! `[[tie]]` patch tests: two blocks of different materials, the upper one's
//! bottom nodes tied to the lower one's top. With coincident nodes a normal
//! tie carries a pressure exactly and lets the blocks slide along each
//! other; a full tie carries shear too. Non-matching meshes (nodes inside
//! segments) are only checked for what they carry: a node-to-segment tie
//! does not pass the patch test (the interpolated nodal forces are not the
//! consistent ones of the other side).

use contact2d::newton::Solver;
use contact2d::results::StepResult;
use std::path::Path;

const P: f64 = 2.0;
const E: [f64; 2] = [100.0, 300.0];
const NU: [f64; 2] = [0.3, 0.1];

/// The two blocks [0, 2] x [0, 1] (lower, `nx` elements wide) and [0, 2] x
/// [1, 2] (upper, 4 wide) with the tie and the loading `load` (TOML tables)
/// appended.
fn scene(kind: &str, nx: usize, load: &str) -> String {
    format!(
        r#"
[analysis]
kind = "plane_strain"

[[material]]
name = "soft"
model = "linear_elastic"
E = {e0}
nu = {nu0}

[[material]]
name = "stiff"
model = "linear_elastic"
E = {e1}
nu = {nu1}

[[body]]
name = "lower"
material = "soft"
mesh = {{ generator = "rectangle", origin = [0.0, 0.0], size = [2.0, 1.0], divisions = [{nx}, 2] }}

[[body]]
name = "upper"
material = "stiff"
mesh = {{ generator = "rectangle", origin = [0.0, 1.0], size = [2.0, 1.0], divisions = [4, 2] }}

[[tie]]
name = "glue"
nodes = "upper.bottom"
to = "lower.top"
kind = "{kind}"

[[function]]
name = "ramp"
points = [[0.0, 0.0], [1.0, 1.0]]

{load}

[steps]
times = [1.0]
"#,
        e0 = E[0],
        nu0 = NU[0],
        e1 = E[1],
        nu1 = NU[1],
    )
}

fn run(text: &str) -> (Solver, StepResult) {
    let problem = contact2d::scene::parse(text, Path::new("tie.toml")).unwrap();
    let mut solver = Solver::new(problem).unwrap();
    let step = solver.advance(1.0, &mut |_, _| {}).unwrap();
    (solver, step)
}

/// Rollers on the left sides and the lower bottom, a pressure on the top.
const PRESSED: &str = r#"
[[driver]]
name = "base"
set = "lower.bottom"
uy = 0.0

[[driver]]
name = "lower_left"
set = "lower.left"
ux = 0.0

[[driver]]
name = "upper_left"
set = "upper.left"
ux = 0.0

[[pressure]]
set = "upper.top"
value = { function = "ramp", scale = 2.0 }
"#;

fn displacement(solver: &Solver, p: [f64; 2]) -> [f64; 2] {
    let mesh = &solver.problem().mesh;
    let n = (0..mesh.nodes.len())
        .filter(|&n| mesh.nodes[n] == p)
        .collect::<Vec<_>>();
    assert!(!n.is_empty(), "no node at {p:?}");
    // Coincident nodes of the two bodies: the last one is the upper body's.
    solver.state().displacement(*n.last().unwrap())
}

#[test]
fn normal_tie_carries_a_pressure_exactly_and_lets_the_blocks_slide() {
    let (solver, step) = run(&scene("normal", 4, PRESSED));
    // Each block in its own uniaxial plane-strain state, sigma_yy = -P:
    // eps_yy = -(1 - nu^2) P / E, eps_xx = nu (1 + nu) P / E.
    let eps = |b: usize| {
        [
            NU[b] * (1.0 + NU[b]) * P / E[b],
            -(1.0 - NU[b] * NU[b]) * P / E[b],
        ]
    };
    let (lo, up) = (eps(0), eps(1));
    let top = displacement(&solver, [2.0, 2.0]);
    let uy_top = lo[1] + up[1];
    assert!((top[1] - uy_top).abs() <= 1e-12 * uy_top.abs(), "{top:?}");
    assert!((top[0] - 2.0 * up[0]).abs() <= 1e-12 * up[0], "{top:?}");
    // The lower block's top right corner moved by its own strain: the upper
    // one slid over it by the difference (free tangentially).
    let mesh = &solver.problem().mesh;
    let lower_corner = (0..mesh.nodes.len())
        .find(|&n| mesh.nodes[n] == [2.0, 1.0])
        .unwrap();
    let u = solver.state().displacement(lower_corner);
    assert!((u[0] - 2.0 * lo[0]).abs() <= 1e-12 * lo[0], "{u:?}");
    // Equilibrium: the base carries P times the width, and the tie passes
    // the same force from the lower block to the upper one.
    let base = &step.drivers.iter().find(|d| d.0 == "base").unwrap().1;
    assert!((base.ry - 2.0 * P).abs() <= 1e-10 * P, "{base:?}");
    let ties = solver.tie_results();
    let glue = &ties[0].1;
    assert!((glue.force[1] - 2.0 * P).abs() <= 1e-10 * P, "{glue:?}");
    assert!(glue.force[0].abs() <= 1e-10 * P, "{glue:?}");
    // Compression along the normal on every tied node, summing to 2 P.
    assert!(glue.normal.iter().all(|&f| f > 0.0), "{glue:?}");
    let total: f64 = glue.normal.iter().sum();
    assert!((total - 2.0 * P).abs() <= 1e-10 * P);
}

#[test]
fn full_tie_makes_the_interface_move_together() {
    let (solver, step) = run(&scene("full", 4, PRESSED));
    // The blocks' lateral expansions differ, so a full tie shears the
    // interface: both sides of it have the same displacement.
    let mesh = &solver.problem().mesh;
    let lower_corner = (0..mesh.nodes.len())
        .find(|&n| mesh.nodes[n] == [2.0, 1.0])
        .unwrap();
    let upper_corner = displacement(&solver, [2.0, 1.0]);
    let u = solver.state().displacement(lower_corner);
    assert!(
        (u[0] - upper_corner[0]).abs() <= 1e-12 * u[0].abs(),
        "{u:?} {upper_corner:?}"
    );
    assert!((u[1] - upper_corner[1]).abs() <= 1e-12 * u[1].abs());
    let base = &step.drivers.iter().find(|d| d.0 == "base").unwrap().1;
    assert!((base.ry - 2.0 * P).abs() <= 1e-10 * P, "{base:?}");
    let glue = &solver.tie_results()[0].1;
    assert!((glue.force[1] - 2.0 * P).abs() <= 1e-10 * P, "{glue:?}");
}

/// The lower block fixed at its bottom, the upper one dragged sideways.
const DRAGGED: &str = r#"
[[driver]]
name = "base"
set = "lower.bottom"
ux = 0.0
uy = 0.0

[[driver]]
name = "drag"
set = "upper.top"
ux = { function = "ramp", scale = 0.01 }
uy = 0.0
"#;

#[test]
fn normal_tie_transfers_no_shear_and_a_full_tie_does() {
    let (solver, step) = run(&scene("normal", 3, DRAGGED));
    let drag = &step.drivers.iter().find(|d| d.0 == "drag").unwrap().1;
    // The upper block slides rigidly: no force, no strain in the lower one.
    assert!(drag.rx.abs() <= 1e-12, "{drag:?}");
    let u = solver.state().displacement(0);
    assert!(u[0].abs() <= 1e-14 && u[1].abs() <= 1e-14);
    let glue = &solver.tie_results()[0].1;
    assert!(glue.force[0].abs() <= 1e-12 && glue.force[1].abs() <= 1e-12);

    let (solver, step) = run(&scene("full", 3, DRAGGED));
    let drag = &step.drivers.iter().find(|d| d.0 == "drag").unwrap().1;
    let base = &step.drivers.iter().find(|d| d.0 == "base").unwrap().1;
    assert!(drag.rx > 0.0);
    assert!(
        (drag.rx + base.rx).abs() <= 1e-10 * drag.rx,
        "{drag:?} {base:?}"
    );
    let glue = &solver.tie_results()[0].1;
    assert!(
        (glue.force[0] + drag.rx).abs() <= 1e-10 * drag.rx,
        "{glue:?}"
    );
    // The normal into the lower block is -y, the tangent (turned +90
    // degrees) +x: the tangential forces are the nodes' x forces, the
    // normal ones their y forces (compression positive, none here).
    let ft: f64 = glue.tangential.iter().sum();
    assert!((ft + drag.rx).abs() <= 1e-10 * drag.rx, "{glue:?}");
    for (k, f) in glue.nodal.iter().enumerate() {
        assert_eq!(glue.tangential[k], f[0]);
        assert_eq!(glue.normal[k], f[1]);
    }
    // The step result carries the same tie, with the nodes' current
    // positions (the upper block's bottom, dragged with it).
    assert_eq!(&step.ties[0].1, glue);
    let nodes = &solver.problem().mesh.nodes;
    for (k, &n) in glue.position.iter().zip(&solver.problem().ties[0].nodes) {
        let u = solver.state().displacement(n);
        assert_eq!(*k, [nodes[n][0] + u[0], nodes[n][1] + u[1]]);
    }
}

#[test]
fn a_tie_names_what_is_wrong() {
    let off =
        scene("normal", 4, PRESSED).replace(r#"nodes = "upper.bottom""#, r#"nodes = "upper.top""#);
    let e = contact2d::scene::parse(&off, Path::new("tie.toml")).unwrap_err();
    assert!(e.to_string().contains("tie[0].nodes"), "{e}");
    assert!(
        e.to_string()
            .contains("is not on the surface it is tied to `lower.top`"),
        "{e}"
    );
    let same = scene("normal", 4, PRESSED).replace(r#"to = "lower.top""#, r#"to = "upper.top""#);
    let e = contact2d::scene::parse(&same, Path::new("tie.toml")).unwrap_err();
    assert!(
        e.to_string().contains("another body than the tied nodes"),
        "{e}"
    );
}
