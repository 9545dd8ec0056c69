//! scenes/verification/ironing.toml, the 2D ironing benchmark (a stiff half
//! ring pressed into a soft Mooney-Rivlin block, then slid along it), run
//! with both formulations and with either body's surface as contactor, by
//! editing the scene's [[contact]] table: no increment bisected, Newton's
//! iterations per increment bounded, and the ring's reaction forces smooth
//! over the slide (`largest_jump`, docs/contact.md section 11).
//!
//! Run with `cargo test --release --test ironing -- --nocapture` to see the
//! measured numbers.

mod common;

use contact2d::newton::Solver;
use contact2d::results::{LogCategory, StepResult};

const SCENE: &str = "verification/ironing.toml";
/// The slide runs for t in (1, 2].
const SLIDE_START: f64 = 1.0;
/// The scene's own [[contact]] lines, replaced by the variants' own.
const CONTACTOR_RING: &str = "contactor = \"ring.outer\"\ntarget = \"block.top\"";
const CONTACTOR_BLOCK: &str = "contactor = \"block.top\"\ntarget = \"ring.outer\"";
const NODE_TO_SEGMENT: &str = "formulation = \"node_to_segment\"";
const SMOOTH: &str = "formulation = \"node_to_segment\"\nsmooth_target = true";

/// One variant of the scene: its formulation and which surface is contactor.
struct Variant {
    name: &'static str,
    mortar: bool,
    ring_contactor: bool,
    /// Coulomb's coefficient (mu_s = mu_d); 0: frictionless, as shipped.
    mu: f64,
    /// Node-to-segment against the smoothed target (`smooth_target`).
    smooth: bool,
}

/// What a run of the variant gave.
struct Run {
    steps: Vec<StepResult>,
    /// Bisections, fallbacks and failures the solver logged.
    warnings: Vec<String>,
    seconds: f64,
}

fn run(v: &Variant) -> Run {
    try_run(v).unwrap_or_else(|e| panic!("{e}"))
}

/// The variant's run, or the error that stopped it.
fn try_run(v: &Variant) -> Result<Run, String> {
    let friction = format!("mu_s = {:?}\n{NODE_TO_SEGMENT}", v.mu);
    let mut edits = Vec::new();
    if v.mu > 0.0 {
        edits.push((NODE_TO_SEGMENT, friction.as_str()));
    }
    if v.mortar {
        edits.push((NODE_TO_SEGMENT, "formulation = \"mortar\""));
    }
    if v.smooth {
        edits.push((NODE_TO_SEGMENT, SMOOTH));
    }
    if v.ring_contactor {
        edits.push((CONTACTOR_BLOCK, CONTACTOR_RING));
    }
    let problem = common::shipped_scene(SCENE, &edits);
    let times = problem.times.clone();
    let mut solver = Solver::new(problem).unwrap();
    let (mut steps, mut warnings) = (Vec::new(), Vec::new());
    let clock = std::time::Instant::now();
    for t in times {
        let step = solver.advance(t, &mut |c, m| {
            if matches!(c, LogCategory::Warning | LogCategory::Error) {
                warnings.push(format!("{c:?} {m}"));
            }
        });
        match step {
            Ok(s) => steps.push(s),
            Err(e) => return Err(format!("{}: {e}", v.name)),
        }
    }
    let seconds = clock.elapsed().as_secs_f64();
    Ok(Run {
        steps,
        warnings,
        seconds,
    })
}

/// The ring's reaction [Rx, Ry]: the sum of its two driven ends'.
fn ring_force(s: &StepResult) -> [f64; 2] {
    let mut f = [0.0; 2];
    for (name, d) in &s.drivers {
        if name == "left_end" || name == "right_end" {
            f[0] += d.rx;
            f[1] += d.ry;
        }
    }
    f
}

/// The largest force jump during the slide: per component, the largest
/// second difference |R(k+1) - 2 R(k) + R(k-1)| over the slide's
/// increments (t > 1; at a constant sliding speed a smooth force has
/// second differences of order dt^2, a bump at a node crossing shows in
/// full), divided by the mean magnitude |R| of the ring's force over the
/// slide. [Rx, Ry].
fn largest_jump(steps: &[StepResult]) -> [f64; 2] {
    let forces: Vec<[f64; 2]> = (steps.iter())
        .filter(|s| s.time > SLIDE_START + 1e-9)
        .map(ring_force)
        .collect();
    let mean = forces.iter().map(|f| f[0].hypot(f[1])).sum::<f64>() / forces.len() as f64;
    let mut jump = [0.0f64; 2];
    for w in forces.windows(3) {
        for (c, j) in jump.iter_mut().enumerate() {
            *j = j.max((w[2][c] - 2.0 * w[1][c] + w[0][c]).abs() / mean);
        }
    }
    jump
}

