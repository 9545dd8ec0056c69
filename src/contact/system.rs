//! What a contact formulation gives Newton at an iterate, and what it is
//! given: the iterate (`Iterate`, `Start`), the contact part of the system
//! of Eq. (18) (`ContactSystem`: forces, gradient entries, constraint rows,
//! reported results), the nodes an inner solve switches (`Switched`,
//! `Forced`), the start of the increment (`Start`, `StartCache`), and the
//! per-increment change counters that fail an oscillating increment.

use super::search::RigidSegments;
use super::{Kept, PairMemory, StartData};
use crate::assembly::PRESCRIBED;
use crate::problem::{ContactPair, Problem};
use crate::results::{NodeState, PairResult};
use nalgebra::Vector2;

/// Times a node may change between open and closed within one increment
/// before the increment is declared oscillating.
pub(super) const MAX_FLIPS: usize = 6;

/// One row of the constraint block of Eq. (18): `sum c_q du_q = rhs`, with
/// the prescribed dofs kept as dofs (the caller moves known increments to
/// the right-hand side).
#[derive(Clone, Debug)]
pub struct Row {
    pub dofs: Entries,
    pub rhs: f64,
    /// The multiplier's column in the displacement rows when it differs
    /// from the row (a sliding node's friction); empty: the row itself.
    pub column: Entries,
}

/// A row's entries (dof, coefficient): held in place for a node-to-segment
/// row, which acts on its node and at most a target segment's two nodes
/// (the contact system is rebuilt at every inner solve, and two
/// allocations per row were a tenth of that); a longer row (a mortar
/// row's weighted gap spans neighbouring nodes on both surfaces) is held
/// on the heap.
#[derive(Clone, Debug, Default)]
pub struct Entries {
    pub(crate) len: usize,
    pub(crate) at: [(usize, f64); Entries::MAX],
    long: Vec<(usize, f64)>,
}

impl Entries {
    pub const MAX: usize = 6;

    /// The entries of `list`.
    pub fn from_slice(list: &[(usize, f64)]) -> Self {
        let mut e = Entries::default();
        if list.len() > Self::MAX {
            e.long = list.to_vec();
        } else {
            e.at[..list.len()].copy_from_slice(list);
        }
        e.len = list.len();
        e
    }
}

impl std::ops::Deref for Entries {
    type Target = [(usize, f64)];
    fn deref(&self) -> &[(usize, f64)] {
        if self.len > Self::MAX {
            &self.long
        } else {
            &self.at[..self.len]
        }
    }
}

impl<'a> IntoIterator for &'a Entries {
    type Item = &'a (usize, f64);
    type IntoIter = std::slice::Iter<'a, (usize, f64)>;
    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

impl Row {
    /// The direction the row's multiplier acts in on the displacement rows:
    /// its column (a sliding node's friction), or the row itself.
    pub fn acting(&self) -> &[(usize, f64)] {
        if self.column.is_empty() {
            &self.dofs
        } else {
            &self.column
        }
    }
}

/// The contact part of the system for one iteration.
#[derive(Clone, Debug, Default)]
pub struct ContactSystem {
    /// `G^T lambda` per dof: the contact forces, added to the external load.
    pub force: Vec<(usize, f64)>,
    /// Sliding gradient matrix entries (dof, dof, value), added to K; with
    /// those `deferred` (`complete_tangent`).
    pub k: Vec<(usize, usize, f64)>,
    /// Tangent entries a formulation forms only where a solve needs them
    /// (a converged iterate's are never formed): the place in `k` they take
    /// and the pair whose kept decisions form them (`Kept::add_tangent`).
    pub(crate) deferred: Vec<(usize, usize)>,
    pub rows: Vec<Row>,
    /// Per constrained node: its mesh node and the range of its rows.
    pub groups: Vec<(usize, std::ops::Range<usize>)>,
    /// Nodes whose state changed in this update.
    pub changes: usize,
    /// Nodes kept in contact though their force pulls, after the predictor
    /// (`Start::settling`): the increment has not converged while any is.
    pub pending: usize,
    /// Largest overlap (penetration or tangential drift) of a closed node.
    pub max_overlap: f64,
    pub pairs: Vec<PairResult>,
    /// Per rigid target: force on it [Rx, Ry] and moment Mz about its moved
    /// reference point.
    pub rigid: Vec<[f64; 3]>,
    /// Per pair, what its formulation keeps of the decisions the rows were
    /// built from: `predict` and `update` with `keep` start from them.
    pub(crate) kept: Vec<Kept>,
}

impl ContactSystem {
    /// Defers the tangent entries of pair `p` that its kept decisions form
    /// to `complete_tangent`, at the place in `k` they would take now.
    pub(crate) fn defer_tangent(&mut self, p: usize) {
        self.deferred.push((self.k.len(), p));
    }

