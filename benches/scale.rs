//! Speed at scale (issue 14): where an increment's time goes from 1e3 to
//! 1e6 unknowns, and what one `doStep` of a small frictional FMU costs.
//!
//!     cargo bench --bench scale              # 1e3, 1e4 and 1e5 unknowns
//!     cargo bench --bench scale -- --full    # and 1e6 (about 3 GB, a minute)
//!     cargo bench --bench scale -- --fmu     # part 2 alone (for a profiler)
//!
//! Part 1, the plane-strain Hertz press of scenes/hertz_plane_strain.toml
//! with 4-node elements, pressed in one increment (the contact zone closed
//! from nothing), on the disk generator's meshes of 38 to 1200 divisions.
//! Per mesh: unknowns, Newton iterations, numeric factorizations (and how
//! many were LDLT, LU and LDU, and how many solves took an existing
//! factor's trailing block instead, docs/contact.md section 8), wall time of the
//! increment and per iteration, the mean time of one numeric
//! factorization, their ratio, and the split of the
//! time into phases (assembly; contact search, recovery and decisions;
//! building the bordered system; ordering and symbolic analysis; numeric
//! factorization; triangular solves with their checks; the rest), and the
//! error against Hertz (rms of (tn - p(x)) / p0 over the contact zone, from
//! the computed load). Then the same with friction up to 1e5 unknowns
//! (mu_s 0.3, mu_d 0.2: sliding nodes make the systems unsymmetric; the
//! rms there measures friction's departure from frictionless Hertz as well
//! as the mesh's).
//!
//! Part 2, the FMU layer (`fmi::instance::Instance`, what every fmi2 call
//! reaches): the capstan in its drum's frame (scenes/
//! capstan_drum_frame.toml) at 128 strip elements (516 unknowns), its tight end drawn
//! by `pull.uy` one doStep at a time until the strip slides over the
//! whole wrap, then held, five times over on fresh instances: per doStep
//! the median and largest wall time, the Newton iterations, and the time
//! per iteration (and its median and spread over the runs); for the drawn
//! steps of the last run the phase split and the solves an iteration is
//! made of.
//!
//! Nothing is asserted here (timings are not tests); tests/stress.rs and
//! tests/contact_hertz.rs assert the iterations and the accuracy.

#[path = "../tests/common/mod.rs"]
mod common;

use contact2d::newton::Solver;
use std::time::Instant;

fn main() {
    let full = std::env::args().any(|a| a == "--full");
    if std::env::args().any(|a| a == "--fmu") {
        capstan_fmu();
        return;
    }
    println!("Hertz (plane strain, q4), pressed to uy = -0.07 in one increment");
    println!(
        "{:>5} {:>8} {:>3} {:>4} {:>18} {:>9} {:>9} {:>9} {:>6}  phases (% of the increment)                            rms/p0",
        "div", "unknowns", "it", "fac", "ldlt/lu/ldu/trail", "incr s", "s/it", "s/fac", "it/fac"
    );
    let mut sizes = vec![38, 120, 380];
    if full {
        sizes.push(1200);
    }
    for div in sizes {
        hertz(div, false);
    }
    println!("the same with friction (mu_s 0.3, mu_d 0.2; rms against frictionless Hertz)");
    for div in [38, 120, 380] {
        hertz(div, true);
    }
    println!();
    capstan_fmu();
}

fn hertz(div: usize, friction: bool) {
    let divisions = format!("divisions = {div}");
    let mu = if friction {
        "mu_s = 0.3\nmu_d = 0.2"
    } else {
        "mu_s = 0.0"
    };
    let problem = common::shipped_scene(
        "hertz_plane_strain.toml",
        &[
            ("element = \"q8\"", "element = \"q4\""),
            ("divisions = 60", &divisions),
            ("dt = 0.25", "dt = 1.0"),
            ("mu_s = 0.0", mu),
            // The scene's element limit counts 2 div^2 for the disk (the
            // mesh has fewer): 1200 divisions need it raised.
            ("[units]", "[solver]\nmax_elements = 3000000\n\n[units]"),
        ],
    );
    let mut solver = Solver::new(problem).unwrap();
    let step = solver.advance(1.0, &mut |_, _| {}).unwrap();
    let p = solver.phases();
    let e_star = 200000.0 / (1.0 - 0.3 * 0.3);
    let h = common::hertz(&solver, 10.0, e_star);
    let total = p.total.as_secs_f64();
    let per_it = total / step.iterations.max(1) as f64;
    let per_fac = p.linear.numeric.as_secs_f64() / p.factorizations.max(1) as f64;
    println!(
        "{div:>5} {:>8} {:>3} {:>4} {:>18} {total:>9.3} {per_it:>9.4} {per_fac:>9.4} {:>6.2}  {}  {:.2e}",
        solver.dofs(),
        step.iterations,
        p.factorizations,
        format!("{}/{}/{}/{}", p.ldlt, p.lu, p.ldu, p.trailing),
        per_it / per_fac,
        p.split(),
        h.rms,
    );
}

