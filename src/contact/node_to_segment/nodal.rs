//! Contact states decided node by node on the current iterate (the default
//! `decisions = "nodal"`): each contactor node's normal and tangential force
//! (its out-of-balance force, as the paper recovers it), its gap, and its
//! slip from where it was on the target when the increment began decide
//! open, stick or slip at every iteration, as a semismooth Newton does on
//! the complementarity conditions (Hueber, Stadler & Wohlmuth 2008). The
//! friction of a sliding node is `mu_d p_n` with `p_n` the unknown normal
//! force, so its row is linearised consistently and Newton converges
//! quadratically once the states settle (docs/contact.md section 8).

use super::decision::Decision;
use super::memory::{Memory, NodeMemory};
use super::reported::reported_tractions;
use super::rows::add_rows;
use super::{Nodal, TENSION_TOLERANCE, linearise};
use crate::assembly::PRESCRIBED;
use crate::contact::Formulation;
use crate::contact::Prediction;
use crate::contact::report::Report;
use crate::contact::search::{
    self, SearchCache, Segments, TargetSegment, contactor_positions, target_segments,
};
use crate::contact::segment::ContactPoint;
use crate::contact::sensitivity::{At, Linearised};
use crate::contact::system::{self, ContactSystem, Forced, Iterate, count_flip, count_slip};
use crate::contact::{Kept, PairMemory, mismatch};
use crate::problem::{ContactPair, FrictionRule, Recovery, Target};
use crate::results::{NodeState, PairResult};
use nalgebra::Vector2;

/// What `Nodal::update` does: decide every node from the iterate, or keep
/// the decisions it made at this iterate except the forced nodes'.
enum Plan<'a> {
    Decide,
    Keep {
        kept: &'a Decided,
        forced: &'a [(usize, Forced)],
    },
}

/// A pair's decisions at an iterate, kept for its inner solves and for the
/// linearisation of a converged state (`contact::Kept`).
pub(crate) struct Decided {
    pub(super) decisions: Vec<Decision>,
    /// Which nodes were in contact when the iterate's decisions were made:
    /// their out-of-balance forces are contact forces (a node the
    /// linearised problem closes carries none yet).
    active: Vec<bool>,
}

/// How near a reflex corner (in beta, of either segment) a frictionless node
/// is taken to be at it.
const CORNER_REACH: f64 = 1e-3;

/// How near a reflex corner (in beta) a frictionless node that has just
/// crossed back over it is tested at it (`corner`): anywhere on the half
/// of the segment next to the corner.
const CROSSED_BACK_REACH: f64 = 0.5;

/// Times a frictionless node may leave a corner hold in one increment and
/// be held again when it comes back within `CORNER_REACH`: the force of an
/// early iterate may lie outside the cone of the two normals and release a
/// node that belongs at the corner; held no more after that, it would cross
/// the corner to and fro at every iteration. The limit keeps a node whose
/// force does leave the cone from cycling between hold and release.
const CORNER_LEAVES: u32 = 3;

impl Formulation for Nodal {
    /// One pair's update under the nodal decisions, in phases: the pair at
    /// the iterate (target search geometry and the nodes' forces,
    /// `PairIterate::new`), every node's decision (`decisions`, `decide`;
    /// with `keep`, the kept decisions but for the forced nodes'), the
    /// changes counted (`count_changes`), and the rows of Eq. (18) with the
    /// reported results (`rows_and_results`).
    fn update(
        &self,
        at: &Iterate,
        (_, pair): (usize, &ContactPair),
        mem: &mut PairMemory,
        counters: [&mut [usize]; 2],
        log: &mut dyn FnMut(&str),
        out: &mut ContactSystem,
        keep: Option<(&Kept, &[(usize, Forced)])>,
    ) -> Result<PairResult, String> {
        let PairMemory::NodeToSegment(mem) = mem else {
            return Err(mismatch(pair, "memory"));
        };
        let plan = match keep {
            Some((Kept::Nodal(kept), forced)) => Plan::Keep { kept, forced },
            Some(_) => return Err(mismatch(pair, "inner solve's decisions")),
            None => Plan::Decide,
        };
        let active = match &plan {
            Plan::Keep { kept, .. } => Some(&kept.active[..]),
            Plan::Decide => None,
        };
        let view = PairIterate::new(at, pair, mem, active)?;
        let decisions = decisions(&view, mem, &plan);
        out.pending += decisions.iter().filter(|d| d.held_back).count();
        if matches!(plan, Plan::Decide) {
            count_changes(pair, mem, &decisions, counters, log, out)?;
        }
        // An inner solve's system serves its rows alone: no report.
        let report = matches!(plan, Plan::Decide);
        let result = rows_and_results(at, &view, mem, &decisions, out, report)?;
        out.kept.push(Kept::Nodal(std::sync::Arc::new(Decided {
            decisions,
            active: view.active,
        })));
        Ok(result)
    }

