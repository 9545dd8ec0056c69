//! A node sliding along the target (Eqs. 22-24): one row, the normal gap,
//! whose multiplier is the increase of the node's normal force. With
//! friction `s mu_d` that increase brings friction along the slip: the
//! multiplier's column is then `G^T (n_s + s mu_d n_r)` (the negative of
//! `d(G^T lambda)/d p_n`, as `Sliding::k_ul` is for `n_s` alone). Against a
//! flexible target the sliding gradient of Eq. 24 enters the tangent.

use super::{Dofs, entries};
use crate::contact::segment::ContactPoint;
use crate::contact::segment::{NodeMat, NodeVec};
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
        let k_uu = if friction != 0.0 {
            full_gradient(cp, lambda, friction)
        } else {
            c.k_uu
        };
        for a in 0..6 {
            for b in 0..6 {
                if let (Some(da), Some(db)) = (dofs[a], dofs[b])
                    && k_uu[(a, b)] != 0.0
                {
                    out.k.push((da, db, k_uu[(a, b)]));
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

/// A sliding node's gradient matrix with friction, written in full:
/// `-d(G^T lambda)/dU` at fixed normal force, `lambda = p_n (-n_s - friction
/// n_r)`, which is `-b a^T - p_n G^T (n_r - friction n_s) / d e^T` with
/// `e = [0; -n_s; n_s]` the change of the segment's normal times its
/// length (rows/smooth.rs on a straight segment). Frictionless it is
/// Eq. (24)'s `-(a b^T + b a^T)`; with friction Eq. (24)'s symmetric form
/// leaves Newton a linear rate.
#[inline(never)]
fn full_gradient(cp: &ContactPoint, lambda: Vector2<f64>, friction: f64) -> NodeMat {
    let seg = cp.segment();
    let (n_s, n_r, d) = (seg.normal(), seg.tangent(), seg.length());
    let gt = cp.relative_motion().transpose();
    let a = cp.dbeta_du();
    let b = NodeVec::from([0.0, 0.0, lambda.x, lambda.y, -lambda.x, -lambda.y]);
    let p_n = -n_s.dot(&lambda);
    let turn = gt * (n_r - friction * n_s) * (p_n / d);
    let e = NodeVec::from([0.0, 0.0, -n_s.x, -n_s.y, n_s.x, n_s.y]);
    -(b * a.transpose()) - turn * e.transpose()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::segment::Segment;

    /// With friction either way the gradient matrix is minus the derivative
    /// of the spread force `G^T lambda` at fixed normal force (the node at
    /// the foot of its normal, as it is at convergence), to central
    /// differences; frictionless it is Eq. (24)'s.
    #[test]
    fn a_sliding_node_s_gradient_is_its_spread_force_s_derivative() {
        let base = [[0.3, 0.05], [1.0, 0.2], [-0.4, -0.1]].map(|p| Vector2::new(p[0], p[1]));
        let seg = Segment::new(base[1], base[2]).unwrap();
        let mut x = base;
        x[0] = seg.point_at(0.35);
        let p_n = 1.3;
        let dofs: Dofs = [0, 1, 2, 3, 4, 5].map(Some);
        let system = |x: &[Vector2<f64>; 3], friction: f64| {
            let cp = Segment::new(x[1], x[2]).unwrap().project(x[0]);
            let lambda = p_n * (-cp.normal() - friction * cp.tangent());
            let mut out = ContactSystem::default();
            row(&dofs, true, &cp, lambda, friction, &mut out);
            out
        };
        for friction in [0.0, 0.4, -0.25] {
            let mut k = [[0.0; 6]; 6];
            for &(r, c, v) in &system(&x, friction).k {
                k[r][c] += v;
            }
            let h = 1e-6;
            for d in 0..6 {
                let force = |s: f64| {
                    let mut y = x;
                    y[d / 2][d % 2] += s * h;
                    let mut f = [0.0; 6];
                    for &(dof, v) in &system(&y, friction).force {
                        f[dof] += v;
                    }
                    f
                };
                let (f1, f0) = (force(1.0), force(-1.0));
                for e in 0..6 {
                    let derivative = (f1[e] - f0[e]) / (2.0 * h);
                    let err = (k[e][d] + derivative).abs();
                    assert!(
                        err < 1e-7,
                        "friction {friction} k[{e}][{d}] {} {}",
                        k[e][d],
                        -derivative
                    );
                }
            }
        }
    }
}
