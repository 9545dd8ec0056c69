//! Sliding across target nodes and the onset of frictional sliding:
//! scenes/verification/flexible_target.toml (a flexible block dragged along a
//! coarse flexible strip, frictionless and with mu = 0.2) and
//! scenes/verification/cgs4_inclined.toml (a block pushed up an incline under
//! load control, after NAFEMS CGS-4); and
//! scenes/verification/sliding_block.toml with large drag increments; and
//! scenes/hertz_plane_strain.toml with friction (partial slip).
//!
//! Run with `cargo test --release --test contact_scenes_friction -- --nocapture`
//! to see the measured numbers.

mod common;

use contact2d::newton::Solver;
use contact2d::problem::{Problem, Target};
use contact2d::results::{LogCategory, NodeState, PairResult, StepResult};
use std::collections::BTreeSet;

/// The scene `name` under scenes/, with text replacements applied (each
/// must occur).
fn load(name: &str, edits: &[(&str, &str)]) -> Problem {
    common::shipped_scene(name, edits)
}

/// What a run of a scene's load history gave.
struct Run {
    solver: Solver,
    /// One per converged increment.
    steps: Vec<StepResult>,
    /// Per converged increment, per contactor node of pair 0: the target
    /// segment it is on (`State::contact[0].contact(k)`).
    segments: Vec<Vec<usize>>,
    /// Per converged increment, per target segment of pair 0 (body targets
    /// only): the current x of its two ends.
    target_x: Vec<Vec<[f64; 2]>>,
    /// Per converged increment: the largest |slope| of the target segments
    /// of pair 0 (body targets only; 0 for a rigid one).
    target_slope: Vec<f64>,
    /// The first increment that failed: its end time and the error.
    failed: Option<(f64, String)>,
    /// Warnings and errors of the solver (bisections, failures).
    warnings: Vec<String>,
}

/// Advance through the scene's times; stops at the first failed increment.
fn run(problem: Problem) -> Run {
    let times = problem.times.clone();
    let mut solver = Solver::new(problem).unwrap();
    let (mut steps, mut segments, mut target_x, mut target_slope) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut failed = None;
    let mut warnings = Vec::new();
    for t in times {
        let r = solver.advance(t, &mut |c, m| {
            if matches!(c, LogCategory::Warning | LogCategory::Error) {
                warnings.push(format!("{c:?} {m}"));
            }
        });
        match r {
            Ok(step) => {
                let state = solver.state();
                let memory = &state.contact[0];
                segments.push((0..memory.nodes()).map(|k| memory.contact(k).1).collect());
                let p = solver.problem();
                let ends: Vec<[[f64; 2]; 2]> = match &p.contacts[0].target {
                    Target::Body { segments, .. } => segments
                        .iter()
                        .map(|&[a, b]| [position(p, &state.u, a), position(p, &state.u, b)])
                        .collect(),
                    Target::Rigid(_) => Vec::new(),
                };
                target_x.push(ends.iter().map(|[a, b]| [a[0], b[0]]).collect());
                target_slope.push(
                    ends.iter()
                        .map(|[a, b]| ((b[1] - a[1]) / (b[0] - a[0])).abs())
                        .fold(0.0, f64::max),
                );
                steps.push(step);
            }
            Err(e) => {
                failed = Some((t, e.to_string()));
                break;
            }
        }
    }
    Run {
        solver,
        steps,
        segments,
        target_x,
        target_slope,
        failed,
        warnings,
    }
}

fn position(p: &Problem, u: &[f64], n: usize) -> [f64; 2] {
    let x = p.mesh.nodes[n];
    [x[0] + u[2 * n], x[1] + u[2 * n + 1]]
}

fn pair(step: &StepResult) -> &PairResult {
    &step.pairs[0].1
}

/// Largest change of `f` between consecutive entries, relative to their mean.
fn max_jump(values: &[f64]) -> (f64, usize) {
    values
        .windows(2)
        .enumerate()
        .map(|(i, w)| ((w[1] - w[0]).abs() / (0.5 * (w[0] + w[1]).abs()), i + 1))
        .fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a })
}