/// Median and largest Newton iterations per increment.
fn iterations(steps: &[StepResult]) -> (usize, usize) {
    let mut its: Vec<usize> = steps.iter().map(|s| s.iterations).collect();
    its.sort_unstable();
    (its[its.len() / 2], its[its.len() - 1])
}

/// Runs the variant and checks what every variant must show: every
/// increment taken whole (no bisection; an increment tried again with
/// opening and closing decided on the iterate, `StepResult::fallbacks`, is
/// counted and printed, not refused), at most 5 iterations
/// per increment in the median and 15 in the worst, the ring pressing
/// (Ry < 0) throughout the slide; returns the largest jumps.
fn check(v: &Variant) -> [f64; 2] {
    let r = run(v);
    let (median, max) = iterations(&r.steps);
    let bisections: usize = r.steps.iter().map(|s| s.substeps).sum();
    let fallbacks: usize = r.steps.iter().map(|s| s.fallbacks).sum();
    let jump = largest_jump(&r.steps);
    println!(
        "{}: {} increments, iterations median {median} max {max}, \
         {bisections} bisections, {fallbacks} fallbacks, largest jump Rx {:.4} Ry {:.4} of |R|, {:.2} s",
        v.name,
        r.steps.len(),
        jump[0],
        jump[1],
        r.seconds
    );
    assert!(
        r.steps.iter().all(|s| s.substeps == 0),
        "{}: {:?}",
        v.name,
        r.warnings
    );
    assert!(
        median <= 5 && max <= 15,
        "{}: median {median}, max {max}",
        v.name
    );
    for s in r.steps.iter().filter(|s| s.time > SLIDE_START + 1e-9) {
        assert!(
            ring_force(s)[1] < 0.0,
            "{} t = {}: ring lifted",
            v.name,
            s.time
        );
    }
    jump
}

// Measured (2026-11-29, this scene: the ring's 32 sides, increments of
// 0.01), largest jumps Rx / Ry of |R|, iterations median / max:
// - frictionless, block as contactor: node-to-segment 0.0173 / 0.0079
//   (3 / 9), mortar 0.0025 / 0.0013 (3 / 5);
// - frictionless, ring as contactor: mortar 0.0020 / 0.0013 (3 / 5);
//   node-to-segment fails at t = 1.07 against the block's facets (below),
//   and runs against its smoothed top (`smooth_target`): 0.0032 / 0.0023
//   (4 / 5);
// - frictionless, block as contactor against the ring smoothed:
//   node-to-segment 0.0026 / 0.0016 (3 / 5);
// - mu = 0.3, block as contactor: node-to-segment 0.0332 / 0.0130 (3 /
//   9), mortar 0.0059 / 0.0028 (3 / 5); ring as contactor: mortar 0.0056
//   / 0.0009 (3 / 6), node-to-segment against the smoothed top 0.0060 /
//   0.0019 (3 / 7).
// Node-to-segment's jumps come where a block node crosses a vertex of the
// ring's facets (the normal it is held along turns by 5.6 degrees);
// mortar's are those of a rigid circle of 960 sides slid the same way
// under node-to-segment (0.0020 / 0.0010): the ripple the block's mesh
// leaves. Each variant's bounds are its figures rounded up: they guard
// against a change that makes the slide rougher.

#[test]
fn node_to_segment_block_contactor() {
    let jump = check(&Variant {
        name: "node_to_segment, block contactor",
        mortar: false,
        ring_contactor: false,
        mu: 0.0,
        smooth: false,
    });
    assert!(jump[0] < 0.02 && jump[1] < 0.009, "{jump:?}");
}

#[test]
fn mortar_block_contactor() {
    let jump = check(&Variant {
        name: "mortar, block contactor",
        mortar: true,
        ring_contactor: false,
        mu: 0.0,
        smooth: false,
    });
    assert!(jump[0] < 0.003 && jump[1] < 0.0015, "{jump:?}");
}