    /// Forms the deferred tangent entries into `k`, each at its place: the
    /// entries' order is the order in which their sums are taken, so the
    /// tangent is the one formed at once, bit for bit.
    pub fn complete_tangent(&mut self) {
        if self.deferred.is_empty() {
            return;
        }
        let formed = std::mem::take(&mut self.k);
        let mut from = 0;
        for (at, p) in std::mem::take(&mut self.deferred) {
            self.k.extend_from_slice(&formed[from..at]);
            self.kept[p].add_tangent(&mut self.k);
            from = at;
        }
        self.k.extend_from_slice(&formed[from..]);
    }
}

/// Per pair, the nodes the linearised problem decides otherwise than the
/// iterate did (`predict`), with the state each is given.
#[derive(Clone, Debug, Default)]
pub struct Switched(pub(super) Vec<Vec<(usize, Forced)>>);

impl Switched {
    /// How many nodes change.
    pub fn count(&self) -> usize {
        self.0.iter().map(Vec::len).sum()
    }

    /// The (pair, contactor node) of every change.
    pub fn nodes(&self) -> Vec<(usize, usize)> {
        (self.0.iter().enumerate())
            .flat_map(|(p, s)| s.iter().map(move |&(k, _)| (p, k)))
            .collect()
    }

    /// How many nodes open, close, and change between stick and slip.
    pub fn counts(&self) -> [usize; 3] {
        let mut c = [0; 3];
        for &(_, f) in self.0.iter().flatten() {
            c[match f {
                Forced::Open => 0,
                Forced::Close { .. } => 1,
                _ => 2,
            }] += 1;
        }
        c
    }

    /// Drops the opening or closing of a node that has opened or closed
    /// `limit` times in the earlier solves of the same iteration (`flips`,
    /// per pair and node, updated), so that they cannot cycle.
    pub fn limit_flips(&mut self, flips: &mut Vec<Vec<usize>>, limit: usize) {
        flips.resize_with(self.0.len(), Vec::new);
        for (changes, done) in self.0.iter_mut().zip(flips.iter_mut()) {
            changes.retain(|&(k, f)| {
                let flip = matches!(f, Forced::Open | Forced::Close { .. });
                if !flip {
                    return true;
                }
                if done.len() <= k {
                    done.resize(k + 1, 0);
                }
                done[k] += 1;
                done[k] <= limit
            });
        }
    }
}

impl ContactSystem {
    pub fn neqc(&self) -> usize {
        self.rows.len()
    }
}

/// Per-increment counters (flip detection).
#[derive(Clone, Debug, Default)]
pub struct Flips {
    /// Per pair and node: changes between open and closed.
    pub(super) counts: Vec<Vec<usize>>,
    /// Per pair and node: changes between stick and slip (nodal decisions).
    pub(super) slips: Vec<Vec<usize>>,
}

impl Flips {
    /// Counters for every node of `memory`, zero where they were not kept.
    pub(super) fn fit(&mut self, memory: &[PairMemory]) {
        if self.counts.len() != memory.len() {
            self.counts = memory.iter().map(|m| vec![0; m.nodes()]).collect();
            self.slips = self.counts.clone();
        }
    }
}

/// A state a node is given rather than decided from its forces: the
/// linearised problem's own decisions (`Formulation::predict`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Forced {
    Stick,
    Slip(f64),
    /// Released: the linearised problem pulls it off the target.
    Open,
    /// Closed on target segment `j`: the linearised problem moves it into
    /// the target by `overlap`.
    Close {
        j: usize,
        overlap: f64,
    },
}

