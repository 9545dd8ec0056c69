//! Contact search: a target's segments at an iterate (a rigid target's kept
//! per pose), the grid and caches that narrow the candidates, and where a
//! contactor node meets the target (projection, following a sliding node
//! across segments, reflex corners).

use super::PairMemory;
use super::segment::{ContactPoint, Segment};
use crate::problem::{ContactPair, Problem, Target};
use crate::results::NodeState;
use nalgebra::Vector2;
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

/// Contact points this far (in beta) outside a segment still count as on it,
/// so round-off at a target node does not lose the contact.
pub(crate) const BETA_TOLERANCE: f64 = 1e-6;

/// A target segment at the current time: end points and node numbers
/// (None for a rigid target), and on a smoothed target the outer
/// neighbours' node numbers `[P, Q]` (None at an end of the target, where
/// the curve mirrors the end node).
#[derive(Clone)]
pub(crate) struct TargetSegment {
    pub(crate) seg: Segment,
    pub(crate) nodes: Option<[usize; 2]>,
    pub(crate) around: [Option<usize>; 2],
    lo: [f64; 2],
    hi: [f64; 2],
}

impl TargetSegment {
    /// Whether `x` lies within `reach` of the segment's bounding box.
    fn within(&self, x: Vector2<f64>, reach: f64) -> bool {
        !(x.x < self.lo[0] - reach
            || x.x > self.hi[0] + reach
            || x.y < self.lo[1] - reach
            || x.y > self.hi[1] + reach)
    }

    /// The segment's box: its ends', or a smoothed segment's Bezier control
    /// points' (the curve lies in their hull).
    pub(crate) fn new(seg: Segment, nodes: Option<[usize; 2]>) -> Self {
        let (xa, xb) = (seg.xa(), seg.xb());
        let mut lo = [xa.x.min(xb.x), xa.y.min(xb.y)];
        let mut hi = [xa.x.max(xb.x), xa.y.max(xb.y)];
        if let (Some(c0), Some(c1)) = (seg.curve(0.0), seg.curve(1.0)) {
            for p in [xa + c0.d1 / 3.0, xb - c1.d1 / 3.0] {
                lo = [lo[0].min(p.x), lo[1].min(p.y)];
                hi = [hi[0].max(p.x), hi[1].max(p.y)];
            }
        }
        TargetSegment {
            seg,
            nodes,
            around: [None; 2],
            lo,
            hi,
        }
    }
}