/// Mortar's jumps are a small fraction of node-to-segment's on the same
/// meshes, per component, frictionless and with mu = 0.3 (block as
/// contactor, the variant both formulations run). Measured 0.14 / 0.16
/// and 0.18 / 0.22; the bound, a quarter, says "small fraction" without
/// leaning on the last digit.
#[test]
fn mortar_jumps_are_a_fraction_of_node_to_segments() {
    for mu in [0.0, 0.3] {
        let [nts, mortar] = [false, true].map(|mortar| {
            largest_jump(
                &run(&Variant {
                    name: "ratio",
                    mortar,
                    ring_contactor: false,
                    mu,
                    smooth: false,
                })
                .steps,
            )
        });
        for c in 0..2 {
            assert!(
                mortar[c] <= 0.25 * nts[c],
                "mu = {mu}, component {c}: mortar {} against node-to-segment {}",
                mortar[c],
                nts[c]
            );
        }
    }
}

// With the ring's surface as contactor against the block's faceted top,
// node-to-segment fails at t = 1.08, frictionless and with mu = 0.3: the
// soft block's vertices rise between the stiff ring's nodes, ring nodes
// lodge in the valleys between its facets and are held there at the
// vertex, and near-converged iterates are thrown back each time one steps
// past a vertex (docs/performance-log.md, eighth and ninth sessions).
// Against the smoothed top (`smooth_target`, the tests below) it runs. The
// failure names both ways out (`Formulation::failure_hint`).

#[test]
fn node_to_segment_ring_contactor_fails_naming_the_ways_out() {
    let failed = try_run(&Variant {
        name: "node_to_segment, ring contactor",
        mortar: false,
        ring_contactor: true,
        mu: 0.0,
        smooth: false,
    });
    let Err(e) = failed else {
        panic!("node-to-segment against the faceted top ran: update this test and its comment");
    };
    println!("{e}");
    assert!(e.contains("no convergence"), "{e}");
    for remedy in [
        "pair 'iron': ",
        "faceted target",
        "`smooth_target = true`",
        "`formulation = \"mortar\"`",
    ] {
        assert!(e.contains(remedy), "'{remedy}' not in: {e}");
    }
}

/// Node-to-segment with the ring as contactor, against the block's top
/// smoothed (`smooth_target`): no corner for a ring node to lodge in, and
/// the slide runs whole.
#[test]
fn node_to_segment_ring_contactor_smoothed_target() {
    let jump = check(&Variant {
        name: "node_to_segment, ring contactor, smoothed target",
        mortar: false,
        ring_contactor: true,
        mu: 0.0,
        smooth: true,
    });
    assert!(jump[0] < 0.004 && jump[1] < 0.003, "{jump:?}");
}

#[test]
fn node_to_segment_ring_contactor_smoothed_target_with_friction() {
    let jump = check(&Variant {
        name: "node_to_segment, ring contactor, smoothed target, mu = 0.3",
        mortar: false,
        ring_contactor: true,
        mu: 0.3,
        smooth: true,
    });
    assert!(jump[0] < 0.007 && jump[1] < 0.0025, "{jump:?}");
}

#[test]
fn node_to_segment_block_contactor_smoothed_target() {
    let jump = check(&Variant {
        name: "node_to_segment, block contactor, smoothed target",
        mortar: false,
        ring_contactor: false,
        mu: 0.0,
        smooth: true,
    });
    assert!(jump[0] < 0.003 && jump[1] < 0.002, "{jump:?}");
}

#[test]
fn mortar_ring_contactor() {
    let jump = check(&Variant {
        name: "mortar, ring contactor",
        mortar: true,
        ring_contactor: true,
        mu: 0.0,
        smooth: false,
    });
    assert!(jump[0] < 0.0025 && jump[1] < 0.0015, "{jump:?}");
}

#[test]
fn node_to_segment_block_contactor_with_friction() {
    let jump = check(&Variant {
        name: "node_to_segment, block contactor, mu = 0.3",
        mortar: false,
        ring_contactor: false,
        mu: 0.3,
        smooth: false,
    });
    assert!(jump[0] < 0.035 && jump[1] < 0.014, "{jump:?}");
}

#[test]
fn mortar_block_contactor_with_friction() {
    let jump = check(&Variant {
        name: "mortar, block contactor, mu = 0.3",
        mortar: true,
        ring_contactor: false,
        mu: 0.3,
        smooth: false,
    });
    assert!(jump[0] < 0.0065 && jump[1] < 0.003, "{jump:?}");
}

#[test]
fn mortar_ring_contactor_with_friction() {
    let jump = check(&Variant {
        name: "mortar, ring contactor, mu = 0.3",
        mortar: true,
        ring_contactor: true,
        mu: 0.3,
        smooth: false,
    });
    assert!(jump[0] < 0.0065 && jump[1] < 0.0015, "{jump:?}");
}