// ---------------------------------------------------------------------------
// 1. A flexible block dragged along a coarse flexible strip.
// ---------------------------------------------------------------------------

const FLEXIBLE: &str = "verification/flexible_target.toml";
/// Time at which the drag starts (the press is complete).
const DRAG_START: f64 = 1.0;
/// x of the strip's nodes on its top surface.
const TARGET_NODES_X: [f64; 5] = [0.0, 10.0, 20.0, 30.0, 40.0];

/// What both variants of the flexible-target scene must show: every
/// increment converges, every contactor node stays in contact, and each
/// crosses the target nodes at x = 10 and x = 20 (its segment changes,
/// always to the segment under it).
fn check_crossings(name: &str, r: &Run) {
    if let Some((t, e)) = &r.failed {
        panic!("{name}: increment to t = {t} failed: {e}");
    }
    let m = r.solver.problem().contacts[0].contactor.len();
    let drag: Vec<usize> = (0..r.steps.len())
        .filter(|&i| r.steps[i].time >= DRAG_START - 1e-12)
        .collect();
    // Every node in contact throughout the drag.
    for &i in &drag {
        let pr = pair(&r.steps[i]);
        assert_eq!(
            pr.n_open, 0,
            "{name} t = {}: a node opened",
            r.steps[i].time
        );
    }
    // The segment each node is remembered on contains it (in x, to 1e-5:
    // the contact search's beta tolerance of 1e-6 on segments of length
    // 10): segment switching follows the node.
    for &i in &drag {
        for k in 0..m {
            let j = r.segments[i][k];
            let [xa, xb] = r.target_x[i][j];
            let x = pair(&r.steps[i]).nodes.x[k];
            assert!(
                x >= xa.min(xb) - 1e-5 && x <= xa.max(xb) + 1e-5,
                "{name} t = {}: node {k} at x = {x} is remembered on segment {j} [{xa}, {xb}]",
                r.steps[i].time
            );
        }
    }
    // Every node crosses x = 10 and x = 20, and visits at least three
    // target segments.
    let first = pair(&r.steps[drag[0]]);
    let last = pair(r.steps.last().unwrap());
    for k in 0..m {
        let visited: BTreeSet<usize> = drag.iter().map(|&i| r.segments[i][k]).collect();
        let changes = drag
            .windows(2)
            .filter(|w| r.segments[w[0]][k] != r.segments[w[1]][k])
            .count();
        let crossed = TARGET_NODES_X
            .iter()
            .filter(|&&xt| first.nodes.x[k] < xt && last.nodes.x[k] > xt)
            .count();
        assert!(
            visited.len() >= 3 && changes >= 2 && crossed >= 2,
            "{name}: node {k} from x = {} to {}: segments {visited:?}, {changes} changes",
            first.nodes.x[k],
            last.nodes.x[k]
        );
    }
    let crossings: usize = (0..m)
        .map(|k| {
            drag.windows(2)
                .filter(|w| r.segments[w[0]][k] != r.segments[w[1]][k])
                .count()
        })
        .sum();
    let max_it = r.steps.iter().map(|s| s.iterations).max().unwrap();
    let max_bis = r.steps.iter().map(|s| s.substeps).max().unwrap();
    println!(
        "{name}: {} increments converged, max iterations {max_it}, max bisections {max_bis}, \
         {crossings} segment changes of contactor nodes; contactor x from [{:.4}, {:.4}] to [{:.4}, {:.4}]",
        r.steps.len(),
        first.nodes.x[0],
        first.nodes.x[m - 1],
        last.nodes.x[0],
        last.nodes.x[m - 1]
    );
}

