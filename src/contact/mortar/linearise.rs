//! The exact linearisation of a mortar pair's contact conditions at a
//! converged state (`contact::sensitivity` states what it is for), from the
//! rows, forces and tangent of Newton's last system there (rebuilt from
//! what `update` kept): per node in contact its weighted gap held, and
//! while it sticks its weighted slip held, measured as Newton measured it,
//! from where the increment started (`State::step_start_u`), not from the
//! converged state; a sliding node's friction in its multiplier's column;
//! the contact forces' change at fixed multipliers (their Hessians); and
//! each contactor node's force and frame (turning with its chords) for the
//! resultants' changes.

use super::decide::Decision;
use super::rows::{add_forces, add_rows, add_tangent};
use super::{Decided, PairAt};
use crate::contact::report::node_frame;
use crate::contact::sensitivity::{At, Linearised, NodeForce, Row, Turn};
use crate::contact::system::ContactSystem;
use crate::problem::ContactPair;
use nalgebra::Vector2;

/// Pair `p`'s conditions from what its last update kept (`kept`).
pub(super) fn linearise_pair(
    _at: &At,
    (p, pair): (usize, &ContactPair),
    kept: &Decided,
    out: &mut Linearised,
) {
    let here = &kept.at;
    // The rows and forces as Newton's last system has them.
    let mut system = ContactSystem::default();
    add_rows(pair, here, &kept.decisions, &mut system);
    let force = add_forces(here, [&kept.lambda, &kept.lambda_t], &mut system);
    add_tangent(here, [&kept.lambda, &kept.lambda_t], &mut system.k);
    for row in &system.rows {
        let dofs: Vec<(usize, f64)> = row.dofs.to_vec();
        out.rows.push(Row {
            column: row.acting().to_vec(),
            dofs,
            poses: Vec::new(),
        });
    }
    // `system.k` is the tangent, minus the forces' derivative.
    out.k.extend(system.k.iter().map(|&(a, b, v)| (a, b, -v)));
    nodes(p, pair, here, &kept.decisions, &force, out);
}

/// Every contactor node's force and the frame the pair's resultants read
/// it in (`rows::report`: Fn along the inward normal, Ft along the
/// tangent), with how the frame turns.
fn nodes(
    p: usize,
    pair: &ContactPair,
    here: &PairAt,
    _decisions: &[Decision],
    force: &std::collections::BTreeMap<usize, f64>,
    out: &mut Linearised,
) {
    let x: Vec<Vector2<f64>> = here.x.iter().map(|q| Vector2::new(q[0], q[1])).collect();
    let m = x.len();
    let nodes = &pair.contactor;
    for (k, &n) in nodes.iter().enumerate() {
        let f = Vector2::new(
            force.get(&(2 * n)).copied().unwrap_or(0.0),
            force.get(&(2 * n + 1)).copied().unwrap_or(0.0),
        );
        let (tau, nu) = node_frame(&x, pair.closed, k);
        // The chords node_frame averages: to the next node and from the
        // previous one, where the chain has them.
        let chord = |a: usize, b: usize| {
            let d = x[b] - x[a];
            let length = d.norm();
            (
                nodes[a],
                nodes[b],
                Vector2::new(-d.y, d.x) / (length * length),
            )
        };
        let next = (k + 1 < m || pair.closed).then(|| chord(k, (k + 1) % m));
        let previous = (k > 0 || pair.closed).then(|| chord((k + m - 1) % m, k));
        let count = f64::from(u8::from(next.is_some()) + u8::from(previous.is_some()));
        let scaled = |c: Option<(usize, usize, Vector2<f64>)>| c.map(|(a, b, w)| (a, b, w / count));
        out.nodes.push(NodeForce {
            pair: p,
            node: n,
            force: f,
            normal: -nu,
            tangent: -tau,
            point: x[k],
            turn: Turn::Chords {
                chords: [scaled(next), scaled(previous)],
            },
            held: false,
            reference: [0.0; 2],
            multipliers: true,
        });
    }
}
