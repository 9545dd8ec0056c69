//! A mortar pair's decisions, node by node on its own multipliers (the
//! tractions at the node), weighted gap and weighted slip: open, in
//! contact frictionless, sticking, or sliding against its slip (Coulomb,
//! the node's slip measured from the start of the increment). Fresh at an
//! iterate (`decide`), or the linearised problem's (`predict`, `forced`).

use super::memory::{Memory, Node};
use super::{Decided, PairAt};
use crate::contact::Prediction;
use crate::contact::system::{self, ContactSystem, Forced, Iterate, count_flip, count_slip};
use crate::problem::{ContactPair, FrictionRule};
use crate::results::NodeState;

/// A node's traction counts as tension above this fraction of the largest
/// traction of its pair (round-off at a node just touching).
const TENSION_TOLERANCE: f64 = 1e-8;

/// A sliding node's weighted slip may run against its direction by this
/// fraction of its area times the longest side (round-off) and slide on.
const SLIP_TOLERANCE: f64 = 1e-10;

/// A node's decision: its state and, sliding with friction, the sign of
/// its slip along its tangent (its friction acts against it); 0 otherwise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Decision {
    pub state: NodeState,
    pub sign: f64,
}

impl Decision {
    pub const OPEN: Decision = Decision {
        state: NodeState::Open,
        sign: 0.0,
    };

    /// The decision a node's memory holds.
    pub fn of(node: &Node) -> Decision {
        Decision {
            state: node.state,
            sign: node.slip_sign,
        }
    }

    /// The friction of a sliding node along its tangent per unit normal
    /// traction, as its tangential traction reads it: `s mu_d` (0 when it
    /// does not slide with friction). Its tangential traction is `-s mu_d
    /// lambda`.
    pub fn friction(&self, pair: &ContactPair) -> f64 {
        if self.state == NodeState::Slip {
            self.sign * pair.mu_d
        } else {
            0.0
        }
    }

    /// Into a node's memory: its state and slip direction, and whether it
    /// has slid (in this increment, ever) with `friction`.
    pub fn remember(&self, node: &mut Node, friction: bool) {
        node.state = self.state;
        node.slip_sign = self.sign;
        if self.state == NodeState::Slip && friction {
            node.slid = true;
            node.ever_slid = true;
        }
    }

    fn slip(sign: f64) -> Decision {
        Decision {
            state: NodeState::Slip,
            sign,
        }
    }

    const STICK: Decision = Decision {
        state: NodeState::Stick,
        sign: 0.0,
    };
}

/// Each node's decision from its multipliers `[lambda, lambda_t]`, weighted
/// gap and weighted slip:
/// - a node in contact opens when its traction pulls (kept while the
///   iterate settles, counted as pending, with no friction to carry);
/// - an open node closes, as `closing` decides, when its gap weighted by
///   its hat function is negative (or zero, when touching closes); one that
///   shares a side with a node in contact (`enters`) decides so on its
///   weighted gap, its multiplier's conjugate, instead: released there
///   with a weighted gap of zero or more, it stays open (a strip vertex
///   under its side can make its hat-weighted gap negative then);
/// - with friction, a node in contact sticks or slides (`frictional`).
///
/// Changes between open and contact and between stick and slip are
/// counted against the increment's limits, releases logged.
#[allow(clippy::too_many_arguments)]
pub(super) fn decide(
    at: &Iterate,
    pair: &ContactPair,
    mem: &Memory,
    here: &PairAt,
    [lambda, lambda_t]: [&[f64]; 2],
    [flips, slips]: [&mut [usize]; 2],
    log: &mut dyn FnMut(&str),
    out: &mut ContactSystem,
) -> Result<Vec<Decision>, String> {
    let scale = lambda.iter().fold(0.0f64, |a, l| a.max(l.abs()));
    let tension = TENSION_TOLERANCE * scale;
    let mut decisions = Vec::with_capacity(here.gaps.len());
    for (j, gap) in here.gaps.iter().enumerate() {
        let old = Decision::of(&mem.nodes[j]);
        if here.weightless[j] {
            // Set by its side afterwards, not counted.
            decisions.push(old);
            continue;
        }
        let pulls = old.state != NodeState::Open && lambda[j] < -tension;
        let d = if !gap.touched || (pulls && !at.start.settling) {
            Decision::OPEN
        } else if old.state != NodeState::Open {
            // Kept in contact while the iterate settles though it pulls (it
            // can then carry no friction).
            if pulls {
                out.pending += 1;
            }
            frictional(pair, here, &mem.nodes[j], j, [lambda[j], lambda_t[j]])
        } else {
            // Next to the zone, the node's own weighted gap (its
            // multiplier's conjugate) decides; elsewhere the hat-weighted
            // one.
            let g = if enters(here, |k| mem.nodes[k].state, j) {
                gap.value
            } else {
                gap.hat_weighted.0
            };
            if g < 0.0 || (g == 0.0 && at.start.touching) {
                closing(pair, here, &mem.nodes[j], j)
            } else {
                Decision::OPEN
            }
        };
        decisions.push(d);
    }
    if !at.start.settling {
        for j in parting(pair, here, mem, &decisions, [lambda, lambda_t]) {
            decisions[j] = Decision::STICK;
        }
    }
    for (j, &d) in decisions.iter().enumerate() {
        let old = Decision::of(&mem.nodes[j]);
        if d != old {
            out.changes += 1;
            if (d.state == NodeState::Open) != (old.state == NodeState::Open) {
                count_flip(pair, j, flips)?;
            } else {
                count_slip(pair, j, slips)?;
            }
            if d.state == NodeState::Open && old.state != NodeState::Open {
                log(&format!(
                    "pair '{}' node {j}: released (traction {:.3e})",
                    pair.name, lambda[j]
                ));
            }
        }
    }
    Ok(decisions)
}

