//! The shipped contact scenes, solved, against closed forms and invariants.

mod common;

use contact2d::newton::Solver;
use contact2d::results::{LogCategory, NodeState, StepResult};

/// Every increment of the scene `name`, with its Newton log.
fn solve(name: &str) -> (Solver, Vec<StepResult>, Vec<String>) {
    let problem = common::shipped_scene(name, &[]);
    let times = problem.times.clone();
    let mut solver = Solver::new(problem).unwrap();
    let mut log = Vec::new();
    let mut steps = Vec::new();
    for t in times {
        let r = solver
            .advance(t, &mut |c, m| {
                if c == LogCategory::Newton {
                    log.push(m.to_string())
                }
            })
            .unwrap_or_else(|e| panic!("{name} at t = {t}: {e}"));
        steps.push(r);
    }
    (solver, steps, log)
}

fn driver(step: &StepResult, name: &str) -> [f64; 2] {
    let d = &step.drivers.iter().find(|d| d.0 == name).unwrap().1;
    [d.rx, d.ry]
}

#[test]
fn hertz_plane_strain_equilibrium_contact_width_and_states() {
    let (_, steps, _) = solve("hertz_plane_strain.toml");
    for step in &steps {
        let pair = &step.pairs[0].1;
        let press = driver(step, "press");
        let flat = driver(step, "flat");
        // The rigid flat's reaction is the force the press applies: the
        // contact forces are the converged out-of-balance forces (round-off).
        assert!(
            (flat[1] - press[1]).abs() <= 1e-9 * press[1].abs(),
            "{flat:?} {press:?}"
        );
        assert!((pair.fy + flat[1]).abs() <= 1e-9 * press[1].abs());
        // Frictionless: every node in contact slides (NEQC = 1 each), and
        // the force is along the flat's normal: no tangential resultant
        // beyond round-off (measured 1e-16 of Fn).
        assert_eq!(pair.n_stick, 0);
        assert_eq!(step.neqc, pair.n_slip);
        assert!(
            pair.fx.abs() <= 1e-12 * pair.fy,
            "Fx {} Fy {}",
            pair.fx,
            pair.fy
        );
        assert!(
            (pair.fn_ - pair.fy).abs() <= 1e-6 * pair.fy,
            "flat target: Fn = Fy"
        );
    }
    // Hertz half-width from the computed load (the quarter carries P/2).
    let last = steps.last().unwrap();
    let pair = &last.pairs[0].1;
    let p = 2.0 * pair.fy;
    let e_star = 200000.0 / (1.0 - 0.09);
    let a = (4.0 * p * 10.0 / (std::f64::consts::PI * e_star)).sqrt();
    assert!(
        (p - 6600.0).abs() < 0.02 * 6600.0,
        "the paper's maximum load, P = {p}"
    );
    let n = &pair.nodes;
    let last_in = (0..n.x.len())
        .filter(|&k| n.state[k] != NodeState::Open)
        .map(|k| n.x[k])
        .fold(f64::MIN, f64::max);
    let first_out = (0..n.x.len())
        .filter(|&k| n.state[k] == NodeState::Open && n.x[k] > 0.0)
        .map(|k| n.x[k])
        .fold(f64::MAX, f64::min);
    // The contact edge lies between the last closed and the first open
    // node: Hertz's a must fall within that node spacing (one segment).
    assert!(
        last_in - (first_out - last_in) <= a && a <= first_out,
        "a = {a}, last closed {last_in}, first open {first_out}"
    );
}

/// The sliding block scene, with each `(old, new)` replaced once.
fn sliding_block(edits: &[(&str, &str)]) -> Vec<StepResult> {
    let problem = common::shipped_scene("verification/sliding_block.toml", edits);
    let times = problem.times.clone();
    let mut solver = Solver::new(problem).unwrap();
    times
        .into_iter()
        .map(|t| {
            solver
                .advance(t, &mut |_, _| {})
                .unwrap_or_else(|e| panic!("t = {t}: {e}"))
        })
        .collect()
}

fn ratio(step: &StepResult) -> f64 {
    let p = &step.pairs[0].1;
    p.ft / p.fn_
}