/// A hash of every node's state as it would be after `switched`: the
/// inner solves of an iteration stop when they meet a set of states again.
pub fn state_key(memory: &[PairMemory], switched: &Switched) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    for (p, m) in memory.iter().enumerate() {
        for k in 0..m.nodes() {
            let forced = switched
                .0
                .get(p)
                .and_then(|s| s.iter().find(|(j, _)| *j == k));
            let (state, sign) = match forced {
                Some((_, Forced::Stick)) => (NodeState::Stick as u64, 0.0),
                Some((_, Forced::Slip(s))) => (NodeState::Slip as u64, *s),
                Some((_, Forced::Open)) => (NodeState::Open as u64, 0.0),
                Some((_, Forced::Close { j, .. })) => (3 + *j as u64, 0.0),
                None => (m.state(k) as u64, m.slip_sign(k)),
            };
            (state, sign.to_bits()).hash(&mut h);
        }
    }
    h.finish()
}

/// One more change of node `k` between two states (`what`: "open and
/// contact", "stick and slip") in this increment: past `max` the increment
/// fails, naming the node.
pub(super) fn count_change(
    pair: &ContactPair,
    k: usize,
    counts: &mut [usize],
    max: usize,
    what: &str,
) -> Result<(), String> {
    counts[k] += 1;
    if counts[k] > max {
        return Err(format!(
            "pair '{}' node {k} (mesh node {}) alternates between {what} \
             ({} changes in this increment)",
            pair.name, pair.contactor[k], counts[k]
        ));
    }
    Ok(())
}

/// Times one node may change between stick and slip (or its slip
/// direction) within an increment before the increment is declared
/// oscillating (fail fast; the caller bisects).
const MAX_SLIPS: usize = 2 * MAX_FLIPS;

/// The nodes that stick one iteration more, as both formulations' stick /
/// slip decisions have it: of two neighbours (`pairs`) that stuck and are
/// both released (`released`), sliding in opposite directions (`sign`),
/// the one less far outside its friction cone (`excess`, the tangential
/// force over its capacity). Two such neighbours are the last of a stick
/// zone, round the point where the slip changes sign; released together,
/// the slip's zero moved past them and back at alternate iterations
/// without end (a block of nu = 0.45 pressed onto one of nu = 0.07 with
/// friction: the press failed at its first increment under either
/// formulation). Held, the one left decides alone at the next iteration,
/// so a pair that must both slide costs one iteration more. A node held
/// for one pair is not released by the next. The callers leave it out
/// while the iterate settles: a strip held on the capstan's drum by its end
/// forces alone swings on and off the drum in its first iterations, and
/// holding nodes there kept it from the state its fallback converges to
/// (`tests/force_driver.rs`).
pub(super) fn parting(
    pairs: impl Iterator<Item = (usize, usize)>,
    released: impl Fn(usize) -> bool,
    sign: impl Fn(usize) -> f64,
    excess: impl Fn(usize) -> f64,
) -> Vec<usize> {
    let mut held: Vec<usize> = Vec::new();
    for (k, l) in pairs {
        if k == l || !released(k) || !released(l) || sign(k) * sign(l) >= 0.0 {
            continue;
        }
        if held.contains(&k) || held.contains(&l) {
            continue;
        }
        held.push(if excess(k) < excess(l) { k } else { l });
    }
    held
}

