//! Contact pairs inside a Newton iteration (Sections 2-3 of the paper): the
//! contact forces from the out-of-balance forces (traction recovery and the
//! segment decisions of `traction`), the node states, the contact search
//! (bounding boxes, projection, segment switching, release and re-contact),
//! and the rows of Eq. (18) each constrained node adds (`segment`).
//!
//! One call of [`update`] per iteration turns the state after iteration
//! (i-1) into the contact part of the system for iteration (i).

use super::segment::{ContactPoint, Segment};
use super::traction::{self, Geometry, SegmentState};
use crate::assembly::PRESCRIBED;
use crate::problem::{AnalysisKind, ContactPair, Decisions, Kinematics, Problem, Target};
use crate::results::{NodeState, PairResult};
use nalgebra::Vector2;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

/// The hysteresis of the segments' return from sliding to sticking on force
/// grounds (Section 3.4), as a fraction of the capacity: 1, i.e. never. After
/// an iteration a sliding segment's recovered T_t is the friction it applied
/// itself (its nodes are free along the target) plus what its neighbours'
/// changes spill onto its nodes, so the test of Section 3.4 compares mu_d T_n
/// of two iterations, or a transient: with large increments (a drag of 0.05
/// on scenes/verification/sliding_block.toml) it sent segments back to
/// sticking at points they had slid to, and the converged states alternated
/// between increments (2/7/0 and 8/1/0 stick/slip/open). A 0.3 hysteresis
/// only hid this at small increments. A sliding segment returns to sticking
/// kinematically instead: when the slip of its nodes from their anchors runs
/// along its friction, it sticks (and Table 1 puts its nodes back at their
/// anchors).
const SLIDE_HYSTERESIS: f64 = 1.0;
/// A node's contact force counts as tension above this fraction of the
/// largest contact force of its pair (round-off at a node just touching).
pub(super) const TENSION_TOLERANCE: f64 = 1e-8;
/// Contact points this far (in beta) outside a segment still count as on it,
/// so round-off at a target node does not lose the contact.
pub(super) const BETA_TOLERANCE: f64 = 1e-6;
/// Times a node may change between open and closed within one increment
/// before the increment is declared oscillating.
pub(super) const MAX_FLIPS: usize = 6;

/// A contactor node's memory: state, target segment and contact point.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct NodeMemory {
    pub state: NodeState,
    pub segment: usize,
    pub beta: f64,
    /// Where the node last stuck, or where it was at the start of the
    /// increment (segment, beta): a sliding node's slip is measured from
    /// here, to catch a slip against its friction force.
    #[serde(default)]
    pub anchor: Option<(usize, f64)>,
    /// Frictionless, held at a reflex corner of the target (see `corner`).
    #[serde(default)]
    pub corner: bool,
    /// The last target segment switch in this increment (from, to).
    #[serde(default)]
    pub crossed: Option<(usize, usize)>,
    /// Nodal decisions: the direction of its slip along the target's
    /// tangent (A to B) while it slides, +-1.
    #[serde(default)]
    pub slip_sign: f64,
    /// Nodal decisions: it has slid in this increment (sticks with mu_d).
    #[serde(default)]
    pub slid: bool,
    /// Nodal decisions: it has ever slid (mu_d for good under the usual rule).
    #[serde(default)]
    pub ever_slid: bool,
    /// Nodal decisions: how many times it left a corner hold in this
    /// increment (after `CORNER_LEAVES`, held again only from the wedge
    /// itself).
    #[serde(default)]
    pub corner_leaves: u32,
}

/// A contactor segment's memory (segment j joins contactor nodes j, j+1).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SegmentMemory {
    /// Open, Stick or Slip (Slip meaning the segment slides).
    pub state: NodeState,
    pub ever_slid: bool,
    /// Sliding: the sign of its friction resultant along the contactor
    /// (kept while it slides); zero otherwise.
    #[serde(default)]
    pub direction: f64,
}

/// What a pair carries from one iteration, and one increment, to the next.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PairMemory {
    pub nodes: Vec<NodeMemory>,
    pub segments: Vec<SegmentMemory>,
}

impl PairMemory {
    pub fn new(pair: &ContactPair) -> Self {
        let m = pair.contactor.len();
        let segments = if pair.closed { m } else { m.saturating_sub(1) };
        PairMemory {
            nodes: vec![NodeMemory::default(); m],
            segments: vec![SegmentMemory::default(); segments],
        }
    }
}

/// Set every closed node's anchor to its converged contact point: called
/// at the start of an increment.
pub fn begin_increment(memory: &mut [PairMemory]) {
    for node in memory.iter_mut().flat_map(|m| m.nodes.iter_mut()) {
        node.anchor = (node.state != NodeState::Open).then_some((node.segment, node.beta));
        node.crossed = None;
        node.slid = false;
        node.corner_leaves = 0;
    }
}

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

/// A row's entries (dof, coefficient), held in place: a contact row acts
/// on its node and at most a target segment's two nodes. The contact
/// system is rebuilt at every inner solve, and two allocations per row
/// were a tenth of that.
#[derive(Clone, Copy, Debug, Default)]
pub struct Entries {
    len: usize,
    at: [(usize, f64); Entries::MAX],
}

impl Entries {
    pub const MAX: usize = 6;

    /// The entries of `list` (at most `MAX`).
    pub fn from_slice(list: &[(usize, f64)]) -> Self {
        assert!(
            list.len() <= Self::MAX,
            "a contact row of {} entries",
            list.len()
        );
        let mut e = Entries::default();
        e.at[..list.len()].copy_from_slice(list);
        e.len = list.len();
        e
    }
}

impl std::ops::Deref for Entries {
    type Target = [(usize, f64)];
    fn deref(&self) -> &[(usize, f64)] {
        &self.at[..self.len]
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
    /// Sliding gradient matrix entries (dof, dof, value), added to K.
    pub k: Vec<(usize, usize, f64)>,
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
    /// Per pair, the nodal decisions the rows were built from (empty for
    /// the paper's decisions): `predict` and `update` with `keep` start from them.
    pub(crate) decisions: Vec<Vec<super::nodal::Decision>>,
    /// Per pair (nodal decisions), which nodes were in contact when the
    /// iterate's decisions were made (`nodal::Plan::Keep`).
    pub(crate) active: Vec<Vec<bool>>,
}

/// Per pair, the nodes the linearised problem decides otherwise than the
/// iterate did (`predict`), with the state each is given.
#[derive(Clone, Debug, Default)]
pub struct Switched(Vec<Vec<(usize, super::nodal::Forced)>>);

impl Switched {
    /// How many nodes change.
    pub fn count(&self) -> usize {
        self.0.iter().map(Vec::len).sum()
    }

