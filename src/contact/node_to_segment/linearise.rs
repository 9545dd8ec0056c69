//! The exact linearisation of a converged state's contact conditions under
//! the nodal decisions (`contact::sensitivity` states the conditions).

use super::decision::Decision;
use crate::assembly::PRESCRIBED;
use crate::contact::search::rigid_reference;
use crate::contact::segment::ContactPoint;
use crate::contact::sensitivity::{At, Linearised, NodeForce, Row, Turn, material_velocity};
use crate::problem::{ContactPair, Target};
use crate::results::NodeState;
use nalgebra::Vector2;

/// One node in contact as `G` sees it: the node and the target segment's
/// ends with their weights, how the target turns, a rigid target's moved
/// reference point and the contact point.
struct Contact {
    ends: Vec<(usize, f64)>,
    turn: Turn,
    reference: [f64; 2],
    point: Vector2<f64>,
}

impl Contact {
    /// `G^T v` over the dofs.
    fn spread(&self, v: Vector2<f64>) -> Vec<(usize, f64)> {
        let mut e = Vec::with_capacity(6);
        for &(m, w) in &self.ends {
            e.push((2 * m, w * v.x));
            e.push((2 * m + 1, w * v.y));
        }
        e
    }

    /// The condition's terms in a rigid target's pose (none for a body).
    fn rigid_poses(&self, v: Vector2<f64>) -> Vec<(usize, usize, f64)> {
        match self.turn {
            Turn::Rigid { rigid } => {
                let w = material_velocity(self.point, self.reference);
                (0..3).map(|c| (rigid, c, -v.dot(&w[c]))).collect()
            }
            Turn::Segment { .. } | Turn::Chords { .. } => Vec::new(),
        }
    }
}

/// Pair `p`'s conditions from its decisions at the converged state `at`.
pub(super) fn linearise_pair(
    at: &At,
    (p, pair): (usize, &ContactPair),
    decisions: &[Decision],
    out: &mut Linearised,
) -> Result<(), String> {
    let (problem, poses, r, eq) = (at.problem, at.poses, at.r, at.eq);
    let component = |d: usize| if eq[d] == PRESCRIBED { 0.0 } else { r[d] };
    for (k, d) in decisions.iter().enumerate() {
        let Some((j, cp)) = d.point.as_ref() else {
            continue;
        };
        let n = pair.contactor[k];
        let seg = cp.segment();
        let (n_s, n_r, length, beta) = (seg.normal(), seg.tangent(), seg.length(), cp.beta());
        let (target, turn, reference) = match &pair.target {
            Target::Body { segments, .. } => {
                let [a, b] = *segments.get(*j).ok_or_else(|| {
                    format!("contact pair '{}': no target segment {j}", pair.name)
                })?;
                (Some([a, b]), Turn::Segment { a, b, length }, [0.0; 2])
            }
            Target::Rigid(ri) => {
                let reference = rigid_reference(problem, *ri, poses[*ri]);
                (None, Turn::Rigid { rigid: *ri }, reference)
            }
        };
        let held = d.state == NodeState::Stick || d.corner;
        out.nodes.push(NodeForce {
            pair: p,
            node: n,
            force: Vector2::new(component(2 * n), component(2 * n + 1)),
            normal: n_s,
            tangent: n_r,
            point: cp.point(),
            turn,
            held,
            reference,
            multipliers: false,
        });
        let mut ends = vec![(n, 1.0)];
        if let Some([a, b]) = target {
            ends.push((a, -(1.0 - beta)));
            ends.push((b, -beta));
        }
        let contact = Contact {
            ends,
            turn,
            reference,
            point: cp.point(),
        };
        if held {
            held_rows(&contact, out);
        } else {
            sliding_terms(&contact, pair, d, cp, target, out);
        }
    }
    Ok(())
}

/// A held node: `x_k - x_C = 0` in both directions; lambda on the node,
/// its reaction on A and B (Eqs. 19-21): `G^T lambda`.
fn held_rows(contact: &Contact, out: &mut Linearised) {
    for e in [Vector2::new(1.0, 0.0), Vector2::new(0.0, 1.0)] {
        let dofs = contact.spread(e);
        out.rows.push(Row {
            column: dofs.clone(),
            dofs,
            poses: contact.rigid_poses(e),
        });
    }
}

/// A sliding node: the normal gap, the friction that follows its normal
/// force P, and the change of its force at fixed P as the segment turns and
/// its contact point moves along it.
fn sliding_terms(
    contact: &Contact,
    pair: &ContactPair,
    d: &Decision,
    cp: &ContactPoint,
    target: Option<[usize; 2]>,
    out: &mut Linearised,
) {
    let seg = cp.segment();
    let (n_s, n_r, length) = (seg.normal(), seg.tangent(), seg.length());
    let phi = if pair.mu_s == 0.0 && pair.mu_d == 0.0 {
        0.0
    } else {
        d.slip_sign * pair.mu_d
    };
    let c = n_s + phi * n_r;
    let (p_n, lambda) = (d.p_n, d.lambda);
    out.rows.push(Row {
        dofs: contact.spread(n_s),
        poses: contact.rigid_poses(n_s),
        column: contact.spread(-c),
    });
    // d lambda at fixed P as the segment turns: -P (d n_s + phi d n_r)
    // = P omega (n_r - phi n_s).
    let w = p_n * (n_r - phi * n_s);
    match (target, contact.turn) {
        (Some([a, b]), _) => {
            // omega and d beta (Eq. 14, at zero overlap) over the six dofs.
            let mut omega = [(2 * b, n_s.x), (2 * b + 1, n_s.y)].to_vec();
            omega.extend([(2 * a, -n_s.x), (2 * a + 1, -n_s.y)]);
            for e in &mut omega {
                e.1 /= length;
            }
            let raw = seg.project(cp.point() + cp.overlap()).beta();
            let dbeta = if (0.0..=1.0).contains(&raw) {
                contact.spread(n_r / length)
            } else {
                Vec::new()
            };
            for &(m, g) in &contact.ends {
                for c in 0..2 {
                    for &(q, o) in &omega {
                        out.k.push((2 * m + c, q, g * w[c] * o));
                    }
                }
            }
            // G(beta)^T lambda: A carries -(1 - beta) lambda, B -beta lambda.
            for &(q, v) in &dbeta {
                for c in 0..2 {
                    out.k.push((2 * a + c, q, lambda[c] * v));
                    out.k.push((2 * b + c, q, -lambda[c] * v));
                }
            }
        }
        (None, Turn::Rigid { rigid }) => {
            for c in 0..2 {
                out.pose.push((2 * contact.ends[0].0 + c, rigid, 2, w[c]));
            }
        }
        (None, Turn::Segment { .. } | Turn::Chords { .. }) => {}
    }
}