/// Fn and Fy between consecutive increments of the drag, and Fn's spread.
/// Returns (max jump of Fn, max jump of Fy, (max - min) / mean of Fn).
fn smoothness(name: &str, steps: &[&StepResult]) -> (f64, f64, f64) {
    let fn_: Vec<f64> = steps.iter().map(|s| pair(s).fn_).collect();
    let fy: Vec<f64> = steps.iter().map(|s| pair(s).fy).collect();
    let (jn, in_) = max_jump(&fn_);
    let (jy, iy) = max_jump(&fy);
    let mean = fn_.iter().sum::<f64>() / fn_.len() as f64;
    let (lo, hi) = fn_
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &v| (a.min(v), b.max(v)));
    println!(
        "{name}: Fn in [{lo:.4}, {hi:.4}], mean {mean:.4}, spread {:.4}; largest jump between \
         increments: Fn {jn:.5} (to t = {}), Fy {jy:.5} (to t = {})",
        (hi - lo) / mean,
        steps[in_].time,
        steps[iy].time
    );
    (jn, jy, (hi - lo) / mean)
}

// Bounds of the drag (both variants), from the measurements and the physics:
//
// - The block is pressed by a constant 0.02; Fn changes only because the
//   strip's compliance under the block depends on where the block sits on
//   its coarse elements (10 long). Against a practically rigid strip
//   (E = 1e5 instead of 1e4) Fn = 46.2 +- 0.24 %; with E = 1e4, Fn = 43.7 on
//   average: the strip takes 5.6 % of the compliance, and where the block
//   sits can change Fn by about that much, not more: spread < 6 %
//   (measured 4.4 %, frictionless and with friction).
// - That variation has the period of a strip element (10) and an amplitude
//   of 2.2 %: at 0.2 of drag per increment its slope gives
//   2 pi * 2.2 % * 0.2 / 10 = 0.28 % per increment (measured largest jumps
//   0.32 % frictionless, 0.34 % with friction, Fn and Fy alike). A contactor
//   node caught or lost at a target node would change Fn by its share of
//   the load, 1/8 of it (12 %). The bound, 1 %, is three times the smooth
//   drift and a tenth of one node's share.
const MAX_JUMP: f64 = 0.01;
const MAX_SPREAD: f64 = 0.06;

#[test]
fn flexible_target_frictionless_crosses_target_nodes_smoothly() {
    let r = run(load(FLEXIBLE, &[]));
    check_crossings("frictionless", &r);
    // Measured: every increment in 2-4 iterations, no bisection.
    assert!(r.steps.iter().all(|s| s.substeps == 0), "{:?}", r.warnings);
    let drag: Vec<&StepResult> = r
        .steps
        .iter()
        .filter(|s| s.time >= DRAG_START - 1e-12)
        .collect();
    let first = r.steps.len() - drag.len();
    let mut worst: f64 = 0.0;
    for (i, s) in drag.iter().enumerate() {
        let p = pair(s);
        assert_eq!(
            p.n_slip,
            p.nodes.x.len(),
            "t = {}: frictionless nodes slide",
            s.time
        );
        // No friction: the contact forces are normal to the contactor
        // segments; Ft is measured along the target segments, which the
        // loaded strip tilts by up to `slope` (2.7e-4): |Ft| <= slope Fn.
        let slope = r.target_slope[first + i];
        worst = worst.max(p.ft.abs() / (slope * p.fn_));
        assert!(
            p.ft.abs() <= slope * p.fn_,
            "t = {}: Ft = {} Fn = {} slope {slope}",
            s.time,
            p.ft,
            p.fn_
        );
    }
    println!("frictionless: |Ft| / (slope Fn) <= {worst:.3}");
    let (jn, jy, spread) = smoothness("frictionless", &drag);
    assert!(
        jn <= MAX_JUMP && jy <= MAX_JUMP,
        "Fn jump {jn}, Fy jump {jy}"
    );
    assert!(spread <= MAX_SPREAD, "Fn spread {spread}");
}

