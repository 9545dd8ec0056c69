//! Mortar contact against node-to-segment on the same meshes: run time per
//! increment with its accuracy and where the time goes.
//!
//!     cargo bench --bench mortar
//!
//! Two flexible cylinders (Hertz, non-matching arcs) at two refinements,
//! 4- and 8-node, and the axisymmetric shrink fit. Each scene runs with
//! both formulations in turn, three rounds alternating; the best of the
//! rounds is printed: wall time per increment, Newton iterations, the
//! error (Hertz: the largest deviation from Hertz within 0.8 a and the
//! largest node-to-node swing, over p0; shrink fit: the nodal pressures'
//! range against Lame), the mortar run's time over node-to-segment's, and
//! the split of the mortar run's time by phase. Nothing is asserted here;
//! tests/mortar.rs asserts the accuracy.

#[path = "../tests/common/mod.rs"]
mod common;

use common::mortar::{hertz_fit, lame_pressure, shrink_fit, two_cylinders};
use contact2d::newton::Solver;
use std::time::Instant;

/// One run: wall time per increment (s), iterations per increment, the
/// error text, and the phase split.
struct Run {
    per_increment: f64,
    iterations: Vec<usize>,
    error: String,
    split: String,
}

fn cylinders(element: &str, formulation: &str, disk: usize, ring: [usize; 2]) -> Run {
    let text = two_cylinders(element, formulation, disk, ring);
    let fit = hertz_fit(&text);
    // The split of a second run (hertz_fit keeps no solver).
    let problem = contact2d::scene::parse(&text, std::path::Path::new("c.toml")).unwrap();
    let times = problem.times.clone();
    let mut solver = Solver::new(problem).unwrap();
    for t in times {
        solver.advance(t, &mut |_, _| {}).unwrap();
    }
    Run {
        per_increment: fit.seconds / fit.iterations.len() as f64,
        error: format!(
            "deviation {:.4} swing {:.4} of p0",
            fit.deviation, fit.swing
        ),
        iterations: fit.iterations,
        split: solver.phases().split(),
    }
}

fn shrink(element: &str, formulation: &str, radial: usize) -> Run {
    let text = shrink_fit(element, 50.0, radial).replace(
        "formulation = \"mortar\"",
        &format!("formulation = \"{formulation}\""),
    );
    let problem = contact2d::scene::parse(&text, std::path::Path::new("s.toml")).unwrap();
    let start = Instant::now();
    let mut solver = Solver::new(problem).unwrap();
    let step = solver.advance(1.0, &mut |_, _| {}).unwrap();
    let seconds = start.elapsed().as_secs_f64();
    let p = lame_pressure(50.0);
    let tn = &step.pairs[0].1.nodes.tn;
    let (lo, hi) = tn
        .iter()
        .fold((f64::MAX, f64::MIN), |(l, h), &t| (l.min(t), h.max(t)));
    Run {
        per_increment: seconds,
        iterations: vec![step.iterations],
        error: format!(
            "nodal p / Lame - 1 from {:+.2e} to {:+.2e}",
            lo / p - 1.0,
            hi / p - 1.0
        ),
        split: solver.phases().split(),
    }
}

fn main() {
    type Case = (String, Box<dyn Fn(&str) -> Run>);
    let cases: Vec<Case> = vec![
        (
            "cylinders q4 60/[16,480]".into(),
            Box::new(|f| cylinders("q4", f, 60, [16, 480])),
        ),
        (
            "cylinders q4 120/[32,960]".into(),
            Box::new(|f| cylinders("q4", f, 120, [32, 960])),
        ),
        (
            "cylinders q8 40/[10,320]".into(),
            Box::new(|f| cylinders("q8", f, 40, [10, 320])),
        ),
        (
            "cylinders q8 80/[20,640]".into(),
            Box::new(|f| cylinders("q8", f, 80, [20, 640])),
        ),
        ("shrink fit q4 8".into(), Box::new(|f| shrink("q4", f, 8))),
        ("shrink fit q8 4".into(), Box::new(|f| shrink("q8", f, 4))),
    ];
    for (name, run) in &cases {
        let mut best: [Option<Run>; 2] = [None, None];
        for _ in 0..3 {
            for (i, formulation) in ["node_to_segment", "mortar"].into_iter().enumerate() {
                let r = run(formulation);
                if best[i]
                    .as_ref()
                    .is_none_or(|b| r.per_increment < b.per_increment)
                {
                    best[i] = Some(r);
                }
            }
        }
        let [Some(nts), Some(mortar)] = best else {
            unreachable!()
        };
        for (label, r) in [("node_to_segment", &nts), ("mortar", &mortar)] {
            println!(
                "{name:<26} {label:<16} {:>8.1} ms/increment  iterations {:?}  {}",
                1e3 * r.per_increment,
                r.iterations,
                r.error
            );
        }
        println!(
            "{name:<26} mortar / node_to_segment {:.2}; mortar's time by phase: {}",
            mortar.per_increment / nts.per_increment,
            mortar.split
        );
    }
}
