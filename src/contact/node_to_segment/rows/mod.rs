//! The rows of Eq. (18) one contactor node in contact on a target segment
//! adds, one kind a file: two for a node held in both directions
//! (`stick`: sticking, Eqs. 19-21, or at a reflex corner), one for a sliding
//! node (`slide`: Eqs. 22-24); on a smoothed target's curve, both kinds
//! over the curve's four nodes (`smooth`).

mod slide;
mod smooth;
mod stick;

use crate::contact::search::TargetSegment;
use crate::contact::segment::ContactPoint;
use crate::contact::system::{ContactSystem, Entries};
use nalgebra::Vector2;

/// The dofs a node's rows act on: the node's two, then the target
/// segment's ends' four (None against a rigid target).
type Dofs = [Option<usize>; 6];

/// A row's entries over `dofs`, the coefficient of local dof `l` being
/// `v(l)`.
#[inline(always)]
fn entries(dofs: &Dofs, v: &dyn Fn(usize) -> f64) -> Entries {
    let mut e = Entries::default();
    for (l, dof) in dofs.iter().enumerate() {
        if let Some(dof) = *dof {
            e.at[e.len] = (dof, v(l));
            e.len += 1;
        }
    }
    e
}

/// The rows of Eq. (18) for one node `n` in contact at `cp` on the target
/// segment `segment` (its nodes None: rigid), with `lambda` its contact
/// force: held in both directions (`held`: sticking, or at a corner) or
/// sliding with `friction` (`s mu_d`, or 0) along its slip.
pub(super) fn add_rows(
    segment: &TargetSegment,
    n: usize,
    cp: &ContactPoint,
    held: bool,
    lambda: Vector2<f64>,
    friction: f64,
    out: &mut ContactSystem,
) {
    let first_row = out.rows.len();
    if cp.segment().is_smooth() {
        smooth::rows(n, segment, cp, held, lambda, friction, out);
        out.groups.push((n, first_row..out.rows.len()));
        return;
    }
    let target = segment.nodes;
    let mut dofs = [Some(2 * n), Some(2 * n + 1), None, None, None, None];
    if let Some([a, b]) = target {
        dofs[2..].copy_from_slice(&[Some(2 * a), Some(2 * a + 1), Some(2 * b), Some(2 * b + 1)]);
    }
    if held {
        stick::rows(&dofs, cp, lambda, out);
    } else {
        slide::row(&dofs, target.is_some(), cp, lambda, friction, out);
    }
    out.groups.push((n, first_row..out.rows.len()));
}