#[test]
fn flexible_target_with_friction_slides_at_mu_across_target_nodes() {
    let mu = 0.2;
    let r = run(load(FLEXIBLE, &[("mu_s = 0.0", "mu_s = 0.2")]));
    check_crossings("mu = 0.2", &r);
    for w in &r.warnings {
        println!("mu = 0.2: {w}");
    }
    // Sliding: from the first increment in which every node slides on.
    // (Measured: the breakaway increment, t = 1.05, needs two bisections
    // and 28 iterations; every later one converges whole, in 5-6.)
    let start = r
        .steps
        .iter()
        .position(|s| s.time > DRAG_START && pair(s).n_slip == pair(s).nodes.x.len())
        .expect("the block slides");
    let sliding: Vec<&StepResult> = r.steps[start..].iter().collect();
    println!(
        "mu = 0.2: every node slides from t = {} on ({} increments)",
        sliding[0].time,
        sliding.len()
    );
    assert!(
        sliding[0].time <= DRAG_START + 0.05 + 1e-12,
        "the block breaks away in the first drag increment (0.2 of drag, where \
         shearing the block to mu Fn takes about 0.011)"
    );
    let (mut worst, mut worst_rel): (f64, f64) = (0.0, 0.0);
    let max_slope = r.target_slope[start..].iter().copied().fold(0.0, f64::max);
    for (i, s) in sliding.iter().enumerate() {
        let p = pair(s);
        assert_eq!(
            p.n_slip,
            p.nodes.x.len(),
            "t = {}: the block keeps sliding ({}/{}/{})",
            s.time,
            p.n_stick,
            p.n_slip,
            p.n_open
        );
        // Dragged toward +x: friction on the block acts toward -x.
        let ratio = -p.ft / p.fn_;
        worst = worst.max((ratio - mu).abs());
        // Every segment slides, so the friction resultant is mu T_n in the
        // contactor's frame exactly; Ft and Fn are measured in the frames
        // of the target segments, which the loaded strip tilts by up to
        // `slope` (2.7e-4): turned by that angle, Ft/Fn may differ from mu
        // by (1 + mu^2) slope.
        let slope = r.target_slope[start + i];
        worst_rel = worst_rel.max((ratio - mu).abs() / ((1.0 + mu * mu) * slope));
        assert!(
            (ratio - mu).abs() <= (1.0 + mu * mu) * slope,
            "t = {} (sliding increment {i}): Ft/Fn = {ratio}, target slope {slope}",
            s.time
        );
    }
    println!(
        "mu = 0.2: |-Ft/Fn - mu| <= {worst:.3e} while sliding, at most {worst_rel:.3} of \
         (1 + mu^2) times the target slope (largest slope {max_slope:.3e})"
    );
    let (jn, jy, spread) = smoothness("mu = 0.2", &sliding);
    assert!(
        jn <= MAX_JUMP && jy <= MAX_JUMP,
        "Fn jump {jn}, Fy jump {jy}"
    );
    assert!(spread <= MAX_SPREAD, "Fn spread {spread}");
}

// ---------------------------------------------------------------------------
// 2. CGS-4-like: a block pushed up an incline (tan alpha = 0.1, mu = 0.3).
// ---------------------------------------------------------------------------

const CGS4: &str = "verification/cgs4_inclined.toml";
const TAN_ALPHA: f64 = 0.1;
const MU: f64 = 0.3;
/// The block's weight (body force 1 on a 4 x 1 block).
const WEIGHT: f64 = 4.0;

/// F/G at which the block starts to slide up the slope.
fn onset() -> f64 {
    (TAN_ALPHA + MU) / (1.0 - MU * TAN_ALPHA)
}

/// F/G at time t (the scene's "push" function: t - 1 on [1, 2]).
fn push(t: f64) -> f64 {
    (t - 1.0).max(0.0)
}

struct Cgs4 {
    run: Run,
    /// F/G of the last converged increment and of the first failed one.
    last: f64,
    failed: Option<f64>,
}