    fn inner_solves(&self) -> bool {
        true
    }

    fn predict(
        &self,
        at: &Prediction,
        pair: (usize, &ContactPair),
        mem: &PairMemory,
        kept: &Kept,
        cache: &mut SearchCache,
    ) -> Result<Option<Vec<(usize, Forced)>>, String> {
        let (PairMemory::NodeToSegment(mem), Kept::Nodal(kept)) = (mem, kept) else {
            return Ok(None);
        };
        predict_pair(at, pair, mem, kept, cache).map(Some)
    }

    /// None on a smoothed target (its curve's linearisation is not written).
    fn sensitivities(&self, pair: &ContactPair) -> bool {
        !matches!(
            pair.target,
            Target::Body {
                smooth: Some(_),
                ..
            }
        )
    }

    fn linearise(
        &self,
        at: &At,
        pair: (usize, &ContactPair),
        kept: &Kept,
        out: &mut Linearised,
    ) -> Result<(), String> {
        if !self.sensitivities(pair.1) {
            return Err(format!(
                "contact pair '{}' has a smoothed target (smooth_target = true): the \
                 linearisation of its curve's rows is not written",
                pair.1.name
            ));
        }
        let Kept::Nodal(kept) = kept else {
            return Err(mismatch(pair.1, "converged state's decisions"));
        };
        linearise::linearise_pair(at, pair, &kept.decisions, out)
    }

    /// Against a body's faceted surface, the nodes that went from one
    /// target segment to another in the increment: a node can lodge at a
    /// facet's corner and be thrown back each time it steps past it (the
    /// ironing with the ring's surface as contactor, tests/ironing.rs).
    fn failure_hint(&self, pair: &ContactPair, mem: &PairMemory) -> Option<String> {
        let PairMemory::NodeToSegment(mem) = mem else {
            return None;
        };
        let faceted = matches!(pair.target, Target::Body { smooth: None, .. });
        let crossed = mem.nodes.iter().filter(|n| n.crossed.is_some()).count();
        (faceted && crossed > 0).then(|| {
            format!(
                "pair '{}': {crossed} contactor node(s) moved between segments of its faceted \
                 target, where a node can lodge at a corner; `smooth_target = true` or \
                 `formulation = \"mortar\"` on the pair may converge",
                pair.name
            )
        })
    }
}

/// One pair at the iterate, as its nodes' decisions read it: the target now
/// and when the increment began, the contactor's positions then and now,
/// its nodes' out-of-balance forces, and the tolerances taken from them.
struct PairIterate<'a> {
    pair: &'a ContactPair,
    segments: Segments,
    segments0: Segments,
    x: Vec<Vector2<f64>>,
    x0: Vec<Vector2<f64>>,
    /// The longest contactor segment.
    h: f64,
    /// How far the target has moved in this increment.
    target_motion: f64,
    /// Each node's out-of-balance force.
    force: Vec<Vector2<f64>>,
    /// Each node has a prescribed dof (a driver moves it).
    driven: Vec<bool>,
    /// Each node has every dof prescribed (its drivers place it).
    placed: Vec<bool>,
    /// In contact after the previous iteration.
    active: Vec<bool>,
    /// A node's force pulls when its normal part is above this.
    tension: f64,
    frictionless: bool,
    /// `Start::settling`.
    settling: bool,
    /// `Start::touching`.
    touching: bool,
}

impl<'a> PairIterate<'a> {
    /// Target search geometry and force recovery: the target's segments
    /// and the contactor's positions, now and at the start of the
    /// increment, and each node's force.
    fn new(
        at: &Iterate,
        pair: &'a ContactPair,
        mem: &Memory,
        active: Option<&[bool]>,
    ) -> Result<Self, String> {
        let (problem, start) = (at.problem, at.start);
        let segments = target_segments(at.targets, problem, pair, at.u, at.poses)?;
        let segments0 = target_segments(at.targets, problem, pair, start.u, start.poses)?;
        let m = pair.contactor.len();
        let (x, x0) = (
            contactor_positions(problem, pair, at.u),
            contactor_positions(problem, pair, start.u),
        );
        // How far a free node may have gone into the target and still be
        // caught (`reach`): a few contactor segments (not the far side of a
        // thin target), plus how far the node and the target have moved in
        // this increment, so that a large increment closes the whole zone
        // at once on any mesh.
        let mut h: f64 = 0.0;
        for w in x.windows(2) {
            h = h.max((w[1] - w[0]).norm());
        }
        let mut target_motion: f64 = 0.0;
        // One shared set (a rigid target at its start pose) has not moved:
        // the capstan's drum has 5120 chords.
        let moved = !std::sync::Arc::ptr_eq(&segments, &segments0);
        for (s, s0) in (segments.iter().zip(segments0.iter())).filter(|_| moved) {
            target_motion = target_motion
                .max((s.seg.xa() - s0.seg.xa()).norm())
                .max((s.seg.xb() - s0.seg.xb()).norm());
        }
        // The out-of-balance force is the contact force at a node in
        // contact; at a prescribed dof it is the driver's reaction (a
        // symmetry plane).
        let force = at.contactor_forces(pair);
        let prescribed = |d: usize| at.eq[d] == PRESCRIBED;
        let driven = (pair.contactor.iter())
            .map(|&n| prescribed(2 * n) || prescribed(2 * n + 1))
            .collect();
        let placed = (pair.contactor.iter())
            .map(|&n| prescribed(2 * n) && prescribed(2 * n + 1))
            .collect();
        let active: Vec<bool> = match active {
            Some(a) => a.to_vec(),
            None => (mem.nodes.iter())
                .map(|n| n.state != NodeState::Open)
                .collect(),
        };
        let force_scale = (0..m)
            .filter(|&k| active[k])
            .map(|k| force[k].norm())
            .fold(0.0, f64::max);
        Ok(PairIterate {
            pair,
            segments,
            segments0,
            x,
            x0,
            h,
            target_motion,
            force,
            driven,
            placed,
            active,
            tension: TENSION_TOLERANCE * force_scale,
            frictionless: pair.mu_s == 0.0 && pair.mu_d == 0.0,
            settling: start.settling,
            touching: start.touching,
        })
    }

