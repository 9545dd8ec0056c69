//! The rows of Eq. (18) one contactor node in contact on a target segment
//! adds: two for a node held in both directions (sticking, Eqs. 19-21),
//! one for a sliding node (Eqs. 22-24).

use crate::contact::segment::ContactPoint;
use crate::contact::system::{ContactSystem, Entries, Row};
use nalgebra::Vector2;

/// The rows of Eq. (18) for one node `n` in contact at `cp` on a target
/// segment with nodes `target` (None: rigid), with `lambda` its contact
/// force: two for a node held in both directions (sticking, Eqs. 19-21, or
/// at a corner), else one for a sliding node (Eqs. 22-24), whose
/// multiplier is the increase of its normal force. `friction` (`s mu_d`,
/// or 0) is the friction that increase brings along the slip: the
/// multiplier's column is then `G^T (n_s + s mu_d n_r)` (the negative of
/// `d(G^T lambda)/d p_n`, as `Sliding::k_ul` is for `n_s` alone), its row
/// the normal gap.
pub(super) fn add_rows(
    target: Option<[usize; 2]>,
    n: usize,
    cp: &ContactPoint,
    held: bool,
    lambda: Vector2<f64>,
    friction: f64,
    out: &mut ContactSystem,
) {
    let mut dofs = [Some(2 * n), Some(2 * n + 1), None, None, None, None];
    if let Some([a, b]) = target {
        dofs[2..].copy_from_slice(&[Some(2 * a), Some(2 * a + 1), Some(2 * b), Some(2 * b + 1)]);
    }
    let first_row = out.rows.len();
    let entries = |v: &dyn Fn(usize) -> f64| -> Entries {
        let mut e = Entries::default();
        for (l, dof) in dofs.iter().enumerate() {
            if let Some(dof) = *dof {
                e.at[e.len] = (dof, v(l));
                e.len += 1;
            }
        }
        e
    };
    if held {
        let c = cp.sticking(lambda);
        for l in 0..6 {
            if let Some(dof) = dofs[l] {
                out.force.push((dof, c.r_c[l]));
            }
        }
        for row in 0..2 {
            out.rows.push(Row {
                dofs: entries(&|l| c.k_ul[(l, row)]),
                rhs: c.delta_c[row],
                column: Entries::default(),
            });
        }
        out.max_overlap = out.max_overlap.max(cp.overlap().norm());
    } else {
        let c = cp.sliding(lambda);
        for l in 0..6 {
            if let Some(dof) = dofs[l] {
                out.force.push((dof, c.r_c[l]));
            }
        }
        if target.is_some() {
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
            entries(&|l| v[l])
        } else {
            Entries::default()
        };
        out.rows.push(Row {
            dofs: entries(&|l| c.k_ul[l]),
            rhs: c.delta_c,
            column,
        });
        out.max_overlap = out.max_overlap.max(c.delta_c.abs());
    }
    out.groups.push((n, first_row..out.rows.len()));
}