fn cgs4() -> Cgs4 {
    let started = std::time::Instant::now();
    let run = run(load(CGS4, &[]));
    let seconds = started.elapsed().as_secs_f64();
    let last = push(run.steps.last().unwrap().time);
    let failed = run.failed.as_ref().map(|(t, _)| push(*t));
    let l = onset();
    println!(
        "cgs4: onset F/G = {l:.6}; last converged F/G = {last:.5} ({:+.3} %), first failed {} \
         ({} increments converged, {seconds:.2} s)",
        (last / l - 1.0) * 100.0,
        failed.map_or("none".into(), |f| format!(
            "{f:.5} ({:+.3} %)",
            (f / l - 1.0) * 100.0
        )),
        run.steps.len()
    );
    for s in run.steps.iter().filter(|s| s.time > 1.35) {
        let p = pair(s);
        let states: String = p
            .nodes
            .state
            .iter()
            .map(|s| match s {
                NodeState::Open => '.',
                NodeState::Stick => 'S',
                NodeState::Slip => 'P',
            })
            .collect();
        println!(
            "  F/G {:.4}: {:2} iterations, {} bisections, Ft/Fn = {:.6}, nodes {states}",
            push(s.time),
            s.iterations,
            s.substeps,
            -p.ft / p.fn_
        );
    }
    if let Some((t, e)) = &run.failed {
        println!("  failed at t = {t}: {e}");
    }
    Cgs4 { run, last, failed }
}

/// What holds now: the interface carries exactly the applied load at every
/// converged increment; every increment below the slip onset converges
/// (there is an equilibrium state with part of the interface sticking);
/// and under load control the run stops within the scene's ramp, which
/// ends 0.64 % above the onset.
#[test]
fn cgs4_incline_converges_up_to_slip_onset_and_stops_past_it() {
    let c = cgs4();
    let (s, co) = (
        TAN_ALPHA / (1.0f64 + TAN_ALPHA * TAN_ALPHA).sqrt(),
        1.0 / (1.0f64 + TAN_ALPHA * TAN_ALPHA).sqrt(),
    );
    for st in &c.run.steps {
        let (g, f) = (WEIGHT * st.time.min(1.0), WEIGHT * push(st.time));
        let p = pair(st);
        // Equilibrium of the block normal and tangential to the interface
        // (the rigid line y = 0 of the turned problem): round-off.
        let n = g * co + f * s;
        let t = f * co - g * s;
        assert!(
            (p.fn_ - n).abs() <= 1e-8 * n,
            "t = {}: Fn {} N {n}",
            st.time,
            p.fn_
        );
        assert!(
            (-p.ft - t).abs() <= 1e-8 * n,
            "t = {}: Ft {} T {t}",
            st.time,
            p.ft
        );
        assert_eq!(
            p.n_open, 0,
            "t = {}: the block stays on the incline",
            st.time
        );
    }
    let failed = c
        .failed
        .expect("no static equilibrium past the onset: the run must stop");
    assert!(
        failed > onset(),
        "failed at F/G = {failed} below the onset {}",
        onset()
    );
    assert!(failed <= 0.415 + 1e-12);
}

/// The requirement: the slip onset found under load control (the
/// last converged F/G and the first failed one) lies within 0.1 % of
/// (tan alpha + mu) / (1 - mu tan alpha), and no converged state carries
/// more friction than mu Fn.
#[test]
fn cgs4_slip_onset_within_0p1_percent() {
    let c = cgs4();
    let l = onset();
    let mut wrong = Vec::new();
    if (c.last / l - 1.0).abs() > 1e-3 {
        wrong.push(format!("last converged F/G = {:.5} against {l:.6}", c.last));
    }
    match c.failed {
        Some(f) if (f / l - 1.0).abs() <= 1e-3 => {}
        Some(f) => wrong.push(format!("first failed F/G = {f:.5} against {l:.6}")),
        None => wrong.push("no failure: the run must stop past the onset".into()),
    }
    // No converged state carries more friction than mu Fn (there is no
    // static equilibrium past the onset).
    if let Some(st) = c
        .run
        .steps
        .iter()
        .find(|st| pair(st).ft.abs() > MU * pair(st).fn_ * (1.0 + 1e-9))
    {
        wrong.push(format!(
            "Coulomb's bound exceeded from F/G = {:.4} on: |Ft|/Fn = {:.6}",
            push(st.time),
            pair(st).ft.abs() / pair(st).fn_
        ));
    }
    assert!(wrong.is_empty(), "{}", wrong.join("; "));
}

