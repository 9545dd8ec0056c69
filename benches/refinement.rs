//! Run time against error for the verification scenes under mesh refinement,
//! and the throughput of a large mesh.
//!
//!     cargo bench --bench refinement
//!
//! Prints one line per run: scene, mesh, unknowns, increments, Newton
//! iterations, factorizations, wall time and the error against the exact or
//! published value. Nothing is asserted here; tests/scenes.rs asserts the
//! accuracy on the shipped meshes.

#[path = "../tests/common/mod.rs"]
mod common;

use contact2d::newton::Solver;
use std::time::Instant;

struct Run {
    solver: Solver,
    seconds: f64,
    iterations: usize,
}

fn run(name: &str, edits: &[(&str, String)]) -> Run {
    let edits: Vec<(&str, &str)> = edits.iter().map(|(o, n)| (*o, n.as_str())).collect();
    let problem = common::shipped_scene(name, &edits);
    let times = problem.times.clone();
    let start = Instant::now();
    let mut solver = Solver::new(problem).unwrap();
    let mut iterations = 0;
    for t in times {
        let r = solver.advance(t, &mut |_, _| {}).unwrap();
        iterations += r.iterations;
    }
    Run {
        seconds: start.elapsed().as_secs_f64(),
        solver,
        iterations,
    }
}

fn print(scene: &str, mesh: &str, r: &Run, error: &str) {
    println!(
        "{scene:<11} {mesh:<12} dofs {:>7}  increments {:>2}  iterations {:>3}  factorizations {:>3}  {:>9.4} s  {error}",
        r.solver.dofs(),
        r.solver.problem().times.len(),
        r.iterations,
        r.solver.factorizations(),
        r.seconds,
    );
}

/// Largest relative error of nodal u_r against Lame (a = 1, b = 2, p = 100).
fn lame_error(s: &Solver) -> f64 {
    let (a, b, p, e, nu) = (1.0, 2.0, 100.0, 210000.0, 0.3);
    let k = p * a * a / (b * b - a * a);
    let exact = |r: f64| (1.0f64 + nu) * k / e * ((1.0 - 2.0 * nu) * r + b * b / r);
    let mesh = &s.problem().mesh;
    (0..mesh.nodes.len())
        .map(|n| (s.state().displacement(n)[0] / exact(mesh.nodes[n][0]) - 1.0).abs())
        .fold(0.0, f64::max)
}

/// Segment-mean normal traction against Hertz over the contact zone.
fn hertz_error(s: &Solver) -> String {
    use contact2d::results::NodeState;
    let r = s.last_pairs();
    let pr = &r[0].1;
    let load = 2.0 * pr.fy;
    let e_star = 200000.0 / (1.0 - 0.09);
    let a = (4.0 * load * 10.0 / (std::f64::consts::PI * e_star)).sqrt();
    let p0 = 2.0 * load / (std::f64::consts::PI * a);
    let integral = |x: f64| {
        let x = x.min(a);
        p0 * (x * (1.0 - x * x / (a * a)).sqrt() + a * (x / a).asin()) / 2.0
    };
    let n = &pr.nodes;
    // Hertz's (linear) theory is written in the reference coordinate: under
    // the pressure, surface points move toward the centre by about
    // (1 - 2 nu)(1 + nu) p / (2 E) x, 1 % of x here.
    let reference: Vec<f64> = s.problem().contacts[0]
        .contactor
        .iter()
        .map(|&c| s.problem().mesh.nodes[c][0])
        .collect();
    let mut sum = 0.0;
    let mut count = 0;
    for k in 0..n.x.len() - 1 {
        if reference[k] >= a || n.state[k] == NodeState::Open {
            break;
        }
        let (x0, x1) = (reference[k], reference[k + 1]);
        let mean = 0.5 * (n.tn[k] + n.tn[k + 1]);
        let exact = (integral(x1) - integral(x0)) / (x1 - x0);
        sum += (mean - exact).powi(2);
        count += 1;
    }
    format!(
        "P {load:.1}  a {a:.4}  segments {count}  rms(segment-mean tn - Hertz)/p0 {:.3e}",
        (sum / count.max(1) as f64).sqrt() / p0
    )
}

fn main() {
    for element in ["q4", "q8"] {
        for n in [4, 8, 16, 32, 64] {
            let r = run(
                "verification/lame_cylinder.toml",
                &[
                    ("element = \"q8\"", format!("element = \"{element}\"")),
                    ("divisions = [8, 1]", format!("divisions = [{n}, 1]")),
                ],
            );
            let mesh = format!("{element} {n}x1");
            print(
                "lame",
                &mesh,
                &r,
                &format!("max |u_r error| {:.3e}", lame_error(&r.solver)),
            );
        }
    }
    for (nx, ny) in [(25, 1), (50, 2), (100, 4), (200, 8)] {
        let r = run(
            "verification/cantilever_tip_load.toml",
            &[("divisions = [50, 2]", format!("divisions = [{nx}, {ny}]"))],
        );
        let p = r.solver.problem();
        let tip = p.mesh.node_sets["beam.tip"][0];
        let [ux, uy] = r.solver.state().displacement(tip);
        let error = format!(
            "v/L {:.6} ({:+.2e}), u/L {:.6} ({:+.2e}) vs Mattiasson 0.30172, 0.05643",
            -uy / 10.0,
            -uy / 10.0 / 0.30172 - 1.0,
            -ux / 10.0,
            -ux / 10.0 / 0.05643 - 1.0
        );
        print("cantilever", &format!("q8 {nx}x{ny}"), &r, &error);
    }
    // Hertz, plane strain: RMS error of the segment-mean normal traction
    // over the contact zone against Hertz (with P from the computed load),
    // as a fraction of p0 (the paper plotted segment means).
    for n in [10, 20, 30, 40] {
        let r = run(
            "hertz_plane_strain.toml",
            &[(
                "divisions = 20, ratio = 20.0",
                format!("divisions = {n}, ratio = {n}.0"),
            )],
        );
        let step_pairs = hertz_error(&r.solver);
        print("hertz", &format!("q8 disk {n}"), &r, &step_pairs);
    }
    // Throughput: a large axisymmetric Q8 mesh, one linear increment.
    for (nx, ny) in [(100, 25), (200, 50), (400, 100)] {
        let r = run(
            "verification/lame_cylinder.toml",
            &[
                ("divisions = [8, 1]", format!("divisions = [{nx}, {ny}]")),
                ("dt = 0.5", "dt = 1.0".to_string()),
            ],
        );
        let mesh = format!("q8 {nx}x{ny}");
        print(
            "lame large",
            &mesh,
            &r,
            &format!("max |u_r error| {:.3e}", lame_error(&r.solver)),
        );
    }
}
