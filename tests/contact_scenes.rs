//! The shipped contact scenes, solved, against closed forms and invariants.

use contact2d::newton::Solver;
use contact2d::results::{LogCategory, NodeState, StepResult};
use contact2d::scene;
use std::path::PathBuf;

/// Every increment of the scene `name`, with its Newton log.
fn solve(name: &str) -> (Solver, Vec<StepResult>, Vec<String>) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name);
    let problem = scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
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
        // Frictionless: every node in contact slides (NEQC = 1 each), and the
        // tangential resultant is only what the contactor-frame normals of
        // the paper's recovery leave (measured 1e-4 of Fn).
        assert_eq!(pair.n_stick, 0);
        assert_eq!(step.neqc, pair.n_slip);
        assert!(
            pair.fx.abs() <= 1e-3 * pair.fy,
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

#[test]
fn sliding_block_breaks_away_slides_and_reverses() {
    let (_, steps, _) = solve("verification/sliding_block.toml");
    let (mu_s, mu_d) = (0.3, 0.2);
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
    let at = |t: f64| {
        &steps
            .iter()
            .find(|s| (s.time - t).abs() < 1e-12)
            .unwrap()
            .pairs[0]
            .1
    };
    // Pressed only: no tangential force.
    assert!(at(1.0).ft.abs() <= 1e-9 * at(1.0).fn_);
    // Dragged: sliding at mu_d (the usual rule after the first slip). The
    // uniform friction traction of each sliding segment gives Ft = mu_d Fn
    // exactly only when every segment slides; the two end nodes stay
    // sticking here (see the notes), measured Ft/Fn = 0.19968.
    for t in [2.0, 2.5, 3.0] {
        let p = at(t);
        let ratio = -p.ft / p.fn_;
        assert!(
            (ratio / mu_d - 1.0).abs() < 5e-3,
            "t = {t}: Ft/Fn = {ratio}"
        );
        assert!(p.n_slip >= p.n_stick, "t = {t}: mostly sliding");
    }
    // Drag reversed: the tangential force changes sign, through a phase with
    // more sticking nodes, and ends sliding the other way.
    assert!(at(3.25).ft > 0.0 && at(3.25).n_stick > at(3.0).n_stick);
    let p = at(4.0);
    assert!(
        (p.ft / p.fn_ / mu_d - 1.0).abs() < 5e-3,
        "Ft/Fn = {}",
        p.ft / p.fn_
    );
}