    /// How many nodes open, close, and change between stick and slip.
    pub fn counts(&self) -> [usize; 3] {
        let mut c = [0; 3];
        for &(_, f) in self.0.iter().flatten() {
            c[match f {
                super::nodal::Forced::Open => 0,
                super::nodal::Forced::Close { .. } => 1,
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
                let flip = matches!(
                    f,
                    super::nodal::Forced::Open | super::nodal::Forced::Close { .. }
                );
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

/// A target segment at the current time: end points and node numbers
/// (None for a rigid target).
#[derive(Clone)]
pub(super) struct TargetSegment {
    pub(super) seg: Segment,
    pub(super) nodes: Option<[usize; 2]>,
    lo: [f64; 2],
    hi: [f64; 2],
}

pub(super) fn position(problem: &Problem, u: &[f64], n: usize) -> Vector2<f64> {
    let x = problem.mesh.nodes[n];
    Vector2::new(x[0] + u[2 * n], x[1] + u[2 * n + 1])
}

/// Poses [ux, uy, theta] of the rigid targets at time t, from the scene's
/// functions.
pub fn scene_poses(problem: &Problem, t: f64) -> Vec<[f64; 3]> {
    let f = &problem.functions;
    problem
        .rigids
        .iter()
        .map(|r| [r.ux.at(t, f), r.uy.at(t, f), r.theta.at(t, f)])
        .collect()
}

/// The reference point of rigid target `r` moved to pose [ux, uy, theta]
/// (what `rigid_points` also returns, without building the points).
pub fn rigid_reference(problem: &Problem, r: usize, pose: [f64; 3]) -> [f64; 2] {
    let [cx, cy] = problem.rigids[r].reference;
    [cx + pose[0], cy + pose[1]]
}

/// Points of rigid target `r` at pose [ux, uy, theta]: rotated by theta
/// about the reference and translated by (ux, uy). Also returns the moved
/// reference point.
pub fn rigid_points(problem: &Problem, r: usize, pose: [f64; 3]) -> (Vec<[f64; 2]>, [f64; 2]) {
    let rigid = &problem.rigids[r];
    let [ux, uy, th] = pose;
    let (s, c) = th.sin_cos();
    let [cx, cy] = rigid.reference;
    let points = rigid
        .points
        .iter()
        .map(|p| {
            let (dx, dy) = (p[0] - cx, p[1] - cy);
            [cx + c * dx - s * dy + ux, cy + s * dx + c * dy + uy]
        })
        .collect();
    (points, [cx + ux, cy + uy])
}

/// A target's segments, shared: a rigid target's are kept per pose.
pub(super) type Segments = Arc<TargetSet>;

/// The candidates of the free nodes' searches in the linearised problem's
/// decisions (`predict`), kept across an increment's inner solves: per
/// pair and node, a box twice the search's and the target's candidates in
/// it. A later search whose box lies inside, on the same target segments,
/// reads them (a superset of its own, each filtered by its box again, so
/// it finds what a fresh search finds) instead of the grid (the
/// capstan's free strip ends, 4 % of the FMU's time).
#[derive(Default)]
pub struct SearchCache(HashMap<(usize, usize), CachedBox>);

struct CachedBox {
    /// Held, so that the segments cannot be replaced at the same address.
    segments: Segments,
    lo: [f64; 2],
    hi: [f64; 2],
    candidates: Vec<u32>,
}

impl SearchCache {
    /// `search` for node `k` of pair `p`.
    pub(super) fn search(
        &mut self,
        (p, k): (usize, usize),
        segments: &Segments,
        x: Vector2<f64>,
        reach: f64,
    ) -> Option<(usize, ContactPoint)> {
        let (lo, hi) = ([x.x - reach, x.y - reach], [x.x + reach, x.y + reach]);
        let inside = |c: &CachedBox| {
            Arc::ptr_eq(&c.segments, segments)
                && (0..2).all(|a| c.lo[a] <= lo[a] && hi[a] <= c.hi[a])
        };
        if !(lo.iter().chain(&hi)).all(|v| v.is_finite()) {
            return search(segments, x, reach, false);
        }
        if !self.0.get(&(p, k)).is_some_and(inside) {
            let wide = 2.0 * reach;
            let (lo, hi) = ([x.x - wide, x.y - wide], [x.x + wide, x.y + wide]);
            let candidates = segments.candidates(lo, hi);
            let segments = Arc::clone(segments);
            (self.0).insert(
                (p, k),
                CachedBox {
                    segments,
                    lo,
                    hi,
                    candidates,
                },
            );
        }
        let cached = &self.0[&(p, k)];
        search_among(segments, &cached.candidates, x, reach, false)
    }
}

/// A target's segments with a uniform grid over their boxes, so that a
/// search near a point visits the segments near it instead of all of them:
/// the capstan's drum has 5120 chords against 129 contactor nodes, and the
/// search, `follow` and the outputs' nearest point scanned every chord for
/// every node (issue 14). The grid only narrows the candidates: they are
/// visited in index order, as the full scan visits them, so the results are
/// the scan's bit for bit.
pub(super) struct TargetSet {
    list: Vec<TargetSegment>,
    grid: Option<Grid>,
}

/// Targets of fewer segments are scanned whole.
const GRID_FROM: usize = 32;

struct Grid {
    origin: [f64; 2],
    cell: f64,
    dims: [usize; 2],
    /// Cell `c` holds the segments `items[start[c]..start[c + 1]]`.
    start: Vec<u32>,
    items: Vec<u32>,
}

impl std::ops::Deref for TargetSet {
    type Target = [TargetSegment];
    fn deref(&self) -> &[TargetSegment] {
        &self.list
    }
}

impl TargetSet {
    pub(super) fn new(list: Vec<TargetSegment>) -> Self {
        let grid = (list.len() >= GRID_FROM)
            .then(|| Grid::new(&list))
            .flatten();
        TargetSet { list, grid }
    }

    /// The indices, ascending, of the segments whose boxes meet the box
    /// `[lo, hi]` (and maybe a few more near it).
    pub(super) fn candidates(&self, lo: [f64; 2], hi: [f64; 2]) -> Vec<u32> {
        match &self.grid {
            Some(g) => g.candidates(lo, hi, self.list.len()),
            None => (0..self.list.len() as u32).collect(),
        }
    }

    /// The segments of `candidates` in index order.
    pub(super) fn visit(
        &self,
        lo: [f64; 2],
        hi: [f64; 2],
    ) -> impl Iterator<Item = (usize, &TargetSegment)> {
        let c = self.candidates(lo, hi);
        c.into_iter().map(|j| (j as usize, &self.list[j as usize]))
    }
}

impl Grid {
    /// Cells about twice the mean segment box, at most 4 per segment; None
    /// for a target of no extent or non-finite coordinates.
    fn new(list: &[TargetSegment]) -> Option<Grid> {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        let mut size = 0.0;
        for s in list {
            for a in 0..2 {
                lo[a] = lo[a].min(s.lo[a]);
                hi[a] = hi[a].max(s.hi[a]);
            }
            size += (s.hi[0] - s.lo[0]).max(s.hi[1] - s.lo[1]);
        }
        let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        if !(extent.is_finite() && extent > 0.0) {
            return None;
        }
        let n = list.len() as f64;
        let mut cell = (2.0 * size / n).max(extent / 4096.0);
        let cells = |cell: f64| [0, 1].map(|a| ((hi[a] - lo[a]) / cell) as usize + 1);
        while (cells(cell)[0] * cells(cell)[1]) as f64 > 4.0 * n {
            cell *= 2.0;
        }
        let dims = cells(cell);
        let mut g = Grid {
            origin: lo,
            cell,
            dims,
            start: vec![0; dims[0] * dims[1] + 1],
            items: Vec::new(),
        };
        // Count, then fill (a segment in every cell its box meets).
        for s in list {
            let range = g.range(s.lo, s.hi);
            for cy in range[1].clone() {
                for cx in range[0].clone() {
                    g.start[cy * dims[0] + cx + 1] += 1;
                }
            }
        }
        for c in 0..dims[0] * dims[1] {
            g.start[c + 1] += g.start[c];
        }
        let mut next = g.start.clone();
        g.items = vec![0; g.start[dims[0] * dims[1]] as usize];
        for (j, s) in list.iter().enumerate() {
            let range = g.range(s.lo, s.hi);
            for cy in range[1].clone() {
                for cx in range[0].clone() {
                    let c = cy * dims[0] + cx;
                    g.items[next[c] as usize] = j as u32;
                    next[c] += 1;
                }
            }
        }
        Some(g)
    }

    /// The cells the box `[lo, hi]` meets, per axis (clamped to the grid).
    fn range(&self, lo: [f64; 2], hi: [f64; 2]) -> [std::ops::Range<usize>; 2] {
        [0, 1].map(|a| {
            let at = |x: f64| ((x - self.origin[a]) / self.cell).floor();
            let last = self.dims[a] as f64 - 1.0;
            let (i0, i1) = (at(lo[a]).max(0.0), at(hi[a]).min(last));
            if i0 > i1 || i0.is_nan() || i1.is_nan() {
                0..0
            } else {
                i0 as usize..i1 as usize + 1
            }
        })
    }

    fn candidates(&self, lo: [f64; 2], hi: [f64; 2], n: usize) -> Vec<u32> {
        let range = self.range(lo, hi);
        let unknown = lo.iter().chain(&hi).any(|v| v.is_nan());
        if unknown || range[0].len() * range[1].len() >= n {
            return (0..n as u32).collect();
        }
        // Marked in a bit set (a segment lies in every cell its box meets),
        // then read out in ascending order: a search box across the capstan's
        // 5120 chords holds some 200, which a sort took 6 us for.
        let mut seen = vec![0u64; n.div_ceil(64)];
        let (mut first, mut last) = (usize::MAX, 0);
        for cy in range[1].clone() {
            let row = cy * self.dims[0];
            let (a, b) = (
                self.start[row + range[0].start],
                self.start[row + range[0].end],
            );
            for &j in &self.items[a as usize..b as usize] {
                let w = j as usize / 64;
                seen[w] |= 1 << (j % 64);
                first = first.min(w);
                last = last.max(w);
            }
        }
        let mut out = Vec::new();
        for w in first..=last.min(seen.len().saturating_sub(1)) {
            let mut bits = seen[w];
            while bits != 0 {
                out.push((64 * w) as u32 + bits.trailing_zeros());
                bits &= bits - 1;
            }
        }
        out
    }
}

/// The segments of each rigid target at the last two poses asked for (a
/// step's start and its end), so that a rigid arc of thousands of chords is
/// built once per pose instead of at every search, output and check of a
/// step: a held step asks for the same pose a few times, and building the
/// capstan's 5120 chords was most of its cost. Keyed by the pose's bits and
/// the target's point count and end points.
#[derive(Default)]
pub struct RigidSegments(Mutex<HashMap<usize, Vec<(RigidKey, Segments)>>>);

type RigidKey = ([u64; 3], usize, [u64; 4]);

/// A clone starts empty (the segments are rebuilt on demand).
impl Clone for RigidSegments {
    fn clone(&self) -> Self {
        RigidSegments::default()
    }
}

impl std::fmt::Debug for RigidSegments {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("RigidSegments")
    }
}

impl RigidSegments {
    fn get_or_build(
        &self,
        r: usize,
        key: RigidKey,
        build: impl FnOnce() -> Result<TargetSet, String>,
    ) -> Result<Segments, String> {
        let lock = || {
            self.0
                .lock()
                .unwrap_or_else(|poisoned| poisoned.into_inner())
        };
        if let Some((_, s)) = lock()
            .get(&r)
            .and_then(|l| l.iter().find(|(k, _)| *k == key))
        {
            return Ok(s.clone());
        }
        let built = Arc::new(build()?);
        let mut cache = lock();
        let list = cache.entry(r).or_default();
        list.insert(0, (key, built.clone()));
        list.truncate(2);
        Ok(built)
    }
}

pub(super) fn target_segments(
    problem: &Problem,
    pair: &ContactPair,
    u: &[f64],
    poses: &[[f64; 3]],
) -> Result<Segments, String> {
    let make = |xa: Vector2<f64>, xb: Vector2<f64>, nodes| {
        let seg = Segment::new(xa, xb).map_err(|e| format!("pair '{}': {e}", pair.name))?;
        Ok(TargetSegment {
            seg,
            nodes,
            lo: [xa.x.min(xb.x), xa.y.min(xb.y)],
            hi: [xa.x.max(xb.x), xa.y.max(xb.y)],
        })
    };
    match &pair.target {
        Target::Body { segments, .. } => segments
            .iter()
            .map(|&[a, b]| {
                make(
                    position(problem, u, a),
                    position(problem, u, b),
                    Some([a, b]),
                )
            })
            .collect::<Result<Vec<_>, String>>()
            .map(|list| Arc::new(TargetSet::new(list))),
        Target::Rigid(r) => {
            let points = &problem.rigids[*r].points;
            let ends = [points.first(), points.last()].map(|p| p.copied().unwrap_or_default());
            let key = (
                poses[*r].map(f64::to_bits),
                points.len(),
                [ends[0][0], ends[0][1], ends[1][0], ends[1][1]].map(f64::to_bits),
            );
            problem.rigid_segments.get_or_build(*r, key, || {
                let (points, _) = rigid_points(problem, *r, poses[*r]);
                points
                    .windows(2)
                    .map(|w| {
                        let v = |p: [f64; 2]| Vector2::new(p[0], p[1]);
                        make(v(w[0]), v(w[1]), None)
                    })
                    .collect::<Result<Vec<_>, String>>()
                    .map(TargetSet::new)
            })
        }
    }
}

/// Per pair, contactor nodes with their distances (`near_target`).
pub type NearNodes = Vec<Vec<(usize, f64)>>;

/// Per pair, the contactor nodes (indices into `pair.contactor`) that may
/// touch in an increment whose nodes move by at most `reach`, each with its
/// distance from the target: those within `reach` of a segment of the
/// target at `poses` (where the increment takes it), the nodes at `u`
/// (where it starts), and those the memory holds in contact (distance 0).
/// Rigid targets only (None for a pair against a body, whose segments move
/// with the solution).
pub fn near_target(
    problem: &Problem,
    poses: &[[f64; 3]],
    u: &[f64],
    memory: &[PairMemory],
    reach: f64,
) -> Result<Option<NearNodes>, String> {
    let mut out = Vec::with_capacity(problem.contacts.len());
    for (p, pair) in problem.contacts.iter().enumerate() {
        if !matches!(pair.target, Target::Rigid(_)) {
            return Ok(None);
        }
        let segments = target_segments(problem, pair, u, poses)?;
        let near = (pair.contactor.iter().enumerate())
            .filter_map(|(k, &n)| {
                if memory[p].nodes[k].state != NodeState::Open {
                    return Some((k, 0.0));
                }
                let x = position(problem, u, n);
                let (lo, hi) = ([x.x - reach, x.y - reach], [x.x + reach, x.y + reach]);
                let distance = (segments.visit(lo, hi))
                    .map(|(_, s)| {
                        let raw = s.seg.project(x);
                        let miss = (-raw.beta()).max(raw.beta() - 1.0).max(0.0) * s.seg.length();
                        miss.hypot(raw.normal_overlap())
                    })
                    .fold(f64::INFINITY, f64::min);
                (distance <= reach).then_some((k, distance))
            })
            .collect();
        out.push(near);
    }
    Ok(Some(out))
}

/// The contact point of a node at `x` on target segment `seg`: the foot of the normal,
/// when it falls on the segment to `BETA_TOLERANCE`; a foot just beyond an end is
/// referred to that end node (beta clamped to [0, 1]). The normal overlap is the same
/// either way (the point moves along the segment's line); what the clamp removes is a
/// contact point off the target: a node referred to beta = 1 + 1e-8 ties its row to A
/// with the weight -1e-8, and where the other dofs of the row are prescribed (a node on
/// a symmetry plane against the target node there) that weight is all the row has, so
/// the row moves A by (overlap / 1e-8): docs/contact.md item 10.
pub(super) fn on_segment(seg: &Segment, x: Vector2<f64>) -> Option<ContactPoint> {
    let cp = seg.project(x);
    cp.is_within(BETA_TOLERANCE)
        .then(|| seg.contact_at(x, cp.beta().clamp(0.0, 1.0)))
}

/// The segment a free node at `x` has penetrated (or, with `touching`,
/// touches), with its projection: the candidate (bounding box within
/// `reach`) whose projection falls on the segment with a positive (or zero)
/// overlap smaller than `reach`, nearest first.
///
/// At a reflex corner of the target (the target turns toward the contactor:
/// round a hole, or at the end of a target on a symmetry plane), a node that
/// has penetrated next to the corner projects beyond the ends of both
/// segments meeting there (the wedge between their normals), and none takes
/// it. Then the segment it misses by the least takes it, at the corner, if
/// it misses it by no more than its overlap (`excess(beta) * length <=
/// overlap`: corners up to 45 degrees). A node past the end of a target by
/// more than its overlap is not found.
pub(super) fn search(
    segments: &TargetSet,
    x: Vector2<f64>,
    reach: f64,
    touching: bool,
) -> Option<(usize, ContactPoint)> {
    let (lo, hi) = ([x.x - reach, x.y - reach], [x.x + reach, x.y + reach]);
    search_among(segments, &segments.candidates(lo, hi), x, reach, touching)
}

/// `search` over `candidates` (ascending), any that hold those
/// `TargetSet::candidates` gives for its box.
fn search_among(
    segments: &TargetSet,
    candidates: &[u32],
    x: Vector2<f64>,
    reach: f64,
    touching: bool,
) -> Option<(usize, ContactPoint)> {
    let mut best: Option<(usize, ContactPoint)> = None;
    let mut wedge: Option<(usize, ContactPoint, f64)> = None;
    for (j, s) in candidates
        .iter()
        .map(|&j| (j as usize, &segments[j as usize]))
    {
        if x.x < s.lo[0] - reach
            || x.x > s.hi[0] + reach
            || x.y < s.lo[1] - reach
            || x.y > s.hi[1] + reach
        {
            continue;
        }
        let Some(cp) = on_segment(&s.seg, x) else {
            let raw = s.seg.project(x);
            let d = raw.normal_overlap();
            let miss = (-raw.beta()).max(raw.beta() - 1.0) * s.seg.length();
            if d > 0.0 && d <= reach && miss <= d && wedge.as_ref().is_none_or(|w| miss < w.2) {
                let at_corner = s.seg.contact_at(x, raw.beta().clamp(0.0, 1.0));
                wedge = Some((j, at_corner, miss));
            }
            continue;
        };
        let d = cp.normal_overlap();
        if d < 0.0 || (d == 0.0 && !touching) || d > reach {
            continue;
        }
        if best.as_ref().is_none_or(|(_, b)| d < b.normal_overlap()) {
            best = Some((j, cp));
        }
    }
    best.or(wedge.map(|(j, cp, _)| (j, cp)))
}

/// A sliding node's new contact point: the projection on its segment, or on
/// the segment it has slid onto (any segment whose projection contains it,
/// nearest in |overlap|). None when it has slid off the target.
pub(super) fn follow(
    segments: &TargetSet,
    j: usize,
    x: Vector2<f64>,
    reach: f64,
) -> Option<(usize, ContactPoint)> {
    if let Some(cp) = on_segment(&segments[j].seg, x) {
        return Some((j, cp));
    }
    let mut best: Option<(usize, ContactPoint)> = None;
    let (lo, hi) = ([x.x - reach, x.y - reach], [x.x + reach, x.y + reach]);
    for (i, s) in segments.visit(lo, hi) {
        if x.x < s.lo[0] - reach
            || x.x > s.hi[0] + reach
            || x.y < s.lo[1] - reach
            || x.y > s.hi[1] + reach
        {
            continue;
        }
        let Some(c) = on_segment(&s.seg, x) else {
            continue;
        };
        if c.normal_overlap().abs() > reach {
            continue;
        }
        if best
            .as_ref()
            .is_none_or(|(_, b)| c.normal_overlap().abs() < b.normal_overlap().abs())
        {
            best = Some((i, c));
        }
    }
    best
}

/// The segment meeting segment `j` at its end `end_j` (beta 0 or 1) when the
/// target body's angle there exceeds 180 degrees (a reflex corner, as round
/// a hole): `(i, end_i)`. The body lies to the left of the segments, so
/// walking along the surface a reflex corner turns right.
pub(super) fn reflex(segments: &[TargetSegment], j: usize, end_j: f64) -> Option<(usize, f64)> {
    let s = &segments[j].seg;
    let (at, end_i) = if end_j == 1.0 {
        (s.xb(), 0.0)
    } else {
        (s.xa(), 1.0)
    };
    let i = (0..segments.len()).find(|&i| {
        i != j && {
            let o = &segments[i].seg;
            (if end_i == 0.0 { o.xa() } else { o.xb() }) == at
        }
    })?;
    let o = &segments[i].seg;
    let (t_in, t_out) = if end_j == 1.0 {
        (s.tangent(), o.tangent())
    } else {
        (o.tangent(), s.tangent())
    };
    let turn = t_in.x * t_out.y - t_in.y * t_out.x;
    (turn < -1e-6).then_some((i, end_i))
}

/// A frictionless sliding node at a reflex corner of the target: it slides
/// back across a corner it crossed in this increment (from segment `from`
/// onto segment `j`, having crossed from `j` onto `from` before), or it is
/// held at the corner and still lies beyond the corner's end of both
/// segments (to `BETA_TOLERANCE`), where neither segment's normal reaches it.
/// Returns `(end_j, i, end_i)`: the corner is the end `end_j` of `j` and
/// `end_i` of the other segment `i`. A node crossing a corner once (sliding
/// along a dented flat target) is not held.
fn corner(
    segments: &[TargetSegment],
    from: usize,
    j: usize,
    x: Vector2<f64>,
    node: &NodeMemory,
) -> Option<(f64, usize, f64)> {
    if from != j && from < segments.len() && node.crossed == Some((j, from)) {
        for end_j in [0.0, 1.0] {
            if let Some((i, end_i)) = reflex(segments, j, end_j)
                && i == from
            {
                return Some((end_j, i, end_i));
            }
        }
    }
    if !node.corner {
        return None;
    }
    let beta = segments[j].seg.project(x).beta();
    let end_j = if beta >= 1.0 - BETA_TOLERANCE {
        1.0
    } else if beta <= BETA_TOLERANCE {
        0.0
    } else {
        return None;
    };
    let (i, end_i) = reflex(segments, j, end_j)?;
    let beta_i = segments[i].seg.project(x).beta();
    let beyond = if end_i == 0.0 {
        beta_i <= BETA_TOLERANCE
    } else {
        beta_i >= 1.0 - BETA_TOLERANCE
    };
    beyond.then_some((end_j, i, end_i))
}

/// The contact point of a node at its anchor (the material point of the
/// target where it was at the start of the increment, or where it first
/// touched in it), when the anchor is on the target and within `reach`.
/// Sticking holds a node there: with large increments a node may slide, or
/// be released and come back, in early iterations; its slip over the
/// increment, which the friction must oppose, is measured from the anchor.
fn anchor_point(
    segments: &[TargetSegment],
    anchor: Option<(usize, f64)>,
    x: Vector2<f64>,
    reach: f64,
) -> Option<(usize, ContactPoint)> {
    let (j, beta) = anchor?;
    let cp = segments.get(j)?.seg.contact_at(x, beta);
    (cp.overlap().norm() <= reach).then_some((j, cp))
}

pub(super) fn geometry(problem: &Problem) -> Geometry {
    match problem.analysis {
        AnalysisKind::PlaneStrain { thickness } | AnalysisKind::PlaneStress { thickness } => {
            Geometry::Planar { thickness }
        }
        AnalysisKind::Axisymmetric => Geometry::Axisymmetric,
    }
}

fn to_segment_state(s: NodeState) -> SegmentState {
    match s {
        NodeState::Open => SegmentState::Open,
        NodeState::Stick => SegmentState::Stick,
        NodeState::Slip => SegmentState::Slide,
    }
}

fn from_segment_state(s: SegmentState) -> NodeState {
    match s {
        SegmentState::Open => NodeState::Open,
        SegmentState::Stick => NodeState::Stick,
        SegmentState::Slide => NodeState::Slip,
    }
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

/// One more change of node `k` between open and contact (`MAX_FLIPS`).
pub(super) fn count_flip(pair: &ContactPair, k: usize, flips: &mut [usize]) -> Result<(), String> {
    count_change(pair, k, flips, MAX_FLIPS, "open and contact")
}

/// Whether the inner solves apply: every pair decides nodally (`update`
/// with `keep` keeps the nodal decisions only).
pub fn inner_solves(problem: &Problem) -> bool {
    problem
        .contacts
        .iter()
        .all(|p| p.decisions == Decisions::Nodal)
}

/// A hash of every node's state as it would be after `switched`: the
/// inner solves of an iteration stop when they meet a set of states again.
pub fn state_key(memory: &[PairMemory], switched: &Switched) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    for (p, m) in memory.iter().enumerate() {
        for (k, node) in m.nodes.iter().enumerate() {
            let forced = switched
                .0
                .get(p)
                .and_then(|s| s.iter().find(|(j, _)| *j == k));
            let (state, sign) = match forced {
                Some((_, super::nodal::Forced::Stick)) => (NodeState::Stick as u64, 0.0),
                Some((_, super::nodal::Forced::Slip(s))) => (NodeState::Slip as u64, *s),
                Some((_, super::nodal::Forced::Open)) => (NodeState::Open as u64, 0.0),
                Some((_, super::nodal::Forced::Close { j, .. })) => (3 + *j as u64, 0.0),
                None => (node.state as u64, node.slip_sign),
            };
            (state, sign.to_bits()).hash(&mut h);
        }
    }
    h.finish()
}

/// The nodes whose stick/slip state the linearised problem decides
/// otherwise than `system`'s rows did: after solving with them, `u_new` the
/// displacements reached and `force_new` the out-of-balance force per dof
/// there as the solve predicts it (zero at prescribed dofs). Tolerances
/// [force, length] as the iteration's equilibrium. None when every pair
/// keeps its states, or when a pair uses the paper's decisions.
#[allow(clippy::too_many_arguments)]
pub fn predict(
    problem: &Problem,
    poses: &[[f64; 3]],
    [u_now, u_new]: [&[f64]; 2],
    force_new: &[f64],
    memory: &[PairMemory],
    system: &ContactSystem,
    tolerance: [f64; 2],
    settling: bool,
    cache: &mut SearchCache,
) -> Result<Option<Switched>, String> {
    if system.decisions.len() != problem.contacts.len() {
        return Ok(None);
    }
    let mut out = Vec::with_capacity(problem.contacts.len());
    for (p, pair) in problem.contacts.iter().enumerate() {
        if pair.decisions != Decisions::Nodal {
            return Ok(None);
        }
        let force = |n: usize| Vector2::new(force_new[2 * n], force_new[2 * n + 1]);
        out.push(super::nodal::predict_pair(
            problem,
            pair,
            poses,
            [u_now, u_new],
            &force,
            &memory[p],
            &system.decisions[p],
            settling.then_some(&system.active[p][..]),
            tolerance,
            (p, cache),
        )?);
    }
    let switched = Switched(out);
    Ok((switched.count() > 0).then_some(switched))
}

/// The contact part of the system at displacements `u` and rigid target
/// poses `poses` ([ux, uy, theta] per rigid target), from the out-of-balance
/// forces `r` (F_int - R_ext, contact excluded) and the memory after the
/// previous iteration, which it updates. `eq` maps dofs to equations
/// (PRESCRIBED for prescribed dofs).
///
/// `keep`: the system `update` built at this same iterate (from these `u`
/// and `r`) and the nodes the linearised problem switched (`predict`): those
/// get their new states, every other node keeps its decision, giving the
/// rows of the linearised problem's next active set (nodal decisions only).
#[allow(clippy::too_many_arguments)]
pub fn update(
    problem: &Problem,
    poses: &[[f64; 3]],
    u: &[f64],
    r: &[f64],
    eq: &[u32],
    start: &Start,
    memory: &mut [PairMemory],
    flips: &mut Flips,
    log: &mut dyn FnMut(&str),
    keep: Option<(&ContactSystem, &Switched)>,
) -> Result<ContactSystem, String> {
    let mut out = ContactSystem {
        rigid: vec![[0.0; 3]; problem.rigids.len()],
        ..Default::default()
    };
    if flips.counts.len() != memory.len() {
        flips.counts = memory.iter().map(|m| vec![0; m.nodes.len()]).collect();
        flips.slips = flips.counts.clone();
    }
    let at = Iterate {
        problem,
        poses,
        u,
        r,
        eq,
        start,
    };
    for (p, pair) in problem.contacts.iter().enumerate() {
        let result = match pair.decisions {
            Decisions::Paper => {
                let result = paper_pair(
                    &at,
                    pair,
                    &mut memory[p],
                    &mut flips.counts[p],
                    log,
                    &mut out,
                )?;
                out.decisions.push(Vec::new());
                out.active.push(Vec::new());
                result
            }
            Decisions::Nodal => super::nodal::update_pair(
                &at,
                pair,
                &mut memory[p],
                [&mut flips.counts[p], &mut flips.slips[p]],
                log,
                &mut out,
                match keep {
                    Some((previous, switched)) => super::nodal::Plan::Keep {
                        decisions: &previous.decisions[p],
                        forced: &switched.0[p],
                        active: &previous.active[p],
                    },
                    None => super::nodal::Plan::Decide,
                },
            )?,
        };
        out.pairs.push(result);
    }
    Ok(out)
}

/// The iterate a pair's contact is updated at: displacements, rigid target
/// poses, out-of-balance forces (F_int - R_ext, contact excluded), the
/// dof-to-equation map, and the state the increment started from.
pub(super) struct Iterate<'a> {
    pub(super) problem: &'a Problem,
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

/// The positions of `pair`'s contactor nodes at displacements `u`.
pub(super) fn contactor_positions(
    problem: &Problem,
    pair: &ContactPair,
    u: &[f64],
) -> Vec<Vector2<f64>> {
    (pair.contactor.iter())
        .map(|&n| position(problem, u, n))
        .collect()
}

/// A pair's reported results, built node by node.
pub(super) struct Report {
    pub(super) result: PairResult,
    /// Per contactor node in contact: the target's frame at its contact
    /// point, as the contactor sees it (tangent toward the next node,
    /// inward normal), for the reported nodal tractions.
    pub(super) frames: Vec<Option<(Vector2<f64>, Vector2<f64>)>>,
}

impl Report {
    pub(super) fn new(m: usize) -> Self {
        Report {
            result: PairResult::default(),
            frames: vec![None; m],
        }
    }

    /// Contactor node k in contact at `cp` with contact force `f`: the
    /// pair's Fx, Fy and its normal (compression positive) and tangential
    /// (along the contactor, from node k toward k + 1, i.e. against the
    /// target's A -> B) parts, the node's frame, and the reaction on a
    /// rigid target (its moment about the moved reference point). Returns
    /// the node's [normal, tangential] force.
    pub(super) fn contact(
        &mut self,
        at: &Iterate,
        pair: &ContactPair,
        k: usize,
        f: Vector2<f64>,
        cp: &ContactPoint,
        rigid: &mut [[f64; 3]],
    ) -> [f64; 2] {
        let (normal, tangent) = (cp.segment().normal(), cp.segment().tangent());
        let result = &mut self.result;
        result.fx += f.x;
        result.fy += f.y;
        result.fn_ -= f.dot(&normal);
        result.ft -= f.dot(&tangent);
        self.frames[k] = Some((-tangent, -normal));
        if let Target::Rigid(ri) = pair.target {
            let reference = rigid_reference(at.problem, ri, at.poses[ri]);
            let xc = cp.point();
            let rr = &mut rigid[ri];
            rr[0] -= f.x;
            rr[1] -= f.y;
            rr[2] -= (xc.x - reference[0]) * f.y - (xc.y - reference[1]) * f.x;
        }
        [-f.dot(&normal), -f.dot(&tangent)]
    }

    /// Contactor node k at `x` with `state`, and its [normal, tangential]
    /// force: the state counts and the node's entries.
    pub(super) fn node(&mut self, x: Vector2<f64>, state: NodeState, force: [f64; 2]) {
        let result = &mut self.result;
        match state {
            NodeState::Open => result.n_open += 1,
            NodeState::Stick => result.n_stick += 1,
            NodeState::Slip => result.n_slip += 1,
        }
        result.nodes.x.push(x.x);
        result.nodes.y.push(x.y);
        result.nodes.state.push(state);
        result.nodes.pn.push(force[0]);
        result.nodes.pt.push(force[1]);
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
}

/// The paper's Section 3 for one pair, in phases: the pair at the iterate
/// (target search geometry, `PaperPair::new`), force recovery (recovered
/// tractions and Section 3's segment decisions, `recover`), state
/// decisions (re-contacts, the return to sticking, Table 1 and each node's
/// contact: `decide_segments`, `table1`, `node_contact`), and the rows of
/// Eq. (18) with the reported results (`node_rows`, `quadratic_report`).
fn paper_pair(
    at: &Iterate,
    pair: &ContactPair,
    mem: &mut PairMemory,
    flips: &mut [usize],
    log: &mut dyn FnMut(&str),
    out: &mut ContactSystem,
) -> Result<PairResult, String> {
    let view = PaperPair::new(at, pair)?;
    let rec = recover(&view, mem)?;
    let recontact = decide_segments(&view, &rec, mem, log);
    let table1 = table1(&view, &rec, mem);
    let mut report = Report::new(view.x.len());
    for (k, &state) in table1.iter().enumerate() {
        let old = mem.nodes[k];
        let contact = node_contact(&view, &rec, k, &old, state, recontact[k], log);
        if (contact.state == NodeState::Open) != (old.state == NodeState::Open) {
            count_flip(pair, k, flips)?;
        }
        mem.nodes[k] = node_rows(&view, &rec, k, &old, contact, &mut report, out);
    }
    quadratic_report(&view, &rec, &mut report);
    Ok(report.result)
}

/// One pair at the iterate under the paper's decisions: the target's
/// segments, the contactor's positions and the reach of the search.
struct PaperPair<'a> {
    at: &'a Iterate<'a>,
    pair: &'a ContactPair,
    segments: Segments,
    x: Vec<Vector2<f64>>,
    reach: f64,
    frictionless: bool,
}

impl<'a> PaperPair<'a> {
    /// Target search geometry: the target's segments and the contactor's
    /// positions at the iterate.
    fn new(at: &'a Iterate<'a>, pair: &'a ContactPair) -> Result<Self, String> {
        let segments = target_segments(at.problem, pair, at.u, at.poses)?;
        let x = contactor_positions(at.problem, pair, at.u);
        // Reach of the search: a few contactor segment lengths, so a node is
        // not caught by the far side of a thin target.
        let mut reach: f64 = 0.0;
        for w in x.windows(2) {
            reach = reach.max((w[1] - w[0]).norm());
        }
        let reach = if reach > 0.0 {
            2.0 * reach
        } else {
            f64::INFINITY
        };
        Ok(PaperPair {
            at,
            pair,
            segments,
            x,
            reach,
            frictionless: pair.mu_s == 0.0 && pair.mu_d == 0.0,
        })
    }

    /// The contactor segments joining node k: before it and after it.
    fn adjoining(&self, k: usize, nseg: usize) -> [Option<usize>; 2] {
        let before = if k > 0 {
            Some(k - 1)
        } else {
            self.pair.closed.then(|| nseg - 1)
        };
        [before, (k < nseg).then_some(k)]
    }
}

/// What the force recovery gives a pair under the paper's decisions.
struct Recovered {
    /// In contact after the previous iteration.
    active: Vec<bool>,
    /// Each node's out-of-balance force.
    force: Vec<Vector2<f64>>,
    /// The segments' states after the previous iteration.
    prev: Vec<SegmentState>,
    /// Section 3 at the current positions.
    ev: traction::Evaluation,
    /// Reported nodal tractions.
    area: PerArea,
    /// Scale of the contact forces of this pair, for the tension test.
    force_scale: f64,
}

impl Recovered {
    /// The force a node in contact reports: its out-of-balance force, which
    /// at convergence is the contact force in every direction (the
    /// multipliers take up what the recovered forces leave).
    fn reported(&self, k: usize) -> Vector2<f64> {
        if self.active[k] {
            self.force[k]
        } else {
            Vector2::zeros()
        }
    }
}

/// Force recovery: contact forces from the out-of-balance forces (Section
/// 3): the recovered tractions, segment decisions and nodal contact forces
/// of `traction::evaluate`, and the reported tractions (`per_area`).
fn recover(view: &PaperPair, mem: &PairMemory) -> Result<Recovered, String> {
    let (at, problem, pair) = (view.at, view.at.problem, view.pair);
    let m = pair.contactor.len();
    let geometry = geometry(problem);
    let active: Vec<bool> = mem
        .nodes
        .iter()
        .map(|n| n.state != NodeState::Open)
        .collect();
    // At a prescribed dof the out-of-balance force is the driver's
    // reaction, not contact: taken as zero (a symmetry plane).
    let force = at.contactor_forces(pair);
    let force_xy: Vec<[f64; 2]> = force.iter().map(|v| [v.x, v.y]).collect();
    let prev: Vec<SegmentState> = mem
        .segments
        .iter()
        .map(|s| to_segment_state(s.state))
        .collect();
    let ever: Vec<bool> = mem.segments.iter().map(|s| s.ever_slid).collect();
    let directions: Vec<f64> = mem.segments.iter().map(|s| s.direction).collect();
    // Section 3 on the contactor at positions `at`.
    let evaluate = |at: &[Vector2<f64>]| {
        let xs: Vec<[f64; 2]> = at.iter().map(|v| [v.x, v.y]).collect();
        traction::evaluate(
            geometry,
            pair.recovery,
            pair.mu_s,
            pair.mu_d,
            pair.rule,
            pair.closed,
            &xs,
            &active,
            &force_xy,
            &prev,
            &ever,
            &directions,
            SLIDE_HYSTERESIS,
        )
        .map_err(|e| format!("pair '{}': {e}", pair.name))
    };
    let ev = evaluate(&view.x)?;
    let area = per_area(view, &ev, &evaluate)?;
    let force_scale = (0..m)
        .filter(|&k| active[k])
        .map(|k| force_xy[k][0].hypot(force_xy[k][1]))
        .fold(0.0, f64::max);
    Ok(Recovered {
        active,
        force,
        prev,
        ev,
        area,
        force_scale,
    })
}

/// The reported nodal tractions `t_n`, `t_t` of Section 3's evaluation
/// `ev`, and the positions they are per unit area of; `evaluate` is
/// Section 3 on the contactor at other positions.
fn per_area(
    view: &PaperPair,
    ev: &traction::Evaluation,
    evaluate: &Section3,
) -> Result<PerArea, String> {
    let (problem, pair) = (view.at.problem, view.pair);
    // Reported tractions are per unit area of the geometry the element
    // stresses live on: the reference one under small-strain kinematics
    // (linear theory, as Hertz's), the current one under total
    // Lagrangian kinematics (Cauchy tractions). Section 3's decisions only
    // compare tractions of the same segment, so they do not depend on it.
    let reference_area = matches!(
        problem.kinematics,
        Kinematics::SmallStrain | Kinematics::MaterialNonlinearOnly
    );
    let x_area: Vec<Vector2<f64>> = if reference_area {
        pair.contactor
            .iter()
            .map(|&n| Vector2::new(problem.mesh.nodes[n][0], problem.mesh.nodes[n][1]))
            .collect()
    } else {
        view.x.clone()
    };
    let (node_tn, node_tt): (Vec<f64>, Vec<f64>) = if reference_area {
        let out = evaluate(&x_area)?;
        // Magnitude per reference area, direction from the current
        // surface (the reference surface is turned against the current
        // one where the contact flattens it, by about a/R at the edge:
        // decomposing there would move mu-sized parts of tn into tt).
        let scale = |k: usize| {
            let cur = ev.node_tn[k].hypot(ev.node_tt[k]);
            let reference = out.node_tn[k].hypot(out.node_tt[k]);
            if cur > 0.0 { reference / cur } else { 0.0 }
        };
        (0..view.x.len())
            .map(|k| (ev.node_tn[k] * scale(k), ev.node_tt[k] * scale(k)))
            .unzip()
    } else {
        (ev.node_tn.clone(), ev.node_tt.clone())
    };
    Ok(PerArea {
        x: x_area,
        tn: node_tn,
        tt: node_tt,
    })
}

/// Section 3 on the contactor at given positions.
type Section3<'e> = dyn Fn(&[Vector2<f64>]) -> Result<traction::Evaluation, String> + 'e;

/// Reported nodal tractions and the positions they are per unit area of.
struct PerArea {
    x: Vec<Vector2<f64>>,
    tn: Vec<f64>,
    tt: Vec<f64>,
}

/// A node not in contact that has penetrated: where (segment and contact
/// point), and whether it has slid from its anchor while free.
type Recontact = Option<((usize, ContactPoint), bool)>;

/// State decisions, per segment: Section 3's decisions into the memory,
/// the segments of nodes that come back sliding (`recontacts`), and the
/// return to sticking (`return_to_sticking`). Returns the re-contacts.
fn decide_segments(
    view: &PaperPair,
    rec: &Recovered,
    mem: &mut PairMemory,
    log: &mut dyn FnMut(&str),
) -> Vec<Recontact> {
    for (s, seg) in mem.segments.iter_mut().enumerate() {
        seg.state = from_segment_state(rec.ev.segments[s].state);
        seg.ever_slid = rec.ev.segments[s].ever_slid;
        seg.direction = rec.ev.segments[s].sign;
    }
    let recontact = recontacts(view, rec, mem);
    if !view.frictionless {
        return_to_sticking(view, rec, mem, log);
    }
    recontact
}

/// Nodes not in contact that have penetrated. One that was in contact at
/// the start of the increment and comes back in it (released in an early
/// iteration of a large increment) has slid from its anchor while free: it
/// comes back sliding, and a segment of it that has just come back (it was
/// open), or slides, takes a friction against that slip.
fn recontacts(view: &PaperPair, rec: &Recovered, mem: &mut PairMemory) -> Vec<Recontact> {
    let (segments, x) = (&view.segments, &view.x);
    let m = x.len();
    let nseg = mem.segments.len();
    let mut recontact: Vec<Recontact> = vec![None; m];
    for k in (0..m).filter(|&k| mem.nodes[k].state == NodeState::Open) {
        let Some((j, cp)) = search(segments, x[k], view.reach, false) else {
            continue;
        };
        let slip = match (view.frictionless, mem.nodes[k].anchor) {
            (false, Some((sa, ba))) if sa < segments.len() => {
                cp.point() - segments[sa].seg.point_at(ba)
            }
            _ => Vector2::zeros(),
        };
        let slid = slip.norm() > 1e-9 * segments[j].seg.length();
        recontact[k] = Some(((j, cp), slid));
        if !slid {
            continue;
        }
        for s in view.adjoining(k, nseg).into_iter().flatten() {
            // Contactor segment s runs from node s to node s + 1.
            let tau = x[(s + 1) % m] - x[s];
            let seg = &mut mem.segments[s];
            if seg.state != NodeState::Stick || rec.prev[s] == SegmentState::Open {
                seg.state = NodeState::Slip;
                seg.direction = -slip.dot(&tau).signum();
                seg.ever_slid = true;
            }
        }
    }
    recontact
}

/// Return to sticking, per segment: a segment that slides on in the
/// direction it kept, while the slip of its nodes from their anchors runs
/// along its friction (the uniform friction of Fig. 5 would do work over
/// the increment: the drag has reversed), sticks; Table 1 then puts its
/// nodes back at their anchors, and the next decision checks the capacity
/// and takes the new direction. Coulomb is applied over the segment
/// (Section 3), and so is this check: the uniform friction loads a node
/// next to a heavily loaded one with half the segment's friction whatever
/// its own normal force, so a single node's slip may run along its share
/// while the segment dissipates.
fn return_to_sticking(
    view: &PaperPair,
    rec: &Recovered,
    mem: &mut PairMemory,
    log: &mut dyn FnMut(&str),
) {
    let (segments, x, active) = (&view.segments, &view.x, &rec.active);
    let m = x.len();
    let slips: Vec<Option<Vector2<f64>>> = (0..m)
        .map(|k| {
            let node = &mem.nodes[k];
            if !active[k] || node.state != NodeState::Slip {
                return None;
            }
            let (sa, ba) = node.anchor?;
            let (_, cp) = follow(segments, node.segment, x[k], view.reach)?;
            (sa < segments.len()).then(|| cp.point() - segments[sa].seg.point_at(ba))
        })
        .collect();
    for s in 0..mem.segments.len() {
        let seg = mem.segments[s];
        if seg.state != NodeState::Slip
            || rec.prev[s] != SegmentState::Slide
            || seg.direction == 0.0
        {
            continue;
        }
        let (a, b) = (s, (s + 1) % m);
        // Only a segment that slides as a whole: a node in contact at
        // either end that is held by its other segment (Table 1)
        // does not slide, and the friction's share at the free node
        // alone says nothing of the segment's slip.
        if [a, b].iter().any(|&k| active[k] && slips[k].is_none()) {
            continue;
        }
        let d = x[b] - x[a];
        let tau = d / d.norm();
        let slip: f64 = [a, b]
            .iter()
            .filter_map(|&k| slips[k])
            .map(|v| v.dot(&tau))
            .sum();
        if slip * seg.direction > 0.0 && slip.abs() > 1e-12 * d.norm() {
            log(&format!(
                "pair '{}' segment {s}: slip {slip:.3e} along its friction, sticks",
                view.pair.name
            ));
            mem.segments[s].state = NodeState::Stick;
            mem.segments[s].direction = 0.0;
        }
    }
}

/// Table 1 on the segment states as they now are.
fn table1(view: &PaperPair, rec: &Recovered, mem: &PairMemory) -> Vec<NodeState> {
    let nseg = mem.segments.len();
    (0..view.x.len())
        .map(|k| {
            let has = |st: NodeState| {
                view.adjoining(k, nseg)
                    .into_iter()
                    .flatten()
                    .any(|s| mem.segments[s].state == st)
            };
            if !rec.active[k] || rec.ev.node_states[k] == NodeState::Open {
                NodeState::Open
            } else if has(NodeState::Stick) {
                NodeState::Stick
            } else if has(NodeState::Slip) {
                NodeState::Slip
            } else {
                NodeState::Open
            }
        })
        .collect()
}

/// One node's contact after the decisions: its state, where it meets the
/// target, the force its rows carry, and whether it is held at a corner.
struct NodeContact {
    state: NodeState,
    point: Option<(usize, ContactPoint)>,
    lambda: Vector2<f64>,
    at_corner: bool,
}

/// State decisions, per node: the state Table 1 gives node k (`state`) and
/// where it meets the target now. A node that sticks on keeps its material
/// point; one that sticks anew or slides is followed along the target
/// (`follow_node`); a node released in this iteration still sits on the
/// target to round-off: it is not searched again until it has moved, and
/// one that was open comes back where it has penetrated (`recontact`).
fn node_contact(
    view: &PaperPair,
    rec: &Recovered,
    k: usize,
    old: &NodeMemory,
    state: NodeState,
    recontact: Recontact,
    log: &mut dyn FnMut(&str),
) -> NodeContact {
    let mut contact = NodeContact {
        state,
        point: None,
        lambda: Vector2::zeros(),
        at_corner: false,
    };
    if rec.active[k] && state != NodeState::Open {
        let f = rec.ev.forces[k];
        contact.lambda = Vector2::new(f[0], f[1]);
    }
    match state {
        NodeState::Stick if old.state == NodeState::Stick => {
            let seg = &view.segments[old.segment].seg;
            contact.point = Some((old.segment, seg.contact_at(view.x[k], old.beta)));
        }
        NodeState::Stick | NodeState::Slip => follow_node(view, rec, k, old, &mut contact, log),
        NodeState::Open if old.state == NodeState::Open => {
            if let Some((found, slid)) = recontact {
                contact.point = Some(found);
                // A new contact sticks (slides if frictionless); one that
                // has slid while free comes back sliding.
                contact.state = if slid || view.frictionless {
                    NodeState::Slip
                } else {
                    NodeState::Stick
                };
            }
        }
        NodeState::Open => {}
    }
    contact
}

/// A node in contact that Table 1 makes slide, or stick anew: followed
/// along the target (segment switching), held at a reflex corner when
/// frictionless, released when its force pulls or it has slid off the
/// target, and sent back to its anchor when it sticks.
fn follow_node(
    view: &PaperPair,
    rec: &Recovered,
    k: usize,
    old: &NodeMemory,
    contact: &mut NodeContact,
    log: &mut dyn FnMut(&str),
) {
    let (segments, x, pair) = (&view.segments, view.x[k], view.pair);
    let mut point = follow(segments, old.segment, x, view.reach);
    let tol = TENSION_TOLERANCE * rec.force_scale;
    // Frictionless at a reflex corner of the target: held at
    // the corner while its force lies in the cone of the two
    // segments' normals, else sliding on the segment that can
    // carry it (docs/contact.md item 10).
    if view.frictionless
        && contact.state == NodeState::Slip
        && let Some((j, _)) = point
        && let Some((end_j, i, end_i)) = corner(segments, old.segment, j, x, old)
    {
        let (nj, ni) = (segments[j].seg.normal(), segments[i].seg.normal());
        let f = rec.force[k];
        // f = -(a n_j + b n_i): the target pushes the node out.
        let det = nj.x * ni.y - nj.y * ni.x;
        let a = -(f.x * ni.y - f.y * ni.x) / det;
        let b = -(nj.x * f.y - nj.y * f.x) / det;
        if a >= -tol && b >= -tol {
            point = Some((j, segments[j].seg.contact_at(x, end_j)));
            contact.at_corner = true;
        } else if a < -tol && b >= -tol {
            point = Some((i, segments[i].seg.contact_at(x, end_i)));
        }
    }
    // Beyond the segment release of Section 3.2: a node
    // whose own contact force pulls it into the target
    // (tension) is released.
    if let Some((j, _)) = point.as_ref() {
        let pull = segments[*j].seg.normal().dot(&rec.force[k]);
        if pull > tol {
            log(&format!(
                "pair '{}' node {k}: contact force in tension ({pull:.3e}), released",
                pair.name
            ));
            point = None;
        }
    }
    if point.is_none() {
        log(&format!(
            "pair '{}' node {k}: no longer in contact, released",
            pair.name
        ));
        contact.state = NodeState::Open;
        contact.lambda = Vector2::zeros();
    }
    // A sliding node that Table 1 makes stick also goes
    // back to its anchor: sticking means no slip over the
    // increment (see `anchor_point`).
    if contact.state == NodeState::Stick
        && point.is_some()
        && let Some(at) = anchor_point(segments, old.anchor, x, view.reach)
    {
        point = Some(at);
    }
    contact.point = point;
}

/// Constraint rows and reported results for node k after its decision
/// (`old` its memory before): its rows of Eq. (18) (the paper's friction
/// held over the iteration: none in the multiplier's column), its reported
/// force and tractions, and its memory after the iteration (returned).
fn node_rows(
    view: &PaperPair,
    rec: &Recovered,
    k: usize,
    old: &NodeMemory,
    contact: NodeContact,
    report: &mut Report,
    out: &mut ContactSystem,
) -> NodeMemory {
    let NodeContact {
        state,
        point,
        mut lambda,
        mut at_corner,
    } = contact;
    at_corner &= state != NodeState::Open;
    if state != old.state || at_corner != old.corner {
        out.changes += 1;
    }
    let mut node = NodeMemory {
        state,
        corner: at_corner,
        ..*old
    };
    if let Some((j, cp)) = point.filter(|_| state != NodeState::Open) {
        if old.state != NodeState::Open && j != old.segment {
            node.crossed = Some((old.segment, j));
        }
        node.segment = j;
        node.beta = cp.beta();
        // The anchor moves only when an increment begins: a node
        // that sticks is at its anchor (or new to contact).
        if node.anchor.is_none() {
            node.anchor = Some((j, cp.beta()));
        }
        let held = state == NodeState::Stick || at_corner;
        if held && at_corner && rec.active[k] {
            // Held in both directions: its whole force.
            lambda = rec.force[k];
        }
        if !held && view.frictionless && rec.active[k] {
            // No friction: the force is along the target normal.
            // (The recovery's contactor-frame normals would leave
            // a component along the target that no row carries:
            // a phantom friction, and a linear Newton rate.)
            let n = cp.segment().normal();
            lambda = n * n.dot(&rec.force[k]);
        }
        // The paper's friction is held over the iteration: no
        // friction in the multiplier's column.
        let n = view.pair.contactor[k];
        add_rows(view.segments[j].nodes, n, &cp, held, lambda, 0.0, out);
        report.contact(view.at, view.pair, k, rec.reported(k), &cp, &mut out.rigid);
    }
    // The paper's decisions read tractions: its nodes' forces are taken
    // as their tractions' signs.
    let (tn, tt) = if state == NodeState::Open {
        (0.0, 0.0)
    } else {
        (rec.area.tn[k], rec.area.tt[k])
    };
    report.result.nodes.tn.push(tn);
    report.result.nodes.tt.push(tt);
    report.node(view.x[k], state, [tn, tt]);
    node
}

/// Reported tractions on 8-node sides: recovered with the sides' own
/// quadratic shape functions from the forces of the nodes in contact
/// (the paper's linear recovery, used for the decisions above, makes
/// corner and mid-side values alternate on 8-node sides).
fn quadratic_report(view: &PaperPair, rec: &Recovered, report: &mut Report) {
    let (problem, pair, m) = (view.at.problem, view.pair, view.x.len());
    let q8 = problem.bodies[pair.body]
        .elements
        .clone()
        .next()
        .is_some_and(|e| problem.mesh.elements[e].kind == crate::mesh::ElementKind::Q8);
    if !(q8 && m % 2 == (if pair.closed { 0 } else { 1 })) {
        return;
    }
    let result = &mut report.result;
    let closed_now: Vec<bool> = (0..m)
        .map(|k| result.nodes.state[k] != NodeState::Open)
        .collect();
    let f: Vec<Vector2<f64>> = (0..m)
        .map(|k| {
            if closed_now[k] && rec.active[k] {
                rec.reported(k)
            } else {
                Vector2::zeros()
            }
        })
        .collect();
    let geometry = geometry(problem);
    let Some(t) = quadratic_tractions(geometry, pair.closed, &rec.area.x, &closed_now, &f) else {
        return;
    };
    for k in 0..m {
        if !closed_now[k] {
            continue;
        }
        // The target's frame where the node touches it: the
        // contactor's own frame tilts at the contact edge,
        // where its next side lifts off, and would show a
        // normal force as a tangential traction.
        let (tau, nu) = report.frames[k].unwrap_or_else(|| node_frame(&view.x, pair.closed, k));
        result.nodes.tn[k] = t[k].dot(&nu);
        result.nodes.tt[k] = t[k].dot(&tau);
    }
}

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

/// Reported nodal tractions `t_n`, `t_t` of a pair from the forces of its
/// nodes in contact (`frames[k]`: the target's tangent toward the next
/// contactor node and inward normal where node k touches; None: open), per
/// unit area of the configuration the element stresses are written on (the
/// reference one under small strain, the current one under total
/// Lagrangian kinematics). 8-node sides use their quadratic shape
/// functions, 4-node sides `recovery` (Eqs. 26/27 or lumped).
pub(super) fn reported_tractions(
    problem: &Problem,
    pair: &ContactPair,
    x: &[Vector2<f64>],
    active: &[bool],
    force: &[Vector2<f64>],
    frames: &[Option<(Vector2<f64>, Vector2<f64>)>],
    recovery: crate::problem::Recovery,
) -> Result<(Vec<f64>, Vec<f64>), String> {
    let geometry = geometry(problem);
    let m = x.len();
    let reference_area = matches!(
        problem.kinematics,
        Kinematics::SmallStrain | Kinematics::MaterialNonlinearOnly
    );
    let x_area: Vec<Vector2<f64>> = if reference_area {
        (pair.contactor.iter())
            .map(|&n| Vector2::new(problem.mesh.nodes[n][0], problem.mesh.nodes[n][1]))
            .collect()
    } else {
        x.to_vec()
    };
    let on: Vec<bool> = (0..m).map(|k| frames[k].is_some() && active[k]).collect();
    let f: Vec<Vector2<f64>> = (0..m)
        .map(|k| if on[k] { force[k] } else { Vector2::zeros() })
        .collect();
    let q8 = problem.bodies[pair.body]
        .elements
        .clone()
        .next()
        .is_some_and(|e| problem.mesh.elements[e].kind == crate::mesh::ElementKind::Q8);
    let quadratic = if q8 && m % 2 == (if pair.closed { 0 } else { 1 }) {
        quadratic_tractions(geometry, pair.closed, &x_area, &on, &f)
    } else {
        None
    };
    let t = match quadratic {
        Some(t) => t,
        None => {
            let xs: Vec<[f64; 2]> = x_area.iter().map(|v| [v.x, v.y]).collect();
            let fs: Vec<[f64; 2]> = f.iter().map(|v| [v.x, v.y]).collect();
            let chain = traction::Chain::new(geometry, pair.closed, &xs)
                .map_err(|e| format!("pair '{}': {e}", pair.name))?;
            traction::recover_tractions(&chain, recovery, &on, &fs)
                .map_err(|e| format!("pair '{}': {e}", pair.name))?
                .into_iter()
                .map(|t| Vector2::new(t[0], t[1]))
                .collect()
        }
    };
    Ok((0..m)
        .map(|k| match frames[k] {
            Some((tau, nu)) if on[k] => (t[k].dot(&nu), t[k].dot(&tau)),
            _ => (0.0, 0.0),
        })
        .unzip())
}

/// Unit tangent (toward the next node) and inward normal of a contactor
/// chain at node k: the average of its segments' directions.
pub(super) fn node_frame(
    x: &[Vector2<f64>],
    closed: bool,
    k: usize,
) -> (Vector2<f64>, Vector2<f64>) {
    let m = x.len();
    let mut tau = Vector2::zeros();
    if k + 1 < m || closed {
        tau += (x[(k + 1) % m] - x[k]).normalize();
    }
    if k > 0 || closed {
        tau += (x[k] - x[(k + m - 1) % m]).normalize();
    }
    let tau = tau.normalize();
    (tau, Vector2::new(-tau.y, tau.x))
}

/// Nodal tractions on a chain of 8-node sides (corner, mid-side, corner,
/// ...) from nodal forces: the consistent system of the quadratic side
/// interpolation, over the nodes in contact (the others carry zero). Weights
/// by 3-point Gauss integration, exact for the quadratic-times-quadratic
/// (times linear radius) integrands of straight sides. None if singular or
/// too large for the dense solve (then the linear recovery stays).
pub(super) fn quadratic_tractions(
    geometry: Geometry,
    closed: bool,
    x: &[Vector2<f64>],
    on: &[bool],
    f: &[Vector2<f64>],
) -> Option<Vec<Vector2<f64>>> {
    let m = x.len();
    let index: Vec<Option<usize>> = {
        let mut next = 0;
        on.iter()
            .map(|&a| {
                a.then(|| {
                    next += 1;
                    next - 1
                })
            })
            .collect()
    };
    let n = on.iter().filter(|&&a| a).count();
    if n == 0 || n > 600 {
        return None;
    }
    let mut a = nalgebra::DMatrix::<f64>::zeros(n, n);
    let sides = if closed { m / 2 } else { (m - 1) / 2 };
    // Per node: the integral of its shape function over its sides (the
    // lumped tributary), and whether one of its sides is partly open.
    let mut tributary = vec![0.0; m];
    let mut edge = vec![false; m];
    let gauss = [
        (-(0.6f64).sqrt(), 5.0 / 9.0),
        (0.0, 8.0 / 9.0),
        ((0.6f64).sqrt(), 5.0 / 9.0),
    ];
    for s in 0..sides {
        let nodes = [2 * s, 2 * s + 1, (2 * s + 2) % m];
        if nodes.iter().any(|&k| !on[k]) {
            for &k in &nodes {
                edge[k] = true;
            }
        }
        for &(xi, w) in &gauss {
            let nshape = [0.5 * xi * (xi - 1.0), 1.0 - xi * xi, 0.5 * xi * (xi + 1.0)];
            let dshape = [xi - 0.5, -2.0 * xi, xi + 0.5];
            let mut dx = Vector2::zeros();
            let mut pos = Vector2::zeros();
            for i in 0..3 {
                dx += dshape[i] * x[nodes[i]];
                pos += nshape[i] * x[nodes[i]];
            }
            let weight = w
                * dx.norm()
                * match geometry {
                    Geometry::Planar { thickness } => thickness,
                    Geometry::Axisymmetric => 2.0 * std::f64::consts::PI * pos.x,
                };
            for i in 0..3 {
                tributary[nodes[i]] += weight * nshape[i];
                let Some(r) = index[nodes[i]] else { continue };
                for j in 0..3 {
                    if let Some(c) = index[nodes[j]] {
                        a[(r, c)] += weight * nshape[i] * nshape[j];
                    }
                }
            }
        }
    }
    let lu = a.lu();
    let mut t = vec![Vector2::zeros(); m];
    for comp in 0..2 {
        let b = nalgebra::DVector::from_iterator(n, (0..m).filter(|&k| on[k]).map(|k| f[k][comp]));
        let sol = lu.solve(&b)?;
        for k in 0..m {
            if let Some(r) = index[k] {
                t[k][comp] = sol[r];
            }
        }
    }
    // On a side partly open the traction is not quadratic (it falls to
    // zero like a square root at the contact edge): its closed nodes report
    // their force over their tributary instead of the quadratic fit, which
    // overshoots there.
    for k in 0..m {
        if on[k] && edge[k] && tributary[k] > 0.0 {
            t[k] = f[k] / tributary[k];
        }
    }
    t.iter()
        .all(|v| v.x.is_finite() && v.y.is_finite())
        .then_some(t)
}

/// Whether any dof of `rows` is prescribed in `eq`.
pub fn touches_prescribed(rows: &[Row], eq: &[u32]) -> bool {
    rows.iter()
        .any(|r| r.dofs.iter().any(|&(d, _)| eq[d] == PRESCRIBED))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seg(a: [f64; 2], b: [f64; 2]) -> TargetSegment {
        let (xa, xb) = (Vector2::new(a[0], a[1]), Vector2::new(b[0], b[1]));
        TargetSegment {
            seg: Segment::new(xa, xb).unwrap(),
            nodes: None,
            lo: [a[0].min(b[0]), a[1].min(b[1])],
            hi: [a[0].max(b[0]), a[1].max(b[1])],
        }
    }

    /// A foot of the normal just beyond an end is referred to the end node:
    /// beta exactly 1, the same normal overlap; beyond the tolerance, none.
    #[test]
    fn contact_point_beyond_an_end_is_the_end_node() {
        let s = seg([0.0, 0.0], [1.0, 0.0]);
        let x = Vector2::new(1.0 + 1e-8, 1e-8);
        let raw = s.seg.project(x);
        let cp = on_segment(&s.seg, x).unwrap();
        assert_eq!(cp.beta(), 1.0);
        assert!(raw.beta() > 1.0);
        assert_eq!(cp.normal_overlap(), raw.normal_overlap());
        assert_eq!(cp.point(), s.seg.xb());
        assert!(on_segment(&s.seg, Vector2::new(1.0 + 1e-3, 0.0)).is_none());
        let inside = on_segment(&s.seg, Vector2::new(0.25, 0.1)).unwrap();
        assert_eq!(inside.beta(), 0.25);
    }

    /// Reflex corners: the body lies to the left of A -> B, so a surface
    /// that turns right (round a hole) has reflex corners, one that turns
    /// left (round a disk) does not; a straight one has no corner.
    #[test]
    fn reflex_corners_turn_right() {
        // Turning right: (0,0) -> (1,0) -> (2,-0.1), body above.
        let right = [seg([0.0, 0.0], [1.0, 0.0]), seg([1.0, 0.0], [2.0, -0.1])];
        assert_eq!(reflex(&right, 0, 1.0), Some((1, 0.0)));
        assert_eq!(reflex(&right, 1, 0.0), Some((0, 1.0)));
        assert_eq!(reflex(&right, 0, 0.0), None);
        let left = [seg([0.0, 0.0], [1.0, 0.0]), seg([1.0, 0.0], [2.0, 0.1])];
        assert_eq!(reflex(&left, 0, 1.0), None);
        let straight = [seg([0.0, 0.0], [1.0, 0.0]), seg([1.0, 0.0], [2.0, 0.0])];
        assert_eq!(reflex(&straight, 0, 1.0), None);
    }

    /// A node is at a corner when it slides back across one it crossed in
    /// the increment, or when it is held there and lies beyond both
    /// segments' ends; not when it crosses once.
    #[test]
    fn corner_after_crossing_back_or_while_held() {
        let s = [seg([0.0, 0.0], [1.0, 0.0]), seg([1.0, 0.0], [2.0, -0.1])];
        // Penetrated 1e-7 into the body (above) at the corner: beyond the
        // end of both segments.
        let x = Vector2::new(1.0, 1e-7);
        assert!(s[0].seg.project(x).beta() >= 1.0 && s[1].seg.project(x).beta() < 0.0);
        let fresh = NodeMemory::default();
        assert_eq!(corner(&s, 1, 0, x, &fresh), None, "crossing once");
        let back = NodeMemory {
            crossed: Some((0, 1)),
            ..fresh
        };
        assert_eq!(corner(&s, 1, 0, x, &back), Some((1.0, 1, 0.0)));
        let held = NodeMemory {
            corner: true,
            ..fresh
        };
        assert_eq!(corner(&s, 0, 0, x, &held), Some((1.0, 1, 0.0)));
        // Held, but now inside segment 0: it has left the corner.
        assert_eq!(corner(&s, 0, 0, Vector2::new(0.5, 1e-7), &held), None);
    }

    /// A free node that has penetrated next to a reflex corner, in the
    /// wedge between the two segments' normals, is found at the corner.
    #[test]
    fn a_node_in_the_wedge_of_a_reflex_corner_is_found_at_the_corner() {
        // A valley (the target body below, walked from +x to -x): a node
        // 0.01 below its bottom projects beyond the end of both segments
        // (beta = 1.001 and -0.001).
        let valley = [seg([1.0, 0.1], [0.0, 0.0]), seg([0.0, 0.0], [-1.0, 0.1])];
        let x = Vector2::new(0.0, -0.01);
        for s in &valley {
            assert!(on_segment(&s.seg, x).is_none());
        }
        let (_, cp) = search(&TargetSet::new(valley.into()), x, 1.0, false)
            .expect("penetrated node not found");
        assert_eq!(cp.point(), Vector2::zeros());
        assert!(cp.normal_overlap() > 0.0099 && cp.normal_overlap() <= 0.01);
    }

    #[test]
    fn a_node_past_the_end_of_a_target_by_more_than_its_overlap_is_not_found() {
        let flat = TargetSet::new(vec![seg([1.0, 0.0], [0.0, 0.0])]);
        assert!(search(&flat, Vector2::new(-0.05, -0.01), 1.0, false).is_none());
        // Within its overlap of the end it is held at the end.
        let (_, cp) = search(&flat, Vector2::new(-0.005, -0.01), 1.0, false).unwrap();
        assert_eq!(cp.beta(), 1.0);
    }

    /// Numbers uniform in [0, 1) from `seed` (a linear congruential
    /// generator: the tests' points and reaches, the same at every run).
    fn uniform(seed: u64) -> impl FnMut() -> f64 {
        let mut state = seed;
        move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// A node's searches through the cache (`SearchCache`) find what fresh
    /// searches find, while the node wanders in small and large steps about
    /// the capstan's drum with reaches that grow and shrink, and when the
    /// segments are another set (a new pose): its candidates are read again.
    #[test]
    fn cached_searches_find_what_fresh_searches_find() {
        let arc = |shift: f64| -> Vec<TargetSegment> {
            (0..2000)
                .map(|k| {
                    let at = |k: usize| {
                        let a = -0.4 + 3.9 * k as f64 / 2000.0;
                        [100.0 * a.cos() + shift, 100.0 * a.sin()]
                    };
                    seg(at(k), at(k + 1))
                })
                .collect()
        };
        let sets = [
            Arc::new(TargetSet::new(arc(0.0))),
            Arc::new(TargetSet::new(arc(0.5))),
        ];
        let mut random = uniform(777);
        let mut cache = SearchCache::default();
        let mut x = Vector2::new(99.5, 3.0);
        let (mut hits, mut found) = (0, 0);
        for step in 0..4000 {
            let big = random() < 0.05;
            let d = if big { 3.0 } else { 0.02 };
            x += Vector2::new(d * (2.0 * random() - 1.0), d * (2.0 * random() - 1.0));
            let reach = [0.5, 1.0, 2.0, 5.0][(4.0 * random()) as usize % 4];
            let segments = &sets[usize::from(step % 500 >= 250)];
            let before = cache.0.get(&(0, 7)).map(|c| c.candidates.len());
            let cached = cache.search((0, 7), segments, x, reach);
            hits += usize::from(
                before.is_some() && cache.0[&(0, 7)].candidates.len() == before.unwrap(),
            );
            found += usize::from(cached.is_some());
            assert_eq!(
                cached,
                search(segments, x, reach, false),
                "at {x:?}, reach {reach}"
            );
        }
        // Both paths taken, and contacts found as well as not.
        assert!(
            hits > 1000 && found > 100 && found < 3900,
            "{hits} hits, {found} found"
        );
    }

    /// The grid only narrows the candidates: `search`, `follow` and the
    /// outputs' `nearest` give exactly what a scan of every segment gives,
    /// on a fine arc (the capstan's drum), a wall (no extent across) and a
    /// zigzag, at points near and far, for reaches small and large.
    #[test]
    fn the_grid_finds_what_a_full_scan_finds() {
        let arc: Vec<TargetSegment> = (0..2000)
            .map(|k| {
                let at = |k: usize| {
                    let a = -0.4 + 3.9 * k as f64 / 2000.0;
                    [100.0 * a.cos(), 100.0 * a.sin()]
                };
                seg(at(k), at(k + 1))
            })
            .collect();
        let wall: Vec<TargetSegment> = (0..64)
            .map(|k| seg([1.0, 64.0 - k as f64], [1.0, 63.0 - k as f64]))
            .collect();
        let zigzag: Vec<TargetSegment> = (0..100)
            .map(|k| {
                let y = |k: usize| if k.is_multiple_of(2) { 0.0 } else { 0.3 };
                seg([k as f64 * 0.1, y(k)], [(k + 1) as f64 * 0.1, y(k + 1)])
            })
            .collect();
        let mut random = uniform(12345);
        for (list, centre, size) in [
            (arc, [0.0, 0.0], 110.0),
            (wall, [1.0, 32.0], 40.0),
            (zigzag, [5.0, 0.15], 6.0),
        ] {
            let n = list.len();
            let gridded = TargetSet::new(list.clone());
            assert!(gridded.grid.is_some());
            let scanned = TargetSet { list, grid: None };
            for _ in 0..3000 {
                let near = random() < 0.5;
                let r = if near { 0.05 * size } else { size };
                let x = Vector2::new(
                    centre[0] + r * (2.0 * random() - 1.0),
                    centre[1] + r * (2.0 * random() - 1.0),
                );
                let reach = [1e-3, 0.1, 3.0, 1e3][(4.0 * random()) as usize % 4] * size / 100.0;
                let touching = random() < 0.5;
                let j = (random() * n as f64) as usize % n;
                assert_eq!(
                    search(&gridded, x, reach, touching),
                    search(&scanned, x, reach, touching),
                    "search at {x:?}, reach {reach}"
                );
                assert_eq!(
                    follow(&gridded, j, x, reach),
                    follow(&scanned, j, x, reach),
                    "follow from {j} at {x:?}, reach {reach}"
                );
                assert_eq!(
                    super::super::outputs::nearest(&gridded, x),
                    super::super::outputs::nearest(&scanned, x),
                    "nearest to {x:?}"
                );
            }
        }
    }
}
