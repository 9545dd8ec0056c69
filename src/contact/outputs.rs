//! Per contactor node quantities of a converged state that the outputs
//! report and the iteration does not need: the gap to the target and the
//! slip over the last step; and the outputs of a problem at rest.

use super::PairMemory;
use super::search::{self, RigidSegments, TargetSegment, TargetSet};
use crate::problem::{ContactPair, Problem};
use crate::results::{DriverResult, NodeState, PairNodes, PairResult, StepResult};
use nalgebra::Vector2;

/// The outputs of a problem at rest (before its first increment): zero
/// forces, every contactor node open at its position in `u`.
pub fn rest_step(problem: &Problem, time: f64, u: &[f64]) -> StepResult {
    let drivers = problem
        .drivers
        .iter()
        .map(|d| (d.name.clone(), DriverResult::default()))
        .chain(problem.rigids.iter().map(|r| {
            let rest = DriverResult {
                mz: Some(0.0),
                ..Default::default()
            };
            (r.name.clone(), rest)
        }))
        .collect();
    let poses = search::scene_poses(problem, time);
    let targets = RigidSegments::default();
    let pairs = problem
        .contacts
        .iter()
        .map(|c| {
            let m = c.contactor.len();
            let at = |n: usize, i: usize| problem.mesh.nodes[n][i] + u[2 * n + i];
            // Every node open: its gap is its distance to the target (a
            // degenerate target segment, which the first step reports,
            // leaves it unknown).
            let rest = PairMemory::new(c);
            let gap = gaps_and_slips(problem, &targets, c, u, &poses, &rest, None)
                .map_or_else(|_| vec![f64::NAN; m], |(gap, _)| gap);
            let nodes = PairNodes {
                x: c.contactor.iter().map(|&n| at(n, 0)).collect(),
                y: c.contactor.iter().map(|&n| at(n, 1)).collect(),
                tn: vec![0.0; m],
                tt: vec![0.0; m],
                state: vec![NodeState::Open; m],
                gap,
                slip: vec![0.0; m],
                angle: Vec::new(),
                pn: vec![0.0; m],
                pt: vec![0.0; m],
            };
            let mut nodes = nodes;
            nodes.angle = angles(problem, c, &nodes.x, &nodes.y);
            let result = PairResult {
                n_open: m,
                nodes,
                ..Default::default()
            };
            (c.name.clone(), result)
        })
        .collect();
    StepResult {
        time,
        converged: true,
        drivers,
        pairs,
        ..Default::default()
    }
}

/// Each node's angle along the wrap, for a contactor on a strip (else
/// none), from its current position (`x`, `y`).
pub fn angles(problem: &Problem, pair: &ContactPair, x: &[f64], y: &[f64]) -> Vec<f64> {
    problem.contactor_strip(pair).map_or_else(Vec::new, |path| {
        (x.iter().zip(y))
            .map(|(&x, &y)| path.angle_from_exit([x, y]))
            .collect()
    })
}

/// The gap and slip of every contactor node of `pair` in the state `u`,
/// `poses`, `now` (node memory), against the state at the start of the step
/// (`start`, None at rest):
///
/// - gap: the signed normal distance to the target, positive clear of it,
///   negative into it. A node in contact: from its contact point (zero to the
///   tolerance Newton converged to); an open node: to the nearest point of the
///   target (a segment's end beyond which the node lies counts as a point).
/// - slip: how far the node has moved along the contactor, relative to the
///   target's material point it touched when the step began (carried with the
///   target: rigid motion, or the target body's surface). Measured in the
///   contactor's direction (toward the next node), the direction of `tt`, so
///   that friction opposes it: a sliding node has `slip * tt <= 0`. Zero for a
///   node open at the end of the step or at its start (one that touched down
///   in the step has no material point to slip from).
pub fn gaps_and_slips(
    problem: &Problem,
    targets: &RigidSegments,
    pair: &ContactPair,
    u: &[f64],
    poses: &[[f64; 3]],
    now: &PairMemory,
    start: Option<&PairMemory>,
) -> Result<(Vec<f64>, Vec<f64>), String> {
    let segments = search::target_segments(targets, problem, pair, u, poses)?;
    let x: Vec<Vector2<f64>> = (pair.contactor.iter())
        .map(|&n| search::position(problem, u, n))
        .collect();
    let m = x.len();
    let mut gaps = Vec::with_capacity(m);
    let mut slips = Vec::with_capacity(m);
    for k in 0..now.nodes() {
        let (state, segment, beta) = now.contact(k);
        let contact = (state != NodeState::Open)
            .then(|| segments.get(segment))
            .flatten();
        gaps.push(match contact {
            Some(s) => s.seg.contact_at(x[k], beta).gap(),
            None => nearest_gap(&segments, x[k]),
        });
        let began = start
            .filter(|s| k < s.nodes())
            .map(|s| s.contact(k))
            .filter(|b| b.0 != NodeState::Open)
            .and_then(|b| Some((segments.get(b.1)?, b.2)));
        let slip = match (contact, began) {
            (Some(_), Some((s, beta))) => {
                along(&x, k, pair.closed).dot(&(x[k] - s.seg.point_at(beta)))
            }
            _ => 0.0,
        };
        slips.push(slip);
    }
    Ok((gaps, slips))
}