/// The nodes that stick one iteration more (`system::parting`): of two
/// nodes next to each other on a side, released from sticking in opposite
/// directions, the one less far outside its friction cone (`|lambda_t| /
/// (mu lambda)`). The caller leaves it out while the iterate settles.
fn parting(
    pair: &ContactPair,
    here: &PairAt,
    mem: &Memory,
    decided: &[Decision],
    [lambda, lambda_t]: [&[f64]; 2],
) -> Vec<usize> {
    let excess = |k: usize| {
        let mu = pair.sticking_mu(mem.nodes[k].ever_slid);
        lambda_t[k].abs() / (mu * lambda[k]).max(f64::MIN_POSITIVE)
    };
    system::parting(
        (here.contactor.sides.iter()).flat_map(|side| side.windows(2).map(|w| (w[0], w[1]))),
        |k| mem.nodes[k].state == NodeState::Stick && decided[k].state == NodeState::Slip,
        |k| decided[k].sign,
        excess,
    )
}

/// A node in contact with traction `[lambda, lambda_t]` (frictionless: it
/// slides):
/// - sliding (sign s), it slides on while its weighted slip since the
///   start of the increment runs its way (`s u_j >= 0`, friction against
///   it) and sticks when the slip has turned back;
/// - sticking, it sticks while `|lambda_t| <= mu lambda` (mu: the pair's
///   sticking coefficient, `ContactPair::sticking_mu`) and slides against
///   its tangential traction otherwise.
///
/// Under the experiment's rule (mu_s throughout) a node that slid in an
/// earlier increment but not yet in this one is decided as a sticking one.
/// A node on a symmetry plane sticks, with no friction (`PairAt::
/// on_symmetry_plane`).
fn frictional(
    pair: &ContactPair,
    here: &PairAt,
    node: &Node,
    j: usize,
    [lambda, lambda_t]: [f64; 2],
) -> Decision {
    if !here.friction {
        return Decision::slip(0.0);
    }
    if here.on_symmetry_plane(j) {
        return Decision::STICK;
    }
    let restarts = pair.rule == FrictionRule::AlwaysMuS && !node.slid;
    let u = here.gaps[j].slip.0;
    if node.state == NodeState::Slip && node.slip_sign != 0.0 && !restarts {
        let s = node.slip_sign;
        let tolerance = SLIP_TOLERANCE * here.area[j] * here.h;
        return if s * u >= -tolerance {
            Decision::slip(s)
        } else {
            Decision::STICK
        };
    }
    if lambda_t.abs() <= pair.sticking_mu(node.ever_slid) * lambda.max(0.0) {
        Decision::STICK
    } else {
        Decision::slip(-lambda_t.signum())
    }
}

/// A node that closes: frictionless it slides; with friction it sticks,
/// unless its weighted slip since the start of the increment exceeds mu
/// times its weighted overlap (it arrives sliding), then it slides along
/// that slip.
fn closing(pair: &ContactPair, here: &PairAt, node: &Node, j: usize) -> Decision {
    if !here.friction {
        return Decision::slip(0.0);
    }
    if here.on_symmetry_plane(j) {
        return Decision::STICK;
    }
    let (u, g) = (here.gaps[j].slip.0, here.gaps[j].value);
    if u.abs() > pair.sticking_mu(node.ever_slid) * (-g).max(0.0) {
        Decision::slip(u.signum())
    } else {
        Decision::STICK
    }
}

/// The decision the linearised problem gives node j (`Forced`).
pub(super) fn forced(
    pair: &ContactPair,
    here: &PairAt,
    mem: &Memory,
    j: usize,
    f: Forced,
) -> Decision {
    match f {
        Forced::Open => Decision::OPEN,
        Forced::Close { .. } => closing(pair, here, &mem.nodes[j], j),
        Forced::Stick => Decision::STICK,
        Forced::Slip(s) => Decision::slip(s),
    }
}