/// One more change of node `k` between stick and slip (`MAX_SLIPS`).
pub(super) fn count_slip(pair: &ContactPair, k: usize, slips: &mut [usize]) -> Result<(), String> {
    count_change(pair, k, slips, MAX_SLIPS, "stick and slip")
}

/// One more change of node `k` between open and contact (`MAX_FLIPS`).
pub(super) fn count_flip(pair: &ContactPair, k: usize, flips: &mut [usize]) -> Result<(), String> {
    count_change(pair, k, flips, MAX_FLIPS, "open and contact")
}

/// The iterate a pair's contact is updated at: displacements, rigid target
/// poses, out-of-balance forces (F_int - R_ext, contact excluded), the
/// dof-to-equation map, and the state the increment started from.
pub(crate) struct Iterate<'a> {
    pub(super) problem: &'a Problem,
    /// The rigid targets' segments kept per pose (`search::RigidSegments`).
    pub(super) targets: &'a RigidSegments,
    pub(super) poses: &'a [[f64; 3]],
    pub(super) u: &'a [f64],
    pub(super) r: &'a [f64],
    pub(super) eq: &'a [u32],
    /// The converged state the increment starts from.
    pub(super) start: &'a Start<'a>,
}

impl Iterate<'_> {
    /// The out-of-balance force at each contactor node of `pair`, a
    /// prescribed component taken as zero: there it is the driver's
    /// reaction, not contact (a symmetry plane).
    pub(super) fn contactor_forces(&self, pair: &ContactPair) -> Vec<Vector2<f64>> {
        let component = |d: usize| {
            if self.eq[d] == PRESCRIBED {
                0.0
            } else {
                self.r[d]
            }
        };
        (pair.contactor.iter())
            .map(|&n| Vector2::new(component(2 * n), component(2 * n + 1)))
            .collect()
    }
}

/// The converged state an increment starts from: what the nodal decisions
/// measure slips against.
pub struct Start<'a> {
    /// Displacements at the start of the increment.
    pub u: &'a [f64],
    /// Rigid target poses at the start of the increment.
    pub poses: &'a [[f64; 3]],
    /// The iterate's geometry has not settled: the first after the
    /// increment's predictor (its prescribed and rigid target motion carried
    /// through the tangent), or one reached by a correction still large
    /// against the increment's first. Its nodes in contact are not released
    /// on its forces (see `nodal::decide`).
    pub settling: bool,
    /// Free nodes that touch a target (overlap exactly 0) close as well as
    /// penetrated ones (`Solver::advance`'s retry of an increment whose
    /// first solve found a body held by nothing).
    pub touching: bool,
    /// What a formulation derives from the start alone, kept for the
    /// increment's other iterates (`StartCache`).
    pub cache: &'a StartCache,
}

/// Per pair (by its index), what its formulation computes from an
/// increment's start alone (mortar's couplings where the increment
/// started), with the key it was computed from (the start's positions),
/// which the formulation compares: taken again while the key is equal,
/// made anew otherwise. Keyed by its content, it needs no invalidation: a
/// rolled-back, bisected or restored increment whose start differs makes
/// its own.
#[derive(Default)]
pub struct StartCache(std::sync::Mutex<Vec<Option<StartData>>>);

impl StartCache {
    fn lock(&self) -> std::sync::MutexGuard<'_, Vec<Option<StartData>>> {
        self.0.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Pair `p`'s entry, if it has one.
    pub(super) fn get(&self, p: usize) -> Option<StartData> {
        self.lock().get(p).cloned().flatten()
    }

    /// Pair `p`'s entry made anew.
    pub(super) fn set(&self, p: usize, data: StartData) {
        let mut kept = self.lock();
        if kept.len() <= p {
            kept.resize(p + 1, None);
        }
        kept[p] = Some(data);
    }
}

/// Whether any dof of `rows` is prescribed in `eq`.
pub fn touches_prescribed(rows: &[Row], eq: &[u32]) -> bool {
    rows.iter()
        .any(|r| r.dofs.iter().any(|&(d, _)| eq[d] == PRESCRIBED))
}
