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
    // Hertz: RMS over the contact zone (closed nodes and nodes inside a) of
    // (tn - p(X)) / p0, P from the computed load, tn per unit reference
    // area as reported (tests/common `hertz`, asserted by
    // tests/contact_hertz.rs); over X < 0.8 a; at the centre; and the same
    // with tn per unit current area (the measure that plateaued at 1.7 %).
    let e_star = 200000.0 / (1.0 - 0.09);
    let hertz_runs: [(&str, &str, &str, f64, usize, f64, f64); 9] = [
        // (label, scene, shipped mesh, R, divisions, ratio, press uy)
        (
            "hertz",
            "hertz_plane_strain.toml",
            "divisions = 60, ratio = 60.0",
            10.0,
            15,
            15.0,
            -0.07,
        ),
        (
            "hertz",
            "hertz_plane_strain.toml",
            "divisions = 60, ratio = 60.0",
            10.0,
            30,
            30.0,
            -0.07,
        ),
        (
            "hertz",
            "hertz_plane_strain.toml",
            "divisions = 60, ratio = 60.0",
            10.0,
            60,
            60.0,
            -0.07,
        ),
        (
            "hertz",
            "hertz_plane_strain.toml",
            "divisions = 60, ratio = 60.0",
            10.0,
            120,
            120.0,
            -0.07,
        ),
        // Half the contact width (a/R 0.028 instead of 0.062), same a/h: the
        // centre offset left at convergence falls with (a/R)^2.
        (
            "hertz a/2",
            "hertz_plane_strain.toml",
            "divisions = 60, ratio = 60.0",
            10.0,
            120,
            240.0,
            -0.0175,
        ),
        (
            "sphere",
            "hertz_axisymmetric.toml",
            "divisions = 60, ratio = 100.0",
            100.0,
            30,
            100.0,
            -0.04,
        ),
        (
            "sphere",
            "hertz_axisymmetric.toml",
            "divisions = 60, ratio = 100.0",
            100.0,
            60,
            100.0,
            -0.04,
        ),
        (
            "sphere",
            "hertz_axisymmetric.toml",
            "divisions = 60, ratio = 100.0",
            100.0,
            120,
            100.0,
            -0.04,
        ),
        (
            "sphere",
            "hertz_axisymmetric.toml",
            "divisions = 60, ratio = 100.0",
            100.0,
            120,
            200.0,
            -0.04,
        ),
    ];
    for (label, scene, shipped, radius, n, ratio, uy) in hertz_runs {
        let press = if radius == 10.0 {
            "scale = -0.07"
        } else {
            "scale = -0.04"
        };
        let r = run(
            scene,
            &[
                (shipped, format!("divisions = {n}, ratio = {ratio:.1}")),
                (press, format!("scale = {uy}")),
            ],
        );
        let h = common::hertz(&r.solver, radius, e_star);
        let error = format!(
            "P {:.1}  a/R {:.4}  zone {} nodes  rms(tn - Hertz)/p0 {:.2e}  X<0.8a {:.2e}  \
             centre {:+.2e}  | per current area: rms {:.2e}  centre {:+.2e}",
            h.p,
            h.a / radius,
            h.zone,
            h.rms,
            h.rms_interior,
            h.centre,
            h.rms_current,
            h.centre_current
        );
        print(label, &format!("q8 disk {n}/{ratio}"), &r, &error);
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
    fmu_overhead();
}

/// The FMU layer against the solver alone: Hertz along its own load path
/// through `fmi::instance::Instance` (what every fmi2 call reaches), run
/// time and the largest output difference.
fn fmu_overhead() {
    use contact2d::fmi::instance::{Instance, Status};
    use contact2d::fmi::variables::{Binding, variables};
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/hertz_plane_strain.toml");
    let problem = contact2d::scene::load(&path).unwrap();
    let guid = contact2d::fmi::description::guid(&problem);
    let vars = variables(&problem);
    let times = problem.times.clone();

    let start = std::time::Instant::now();
    let mut solver = Solver::new(problem.clone()).unwrap();
    let mut solver_steps = Vec::new();
    for &t in &times {
        solver_steps.push(solver.advance(t, &mut |_, _| {}).unwrap());
    }
    let solver_s = start.elapsed().as_secs_f64();

    let start = std::time::Instant::now();
    let mut inst = Instance::new("bench", &path, &guid, false, Box::new(|_, _, _| {})).unwrap();
    assert_eq!(inst.enter_initialization(), Status::Ok);
    assert_eq!(inst.exit_initialization(), Status::Ok);
    let mut t0 = 0.0;
    let mut diff: f64 = 0.0;
    for (&t, step) in times.iter().zip(&solver_steps) {
        let uy = problem.drivers[1]
            .uy
            .as_ref()
            .unwrap()
            .at(t, &problem.functions);
        let vr = vars.iter().find(|v| v.name == "press.uy").unwrap().vr;
        assert_eq!(inst.set_real(&[vr], &[uy]), Status::Ok);
        assert_eq!(inst.do_step(t0, t - t0), Status::Ok);
        t0 = t;
        for v in vars.iter().filter(|v| {
            matches!(
                v.binding,
                Binding::Node { .. } | Binding::Pair { .. } | Binding::Reaction { .. }
            )
        }) {
            let want = contact2d::fmi::variables::output(&v.binding, step).unwrap();
            if v.ty == contact2d::fmi::variables::Type::Real {
                let mut got = [0.0];
                inst.get_real(&[v.vr], &mut got);
                diff = diff.max((got[0] - want).abs() / want.abs().max(1.0));
            }
        }
    }
    let fmu_s = start.elapsed().as_secs_f64();
    println!(
        "{:<12} {:<16} solver {:.3} s, through the FMU layer {:.3} s (instantiate and initialize included); largest relative output difference {:.1e}",
        "fmu", "hertz q8 60/60", solver_s, fmu_s, diff
    );
}