/// The nodes the linearised problem decides otherwise than `kept`, from
/// the multipliers fitted to the out-of-balance force it predicts and the
/// weighted gaps and slips it moves the nodes to (linearised at the
/// iterate):
/// - a node in contact whose normal traction times its area pulls by more
///   than the force tolerance opens (not while the iterate settles: it is
///   then kept in contact, with no friction to carry);
/// - an open node whose mean gap where the target covers it (weighted by
///   its hat function) falls below minus the length tolerance closes; one
///   next to a node in contact (`enters`) closes when its weighted gap
///   falls below minus the length tolerance times its area, and on that
///   alone;
/// - with friction, a sticking node whose tangential traction exceeds its
///   capacity slides against it, and a sliding node whose weighted slip
///   turns back by more than the length tolerance (over its area) sticks.
pub(super) fn predict(
    at: &Prediction,
    pair: &ContactPair,
    mem: &Memory,
    kept: &Decided,
) -> Vec<(usize, Forced)> {
    let here = &kept.at;
    let (lambda, lambda_t) = here.multipliers(&kept.decisions, at.force_new);
    let [force_tol, length_tol] = at.tolerance;
    let moved = |gradient: &[(usize, f64)]| -> f64 {
        (gradient.iter())
            .map(|&(d, v)| v * (at.u_new[d] - at.u_now[d]))
            .sum()
    };
    let mut switched = Vec::new();
    for (j, gap) in here.gaps.iter().enumerate() {
        if here.weightless[j] || !gap.touched {
            continue;
        }
        let (a, d) = (here.area[j], kept.decisions[j]);
        if d.state == NodeState::Open {
            // The mean gap over the covered part, linearised as a ratio:
            // as the cover of a node far from the target shrinks, its
            // hat-weighted gap and its weight vanish together, and a
            // linearised hat-weighted gap alone crosses zero though the
            // gap there stays open.
            let ((h, dh), (w, dw)) = (&gap.hat_weighted, &gap.covered);
            if *w <= 0.0 {
                continue;
            }
            if enters(here, |k| kept.decisions[k].state, j) {
                let weighted = gap.value + moved(&gap.gradient);
                if weighted < -length_tol * a {
                    let overlap = -weighted / a;
                    switched.push((j, Forced::Close { j: 0, overlap }));
                }
                continue;
            }
            let mean = h / w;
            let overlap = -(mean + (moved(dh) - mean * moved(dw)) / w);
            if overlap > length_tol {
                switched.push((j, Forced::Close { j: 0, overlap }));
            }
            continue;
        }
        let pulls = lambda[j] * a < -force_tol;
        if pulls && !at.settling {
            switched.push((j, Forced::Open));
            continue;
        }
        if !here.friction {
            continue;
        }
        match d.state {
            NodeState::Stick => {
                let mu = pair.sticking_mu(mem.nodes[j].ever_slid);
                if lambda_t[j].abs() > mu * lambda[j].max(0.0) {
                    switched.push((j, Forced::Slip(-lambda_t[j].signum())));
                }
            }
            // A node kept in contact while the iterate settles though it
            // pulls has no friction to carry: it slides on (sticking again,
            // it slid at once on its traction, and six such nodes switched
            // back and forth at every inner solve of Cattaneo-Mindlin's
            // first iteration).
            _ if d.sign != 0.0 && !pulls => {
                let u = gap.slip.0 + moved(&gap.slip.1);
                if d.sign * u < -length_tol * a {
                    switched.push((j, Forced::Stick));
                }
            }
            _ => {}
        }
    }
    switched
}

/// Whether open node j is where the contact zone grows: it shares a side
/// with a node in contact (`state` of each) and the target covers some of
/// its sides. Such a node closes on its weighted gap alone, the quantity
/// its condition holds at zero, so that it enters with no traction and the
/// forces run on continuously as the zone's edge passes it. On its hat
/// function's gap alone it closed late, already entered by up to 0.006
/// (a fortieth of a side) on the ironing block, and took its traction at
/// once: a force jump of 0.3 % every time the ring's leading edge passed a
/// node. On either gap, a node released with a weighted gap of zero or
/// more over a target vertex showed a negative hat-weighted one and
/// closed again at every iteration. Elsewhere the hat function's gap
/// decides: the dual basis goes
/// negative where the gap grows across a side (a flank rising away, the
/// far side of a quadratic side), so a node far from the contact zone may
/// show a negative weighted gap though clear of the target.
fn enters(here: &PairAt, state: impl Fn(usize) -> NodeState, j: usize) -> bool {
    let next_to_contact = (here.contactor.on[j].iter())
        .flat_map(|&(side, _)| &here.contactor.sides[side])
        .any(|&k| k != j && state(k) != NodeState::Open);
    next_to_contact && here.gaps[j].covered.0 > 0.0
}
