//! What a mortar pair's decisions give Newton and the user: the rows of
//! its nodes in contact, the contact forces with their tangent, and the
//! reported results.

use super::decide::Decision;
use super::{Gradient, PairAt};
use crate::contact::Entries;
use crate::contact::report::{Report, node_frame};
use crate::contact::system::{ContactSystem, Row};
use crate::problem::ContactPair;
use crate::results::{NodeState, PairResult};
use nalgebra::Vector2;
use std::collections::BTreeMap;

/// The rows of each node in contact, divided by the node's area so that
/// they read in lengths (their multipliers forces) as node-to-segment
/// rows do: its weighted gap closed to first order, `grad g_j du = -g_j`;
/// sticking, its weighted slip held as well, `grad u_j du = -u_j` (not on
/// a symmetry plane, where the drivers hold it and the friction is zero:
/// `PairAt::on_symmetry_plane`); sliding
/// with friction, its multiplier's column `grad g_j - s mu_d grad u_j`
/// (the friction its normal traction brings along).
pub(super) fn add_rows(
    pair: &ContactPair,
    here: &PairAt,
    decisions: &[Decision],
    out: &mut ContactSystem,
) {
    let scaled =
        |g: &[(usize, f64)], a: f64| -> Gradient { g.iter().map(|&(d, v)| (d, v / a)).collect() };
    for (j, gap) in here.gaps.iter().enumerate() {
        let d = decisions[j];
        if d.state == NodeState::Open || !gap.touched {
            continue;
        }
        let a = here.area[j];
        let first = out.rows.len();
        let friction = d.friction(pair);
        let column = if friction != 0.0 {
            let mut sum: BTreeMap<usize, f64> = gap.gradient.iter().copied().collect();
            for &(dof, v) in &gap.slip.1 {
                *sum.entry(dof).or_default() -= friction * v;
            }
            let sum: Gradient = sum.into_iter().collect();
            Entries::from_slice(&scaled(&sum, a))
        } else {
            Entries::default()
        };
        out.rows.push(Row {
            dofs: Entries::from_slice(&scaled(&gap.gradient, a)),
            rhs: -gap.value / a,
            column,
        });
        out.max_overlap = out.max_overlap.max((gap.value / a).abs());
        if here.friction && d.state == NodeState::Stick && !here.on_symmetry_plane(j) {
            out.rows.push(Row {
                dofs: Entries::from_slice(&scaled(&gap.slip.1, a)),
                rhs: -gap.slip.0 / a,
                column: Entries::default(),
            });
            out.max_overlap = out.max_overlap.max((gap.slip.0 / a).abs());
        }
        out.groups.push((pair.contactor[j], first..out.rows.len()));
    }
}

/// The contact forces `sum lambda_j grad g_j + lambda_t,j grad u_j` into
/// `out.force`; returns the forces per dof.
pub(super) fn add_forces(
    here: &PairAt,
    [lambda, lambda_t]: [&[f64]; 2],
    out: &mut ContactSystem,
) -> BTreeMap<usize, f64> {
    let mut force: BTreeMap<usize, f64> = BTreeMap::new();
    for (j, gap) in here.gaps.iter().enumerate() {
        for (l, gradient) in [(lambda[j], &gap.gradient), (lambda_t[j], &gap.slip.1)] {
            if l != 0.0 {
                for &(d, v) in gradient {
                    *force.entry(d).or_default() += l * v;
                }
            }
        }
    }
    out.force.extend(force.iter().map(|(&d, &f)| (d, f)));
    force
}

/// The contact forces' tangent `-sum lambda_j hess g_j + lambda_t,j hess
/// u_j` into `k`, from the side pairs' Hessians (`PairAt::second_order`,
/// made on the first call).
pub(super) fn add_tangent(
    here: &PairAt,
    [lambda, lambda_t]: [&[f64]; 2],
    k: &mut Vec<(usize, usize, f64)>,
) {
    // The weighted slip's own term (`slip_from`); the parts hold the rest
    // of its Hessian, with the opposite sign.
    for (gap, &l) in here.gaps.iter().zip(lambda_t) {
        if l != 0.0 {
            k.extend(gap.slip_hessian.iter().map(|&(a, b, v)| (a, b, -l * v)));
        }
    }
    if lambda.iter().chain(lambda_t).all(|&l| l == 0.0) {
        return;
    }
    for part in here.second_order() {
        let count = part.dofs.len();
        let mut h = vec![0.0; count * count];
        let mut any = false;
        for (i, (k, _, _, hessian)) in part.gaps.iter().enumerate() {
            let (l, lt) = (lambda[*k], lambda_t[*k]);
            if l != 0.0 {
                any = true;
                for (hi, v) in h.iter_mut().zip(hessian) {
                    *hi -= l * v;
                }
            }
            if lt != 0.0 {
                any = true;
                for (hi, v) in h.iter_mut().zip(&part.slips[i].2) {
                    *hi += lt * v;
                }
            }
        }
        if !any {
            continue;
        }
        for (a, &da) in part.dofs.iter().enumerate() {
            for (b, &db) in part.dofs.iter().enumerate() {
                let v = h[a * count + b];
                if v != 0.0 {
                    k.push((da, db, v));
                }
            }
        }
    }
}

/// The pair's results: per node its state, normal and tangential forces
/// (its tractions times its area) and tractions; the resultants of the
/// contact forces on the contactor, normal (compression positive) and
/// tangential parts along each node's frame.
pub(super) fn report(
    pair: &ContactPair,
    here: &PairAt,
    decisions: &[Decision],
    [lambda, lambda_t]: [&[f64]; 2],
    force: &BTreeMap<usize, f64>,
) -> PairResult {
    let (contactor, x, area) = (&here.contactor, &here.x, &here.area);
    let xv: Vec<Vector2<f64>> = x.iter().map(|p| Vector2::new(p[0], p[1])).collect();
    let mut report = Report::new(x.len());
    let mut tn = vec![0.0; x.len()];
    let mut tt = vec![0.0; x.len()];
    for (j, &n) in contactor.nodes.iter().enumerate() {
        let f = Vector2::new(
            force.get(&(2 * n)).copied().unwrap_or(0.0),
            force.get(&(2 * n + 1)).copied().unwrap_or(0.0),
        );
        let (tau, nu) = node_frame(&xv, pair.closed, j);
        let result = &mut report.result;
        result.fx += f.x;
        result.fy += f.y;
        result.fn_ += f.dot(&nu);
        result.ft += f.dot(&tau);
        let state = decisions[j].state;
        if state != NodeState::Open {
            (tn[j], tt[j]) = (lambda[j], lambda_t[j]);
        }
        report.node(xv[j], state, [lambda[j] * area[j], lambda_t[j] * area[j]]);
    }
    // A node of no weight (an 8-node side's corner on the axis) reports
    // the tractions of the node whose state it takes. The dual basis
    // field's value there, sum_k lambda_k Phi_k, is no traction: with the
    // side's mid-side node alone in contact it is -lambda_mid (a sphere on
    // a block whose contact zone lay within the first side: the axis node
    // reported -229 against its neighbour's +229).
    for j in (0..x.len()).filter(|&j| here.weightless[j] && decisions[j].state != NodeState::Open) {
        if let Some(k) = here.followed(j, decisions) {
            (tn[j], tt[j]) = (lambda[k], lambda_t[k]);
        }
    }
    let mut result = report.result;
    result.nodes.tn = tn;
    result.nodes.tt = tt;
    result
}