/// The contactor's unit direction at node k: toward the next node (from the
/// previous one inside an open contactor, and at its last node).
pub(super) fn along(x: &[Vector2<f64>], k: usize, closed: bool) -> Vector2<f64> {
    let m = x.len();
    let (a, b) = match (k, closed) {
        (_, _) if m < 2 => return Vector2::zeros(),
        (0, false) => (0, 1),
        (k, false) if k == m - 1 => (m - 2, m - 1),
        (k, _) => ((k + m - 1) % m, (k + 1) % m),
    };
    (x[b] - x[a])
        .try_normalize(0.0)
        .unwrap_or_else(Vector2::zeros)
}

/// The signed distance from x to the nearest point of the target polyline:
/// its size from the nearest point, its sign from that segment's normal
/// (negative on the target's side).
fn nearest_gap(segments: &TargetSet, x: Vector2<f64>) -> f64 {
    nearest(segments, x).map_or(f64::INFINITY, |(gap, _)| gap)
}

/// The nearest segment of the target to x: the signed distance to it (as
/// [`nearest_gap`]) and its normal (into the target). Looked for within a
/// box about x that doubles until the nearest found lies inside it (every
/// segment outside is farther), then over all segments.
pub(super) fn nearest(segments: &TargetSet, x: Vector2<f64>) -> Option<(f64, Vector2<f64>)> {
    nearest_point(segments, x).map(|n| (n.gap, n.normal))
}

/// The target's point nearest to a point: the signed distance (as
/// [`nearest_gap`]), the segment's normal (into the target), the segment
/// and the point's parameter on it.
pub(super) struct Nearest {
    pub gap: f64,
    pub normal: Vector2<f64>,
    pub segment: usize,
    pub beta: f64,
}

/// [`nearest`], with the segment and the parameter of the point on it.
pub(super) fn nearest_point(segments: &TargetSet, x: Vector2<f64>) -> Option<Nearest> {
    let mut r = segments.first().map_or(0.0, |s| s.seg.length());
    for _ in 0..64 {
        if !(r.is_finite() && r > 0.0) {
            break;
        }
        let (lo, hi) = ([x.x - r, x.y - r], [x.x + r, x.y + r]);
        match nearest_of(segments.visit(lo, hi), x) {
            Some(found) if found.gap.abs() <= r => return Some(found),
            _ => r *= 2.0,
        }
    }
    nearest_of(segments.iter().enumerate(), x)
}

/// [`nearest_point`] among `segments`, the first of equals in their order.
fn nearest_of<'a>(
    segments: impl Iterator<Item = (usize, &'a TargetSegment)>,
    x: Vector2<f64>,
) -> Option<Nearest> {
    let mut best = f64::INFINITY;
    let mut found = None;
    for (j, s) in segments {
        let (a, b) = (s.seg.xa(), s.seg.xb());
        // No point of the segment is nearer than its box.
        let dx = (a.x.min(b.x) - x.x).max(x.x - a.x.max(b.x)).max(0.0);
        let dy = (a.y.min(b.y) - x.y).max(x.y - a.y.max(b.y)).max(0.0);
        if dx.hypot(dy) >= best {
            continue;
        }
        let raw = s.seg.project(x);
        let beta = raw.beta().clamp(0.0, 1.0);
        let d = (x - s.seg.point_at(beta)).norm();
        if d < best {
            best = d;
            found = Some(Nearest {
                gap: if raw.gap() < 0.0 { -d } else { d },
                normal: s.seg.frame_at(beta).0,
                segment: j,
                beta,
            });
        }
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contactor_direction_at_ends_and_inside() {
        let x = [
            Vector2::new(0.0, 0.0),
            Vector2::new(1.0, 0.0),
            Vector2::new(1.0, 2.0),
        ];
        assert_eq!(along(&x, 0, false), Vector2::new(1.0, 0.0));
        assert_eq!(along(&x, 2, false), Vector2::new(0.0, 1.0));
        let mid = along(&x, 1, false);
        assert!((mid - Vector2::new(1.0, 2.0) / 5f64.sqrt()).norm() < 1e-15);
        // Closed: the last node's neighbours are the one before and the
        // first.
        assert_eq!(along(&x, 2, true), Vector2::new(-1.0, 0.0));
    }
}