// ---------------------------------------------------------------------------
// 3. The sliding block with large increments.
// ---------------------------------------------------------------------------

/// scenes/verification/sliding_block.toml with large drag increments (as an
/// FMU master takes them): ux grows by `du` per increment after the press.
/// The block must slide at every drag increment, all nodes slipping, with
/// Ft = mu_d Fn and the same drag force whatever the increment, and without
/// bisection. (Before the fix, with du = 0.05 the states alternated between
/// 2/7/0 and 8/1/0 stick/slip/open and Rx between 3.35 and 1.59; with
/// du = 0.02 the second drag increment did not converge.)
#[test]
fn sliding_block_with_large_increments_slides_at_mu_d_every_increment() {
    let mu_d = 0.2;
    for du in [0.05f64, 0.02] {
        let mut problem = load("verification/sliding_block.toml", &[]);
        // The drag function: ux = 0.2 (t - 1) / 2 for t in [1, 3].
        let dt = du / 0.1;
        let n = (2.0 / dt).round() as usize;
        problem.times = std::iter::once(1.0)
            .chain((1..=n).map(|i| 1.0 + i as f64 * dt))
            .collect();
        problem.solver.max_bisections = 0;
        let r = run(problem);
        assert!(
            r.failed.is_none(),
            "du = {du}: {:?} {:?}",
            r.failed,
            r.warnings
        );
        let drags: Vec<&StepResult> = r.steps.iter().filter(|s| s.time > 1.0).collect();
        assert_eq!(drags.len(), n);
        let rx0 = drags[0].drivers.iter().find(|d| d.0 == "top").unwrap().1.rx;
        for s in &drags {
            let p = pair(s);
            let rx = s.drivers.iter().find(|d| d.0 == "top").unwrap().1.rx;
            println!(
                "du = {du}: t = {:.2}: {} iterations, stick/slip/open {}/{}/{}, Ft/Fn = {:.6}, \
                 Rx = {rx:.6}",
                s.time,
                s.iterations,
                p.n_stick,
                p.n_slip,
                p.n_open,
                p.ft / p.fn_
            );
            assert_eq!(s.substeps, 0, "du = {du}, t = {}: bisected", s.time);
            assert_eq!(
                p.n_slip,
                p.nodes.x.len(),
                "du = {du}, t = {}: every node slides",
                s.time
            );
            assert!(
                (-p.ft / (mu_d * p.fn_) - 1.0).abs() < 1e-3,
                "du = {du}, t = {}: Ft/Fn = {}",
                s.time,
                p.ft / p.fn_
            );
            assert!(
                (rx / (mu_d * p.fn_) - 1.0).abs() < 1e-3,
                "du = {du}, t = {}: Rx = {rx}",
                s.time
            );
            assert!(
                (rx / rx0 - 1.0).abs() < 1e-6,
                "du = {du}, t = {}: Rx = {rx} against {rx0}",
                s.time
            );
        }
    }
}