    /// How far node k may have gone into the target and still be caught
    /// (see `new`).
    fn reach(&self, k: usize) -> f64 {
        if self.h > 0.0 {
            2.0 * self.h + (self.x[k] - self.x0[k]).norm() + self.target_motion
        } else {
            f64::INFINITY
        }
    }

    /// Node k's contact force: its out-of-balance force if it was in
    /// contact, none if it was free.
    fn contact_force(&self, k: usize) -> Vector2<f64> {
        if self.active[k] {
            self.force[k]
        } else {
            Vector2::zeros()
        }
    }
}

/// State decisions: every node decided from the iterate (`Plan::Decide`),
/// or the decisions made at this iterate kept but for the forced nodes'
/// (`Plan::Keep`).
fn decisions(view: &PairIterate, mem: &Memory, plan: &Plan) -> Vec<Decision> {
    let decide_node = |k: usize, forced: Option<Forced>| decide(view, k, &mem.nodes[k], forced);
    match plan {
        Plan::Keep { kept, forced } => {
            let mut kept = kept.decisions.to_vec();
            for &(k, f) in forced.iter() {
                kept[k] = decide_node(k, Some(f));
            }
            kept
        }
        Plan::Decide => {
            let mut decided: Vec<Decision> =
                (0..view.x.len()).map(|k| decide_node(k, None)).collect();
            for k in parting(view, mem, &decided) {
                decided[k] = decide_node(k, Some(Forced::Stick));
            }
            decided
        }
    }
}

/// The nodes that stick one iteration more (`system::parting`): of two
/// neighbouring contactor nodes released from sticking in opposite
/// directions, the one less far outside its friction cone (`|q| / (mu
/// p_n)`); none while the iterate settles.
fn parting(view: &PairIterate, mem: &Memory, decided: &[Decision]) -> Vec<usize> {
    let m = decided.len();
    if view.settling || m < 2 {
        return Vec::new();
    }
    let excess = |k: usize| {
        let Some((_, cp)) = decided[k].point.as_ref() else {
            return 0.0;
        };
        let f = view.contact_force(k);
        let (p_n, q) = (-cp.normal().dot(&f), cp.tangent().dot(&f));
        q.abs() / (sticking_mu(view.pair, &mem.nodes[k]) * p_n).max(f64::MIN_POSITIVE)
    };
    let neighbours = if view.pair.closed { m } else { m - 1 };
    system::parting(
        (0..neighbours).map(|k| (k, (k + 1) % m)),
        |k| mem.nodes[k].state == NodeState::Stick && decided[k].state == NodeState::Slip,
        |k| decided[k].slip_sign,
        excess,
    )
}

/// The nodes a fresh decision changes: counted for convergence, and
/// against the increment's limits on changes between open and contact
/// (`flips`) and between stick and slip (`slips`); releases are logged.
fn count_changes(
    pair: &ContactPair,
    mem: &Memory,
    decisions: &[Decision],
    [flips, slips]: [&mut [usize]; 2],
    log: &mut dyn FnMut(&str),
    out: &mut ContactSystem,
) -> Result<(), String> {
    for (k, d) in decisions.iter().enumerate() {
        let old = mem.nodes[k];
        if d.state != old.state
            || d.corner != old.corner
            || (d.state == NodeState::Slip && d.slip_sign != old.nodal.slip_sign)
        {
            out.changes += 1;
            if (d.state == NodeState::Open) != (old.state == NodeState::Open) {
                count_flip(pair, k, flips)?;
            } else {
                count_slip(pair, k, slips)?;
            }
            if old.state != NodeState::Open && d.state == NodeState::Open {
                log(&format!(
                    "pair '{}' node {k}: released (p_n {:.3e})",
                    pair.name, d.p_n
                ));
            }
        }
    }
    Ok(())
}

