//! The rubber sheet of the paper's Section 4.2 (scenes/rubber_sheet.toml):
//! a plane-stress Mooney-Rivlin sheet pushed into a rigid converging
//! channel and pulled back, with mu_s = mu_d = 0.15 (the shipped case),
//! mu_s = 0.20 and mu_d = 0.15 under both rules, and frictionless; the
//! statements of the text about Fig. 12 at t = 8, 14, 18 and 24.
//!
//! Run with `cargo test --release --test paper_rubber_sheet -- --nocapture`
//! to see the measured numbers.

mod common;

use contact2d::contact::PairMemory;
use contact2d::newton::Solver;
use contact2d::results::{NodeState, PairResult};

const SCENE: &str = "rubber_sheet.toml";
const CONTACT: &str = "mu_s = 0.15\nmu_d = 0.15";
const MU_D: f64 = 0.15;
/// The times of Fig. 12: pushed in (8, 14), just reversed (18), pulled
/// out (24).
const TIMES: [f64; 4] = [8.0, 14.0, 18.0, 24.0];

/// One case at the times of Fig. 12.
struct Case {
    name: &'static str,
    /// Per time of `TIMES`: the pair's results.
    pairs: Vec<PairResult>,
    /// Per time of `TIMES`: the state of each contactor segment (Slip: it
    /// slides) as the solver decided it.
    segments: Vec<Vec<NodeState>>,
    /// Increments run and bisections used over the whole history.
    increments: usize,
    bisections: usize,
}

fn run(name: &'static str, contact: &str) -> Case {
    // The paper's decisions (the scene runs the default ones).
    let contact = format!("{contact}\ndecisions = \"paper\"");
    let problem = common::shipped_scene(SCENE, &[(CONTACT, &contact)]);
    let times = problem.times.clone();
    let mut solver = Solver::new(problem).unwrap();
    let (mut pairs, mut segments, mut bisections) = (Vec::new(), Vec::new(), 0);
    for &t in &times {
        let step = solver
            .advance(t, &mut |_, _| {})
            .unwrap_or_else(|e| panic!("{name} at t = {t}: {e}"));
        bisections += step.substeps;
        if TIMES.iter().any(|&f| (f - t).abs() < 1e-9) {
            pairs.push(step.pairs[0].1.clone());
            let PairMemory::NodeToSegment(memory) = &solver.state().contact[0] else {
                panic!("{name}: a node-to-segment pair");
            };
            segments.push(memory.segments.iter().map(|s| s.state).collect());
        }
    }
    assert_eq!(pairs.len(), TIMES.len(), "{name}");
    Case {
        name,
        pairs,
        segments,
        increments: times.len(),
        bisections,
    }
}

/// Indices of the contactor nodes in contact (one run, the sheet's front).
fn closed(p: &PairResult) -> Vec<usize> {
    let c: Vec<usize> = (0..p.nodes.state.len())
        .filter(|&k| p.nodes.state[k] != NodeState::Open)
        .collect();
    assert_eq!(
        c,
        (c[0]..=*c.last().unwrap()).collect::<Vec<_>>(),
        "the contact zone is one run"
    );
    c
}

/// Largest difference of the nodal tractions of two cases over the largest
/// normal traction of the first.
fn traction_gap(a: &PairResult, b: &PairResult) -> f64 {
    let scale = a.nodes.tn.iter().fold(0.0_f64, |m, &x| m.max(x));
    let gap = (0..a.nodes.tn.len())
        .map(|k| {
            (a.nodes.tn[k] - b.nodes.tn[k])
                .abs()
                .max((a.nodes.tt[k] - b.nodes.tt[k]).abs())
        })
        .fold(0.0, f64::max);
    gap / scale
}