pub(crate) fn position(problem: &Problem, u: &[f64], n: usize) -> Vector2<f64> {
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
/// (what `Rigid::points_at` also returns, without building the points).
pub fn rigid_reference(problem: &Problem, r: usize, pose: [f64; 3]) -> [f64; 2] {
    let [cx, cy] = problem.rigids[r].reference;
    [cx + pose[0], cy + pose[1]]
}

/// A target's segments, shared: a rigid target's are kept per pose.
pub(crate) type Segments = Arc<TargetSet>;

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
    pub(crate) fn search(
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
pub(crate) struct TargetSet {
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
    pub(crate) fn new(list: Vec<TargetSegment>) -> Self {
        let grid = (list.len() >= GRID_FROM)
            .then(|| Grid::new(&list))
            .flatten();
        TargetSet { list, grid }
    }

    /// The indices, ascending, of the segments whose boxes meet the box
    /// `[lo, hi]` (and maybe a few more near it).
    pub(crate) fn candidates(&self, lo: [f64; 2], hi: [f64; 2]) -> Vec<u32> {
        match &self.grid {
            Some(g) => g.candidates(lo, hi, self.list.len()),
            None => (0..self.list.len() as u32).collect(),
        }
    }

    /// The segments of `candidates` in index order.
    pub(crate) fn visit(
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

/// The segments of `pair`'s target at displacements `u` and rigid target
/// poses `poses` (a rigid target's from `targets`, built once per pose).
pub(crate) fn target_segments(
    targets: &RigidSegments,
    problem: &Problem,
    pair: &ContactPair,
    u: &[f64],
    poses: &[[f64; 3]],
) -> Result<Segments, String> {
    let make = |xa: Vector2<f64>, xb: Vector2<f64>, nodes| {
        let seg = Segment::new(xa, xb).map_err(|e| format!("pair '{}': {e}", pair.name))?;
        Ok(TargetSegment::new(seg, nodes))
    };
    match &pair.target {
        Target::Body {
            segments, smooth, ..
        } => (segments.iter().enumerate())
            .map(|(j, &[a, b])| {
                let (xa, xb) = (position(problem, u, a), position(problem, u, b));
                let Some(around) = smooth.as_ref().and_then(|s| s.get(j)) else {
                    return make(xa, xb, Some([a, b]));
                };
                // At an end of the target the end node is mirrored.
                let [p, q] = *around;
                let xp = p.map_or(2.0 * xa - xb, |p| position(problem, u, p));
                let xq = q.map_or(2.0 * xb - xa, |q| position(problem, u, q));
                let seg = Segment::new(xa, xb).map_err(|e| format!("pair '{}': {e}", pair.name))?;
                let mut s = TargetSegment::new(seg.smoothed([xp, xq]), Some([a, b]));
                s.around = [p, q];
                Ok(s)
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
            targets.get_or_build(*r, key, || {
                let (points, _) = problem.rigids[*r].points_at(poses[*r]);
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
    targets: &RigidSegments,
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
        let segments = target_segments(targets, problem, pair, u, poses)?;
        let near = (pair.contactor.iter().enumerate())
            .filter_map(|(k, &n)| {
                if memory[p].state(k) != NodeState::Open {
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
pub(crate) fn on_segment(seg: &Segment, x: Vector2<f64>) -> Option<ContactPoint> {
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
pub(crate) fn search(
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
        if !s.within(x, reach) {
            continue;
        }
        let Some(cp) = on_segment(&s.seg, x) else {
            // A smoothed target has no corners, and so no wedge.
            if s.seg.is_smooth() {
                continue;
            }
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
pub(crate) fn follow(
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
        if !s.within(x, reach) {
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

/// The reflex corner at an end of segment `j` that a node at `x` lies
/// within `tol` (in beta) of, with the node's beta on either segment:
/// `(end_j, beta_j, i, end_i, beta_i)`, the corner being the end `end_j` of
/// `j` and `end_i` of the other segment `i`.
pub(crate) fn near_reflex(
    segments: &[TargetSegment],
    j: usize,
    x: Vector2<f64>,
    tol: f64,
) -> Option<(f64, f64, usize, f64, f64)> {
    let beta = segments[j].seg.project(x).beta();
    let end_j = if beta >= 1.0 - tol {
        1.0
    } else if beta <= tol {
        0.0
    } else {
        return None;
    };
    let (i, end_i) = reflex(segments, j, end_j)?;
    Some((end_j, beta, i, end_i, segments[i].seg.project(x).beta()))
}

/// Whether `beta` lies at or beyond the end `end` of its segment (to `tol`).
pub(crate) fn at_end(beta: f64, end: f64, tol: f64) -> bool {
    if end == 0.0 {
        beta <= tol
    } else {
        beta >= 1.0 - tol
    }
}

/// The segment meeting segment `j` at its end `end_j` (beta 0 or 1) when the
/// target body's angle there exceeds 180 degrees (a reflex corner, as round
/// a hole): `(i, end_i)`. The body lies to the left of the segments, so
/// walking along the surface a reflex corner turns right.
pub(crate) fn reflex(segments: &[TargetSegment], j: usize, end_j: f64) -> Option<(usize, f64)> {
    let s = &segments[j].seg;
    // A smoothed target turns smoothly at its nodes: no corner.
    if s.is_smooth() {
        return None;
    }
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

/// The positions of `pair`'s contactor nodes at displacements `u`.
pub(crate) fn contactor_positions(
    problem: &Problem,
    pair: &ContactPair,
    u: &[f64],
) -> Vec<Vector2<f64>> {
    (pair.contactor.iter())
        .map(|&n| position(problem, u, n))
        .collect()
}

#[cfg(test)]
mod tests;