/// Constraint rows and reported results: each node's memory after its
/// decision (`remember`), the rows of Eq. (18) of each node in contact
/// (`rows::add_rows`, a sliding node's friction in its multiplier's
/// column), and, with `report`, the pair's forces, states and tractions
/// and the rigid targets' reactions (`ContactSystem::rigid`); without, an
/// empty result.
fn rows_and_results(
    at: &Iterate,
    view: &PairIterate,
    mem: &mut Memory,
    decisions: &[Decision],
    out: &mut ContactSystem,
    report_results: bool,
) -> Result<PairResult, String> {
    let pair = view.pair;
    let mut report = Report::new(pair.contactor.len());
    for (k, d) in decisions.iter().enumerate() {
        remember(&mut mem.nodes[k], d, view.frictionless);
        // The node's contact force [normal, tangential] in the frame its
        // traction is reported in.
        let mut node_force = [0.0; 2];
        if let Some((j, cp)) = d.point.as_ref() {
            let held = d.state == NodeState::Stick || d.corner;
            let friction = if held { 0.0 } else { d.slip_sign * pair.mu_d };
            let n = pair.contactor[k];
            add_rows(&view.segments[*j], n, cp, held, d.lambda, friction, out);
            if report_results {
                let f = view.contact_force(k);
                node_force = report.contact(at, pair, k, f, cp, &mut out.rigid);
            }
        }
        if report_results {
            report.node(view.x[k], d.state, node_force);
        }
    }
    if !report_results {
        return Ok(PairResult::default());
    }
    // A sliding node's reported friction is its law's; not a driven node's,
    // whose force at its prescribed dof is partly its driver's reaction (a
    // node on a symmetry plane, where the friction along the target is the
    // plane's).
    let sliding: Vec<Option<f64>> = (decisions.iter().enumerate())
        .map(|(k, d)| {
            (d.state == NodeState::Slip && !d.corner && !view.driven[k]).then_some(pair.mu_d)
        })
        .collect();
    // Lumped: each node's traction has the sign of its own force, which the
    // decisions above read (the consistent recovery of Eq. 26 spreads a
    // force over its neighbours and shows a pressed node next to an open one
    // in tension).
    let (tn, tt) = reported_tractions(
        at.problem,
        pair,
        &view.x,
        &view.active,
        &view.force,
        &report.frames,
        Recovery::Lumped,
        &sliding,
    )?;
    let mut result = report.result;
    result.nodes.tn = tn;
    result.nodes.tt = tt;
    Ok(result)
}

/// A node's memory after its decision: state, corner hold, slip, and the
/// segment and contact point it meets the target at (a segment switch
/// recorded as a crossing; the anchor kept once set in the increment).
fn remember(node: &mut NodeMemory, d: &Decision, frictionless: bool) {
    let old = *node;
    node.state = d.state;
    node.corner = d.corner;
    node.nodal.corner_leaves += u32::from(old.corner && !d.corner);
    node.nodal.slip_sign = if d.state == NodeState::Slip {
        d.slip_sign
    } else {
        0.0
    };
    if d.state == NodeState::Slip && !frictionless {
        node.nodal.slid = true;
        node.nodal.ever_slid = true;
    }
    if let Some((j, cp)) = d.point.as_ref() {
        if old.state != NodeState::Open && *j != old.segment {
            node.crossed = Some((old.segment, *j));
        }
        node.segment = *j;
        node.beta = cp.beta();
        if node.anchor.is_none() {
            node.anchor = d.anchor;
        }
    }
}

/// Where a node meets the target and the forces on it there: what its
/// stick/slip decision reads.
struct Touch {
    k: usize,
    /// Target segment and contact point.
    j: usize,
    cp: ContactPoint,
    /// The node's contact force, and its normal (compression positive) and
    /// tangential parts.
    f: Vector2<f64>,
    p_n: f64,
    q: f64,
}

impl Touch {
    /// The foot of the normal on the segment, referred to its end node
    /// beyond an end.
    fn projection(&self, x: Vector2<f64>) -> (usize, ContactPoint) {
        let seg = self.cp.segment();
        let p = seg.project(x);
        (self.j, seg.contact_at(x, p.beta().clamp(0.0, 1.0)))
    }
}

