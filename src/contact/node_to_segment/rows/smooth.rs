//! A node on a smoothed target's curve (`smooth_target`): the rows of
//! `stick` and `slide` with `G` over the node and the curve's four nodes
//! `[P, A, B, Q]`, `G dU = du_k - sum N_i(beta) du_i`, and a sliding node's
//! gradient `-d(G^T lambda)/dU` at fixed normal force, written in full
//! (docs/contact.md, "Smoothed target"): the force spread anew as the
//! contact point moves along the curve, and the force turning with the
//! curve's normal. Frictionless it is `p_n` times the Hessian of the
//! normal overlap, `-(a b^T + b a^T) - p_n (n . x'') a a^T` with
//! `a = G^T n_r / |x'|` the change of beta and `b = dG^T/dbeta lambda`;
//! with friction it is not symmetric (the friction's column already makes
//! the system unsymmetric).

use crate::contact::search::TargetSegment;
use crate::contact::segment::ContactPoint;
use crate::contact::system::{ContactSystem, Entries, Row};
use nalgebra::Vector2;

/// The node `n` and the curve's nodes, each with its coefficient `g` in
/// `G` (1 for the node, `-N_i` for the target's) and `dg/dbeta`; an open
/// end's mirrored node (`x_P = 2 x_A - x_B`) folded into A and B.
fn stencil(n: usize, target: &TargetSegment, cp: &ContactPoint) -> Vec<(usize, f64, f64)> {
    let curve = (cp.segment().curve(cp.beta())).expect("a smoothed segment has its curve");
    let (mut w, mut dw) = (curve.weights, curve.slopes);
    let [p, q] = target.around;
    for v in [&mut w, &mut dw] {
        if p.is_none() {
            v[1] += 2.0 * v[0];
            v[2] -= v[0];
            v[0] = 0.0;
        }
        if q.is_none() {
            v[2] += 2.0 * v[3];
            v[1] -= v[3];
            v[3] = 0.0;
        }
    }
    let [a, b] = target.nodes.expect("a smoothed target is a body");
    let mut out = vec![(n, 1.0, 0.0)];
    for (i, node) in [p, Some(a), Some(b), q].into_iter().enumerate() {
        if let Some(m) = node {
            out.push((m, -w[i], -dw[i]));
        }
    }
    out
}

/// `G^T v` over the stencil's dofs.
fn spread(stencil: &[(usize, f64, f64)], v: Vector2<f64>) -> Entries {
    let mut list = Vec::with_capacity(2 * stencil.len());
    for &(m, g, _) in stencil {
        list.extend([(2 * m, g * v.x), (2 * m + 1, g * v.y)]);
    }
    Entries::from_slice(&list)
}

