//! A node sliding along the target (Eqs. 22-24): one row, the normal gap,
//! whose multiplier is the increase of the node's normal force. With
//! friction `s mu_d` that increase brings friction along the slip: the
//! multiplier's column is then `G^T (n_s + s mu_d n_r)` (the negative of
//! `d(G^T lambda)/d p_n`, as `Sliding::k_ul` is for `n_s` alone). Against a
//! flexible target the sliding gradient of Eq. 24 enters the tangent.

use super::{Dofs, entries};
use crate::contact::segment::ContactPoint;
use crate::contact::system::{ContactSystem, Entries, Row};
use nalgebra::Vector2;

/// The node's contact force, gradient entries (`flexible`: a target body)
/// and row into `out`.
#[inline]
pub(super) fn row(
    dofs: &Dofs,
    flexible: bool,
    cp: &ContactPoint,
    lambda: Vector2<f64>,
    friction: f64,
    out: &mut ContactSystem,
) {
    let c = cp.sliding(lambda);
    for l in 0..6 {
        if let Some(dof) = dofs[l] {
            out.force.push((dof, c.r_c[l]));
        }
    }
    if flexible {
        for a in 0..6 {
            for b in 0..6 {
                if let (Some(da), Some(db)) = (dofs[a], dofs[b])
                    && c.k_uu[(a, b)] != 0.0
                {
                    out.k.push((da, db, c.k_uu[(a, b)]));
                }
            }
        }
    }
    let column = if friction != 0.0 {
        let seg = cp.segment();
        let v = cp.relative_motion().transpose() * (seg.normal() + friction * seg.tangent());
        entries(dofs, &|l| v[l])
    } else {
        Entries::default()
    };
    out.rows.push(Row {
        dofs: entries(dofs, &|l| c.k_ul[l]),
        rhs: c.delta_c,
        column,
    });
    out.max_overlap = out.max_overlap.max(c.delta_c.abs());
}