/// The decision for one node, from the iterate: where it meets the target,
/// whether it is in contact (the normal test), and its state and the force
/// its rows carry (`frictionless_decision`, `frictional_decision`).
fn decide(view: &PairIterate, k: usize, old: &NodeMemory, forced: Option<Forced>) -> Decision {
    let (segments, x, reach) = (&view.segments, view.x[k], view.reach(k));
    // Where the node meets the target, if it does.
    let found = match (forced, old.state) {
        (Some(Forced::Open), _) => return Decision::open(0.0),
        // Closed by the linearised problem: its row at this iterate closes
        // the gap it still shows here.
        (Some(Forced::Close { j, .. }), _) => segments.get(j).map(|s| {
            (
                j,
                s.seg.contact_at(x, s.seg.project(x).beta().clamp(0.0, 1.0)),
            )
        }),
        (_, NodeState::Open) => search::search(segments, x, reach, view.touching),
        (_, NodeState::Stick) => segments
            .get(old.segment)
            .map(|s| (old.segment, s.seg.contact_at(x, old.beta))),
        (_, NodeState::Slip) => search::follow(segments, old.segment, x, reach),
    };
    let Some((j, cp)) = found else {
        return Decision::open(0.0);
    };
    let f = view.contact_force(k);
    let (n_s, n_r) = (cp.normal(), cp.tangent());
    // Normal force (compression positive) and tangential force on the node.
    let (p_n, q) = (-n_s.dot(&f), n_r.dot(&f));
    let overlap = cp.normal_overlap();
    let tension = view.tension;
    let mut held_back = false;
    // A free node that has penetrated closes; a node in contact opens when
    // its force pulls (a gap it shows after a step along a curved target
    // is the linearisation's, and its row closes it).
    if matches!(forced, Some(Forced::Close { .. })) {
    } else if old.state == NodeState::Open {
        if overlap < 0.0 || (overlap == 0.0 && !view.touching) {
            return Decision::open(0.0);
        }
    } else if view.placed[k] && view.segments[j].nodes.is_none() {
        // Placed in full by its drivers against a rigid target, the node
        // has no row that can move it and no contact force (its drivers
        // take the reaction): it touches while it overlaps (a pulled end
        // that starts 1e-6 inside the drum by round-off, then is drawn
        // off it along the tangent).
        if overlap < 0.0 {
            return Decision::open(0.0);
        }
    } else if p_n < -tension
        && (old.state != NodeState::Stick || view.frictionless || q.abs() <= tension)
    {
        // A sticking node pulled along the target as well slides first: held
        // at its anchor on a curved target, its pull shows partly as tension.
        // While the iterate settles, a node in contact keeps it: the
        // predictor carries a rigid target's rotation, or a long slide
        // round a curved target, through the tangent, which stretches the
        // body and leaves it off the target, and that shows as tension at
        // every node of the contact (the incline tilted by 5 degrees, the
        // capstan pulled 6 mm at once: every node released, the body free);
        // the next iterates have the geometry right.
        if !view.settling {
            return Decision::open(p_n);
        }
        held_back = true;
    }
    let touch = Touch {
        k,
        j,
        cp,
        f,
        p_n,
        q,
    };
    let mut decision = if view.frictionless {
        frictionless_decision(view, old, &touch)
    } else {
        frictional_decision(view, old, &touch, forced)
    };
    decision.held_back = held_back;
    decision
}

/// A frictionless node in contact: held at a reflex corner of the target
/// (`corner`), else sliding where it meets the target, its force along the
/// normal.
fn frictionless_decision(view: &PairIterate, old: &NodeMemory, touch: &Touch) -> Decision {
    let x = view.x[touch.k];
    let point = if old.state == NodeState::Stick {
        touch.projection(x)
    } else {
        (touch.j, touch.cp)
    };
    if let Some(held) = corner(&view.segments, point.0, x, touch.f, view.tension, old) {
        return held;
    }
    Decision {
        state: NodeState::Slip,
        point: Some(point),
        lambda: -touch.p_n * touch.cp.normal(),
        p_n: touch.p_n,
        slip_sign: 0.0,
        anchor: old.anchor,
        corner: false,
        held_back: false,
    }
}