// Hertz with friction: scenes/hertz_plane_strain.toml (a quarter cylinder,
// R = 10, 8-node elements, pressed onto a rigid flat in 4 increments, the
// symmetry driver ux = 0 on the axis x = 0) with mu_s = 0.3, mu_d = 0.2.
// Under the pressure the cylinder's surface contracts toward the axis; the
// rigid flat resists, so the answer is partial slip: a central stick zone,
// slip toward the contact edge, and friction on the cylinder pointing away
// from the axis (it opposes the inward slip), carried back by the symmetry
// plane. Before the segment-level return to sticking the nodes at the
// stick-slip boundary alternated between sticking at their anchors and
// sliding along their friction every other iteration (no convergence at
// t = 0.75 and after 6 bisections). Asserted: every increment converges
// without bisection; global equilibrium (the contact's Fx is the symmetry
// plane's -Rx, its Fy the press's -Ry, to 1e-9 Fn); |Ft| <= mu_s Fn; the
// friction on the cylinder points away from the axis (0 < Fx < mu_d Fn);
// the closed nodes within 15 % of the contact half-width stick and the
// outermost one slides. Not asserted (not met with these 4 increments):
// one stick zone (sticking nodes that came into contact in the increment
// sit between sliding ones toward the edge), |tt| = mu_d tn at sliding
// nodes (the reported tractions on the 8-node sides alternate between
// corner and mid-side nodes, see docs/contact.md).
#[test]
fn hertz_with_friction_partial_slip_converges_without_bisection() {
    let (mu_s, mu_d) = (0.3, 0.2);
    let mut problem = load(
        "hertz_plane_strain.toml",
        &[("mu_s = 0.0", "mu_s = 0.3\nmu_d = 0.2")],
    );
    problem.solver.max_bisections = 0;
    let r = run(problem);
    assert!(r.failed.is_none(), "{:?} {:?}", r.failed, r.warnings);
    assert_eq!(r.steps.len(), 4);
    for s in &r.steps {
        let p = pair(s);
        let driver = |name: &str| s.drivers.iter().find(|d| d.0 == name).unwrap().1.clone();
        let (sym, press) = (driver("symmetry"), driver("press"));
        let closed: Vec<usize> = (0..p.nodes.x.len())
            .filter(|&k| p.nodes.state[k] != NodeState::Open)
            .collect();
        let stick_out = closed
            .iter()
            .filter(|&&k| p.nodes.state[k] == NodeState::Stick)
            .map(|&k| p.nodes.x[k])
            .fold(f64::NEG_INFINITY, f64::max);
        let slip_in = closed
            .iter()
            .filter(|&&k| p.nodes.state[k] == NodeState::Slip)
            .map(|&k| p.nodes.x[k])
            .fold(f64::INFINITY, f64::min);
        let contact_out = closed.iter().map(|&k| p.nodes.x[k]).fold(0.0, f64::max);
        println!(
            "t = {:.2}: {} iterations, stick/slip/open {}/{}/{}, Fn = {:.4}, Ft/Fn = {:.5}, \
             Fx = {:.4}, symmetry Rx = {:.4}, stick zone x <= {stick_out:.4}, slip from \
             {slip_in:.4}, contact to {contact_out:.4}",
            s.time,
            s.iterations,
            p.n_stick,
            p.n_slip,
            p.n_open,
            p.fn_,
            p.ft / p.fn_,
            p.fx,
            sym.rx
        );
        assert_eq!(s.substeps, 0, "t = {}: bisected", s.time);
        let scale = 1e-9 * p.fn_;
        assert!(
            (p.fx + sym.rx).abs() < scale,
            "t = {}: Fx {} Rx {}",
            s.time,
            p.fx,
            sym.rx
        );
        assert!(
            (p.fy + press.ry).abs() < scale,
            "t = {}: Fy {} Ry {}",
            s.time,
            p.fy,
            press.ry
        );
        assert!(
            p.ft.abs() <= mu_s * p.fn_,
            "t = {}: Ft/Fn = {}",
            s.time,
            p.ft / p.fn_
        );
        // Friction on the cylinder away from the axis, below mu_d Fn overall.
        assert!(
            p.fx > 0.0 && p.fx < mu_d * p.fn_,
            "t = {}: Fx = {}",
            s.time,
            p.fx
        );
        // Partial slip: a central stick zone (every closed node within 15 %
        // of the contact half-width from the axis sticks) and slip at the
        // contact edge (the outermost closed node slides).
        for &k in &closed {
            if p.nodes.x[k] <= 0.15 * contact_out {
                assert_eq!(
                    p.nodes.state[k],
                    NodeState::Stick,
                    "t = {}: node {k}",
                    s.time
                );
            }
        }
        let edge = *closed
            .iter()
            .max_by(|&&a, &&b| p.nodes.x[a].total_cmp(&p.nodes.x[b]))
            .unwrap();
        assert_eq!(
            p.nodes.state[edge],
            NodeState::Slip,
            "t = {}: edge node {edge}",
            s.time
        );
    }
}