#[test]
fn sliding_block_breaks_away_slides_and_reverses() {
    let steps = sliding_block(&[]);
    let (mu_s, mu_d) = (0.3, 0.2);
    let nodes = steps[0].pairs[0].1.nodes.x.len();
    for step in &steps {
        let pair = &step.pairs[0].1;
        let top = driver(step, "top");
        let plane = driver(step, "plane");
        // Equilibrium of the block: the plane takes what the top applies.
        assert!(
            (plane[0] - top[0]).abs() <= 1e-9 * top[1].abs(),
            "{plane:?} {top:?}"
        );
        assert!((plane[1] - top[1]).abs() <= 1e-9 * top[1].abs());
        // Coulomb's bound holds at every converged state.
        assert!(
            pair.ft.abs() <= mu_s * pair.fn_ * (1.0 + 1e-9),
            "t = {}",
            step.time
        );
        assert_eq!(pair.n_open, 0);
    }
    let at = |t: f64| steps.iter().find(|s| (s.time - t).abs() < 1e-12).unwrap();
    // Pressed only: no tangential force.
    assert!(ratio(at(1.0)).abs() <= 1e-9);
    // Dragged in +x: once sliding, every node slips and Ft = mu_d Fn (0.1 %,
    // the bound; friction on the block points to -x, and Ft is
    // measured along the contactor, +x).
    for step in steps.iter().filter(|s| s.time >= 1.2 && s.time <= 3.0) {
        let p = &step.pairs[0].1;
        assert_eq!(p.n_slip, nodes, "t = {}: all nodes slip", step.time);
        assert!(
            (ratio(step) / -mu_d - 1.0).abs() < 1e-3,
            "t = {}: {}",
            step.time,
            ratio(step)
        );
    }
    // Drag reversed: the tangential force changes sign through a sticking
    // phase, then the block slides the other way at mu_d.
    let reversal: Vec<&StepResult> = steps
        .iter()
        .filter(|s| s.time > 3.0 && s.time < 3.25)
        .collect();
    assert!(
        reversal.iter().any(|s| s.pairs[0].1.n_stick == nodes),
        "a phase of full stick"
    );
    assert!(reversal.iter().any(|s| ratio(s) < -0.1) && reversal.iter().any(|s| ratio(s) > 0.1));
    for step in steps.iter().filter(|s| s.time >= 3.25) {
        assert_eq!(step.pairs[0].1.n_slip, nodes, "t = {}", step.time);
        assert!(
            (ratio(step) / mu_d - 1.0).abs() < 1e-3,
            "t = {}: {}",
            step.time,
            ratio(step)
        );
    }
}

#[test]
fn static_friction_rules_on_a_one_segment_block() {
    // One element, nu = 0: one contactor segment carries the whole shear,
    // so its breakaway is the pair's. Steps of 0.01 in t change Ft/Fn by
    // 0.05 while sticking (a linear elastic element): the capacities 0.2
    // and 0.3 are reached exactly at t = 3.08 and t = 3.1 of the reversal.
    let edit = |rule: &str| {
        sliding_block(&[
            ("nu = 0.3", "nu = 0.0"),
            ("divisions = [8, 4]", "divisions = [1, 1]"),
            // The paper's segment decisions: one segment carries the shear.
            (
                "mu_d = 0.2\n",
                &format!("mu_d = 0.2\nrule = \"{rule}\"\ndecisions = \"paper\"\n"),
            ),
        ])
    };
    for (rule, peak) in [("mu_d_after_slip", 0.2), ("always_mu_s", 0.3)] {
        let steps = edit(rule);
        // The first breakaway: nothing has slid, mu_s applies under both
        // rules; the stuck ratio never exceeds it.
        let first_slip = steps
            .iter()
            .position(|s| s.pairs[0].1.n_slip > 0 && s.time > 1.0)
            .unwrap();
        assert!(ratio(&steps[first_slip - 1]).abs() <= 0.3 + 1e-9);
        // The reversal after sliding: the usual rule re-breaks at mu_d, the
        // experiment at mu_s; then both slide at mu_d.
        let reversal: Vec<&StepResult> = steps
            .iter()
            .filter(|s| s.time > 3.0 && s.time < 3.25)
            .collect();
        let stuck_max = reversal
            .iter()
            .filter(|s| s.pairs[0].1.n_stick > 0)
            .map(|s| ratio(s))
            .fold(f64::MIN, f64::max);
        assert!(
            (stuck_max - peak).abs() < 1e-9,
            "{rule}: stuck peak {stuck_max}"
        );
        let last = steps.last().unwrap();
        assert!(
            (ratio(last) - 0.2).abs() < 1e-9,
            "{rule}: sliding at {}",
            ratio(last)
        );
    }
}

/// A frictionless pair reports no tangential traction at any node, the
/// contact edge included (its Q8 tractions are taken in the target's frame
/// where each node touches it; the contactor's own frame tilts at the edge,
/// where its next side lifts off, and showed 3.2 of tn 1479 there).
#[test]
fn frictionless_pair_reports_no_tangential_traction() {
    for name in ["hertz_plane_strain.toml", "hertz_axisymmetric.toml"] {
        let (_, steps, _) = solve(name);
        for step in &steps {
            let nodes = &step.pairs[0].1.nodes;
            let tn_max = nodes.tn.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for (k, &tt) in nodes.tt.iter().enumerate() {
                // Round-off of the recovered forces: 1e-12 of the largest
                // traction (measured 4e-15 relative).
                assert!(
                    tt.abs() <= 1e-12 * tn_max,
                    "{name} t = {}: node {k} tt = {tt} (tn max {tn_max})",
                    step.time
                );
            }
        }
    }
}