/// The rows of node `n` at `cp` on the smoothed segment `target`: held
/// (two rows, the overlap in both directions) or sliding (one row, the
/// normal gap, with `friction` along the slip in its column). Out of line:
/// the straight segments' callers stay as small as they were.
#[inline(never)]
pub(super) fn rows(
    n: usize,
    target: &TargetSegment,
    cp: &ContactPoint,
    held: bool,
    lambda: Vector2<f64>,
    friction: f64,
    out: &mut ContactSystem,
) {
    let stencil = stencil(n, target, cp);
    let overlap = cp.overlap();
    if held {
        for &(m, g, _) in &stencil {
            out.force
                .extend([(2 * m, g * lambda.x), (2 * m + 1, g * lambda.y)]);
        }
        for e in [Vector2::new(1.0, 0.0), Vector2::new(0.0, 1.0)] {
            out.rows.push(Row {
                dofs: spread(&stencil, -e),
                rhs: e.dot(&overlap),
                column: Entries::default(),
            });
        }
        out.max_overlap = out.max_overlap.max(overlap.norm());
        return;
    }
    let curve = (cp.segment().curve(cp.beta())).expect("a smoothed segment has its curve");
    let (n_s, n_r) = (cp.normal(), cp.tangent());
    let speed = curve.d1.norm();
    // The contact point's distance (in beta) from the foot of the normal:
    // zero but where the foot lies beyond the target's end.
    let c = n_r.dot(&overlap) / speed;
    for &(m, g, dg) in &stencil {
        let f = g * lambda + c * dg * lambda;
        out.force.extend([(2 * m, f.x), (2 * m + 1, f.y)]);
    }
    // -d(G^T lambda)/dU at fixed p_n, lambda = p_n (-n_s - friction n_r):
    // the force spread anew as beta moves (b a^T), and the force turning
    // with the curve's normal, which turns with the target's nodes (e) and
    // with beta along the curve (n_s . x''). Symmetric when frictionless.
    let p_n = -n_s.dot(&lambda);
    let curving = n_s.dot(&curve.d2);
    for &(m1, g1, dg1) in &stencil {
        let b1 = dg1 * lambda;
        let turn1 = p_n * g1 * (n_r - friction * n_s) / speed;
        for &(m2, g2, dg2) in &stencil {
            let a2 = g2 * n_r / speed;
            let e2 = -dg2 * n_s + curving * a2;
            for r in 0..2 {
                for s in 0..2 {
                    let v = -b1[r] * a2[s] - turn1[r] * e2[s];
                    if v != 0.0 {
                        out.k.push((2 * m1 + r, 2 * m2 + s, v));
                    }
                }
            }
        }
    }
    let column = if friction != 0.0 {
        spread(&stencil, n_s + friction * n_r)
    } else {
        Entries::default()
    };
    let gap = -n_s.dot(&overlap);
    out.rows.push(Row {
        dofs: spread(&stencil, n_s),
        rhs: gap,
        column,
    });
    out.max_overlap = out.max_overlap.max(gap.abs());
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::segment::Segment;

    /// Positions `[k, P, A, B, Q]` of a node on a curved target (the target
    /// below, on the left of A -> B walking in -x), at 0.4 of A -> B: the
    /// gradient matrix is the Hessian where the gap is closed.
    fn config(ends: [bool; 2]) -> [Vector2<f64>; 5] {
        let mut x = [
            Vector2::zeros(),
            Vector2::new(1.6, 0.35),
            Vector2::new(0.8, 0.12),
            Vector2::new(-0.1, 0.05),
            Vector2::new(-1.0, 0.2),
        ];
        x[0] = at(&x, ends).0.seg.point_at(0.4);
        x
    }

    /// The target segment A -> B smoothed through P and Q, nodes 1 to 4, and
    /// the node's contact point on it.
    fn at(x: &[Vector2<f64>; 5], ends: [bool; 2]) -> (TargetSegment, ContactPoint) {
        let [k, p, a, b, q] = *x;
        let xp = if ends[0] { 2.0 * a - b } else { p };
        let xq = if ends[1] { 2.0 * b - a } else { q };
        let seg = Segment::new(a, b).unwrap().smoothed([xp, xq]);
        let mut t = TargetSegment::new(seg, Some([2, 3]));
        t.around = [(!ends[0]).then_some(1), (!ends[1]).then_some(4)];
        let cp = seg.project(k);
        (t, cp)
    }

    fn dense(entries: &[(usize, f64)]) -> [f64; 10] {
        let mut v = [0.0; 10];
        for &(d, c) in entries {
            v[d] += c;
        }
        v
    }

    /// The gradient matrix is minus the derivative of the node's contact
    /// force `G^T lambda` spread over the dofs, `lambda = p_n (-n - f n_r)`
    /// at fixed `p_n`, to finite differences, with friction either way.
    #[test]
    fn a_sliding_node_s_gradient_is_its_spread_force_s_derivative() {
        let (p_n, ends) = (1.7, [false, false]);
        for friction in [0.0, 0.3, -0.45] {
            let lambda = |cp: &ContactPoint| p_n * (-cp.normal() - friction * cp.tangent());
            let x = config(ends);
            let (t, cp) = at(&x, ends);
            let mut sys = ContactSystem::default();
            rows(0, &t, &cp, false, lambda(&cp), friction, &mut sys);
            let mut k = [[0.0; 10]; 10];
            for &(r, c, v) in &sys.k {
                k[r][c] += v;
            }
            let h = 1e-6;
            for d in 0..10 {
                let force = |s: f64| {
                    let mut y = x;
                    y[d / 2][d % 2] += s * h;
                    let (t, cp) = at(&y, ends);
                    let mut sys = ContactSystem::default();
                    rows(0, &t, &cp, false, lambda(&cp), friction, &mut sys);
                    dense(&sys.force)
                };
                let (f1, f0) = (force(1.0), force(-1.0));
                for e in 0..10 {
                    let derivative = (f1[e] - f0[e]) / (2.0 * h);
                    let err = (k[e][d] + derivative).abs();
                    assert!(
                        err < 1e-6,
                        "friction {friction} k[{e}][{d}] {} {}",
                        k[e][d],
                        -derivative
                    );
                }
            }
        }
    }

    /// The sliding row is the gradient of the node's normal overlap, and
    /// the gradient matrix the normal force times its Hessian, to finite
    /// differences, with either neighbour mirrored at an end of the target.
    #[test]
    fn a_sliding_node_s_row_and_gradient_are_its_overlap_s_derivatives() {
        for ends in [[false, false], [true, false], [false, true]] {
            let x = config(ends);
            let (t, cp) = at(&x, ends);
            assert!(cp.normal_overlap().abs() < 1e-14);
            assert!((0.0..=1.0).contains(&cp.beta()), "{}", cp.beta());
            assert!(cp.overlap().dot(&cp.tangent()).abs() < 1e-14);
            let p_n = 2.5;
            let mut sys = ContactSystem::default();
            rows(0, &t, &cp, false, -p_n * cp.normal(), 0.0, &mut sys);
            let row = dense(&sys.rows[0].dofs);
            assert!((sys.rows[0].rhs + cp.normal_overlap()).abs() < 1e-15);
            let mut k = [[0.0; 10]; 10];
            for &(r, c, v) in &sys.k {
                k[r][c] += v;
            }
            let h = 1e-6;
            for d in 0..10 {
                let moved = |s: f64| {
                    let mut y = x;
                    y[d / 2][d % 2] += s * h;
                    let (t, cp) = at(&y, ends);
                    let mut sys = ContactSystem::default();
                    rows(0, &t, &cp, false, -p_n * cp.normal(), 0.0, &mut sys);
                    (cp.normal_overlap(), dense(&sys.rows[0].dofs))
                };
                let ((o1, r1), (o0, r0)) = (moved(1.0), moved(-1.0));
                let gradient = (o1 - o0) / (2.0 * h);
                assert!((row[d] - gradient).abs() < 1e-8, "{ends:?} dof {d}");
                for e in 0..10 {
                    let hessian = (r1[e] - r0[e]) / (2.0 * h);
                    let err = (k[e][d] - p_n * hessian).abs();
                    assert!(
                        err < 1e-6,
                        "{ends:?} k[{e}][{d}] {} {}",
                        k[e][d],
                        p_n * hessian
                    );
                }
            }
        }
    }
}