/// A node in contact with friction: its slip from its anchor and its
/// forces decide stick (held at the anchor) or slip (against the slip
/// direction, its friction `mu_d p_n`).
fn frictional_decision(
    view: &PairIterate,
    old: &NodeMemory,
    touch: &Touch,
    forced: Option<Forced>,
) -> Decision {
    let (segments, pair) = (&view.segments, view.pair);
    let (k, j, p_n, q) = (touch.k, touch.j, touch.p_n, touch.q);
    let (x, reach) = (view.x[k], view.reach(k));
    let seg = touch.cp.segment();
    // Where the node was on the target when the increment began (the
    // target's material point under it then): its slip is measured from
    // there, so a converged node either sticks there or slides against its
    // slip (Coulomb over the increment, backward Euler).
    let (ja, beta_a) = old
        .anchor
        .unwrap_or_else(|| start_point(&view.segments0, j, view.x0[k]));
    let anchor = segments
        .get(ja)
        .map_or(touch.cp.point(), |s| s.seg.point_at(beta_a));
    let foot = seg.project(x);
    let slip = foot.tangent().dot(&(foot.point() - anchor));
    let mu_stick = sticking_mu(pair, old);
    let slip_tolerance = 1e-10 * view.h;
    // A sliding node slides on while its slip from the anchor runs along
    // its direction (its friction opposes it) and sticks when the slip has
    // turned back; a sticking node, or one new to contact, sticks while its
    // force is within the capacity and slides against it otherwise.
    let s = match (forced, old.state) {
        (Some(Forced::Slip(s)), _) => Some(s),
        (Some(Forced::Stick), _) => None,
        // Closed by the linearised problem, as a free node that has
        // penetrated (below) by the overlap it predicts.
        (Some(Forced::Close { overlap, .. }), _) => {
            (slip.abs() > mu_stick * overlap).then(|| slip.signum())
        }
        // Under the experiment's rule a node that slid in the previous
        // increment meets this one as a sticking node (below): mu_s holds
        // it again unless its force exceeds that, whereas sliding on it
        // keeps only mu_d and its neighbours take the rest.
        (None, NodeState::Slip) if old.nodal.slip_sign != 0.0 && !restarts_sticking(pair, old) => {
            (old.nodal.slip_sign * slip >= -slip_tolerance).then_some(old.nodal.slip_sign)
        }
        // A node that touches again after sliding free in this increment, or
        // touches first far from where it was: slides along that slip.
        (None, NodeState::Open) => {
            (slip.abs() > mu_stick * touch.cp.normal_overlap()).then(|| slip.signum())
        }
        // Its rows hold a sticking node at the anchor, unless a driver holds
        // it off the anchor along the target (moves it, or holds it while
        // the target moves): then it slides. Only a driven node (a
        // prescribed dof): a free node off its anchor is off by its rows'
        // linearisation (a rigid target turned by the predictor leaves each
        // node of the incline's block 2e-8 off it) or, in the predictor's
        // decisions (the start positions, the targets at their new poses),
        // by the target's motion, which its rows carry it along with.
        (None, NodeState::Stick)
            if view.driven[k] && slip.abs() > slip_tolerance.max(1e-9 * reach) =>
        {
            Some(slip.signum())
        }
        _ => (!holds(segments, (j, touch.cp.beta()), touch.f, mu_stick)).then(|| -q.signum()),
    };
    let slide = |s: f64| {
        let point = touch.projection(x);
        let (n_s, n_r) = (point.1.normal(), point.1.tangent());
        Decision {
            state: NodeState::Slip,
            point: Some(point),
            lambda: p_n * (-n_s - s * pair.mu_d * n_r),
            p_n,
            slip_sign: s,
            anchor: Some((ja, beta_a)),
            corner: false,
            held_back: false,
        }
    };
    let Some(s) = s else {
        let at = segments
            .get(ja)
            .map(|s| (ja, s.seg.contact_at(x, beta_a)))
            .filter(|(_, a)| a.overlap().norm() <= reach);
        if let Some(point) = at {
            return Decision {
                state: NodeState::Stick,
                point: Some(point),
                lambda: touch.f,
                p_n,
                slip_sign: 0.0,
                anchor: Some((ja, beta_a)),
                corner: false,
                held_back: false,
            };
        }
        // The anchor is out of reach (the target has moved on): slide.
        return slide(if slip != 0.0 { slip.signum() } else { 1.0 });
    };
    slide(s)
}

/// The coefficient that holds a sticking node (`ContactPair::sticking_mu`).
fn sticking_mu(pair: &ContactPair, node: &NodeMemory) -> f64 {
    pair.sticking_mu(node.nodal.ever_slid)
}

/// Whether a node held at the target point (segment `j`, `beta`) can carry
/// the force `f` with friction `mu`: `|q| <= mu p_n` on its segment, or, at a
/// reflex vertex of the target (the point at a segment's end, as where the
/// buried pipe's nodes meet the hole's), on any normal between the two
/// segments' there, since a held node's normal is not unique at a vertex:
/// within either segment's friction cone or between their normals. Held in
/// one segment's frame alone, a node on a vertex that its force pushes
/// across slid and slid back over the vertex at every inner solve (the
/// pipe's first increment, 25 iterations at |r|/F = 4.8e-4).
fn holds(segments: &[TargetSegment], (j, beta): (usize, f64), f: Vector2<f64>, mu: f64) -> bool {
    let within = |i: usize, beta: f64| {
        let (n, t) = segments[i].seg.frame_at(beta);
        let p_n = -n.dot(&f);
        t.dot(&f).abs() <= mu * p_n.max(0.0)
    };
    if within(j, beta) {
        return true;
    }
    let end = if beta >= 1.0 - search::BETA_TOLERANCE {
        1.0
    } else if beta <= search::BETA_TOLERANCE {
        0.0
    } else {
        return false;
    };
    let Some((i, end_i)) = search::reflex(segments, j, end) else {
        return false;
    };
    if within(i, end_i) {
        return true;
    }
    let (a, b) = normals_weights(segments[j].seg.normal(), segments[i].seg.normal(), f);
    a >= 0.0 && b >= 0.0
}

