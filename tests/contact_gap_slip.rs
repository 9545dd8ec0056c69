//! The per-node gap and slip outputs (`PairNodes::gap`, `::slip`;
//! `contact::outputs`): exact values where the kinematics give them, and the
//! sign convention (friction opposes slip).

mod common;

use contact2d::newton::Solver;
use contact2d::results::{NodeState, StepResult};

fn run(problem: contact2d::problem::Problem) -> (Solver, Vec<StepResult>) {
    let times = problem.times.clone();
    let mut solver = Solver::new(problem).unwrap();
    let steps = times
        .into_iter()
        .map(|t| solver.advance(t, &mut common::silent()).unwrap())
        .collect();
    (solver, steps)
}

/// The dragged block (scenes/verification/sliding_block.toml): between two
/// increments of full slip under the same normal load, the block translates
/// as a rigid body, so every node slips by the increment of the drag, to
/// Newton's tolerance (1e-9 of the step, relative); friction opposes the
/// slip at every sliding node; nodes in contact have no gap beyond
/// round-off.
#[test]
fn dragged_block_slips_by_the_drag_and_friction_opposes_it() {
    let problem = common::shipped_scene("verification/sliding_block.toml", &[]);
    let (_, steps) = run(problem);
    let drag = |t: f64| {
        // The scene's drag: 0.2 x (0 until 1, ramp to 1 at 3, back to 0.5 at 4).
        0.2 * if t <= 1.0 {
            0.0
        } else if t <= 3.0 {
            (t - 1.0) / 2.0
        } else {
            1.0 - 0.5 * (t - 3.0)
        }
    };
    let mut checked = 0;
    for w in steps.windows(3) {
        let [before, prev, cur] = [&w[0], &w[1], &w[2]];
        let all_slip = |s: &StepResult| {
            s.pairs[0]
                .1
                .nodes
                .state
                .iter()
                .all(|&st| st == NodeState::Slip)
        };
        let n = &cur.pairs[0].1.nodes;
        for k in 0..n.x.len() {
            assert!(
                n.gap[k].abs() < 1e-12,
                "t = {}: node {k} gap {}",
                cur.time,
                n.gap[k]
            );
            if n.state[k] == NodeState::Slip {
                assert!(
                    n.slip[k] * n.tt[k] <= 0.0,
                    "t = {}: node {k} slip {} with tt {}",
                    cur.time,
                    n.slip[k],
                    n.tt[k]
                );
            }
        }
        // Full slip in this increment and the one before, the same way.
        let same_way =
            (drag(cur.time) - drag(prev.time)) * (drag(prev.time) - drag(before.time)) > 0.0;
        if !(all_slip(prev) && all_slip(cur) && all_slip(before) && same_way) {
            continue;
        }
        let step = drag(cur.time) - drag(prev.time);
        // The contactor runs along -x or +x: the slip is the drag, signed
        // along it.
        let along = (n.x[1] - n.x[0]).signum();
        for (k, &slip) in n.slip.iter().enumerate() {
            assert!(
                (slip - along * step).abs() <= 1e-9 * step.abs(),
                "t = {}: node {k} slipped {slip}, the drag moved {step}",
                cur.time
            );
        }
        checked += 1;
    }
    assert!(
        checked >= 10,
        "only {checked} increments of full slip checked"
    );
}

/// The block held at its top on a plane that moves under it
/// (scenes/stress/moving_plane.toml): the slip is relative to the target,
/// so in full slip every node slips by minus the plane's motion, although
/// the contactor nodes hardly move.
#[test]
fn slip_is_relative_to_a_moving_target() {
    let problem = common::shipped_scene("stress/moving_plane.toml", &[]);
    let times = problem.times.clone();
    let (_, steps) = run(problem);
    let plane = |t: f64| 0.2 * (t - 1.0).clamp(0.0, 1.0);
    let mut checked = 0;
    for (i, cur) in steps.iter().enumerate().skip(2) {
        let (prev, before) = (&steps[i - 1], &steps[i - 2]);
        let full = |s: &StepResult| {
            s.pairs[0]
                .1
                .nodes
                .state
                .iter()
                .all(|&st| st == NodeState::Slip)
        };
        if !(full(before) && full(prev) && full(cur)) {
            continue;
        }
        let n = &cur.pairs[0].1.nodes;
        let along = (n.x[1] - n.x[0]).signum();
        let step = plane(times[i]) - plane(times[i - 1]);
        for (k, &slip) in n.slip.iter().enumerate() {
            assert!(
                (slip + along * step).abs() <= 1e-9 * step.abs(),
                "t = {}: node {k} slipped {slip}, the plane moved {step}",
                cur.time
            );
        }
        checked += 1;
    }
    assert!(checked >= 1, "no increment of full slip");
}

/// Open nodes: the gap is the height above the plane. The dragged block
/// with its plane lowered by 0.1 and pressed by 0.01 only never touches:
/// each bottom node's gap is its current height plus 0.1, and it does not
/// slip.
#[test]
fn open_nodes_report_their_distance_to_the_target() {
    let problem = common::shipped_scene(
        "verification/sliding_block.toml",
        &[(
            "points = [[10.0, 0.0], [-10.0, 0.0]]",
            "points = [[10.0, -0.1], [-10.0, -0.1]]",
        )],
    );
    let (_, steps) = run(problem);
    for s in &steps {
        let n = &s.pairs[0].1.nodes;
        assert!(n.state.iter().all(|&st| st == NodeState::Open));
        for k in 0..n.x.len() {
            assert!(
                (n.gap[k] - (n.y[k] + 0.1)).abs() < 1e-12,
                "t = {}: gap {} at y {}",
                s.time,
                n.gap[k],
                n.y[k]
            );
            assert_eq!(n.slip[k], 0.0);
        }
        // Pressed down by 0.01 at the top: the bottom came down too.
        assert!(n.gap.iter().all(|&g| g < 0.1 && g > 0.08));
    }
    // At rest, before the first step, the FMU's outputs carry the gap too.
    let problem = common::shipped_scene(
        "verification/sliding_block.toml",
        &[(
            "points = [[10.0, 0.0], [-10.0, 0.0]]",
            "points = [[10.0, -0.1], [-10.0, -0.1]]",
        )],
    );
    let u = vec![0.0; 2 * problem.mesh.nodes.len()];
    let rest = contact2d::contact::outputs::rest_step(&problem, 0.0, &u);
    assert!(
        rest.pairs[0]
            .1
            .nodes
            .gap
            .iter()
            .all(|&g| (g - 0.1).abs() < 1e-15)
    );
}
