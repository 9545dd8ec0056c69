//! Mistakes in a scene's contact pairs that would otherwise pass in
//! silence, found on the geometry at rest (t = 0, no displacement).

use super::outputs::{along, nearest};
use super::search::{self, RigidSegments};
use crate::problem::{ContactPair, Problem};
use nalgebra::Vector2;

/// What the geometry at rest says about one pair.
#[derive(Debug, Default, PartialEq)]
pub struct AtRest {
    /// The contactor and the target face away from each other at every
    /// contactor node: the pair can never act. The message says which way
    /// to turn what.
    pub facing_away: Option<String>,
    /// Contactor nodes that start inside the target by more than a
    /// round-off overlap: the message gives how many and the largest depth.
    pub overlap: Option<String>,
}

/// An overlap at rest below this fraction of the contactor's shortest
/// segment is how a scene starts in touch (docs/scenes.md), not a mistake.
const TOUCH: f64 = 1e-4;

/// Checks one pair at rest: whether its contactor and target face each other
/// (the contactor's outward normal, the body on its left, against the
/// target's normal into it, at the nearest target segment), and how deep its
/// nodes start inside the target.
pub fn at_rest(problem: &Problem, pair: &ContactPair) -> Result<AtRest, String> {
    let u = problem.initial_u();
    let poses = search::scene_poses(problem, 0.0);
    let segments = search::target_segments(&RigidSegments::default(), problem, pair, &u, &poses)?;
    let x: Vec<Vector2<f64>> = (pair.contactor.iter())
        .map(|&n| search::position(problem, &u, n))
        .collect();
    let mut out = AtRest::default();
    if x.len() < 2 || segments.is_empty() {
        return Ok(out);
    }
    let shortest = (x.windows(2))
        .map(|w| (w[1] - w[0]).norm())
        .fold(f64::INFINITY, f64::min);
    let mut facing = 0;
    let (mut inside, mut deepest, mut at) = (0, 0.0f64, 0);
    for k in 0..x.len() {
        let Some((gap, normal)) = nearest(&segments, x[k]) else {
            continue;
        };
        let t = along(&x, k, pair.closed);
        let outward = Vector2::new(t.y, -t.x);
        if outward.dot(&normal) > 0.0 {
            facing += 1;
        }
        if -gap > TOUCH * shortest {
            inside += 1;
            if -gap > deepest {
                (deepest, at) = (-gap, k);
            }
        }
    }
    if facing == 0 {
        out.facing_away = Some(format!(
            "pair '{}': its contactor and its target face away from each other at every contactor \
             node (the contactor's outward normal, its body on the left, against the target's normal \
             into the target), so it can never act: reverse the target's points (a rigid lies on the \
             left walking from its first point to its last; a body's edge set runs with the body on \
             its left), or name the contactor set on the face of its body that meets the target",
            pair.name
        ));
    }
    if inside > 0 {
        out.overlap = Some(format!(
            "pair '{}': {inside} of {} contactor nodes start inside the target, by up to {deepest:.3e} \
             (node {} at ({:.6e}, {:.6e})); the first increment pushes them out with a force to match. \
             An interference fit means it; a scene that should start in touch needs an overlap far \
             below its displacements (docs/scenes.md)",
            pair.name,
            x.len(),
            at + 1,
            x[at].x,
            x[at].y
        ));
    }
    Ok(out)
}