/// `(a, b)` with `f = -(a n_j + b n_i)`: both at least 0 when the force lies
/// in the cone of the two normals (the target pushes the node out).
fn normals_weights(nj: Vector2<f64>, ni: Vector2<f64>, f: Vector2<f64>) -> (f64, f64) {
    let det = nj.x * ni.y - nj.y * ni.x;
    let a = -(f.x * ni.y - f.y * ni.x) / det;
    let b = -(nj.x * f.y - nj.y * f.x) / det;
    (a, b)
}

/// A node that slid in the previous increment, under the experiment's rule
/// (mu_s kept throughout): at the first decision of an increment its stick
/// or slip is decided on its force against mu_s, as a sticking node's.
/// Under the usual rule it slides on while its slip runs its way (it would
/// stick with mu_d, the friction it slides with).
fn restarts_sticking(pair: &ContactPair, node: &NodeMemory) -> bool {
    pair.rule == FrictionRule::AlwaysMuS && !node.nodal.slid
}

/// The linearised problem's own decisions for one pair, after a solve with
/// this iterate's decisions: `u_new` the displacements the solve reaches
/// (from `u_now`) and `force_new` each dof's out-of-balance force there as
/// the solve predicts it (the contact forces it leaves at the nodes).
///
/// - A node in contact whose predicted normal force pulls (beyond the force
///   tolerance) is released, unless it was in contact at the iterate and
///   the iterate settles (`held`, as `decide` holds it). Sticking or
///   sliding alike: with mu = 10 a sticking node pulled along the target
///   and sent sliding first (as `decide` does) predicted ten times its pull
///   along the target, and the Hertz cylinder bisected.
/// - A free node whose predicted position has penetrated the target (beyond
///   the length tolerance) closes on the segment it has penetrated.
/// - A sticking node whose predicted tangential force exceeds its capacity
///   slides against it; a sliding node whose predicted slip from its anchor
///   has turned back sticks.
///
/// Corner holds are left to the next iterate's decisions.
fn predict_pair(
    at: &Prediction,
    (p, pair): (usize, &ContactPair),
    mem: &Memory,
    kept: &Decided,
    cache: &mut SearchCache,
) -> Result<Vec<(usize, Forced)>, String> {
    let (problem, [u_now, u_new]) = (at.problem, [at.u_now, at.u_new]);
    let force_new = |n: usize| Vector2::new(at.force_new[2 * n], at.force_new[2 * n + 1]);
    // While the iterate settles a node in contact at the iterate is not
    // released on its force (`decide`).
    let held = at.settling.then_some(&kept.active[..]);
    let frictionless = pair.mu_s == 0.0 && pair.mu_d == 0.0;
    let [force_tolerance, length_tolerance] = at.tolerance;
    let segments = target_segments(at.targets, problem, pair, u_new, at.poses)?;
    let x_new = contactor_positions(problem, pair, u_new);
    let mut h: f64 = 0.0;
    for w in x_new.windows(2) {
        h = h.max((w[1] - w[0]).norm());
    }
    let mut out = Vec::new();
    for (k, d) in kept.decisions.iter().enumerate() {
        let Some((j, cp)) = d.point.as_ref() else {
            // A free node the solve moves into the target closes.
            let x = search::position(problem, u_now, pair.contactor[k]);
            let reach = 2.0 * h + (x_new[k] - x).norm();
            if let Some((j, cp)) = cache.search((p, k), &segments, x_new[k], reach)
                && cp.normal_overlap() > length_tolerance
            {
                let overlap = cp.normal_overlap();
                out.push((k, Forced::Close { j, overlap }));
            }
            continue;
        };
        if d.corner {
            continue;
        }
        let node = &mem.nodes[k];
        let f = force_new(pair.contactor[k]);
        let (n_s, n_r) = (cp.normal(), cp.tangent());
        let (p_n, q) = (-n_s.dot(&f), n_r.dot(&f));
        if p_n < -force_tolerance {
            // While the iterate settles a node in contact at the iterate
            // is not released on its force (`decide`): nor on the force its
            // linearisation predicts.
            if !held.is_some_and(|active| active[k]) {
                out.push((k, Forced::Open));
            }
            continue;
        }
        if frictionless || p_n <= 0.0 {
            continue;
        }
        match d.state {
            // As `decide` slides it: beyond its capacity by any amount.
            // With the force tolerance added here, the inner solves settled
            // on stick zones whose nodes the next iterates released by the
            // dozen, at residuals of 1e-8 (the capstan drawn through the
            // FMU: nodes sliding at their capacity with no slip, stuck by
            // a reversal their linearisation predicts): 3 to 6 iterations
            // and 10 to 71 solves per step, now 3 and 10 to 24.
            NodeState::Stick if !holds(&segments, (*j, cp.beta()), f, sticking_mu(pair, node)) => {
                out.push((k, Forced::Slip(-q.signum())));
            }
            NodeState::Slip if d.slip_sign != 0.0 => {
                let Some((ja, beta_a)) = node.anchor else {
                    continue;
                };
                let (Some(seg), Some(anchor)) = (segments.get(*j), segments.get(ja)) else {
                    continue;
                };
                let foot = seg.seg.project(x_new[k]);
                let slip = (foot.tangent()).dot(&(foot.point() - anchor.seg.point_at(beta_a)));
                if d.slip_sign * slip < -length_tolerance {
                    out.push((k, Forced::Stick));
                }
            }
            _ => {}
        }
    }
    Ok(out)
}

