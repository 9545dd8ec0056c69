//! A node held on the target in both directions (sticking, Eqs. 19-21, or
//! frictionless at a reflex corner): two rows, the overlap `delta_c` in
//! both directions, with the contact force `G^T lambda` on the dofs.

use super::{Dofs, entries};
use crate::contact::segment::ContactPoint;
use crate::contact::system::{ContactSystem, Entries, Row};
use nalgebra::Vector2;

/// The node's contact force and its two rows into `out`.
#[inline]
pub(super) fn rows(dofs: &Dofs, cp: &ContactPoint, lambda: Vector2<f64>, out: &mut ContactSystem) {
    let c = cp.sticking(lambda);
    for l in 0..6 {
        if let Some(dof) = dofs[l] {
            out.force.push((dof, c.r_c[l]));
        }
    }
    for row in 0..2 {
        out.rows.push(Row {
            dofs: entries(dofs, &|l| c.k_ul[(l, row)]),
            rhs: c.delta_c[row],
            column: Entries::default(),
        });
    }
    out.max_overlap = out.max_overlap.max(cp.overlap().norm());
}