#[test]
fn rubber_sheet_tractions_as_the_paper_describes() {
    let equal = run("mu_s = mu_d = 0.15", CONTACT);
    let slid = run("mu_s = 0.20, once slid mu_d", "mu_s = 0.20\nmu_d = 0.15");
    let kept = run(
        "mu_s = 0.20 kept (experiment)",
        "mu_s = 0.20\nmu_d = 0.15\nrule = \"always_mu_s\"",
    );
    let free = run("frictionless", "mu_s = 0.0");
    for c in [&equal, &slid, &kept, &free] {
        for (i, p) in c.pairs.iter().enumerate() {
            eprintln!(
                "{:32} t = {:4}: Fn {:9.4} Ft {:+8.4} |Ft|/Fn {:.5} stick/slip/open {}/{}/{}",
                c.name,
                TIMES[i],
                p.fn_,
                p.ft,
                p.ft.abs() / p.fn_,
                p.n_stick,
                p.n_slip,
                p.n_open
            );
        }
        eprintln!(
            "{}: {} increments, {} bisections",
            c.name, c.increments, c.bisections
        );
        assert_eq!(c.increments, 48, "{}: t = 0.5 ... 24", c.name);
    }

    // t = 8, 14, 24: the whole contact zone slides, and |t_t| = mu_d t_n.
    for i in [0, 1, 3] {
        let (p, t) = (&equal.pairs[i], TIMES[i]);
        let zone = closed(p);
        assert!(zone.len() >= 10, "t = {t}: {} nodes in contact", zone.len());
        assert_eq!(p.n_stick, 0, "t = {t}: every node slides");
        // Every segment in contact slides (the solver's decision).
        let segments = &equal.segments[i];
        for j in zone[0]..*zone.last().unwrap() {
            assert_eq!(segments[j], NodeState::Slip, "t = {t}: segment {j}");
        }
        // Each sliding segment applies the uniform friction mu_d T_n
        // (Fig. 5b) and the wall is straight, so |Ft| = mu_d Fn but for the
        // segment at the edge of the zone, from the first closed node to
        // the open one: while the sheet moves in, its node has touched in
        // this increment, and it slides with its friction along the motion
        // (its kept direction +1, the others' -1: the sign of the T_t
        // recovered in the iteration after the touch). The kinematic check
        // of docs/contact.md item 9 does not turn it within the increment
        // (it does in the next one, when the zone has grown past it): the
        // node is anchored where iteration 1 caught it, ahead of where it
        // converges, so its slip from there runs against that friction. So
        // the first closed node's |t_t| / t_n is 0.06 and 0.03 at 8 and 14,
        // and |Ft| is below mu_d Fn by 0.52 %, 0.23 %, 0.05 % at 8, 14, 24.
        // Asserted: |Ft| <= mu_d Fn to round-off, and within 1 %.
        let coulomb = (MU_D * p.fn_ - p.ft.abs()) / (MU_D * p.fn_);
        eprintln!(
            "t = {t}: (mu_d Fn - |Ft|) / (mu_d Fn) = {coulomb:.2e}; edge node |tt|/tn {:.3}",
            p.nodes.tt[zone[0]].abs() / p.nodes.tn[zone[0]]
        );
        assert!((-1e-9..=0.01).contains(&coulomb), "t = {t}: {coulomb}");
        // Node by node the recovered tractions (Eqs. 26/27: linear between
        // the nodes) are the projection of the per-segment uniform friction
        // and differ from mu_d times the recovered t_n where t_n bends
        // sharply: over the three nodes at the sheet's front corner (t_n
        // nearly doubles over the last segment; up to 19 % off) and the
        // two at the edge of the contact zone (up to 80 % off, the edge
        // node above). These are left out, as the paper leaves out the
        // tractions near the loaded face; on the nodes between, |t_t| / t_n
        // is mu_d to 2.5 % (measured), 3 % is asserted.
        let inner = &zone[2..zone.len() - 3];
        let worst = inner
            .iter()
            .map(|&k| (p.nodes.tt[k].abs() / p.nodes.tn[k] - MU_D).abs() / MU_D)
            .fold(0.0, f64::max);
        let ends: Vec<f64> = [zone[0], zone[1]]
            .into_iter()
            .chain(zone[zone.len() - 3..].iter().copied())
            .map(|k| p.nodes.tt[k].abs() / p.nodes.tn[k])
            .collect();
        eprintln!(
            "t = {t}: {} inner nodes |tt|/tn within {:.2} % of mu_d; edge and front nodes {ends:.3?}",
            inner.len(),
            100.0 * worst
        );
        assert!(worst <= 0.03, "t = {t}: {worst}");
    }

    // The tangential tractions at 24 oppose those at 8 and 14: node by node
    // (t_t is positive from a contactor node to the next, the sheet's top
    // face runs from its loaded face to its front) and in the resultant.
    for i in [0, 1, 3] {
        let p = &equal.pairs[i];
        let sign = if i == 3 { 1.0 } else { -1.0 };
        assert!(sign * p.ft > 0.0, "t = {}: Ft {}", TIMES[i], p.ft);
        for k in closed(p) {
            assert!(
                sign * p.nodes.tt[k] > 0.0,
                "t = {}: node {k} tt {}",
                TIMES[i],
                p.nodes.tt[k]
            );
        }
    }

    // t = 18: the tangential tractions have only partly reversed; some
    // segments still stick.
    let p18 = &equal.pairs[2];
    let zone = closed(p18);
    let sticking = (zone[0]..*zone.last().unwrap())
        .filter(|&j| equal.segments[2][j] == NodeState::Stick)
        .count();
    let reversed = zone.iter().filter(|&&k| p18.nodes.tt[k] > 0.0).count();
    eprintln!(
        "t = 18: {sticking} of {} segments stick, {reversed} of {} nodes have reversed t_t",
        zone.len() - 1,
        zone.len()
    );
    assert!(sticking >= 2 && p18.n_stick >= 2, "t = 18: {sticking}");
    assert!(
        reversed >= 2 && reversed <= zone.len() - 2,
        "t = 18: {reversed} reversed"
    );

    // Frictionless against mu = 0.15: the normal resultant Fn of the pair
    // (the contact zone stays far from the loaded face, so the pair is the
    // zone the paper shows) is larger while the sheet is pushed in (8, 14)
    // and smaller once it is pulled back (18, 24). Measured +8.2 %, +5.5 %,
    // -5.5 %, -12.6 %; a margin of 2 % is asserted, so that the ordering is
    // not within the solution's tolerance. It is the resultant that
    // orders as the paper says, not the traction at a given place in the
    // channel: friction holds the front back (at 14 it is 11 mm behind the
    // frictionless one) and the axial compression it causes thickens the
    // sheet, so at equal current x the frictional t_n is the larger at 8
    // and 14 (and the smaller at 24); docs/paper-problems.md, rubber sheet.
    for i in 0..4 {
        let front = |p: &PairResult| {
            closed(p)
                .iter()
                .map(|&k| p.nodes.x[k])
                .fold(f64::INFINITY, f64::min)
        };
        eprintln!(
            "t = {}: front x {:.2} (mu = 0.15), {:.2} (frictionless)",
            TIMES[i],
            front(&equal.pairs[i]),
            front(&free.pairs[i])
        );
    }
    for i in 0..4 {
        let change = free.pairs[i].fn_ / equal.pairs[i].fn_ - 1.0;
        eprintln!("t = {}: frictionless Fn {:+.2} %", TIMES[i], 100.0 * change);
        if i < 2 {
            assert!(change >= 0.02, "t = {}: {change}", TIMES[i]);
        } else {
            assert!(change <= -0.02, "t = {}: {change}", TIMES[i]);
        }
    }

    // mu_s = 0.20 with the usual rule: every segment slides as it comes
    // into contact and uses mu_d from then on, so mu_s acts only in that
    // transient; the tractions at the four times are those of mu_s = mu_d
    // (measured identical); 1e-6 of the largest t_n is asserted.
    for i in 0..4 {
        let gap = traction_gap(&equal.pairs[i], &slid.pairs[i]);
        let fn_gap = (slid.pairs[i].fn_ - equal.pairs[i].fn_).abs() / equal.pairs[i].fn_;
        eprintln!(
            "t = {}: once slid vs mu_s = mu_d: tractions {gap:.2e}, Fn {fn_gap:.2e}",
            TIMES[i]
        );
        assert!(gap <= 1e-6 && fn_gap <= 1e-6, "t = {}", TIMES[i]);
    }

    // The experiment (mu_s = 0.20 kept): at 8, 14 and 24 every segment
    // slides, at mu_d, as with mu_s = mu_d, so the tractions are the same
    // (measured to 3e-14 of the largest t_n; 1e-6 asserted). The paper:
    // "relatively small differences", except the tangential tractions at
    // 18, which "more drastically changed sign". Here too the resultants
    // at 18 differ little (measured Fn +0.14 %, Ft -0.27 %), but where the
    // tractions change sign the sticking segments now hold up to mu_s:
    // the largest reversed t_t, at the node where the sign changes, is
    // 0.104 against 0.063 (|t_t| / t_n 0.30 against 0.18), and t_t drops
    // from there to the old direction over one segment instead of two.
    // Asserted: the largest reversed t_t at least 30 % above mu_s = mu_d's.
    for i in 0..4 {
        let gap = traction_gap(&equal.pairs[i], &kept.pairs[i]);
        eprintln!(
            "t = {}: mu_s kept vs mu_s = mu_d: tractions differ by {gap:.2e} of max t_n, \
             Fn {:+.3} %, Ft {:.4} vs {:.4}",
            TIMES[i],
            100.0 * (kept.pairs[i].fn_ / equal.pairs[i].fn_ - 1.0),
            kept.pairs[i].ft,
            equal.pairs[i].ft
        );
        if i != 2 {
            assert!(gap <= 1e-6, "t = {}: {gap}", TIMES[i]);
        }
    }
    let peak = |p: &PairResult| p.nodes.tt.iter().fold(0.0_f64, |m, &t| m.max(t));
    let (peak_kept, peak_equal) = (peak(&kept.pairs[2]), peak(&equal.pairs[2]));
    eprintln!(
        "t = 18: largest reversed t_t {peak_kept:.4} (mu_s kept), {peak_equal:.4} (mu_s = mu_d)"
    );
    assert!(peak_kept >= 1.3 * peak_equal, "{peak_kept} {peak_equal}");
    let fn_change = (kept.pairs[2].fn_ / equal.pairs[2].fn_ - 1.0).abs();
    assert!(fn_change <= 0.01, "t = 18: Fn {fn_change}");
}