/// The target's material point under a node that was free at the start of
/// the increment: the closest point to its start position on the segment
/// it has now met, in the target's start configuration.
fn start_point(segments0: &[TargetSegment], j: usize, x0: Vector2<f64>) -> (usize, f64) {
    let beta = segments0
        .get(j)
        .map_or(0.0, |s| s.seg.project(x0).beta().clamp(0.0, 1.0));
    (j, beta)
}

/// A frictionless node at a reflex corner of the target (the body's angle
/// there above 180 degrees, as round a hole or inside a ring), in the wedge
/// where neither segment's normal reaches it, or within `CORNER_REACH` of
/// the corner once it has crossed it back: each segment alone leaves it a
/// force along the target that pushes it over the corner onto the other.
/// While its force `f` lies in the cone of the two normals it is held at the
/// corner (two rows, its whole force); otherwise it slides on the segment
/// that can carry the force.
fn corner(
    segments: &[TargetSegment],
    j: usize,
    x: Vector2<f64>,
    f: Vector2<f64>,
    tension: f64,
    old: &NodeMemory,
) -> Option<Decision> {
    // Near the corner (Newton's steps along one segment's line leave a node
    // that belongs at the corner a little short of it or past it) once it
    // has crossed the corner and come back, or is held there; in the wedge
    // beyond both segments' ends in any case. A node dragged across a corner
    // once passes it.
    // A node that crosses back over the corner its last crossing in this
    // increment took it over has shown that its sliding equilibrium on
    // either segment lies across the corner: it is tested at the corner
    // wherever the step left it (within half a segment of it), and the
    // cone of the normals decides, as for a node within `CORNER_REACH`.
    // The ironing ring pressed into its soft block left such a node 0.024
    // and 0.008 of a segment either side of a vertex at alternate
    // iterations, without end (scenes/verification/ironing.toml).
    let back = j != old.segment && old.crossed == Some((j, old.segment));
    let near = |tol: f64| search::near_reflex(segments, j, x, tol);
    let crossed_back = back.then(|| near(CROSSED_BACK_REACH)).flatten();
    let crossed_back = crossed_back.filter(|c| c.2 == old.segment);
    let tol = if crossed_back.is_some() {
        CROSSED_BACK_REACH
    } else {
        CORNER_REACH
    };
    let (end_j, beta, i, end_i, beta_i) = crossed_back.or_else(|| near(tol))?;
    let beyond = |tol: f64| search::at_end(beta, end_j, tol) && search::at_end(beta_i, end_i, tol);
    let returned = old.nodal.corner_leaves < CORNER_LEAVES
        && (old.state == NodeState::Open
            || old.corner
            || old.crossed == Some((j, i))
            || old.crossed == Some((i, j)));
    if !(beyond(search::BETA_TOLERANCE) || (returned && beyond(tol))) {
        return None;
    }
    let (a, b) = normals_weights(segments[j].seg.normal(), segments[i].seg.normal(), f);
    let slide = |k: usize, end: f64| {
        let cp = segments[k].seg.contact_at(x, end);
        let n = segments[k].seg.normal();
        let p_n = -n.dot(&f);
        Decision {
            state: NodeState::Slip,
            point: Some((k, cp)),
            lambda: -p_n * n,
            p_n,
            slip_sign: 0.0,
            anchor: None,
            corner: false,
            held_back: false,
        }
    };
    if a >= -tension && b >= -tension {
        Some(Decision {
            state: NodeState::Slip,
            point: Some((j, segments[j].seg.contact_at(x, end_j))),
            lambda: f,
            p_n: a + b,
            slip_sign: 0.0,
            anchor: None,
            corner: true,
            held_back: false,
        })
    } else if a < -tension && b >= -tension {
        Some(slide(i, end_i))
    } else {
        Some(slide(j, end_j))
    }
}