/// Runs of the FMU sequence (`capstan_fmu`).
const RUNS: usize = 5;

fn capstan_fmu() {
    use contact2d::fmi::instance::{Instance, Status};
    use contact2d::fmi::variables::variables;
    let (text, _) = common::scene_text(
        "capstan_drum_frame.toml",
        &[("divisions = [1, 64]", "divisions = [1, 128]")],
    );
    let dir = std::env::temp_dir().join(format!("contact2d_scale_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("capstan.toml");
    std::fs::write(&path, text).unwrap();
    let problem = contact2d::scene::load(&path).unwrap();
    let guid = contact2d::fmi::description::guid(&problem);
    let vars = variables(&problem);
    let vr = |name: &str| vars.iter().find(|v| v.name == name).unwrap().vr;
    let (pull, iterations, n_stick) = (vr("pull.uy"), vr("solver.iterations"), vr("wrap.n_stick"));

    let h = 0.05;
    let (mut moving, mut held) = (Vec::new(), Vec::new());
    let mut drawn_phases = None;
    // The sequence five times over, each on a fresh instance: the ten drawn
    // steps of one run take some 0.13 s, and one run's figure varies by
    // 5-10 % on this machine; the median run is printed with the spread.
    let mut per_run = Vec::new();
    let mut last_its = 0.0;
    for _run in 0..RUNS {
        let mut inst = Instance::new("bench", &path, &guid, false, Box::new(|_, _, _| {})).unwrap();
        assert_eq!(inst.enter_initialization(), Status::Ok);
        assert_eq!(inst.exit_initialization(), Status::Ok);
        let first = moving.len();
        let mut t = 0.0;
        let mut uy = 0.0;
        let mut sliding_at = None;
        drawn_phases = None;
        for k in 0..80 {
            // Drawn by 0.05 mm per step until the strip slides over the whole
            // wrap and ten steps more; then held for as many steps.
            let moving_phase = sliding_at.is_none_or(|s| k < s + 10);
            if !moving_phase && drawn_phases.is_none() {
                drawn_phases = inst.phases();
            }
            if moving_phase {
                uy -= 0.05;
            }
            assert_eq!(inst.set_real(&[pull], &[uy]), Status::Ok);
            let clock = Instant::now();
            let status = inst.do_step(t, h);
            let wall = clock.elapsed().as_secs_f64();
            assert_eq!(status, Status::Ok, "doStep at t = {t}");
            t += h;
            let mut out = [0; 2];
            assert_eq!(
                inst.get_integer(&[iterations, n_stick], &mut out),
                Status::Ok
            );
            if sliding_at.is_none() && out[1] == 0 {
                sliding_at = Some(k);
            }
            let record = (wall, f64::from(out[0]));
            if moving_phase {
                moving.push(record);
            } else {
                held.push(record);
            }
        }
        let run: &[(f64, f64)] = &moving[first..];
        let its: f64 = run.iter().map(|s| s.1).sum();
        per_run.push(1e3 * run.iter().map(|s| s.0).sum::<f64>() / its.max(1.0));
        last_its = its;
    }
    per_run.sort_by(f64::total_cmp);
    println!(
        "capstan FMU (scenes/capstan_drum_frame.toml at 128 elements, {} unknowns), doStep h = {h}:",
        2 * problem.mesh.nodes.len()
    );
    report("drawn by 0.05 mm", &moving);
    report("held", &held);
    println!(
        "  drawn, ms per iteration in each of {RUNS} runs: median {:.3}, {:.3} .. {:.3}",
        per_run[RUNS / 2],
        per_run[0],
        per_run[RUNS - 1]
    );
    if let Some(p) = drawn_phases {
        println!(
            "  drawn steps of the last run by phase (%): {}",
            p.summary()
        );
        // What an iteration is made of: its solves (each factored, or on
        // the last factor's trailing block), in the last run.
        let its = last_its;
        if its > 0.0 {
            println!(
                "  per drawn iteration: {:.1} solves ({:.1} factored, {:.1} on a trailing block)",
                (p.factorizations + p.trailing) as f64 / its,
                p.factorizations as f64 / its,
                p.trailing as f64 / its,
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

fn report(label: &str, steps: &[(f64, f64)]) {
    if steps.is_empty() {
        return;
    }
    let mut walls: Vec<f64> = steps.iter().map(|s| s.0).collect();
    walls.sort_by(f64::total_cmp);
    let its: f64 = steps.iter().map(|s| s.1).sum();
    let wall: f64 = walls.iter().sum();
    println!(
        "  {label:<17} {:>3} steps  doStep median {:.3} ms, max {:.3} ms  iterations {:.1} per step  {:.3} ms per iteration",
        steps.len(),
        1e3 * walls[walls.len() / 2],
        1e3 * walls[walls.len() - 1],
        its / steps.len() as f64,
        if its > 0.0 { 1e3 * wall / its } else { 0.0 },
    );
}
