//! Mortar contact against node-to-segment on the same meshes: run time per
//! increment with its accuracy and where the time goes.
//!
//!     cargo bench --bench mortar
//!
//! Two flexible cylinders (Hertz, non-matching arcs) at two refinements,
//! 4- and 8-node, and the axisymmetric shrink fit; with friction, the block
//! dragged over the coarse strip (mu = 0.2) and Cattaneo-Mindlin on its
//! shipped meshes (both formulations with the nodal decisions); the drag
//! also on meshes four times finer. Each scene runs with both
//! formulations in turn, three rounds alternating; the best of the
//! rounds is printed: wall time per increment, Newton iterations, the
//! error (Hertz: the largest deviation from Hertz within 0.8 a and the
//! largest node-to-node swing, over p0; shrink fit: the nodal pressures'
//! range against Lame), the mortar run's time over node-to-segment's, and
//! the split of each run's time by phase. `cargo bench --bench mortar --
//! NAME` runs the cases whose name holds NAME. Nothing is asserted here;
//! tests/mortar.rs asserts the accuracy.

#[path = "../tests/common/mod.rs"]
mod common;

use common::mortar::{hertz_fit, lame_pressure, run, shrink_fit, two_cylinders};
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
    let fit = hertz_fit(&two_cylinders(element, formulation, disk, ring));
    Run {
        per_increment: fit.seconds / fit.iterations.len() as f64,
        error: format!(
            "deviation {:.4} swing {:.4} of p0",
            fit.deviation, fit.swing
        ),
        iterations: fit.iterations,
        split: fit.split,
    }
}

fn shrink(element: &str, formulation: &str, radial: usize) -> Run {
    let text = shrink_fit(element, 50.0, radial).replace(
        "target = \"rim.left\"",
        &format!("target = \"rim.left\"\nformulation = \"{formulation}\""),
    );
    assert!(text.contains(&format!("formulation = \"{formulation}\"")));
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
        split: solver.phases().summary(),
    }
}

/// A shipped scene with `edits`, its [[contact]] table's `marker` line
/// replaced to choose `formulation`: time per increment, and the error
/// `error` reads off the last step.
fn shipped(
    name: &str,
    edits: &[(&str, &str)],
    marker: &str,
    formulation: &str,
    error: fn(&contact2d::results::StepResult) -> String,
) -> Run {
    // The formulation named either way: a body target's default is mortar.
    let choice = format!("{marker}\nformulation = \"{formulation}\"");
    let mut all: Vec<(&str, &str)> = edits.to_vec();
    all.push((marker, &choice));
    let ran = run(common::shipped_scene(name, &all));
    Run {
        per_increment: ran.seconds / ran.iterations.len() as f64,
        error: error(&ran.last),
        iterations: ran.iterations,
        split: ran.solver.phases().summary(),
    }
}

/// A driver's reaction [Rx, Ry].
fn reaction(step: &contact2d::results::StepResult, name: &str) -> [f64; 2] {
    let r = &step.drivers.iter().find(|d| d.0 == name).unwrap().1;
    [r.rx, r.ry]
}

/// The shipped drag with mu = 0.2, its meshes' divisions times `refine`
/// (1: the shipped 8/4 elements along the block's bottom / the strip's top).
fn drag(formulation: &str, refine: usize) -> Run {
    let friction = "mu_s = 0.2\nmu_d = 0.2";
    let strip = format!("divisions = [{}, {}]", 4 * refine, 2 * refine);
    let block = format!("divisions = [{}, {}]", 8 * refine, 4 * refine);
    shipped(
        "verification/flexible_target.toml",
        &[
            ("mu_s = 0.0", friction),
            ("divisions = [4, 2]", &strip),
            ("divisions = [8, 4]", &block),
        ],
        friction,
        formulation,
        |step| {
            let [rx, ry] = reaction(step, "top");
            format!("drag Rx / Ry {:.5} (mu 0.2, the strip bends)", -rx / ry)
        },
    )
}

fn cattaneo(formulation: &str) -> Run {
    // Both decide node by node: the shipped scene's paper decisions
    // (node-to-segment's own, friction uniform per segment) keep its
    // systems symmetric, and against them the ratio would measure the
    // decisions, not the formulation (docs/performance-log.md).
    shipped(
        "verification/cattaneo_mindlin.toml",
        &[("decisions = \"paper\"", "")],
        "recovery = \"lumped\"",
        formulation,
        |step| {
            let p = &step.pairs[0].1;
            format!(
                "stick/slip/open {}/{}/{} at Q/(mu P) = 0.85",
                p.n_stick, p.n_slip, p.n_open
            )
        },
    )
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
        ("drag, mu 0.2 (q4 8/4)".into(), Box::new(|f| drag(f, 1))),
        ("drag, mu 0.2 (q4 32/16)".into(), Box::new(|f| drag(f, 4))),
        ("Cattaneo-Mindlin (shipped)".into(), Box::new(cattaneo)),
    ];
    // `cargo bench --bench mortar -- NAME` runs the cases whose name
    // holds NAME.
    let only: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-'))
        .collect();
    let chosen = |name: &str| only.is_empty() || only.iter().any(|o| name.contains(o.as_str()));
    for (name, run) in cases.iter().filter(|(name, _)| chosen(name)) {
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
            let mut sorted = r.iterations.clone();
            sorted.sort_unstable();
            let iterations = if sorted.len() > 8 {
                format!(
                    "median {} max {} over {} increments",
                    sorted[sorted.len() / 2],
                    sorted[sorted.len() - 1],
                    sorted.len()
                )
            } else {
                format!("{:?}", r.iterations)
            };
            println!(
                "{name:<26} {label:<16} {:>8.1} ms/increment  iterations {iterations}  {}",
                1e3 * r.per_increment,
                r.error
            );
        }
        println!(
            "{name:<26} mortar / node_to_segment {:.2}; time by phase, node_to_segment: {}; mortar: {}",
            mortar.per_increment / nts.per_increment,
            nts.split,
            mortar.split
        );
    }
}
