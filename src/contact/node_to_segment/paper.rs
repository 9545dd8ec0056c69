//! The paper's decisions (`decisions = "paper"`, Section 3): contact forces
//! recovered as distributed tractions over the contactor's segments, the
//! segments decided open, sticking or sliding on them (Table 1 gives the
//! nodes' states), re-contacts and the return to sticking, each node's
//! contact point and its rows of Eq. (18) (docs/contact.md section 8b).

use super::memory::{Memory, NodeMemory};
use super::reported::quadratic_tractions;
use super::rows::add_rows;
use super::traction::{self, SegmentState};
use super::{Paper, TENSION_TOLERANCE};
use crate::contact::report::{Report, geometry, node_frame};
use crate::contact::search::BETA_TOLERANCE;
use crate::contact::search::SearchCache;
use crate::contact::search::{
    Segments, TargetSegment, at_end, contactor_positions, follow, near_reflex, reflex, search,
    target_segments,
};
use crate::contact::segment::ContactPoint;
use crate::contact::sensitivity::{At, Linearised};
use crate::contact::system::Forced;
use crate::contact::system::{ContactSystem, Iterate, count_flip};
use crate::contact::{Formulation, Prediction};
use crate::contact::{Kept, PairMemory, mismatch};
use crate::problem::{ContactPair, Kinematics};
use crate::results::{NodeState, PairResult};
use nalgebra::Vector2;

impl Formulation for Paper {
    fn update(
        &self,
        at: &Iterate,
        (_, pair): (usize, &ContactPair),
        mem: &mut PairMemory,
        [flips, _]: [&mut [usize]; 2],
        log: &mut dyn FnMut(&str),
        out: &mut ContactSystem,
        _keep: Option<(&Kept, &[(usize, Forced)])>,
    ) -> Result<PairResult, String> {
        let PairMemory::NodeToSegment(mem) = mem else {
            return Err(mismatch(pair, "memory"));
        };
        let result = paper_pair(at, pair, mem, flips, log, out)?;
        out.kept.push(Kept::None);
        Ok(result)
    }

    fn inner_solves(&self) -> bool {
        false
    }

    fn predict(
        &self,
        _at: &Prediction,
        _pair: (usize, &ContactPair),
        _mem: &PairMemory,
        _kept: &Kept,
        _cache: &mut SearchCache,
    ) -> Result<Option<Vec<(usize, Forced)>>, String> {
        Ok(None)
    }

    fn sensitivities(&self, _pair: &ContactPair) -> bool {
        false
    }

    fn linearise(
        &self,
        _at: &At,
        (_, pair): (usize, &ContactPair),
        _kept: &Kept,
        _out: &mut Linearised,
    ) -> Result<(), String> {
        Err(format!(
            "contact pair '{}' uses the paper's decisions (decisions = \"paper\"): its \
             friction is a fixed point of the recovered segment resultants, which has no \
             derivative; the nodal decisions (the default) have one",
            pair.name
        ))
    }
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
    mem: &mut Memory,
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
        let segments = target_segments(at.targets, at.problem, pair, at.u, at.poses)?;
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
fn recover(view: &PaperPair, mem: &Memory) -> Result<Recovered, String> {
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
    mem: &mut Memory,
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
fn recontacts(view: &PaperPair, rec: &Recovered, mem: &mut Memory) -> Vec<Recontact> {
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
    mem: &mut Memory,
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
fn table1(view: &PaperPair, rec: &Recovered, mem: &Memory) -> Vec<NodeState> {
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
        add_rows(&view.segments[j], n, &cp, held, lambda, 0.0, out);
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
    let (end_j, _, i, end_i, beta_i) = near_reflex(segments, j, x, BETA_TOLERANCE)?;
    at_end(beta_i, end_i, BETA_TOLERANCE).then_some((end_j, i, end_i))
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::segment::Segment;

    fn seg(a: [f64; 2], b: [f64; 2]) -> TargetSegment {
        let (xa, xb) = (Vector2::new(a[0], a[1]), Vector2::new(b[0], b[1]));
        TargetSegment::new(Segment::new(xa, xb).unwrap(), None)
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
}
