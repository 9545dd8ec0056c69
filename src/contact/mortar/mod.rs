//! Mortar (segment-to-segment) contact between two bodies (`formulation =
//! "mortar"`): the contact conditions hold on weighted gaps, one per
//! contactor node, integrated over the contactor against the target's
//! interpolation (`integrate`), and the multipliers are the normal
//! tractions at the contactor's nodes, interpolated by the dual basis of
//! its sides. A uniform pressure between non-matching meshes is carried
//! exactly (the contact patch test), and a target node between two
//! contactor nodes no longer slips through.
//!
//! Per iteration: the weighted gaps with their gradients and Hessians; the
//! multipliers recovered from the contactor's out-of-balance forces (the
//! least-squares fit of the gradients, exact at equilibrium); each node
//! decided on its own multiplier and weighted gap (a node in contact opens
//! when its traction pulls, an open node closes when its gap weighted by
//! its hat function is negative); a row per node in contact, `grad g_j du = -g_j`, scaled by
//! its area; the contact forces `sum lambda_j grad g_j` and the tangent
//! `-sum lambda_j hess g_j`. Frictionless; against a deformable target.
//! The derivation is in docs/contact.md section 11.

mod dual;
mod integrate;
mod surface;

use super::Formulation;
use super::Prediction;
use super::memory::PairMemory;
use super::report::{Report, geometry, node_frame};
use super::search::SearchCache;
use super::sensitivity::{At, Linearised};
use super::system::{ContactSystem, Forced, Iterate, Kept, Row, count_flip};
use crate::assembly::PRESCRIBED;
use crate::problem::{ContactPair, Kinematics};
use crate::results::{NodeState, PairResult};
use integrate::{Part, Setting, field_at_node, integrate};
use nalgebra::Vector2;
use std::collections::BTreeMap;
use surface::Surface;

/// A node's traction counts as tension above this fraction of the largest
/// traction of its pair (round-off at a node just touching).
const TENSION_TOLERANCE: f64 = 1e-8;

/// Mortar contact (`formulation = "mortar"`).
pub(super) struct Mortar;

/// One contactor node's weighted gap summed over its side pairs: value and
/// gradient (mesh dof, coefficient); `touched`: some target side meets one
/// of its sides.
#[derive(Clone, Debug, Default)]
struct NodeGap {
    value: f64,
    gradient: Vec<(usize, f64)>,
    /// The gap weighted by the node's hat function (`integrate::hat`):
    /// value and gradient. The dual basis (and an 8-node side's quadratic
    /// shape functions) take negative values, so a node whose gap grows
    /// along its sides may show a negative weighted gap while clear of the
    /// target everywhere; a node closes on this one, negative only where
    /// the target is entered near the node.
    hat_weighted: (f64, Vec<(usize, f64)>),
    touched: bool,
}

/// A pair at an iterate: its surfaces and positions, the weighted gaps
/// with their side pairs' parts, each contactor node's area and whether
/// it has none, and the contactor's free dofs (the rows of the multipliers'
/// least-squares fit). Kept for the inner solves at the same iterate.
struct PairAt {
    contactor: Surface,
    target: Surface,
    x: Vec<[f64; 2]>,
    y: Vec<[f64; 2]>,
    x_ref: Vec<[f64; 2]>,
    reference_measure: bool,
    geometry: crate::contact::traction::Geometry,
    parts: Vec<Part>,
    gaps: Vec<NodeGap>,
    area: Vec<f64>,
    weightless: Vec<bool>,
    free: BTreeMap<usize, usize>,
}

/// What `update` keeps for `predict` and the inner solves' `update`: the
/// pair at the iterate, and the states and multipliers its rows were built
/// from.
struct Decided {
    at: std::sync::Arc<PairAt>,
    states: Vec<NodeState>,
    lambda: Vec<f64>,
}

impl PairAt {
    fn new(at: &Iterate, pair: &ContactPair) -> Result<Self, String> {
        let problem = at.problem;
        let contactor = Surface::contactor(problem, pair)?;
        let target = Surface::target(problem, pair)?.ok_or_else(|| {
            format!(
                "pair '{}': mortar contact needs a body as target",
                pair.name
            )
        })?;
        let point = |n: usize, u: Option<&[f64]>| {
            let p = problem.mesh.nodes[n];
            u.map_or(p, |u| [p[0] + u[2 * n], p[1] + u[2 * n + 1]])
        };
        let x: Vec<[f64; 2]> = (contactor.nodes.iter())
            .map(|&n| point(n, Some(at.u)))
            .collect();
        let y: Vec<[f64; 2]> = target.nodes.iter().map(|&n| point(n, Some(at.u))).collect();
        let x_ref: Vec<[f64; 2]> = contactor.nodes.iter().map(|&n| point(n, None)).collect();
        let mut free = BTreeMap::new();
        for &n in &pair.contactor {
            for d in [2 * n, 2 * n + 1]
                .into_iter()
                .filter(|&d| at.eq[d] != PRESCRIBED)
            {
                let next = free.len();
                free.entry(d).or_insert(next);
            }
        }
        let mut pair_at = PairAt {
            contactor,
            target,
            x,
            y,
            x_ref,
            reference_measure: matches!(
                problem.kinematics,
                Kinematics::SmallStrain | Kinematics::MaterialNonlinearOnly
            ),
            geometry: geometry(problem),
            parts: Vec::new(),
            gaps: Vec::new(),
            area: Vec::new(),
            weightless: Vec::new(),
            free,
        };
        let (parts, area) = integrate(&pair_at.setting());
        let mut gaps = gather(&parts, pair_at.x.len());
        // A node of no weight (an 8-node side's corner on the axis) has no
        // weighted gap and no multiplier: it follows its side.
        let largest = area.iter().fold(0.0f64, |a, &b| a.max(b));
        let weightless: Vec<bool> = area.iter().map(|&a| a <= 1e-12 * largest).collect();
        for (gap, _) in gaps.iter_mut().zip(&weightless).filter(|(_, w)| **w) {
            gap.touched = false;
        }
        (
            pair_at.parts,
            pair_at.gaps,
            pair_at.area,
            pair_at.weightless,
        ) = (parts, gaps, area, weightless);
        Ok(pair_at)
    }

    fn setting(&self) -> Setting<'_> {
        Setting {
            contactor: &self.contactor,
            target: &self.target,
            x: &self.x,
            y: &self.y,
            x_ref: &self.x_ref,
            reference_measure: self.reference_measure,
            geometry: self.geometry,
            reach: 2.0
                * longest_side(&self.contactor, &self.x).max(longest_side(&self.target, &self.y)),
        }
    }

    /// The multipliers of the nodes `closed` from the out-of-balance force
    /// `force` (per mesh dof): the least-squares fit of `sum lambda_j grad
    /// g_j` to it over the contactor's free dofs (the contact force there
    /// at equilibrium); zero for the other nodes.
    fn multipliers(&self, closed: &[bool], force: &[f64]) -> Vec<f64> {
        let mut b = vec![0.0; self.free.len()];
        for (&d, &i) in &self.free {
            b[i] = force[d];
        }
        let unknowns: Vec<usize> = (0..self.gaps.len())
            .filter(|&j| closed[j] && self.gaps[j].touched)
            .collect();
        let columns: Vec<Vec<(usize, f64)>> = (unknowns.iter())
            .map(|&j| {
                (self.gaps[j].gradient.iter())
                    .filter_map(|&(d, v)| self.free.get(&d).map(|&i| (i, v)))
                    .collect()
            })
            .collect();
        let mut lambda = vec![0.0; self.gaps.len()];
        for (&j, l) in unknowns.iter().zip(least_squares(&columns, &b)) {
            lambda[j] = l;
        }
        lambda
    }

    /// A node of no weight takes its side's state: in contact when a node
    /// of weight on its side is.
    fn weightless_follow(&self, states: &mut [NodeState]) {
        for j in (0..states.len()).filter(|&j| self.weightless[j]) {
            let side = &self.contactor.sides[self.contactor.on[j][0].0];
            let closed =
                (side.iter()).any(|&k| !self.weightless[k] && states[k] != NodeState::Open);
            states[j] = if closed {
                NodeState::Slip
            } else {
                NodeState::Open
            };
        }
    }
}

impl Formulation for Mortar {
    /// One pair's update, in phases: the pair at the iterate (weighted gaps,
    /// `PairAt::new`), the multipliers recovered (`PairAt::multipliers`),
    /// each node's state (`decide`; with `keep`, the kept states but for the
    /// forced nodes'), the rows, forces and tangent (`add_rows`,
    /// `add_forces`) and the reported results (`report`; none for an inner
    /// solve's system, which serves its rows alone).
    fn update(
        &self,
        at: &Iterate,
        pair: &ContactPair,
        mem: &mut PairMemory,
        [flips, _]: [&mut [usize]; 2],
        log: &mut dyn FnMut(&str),
        out: &mut ContactSystem,
        keep: Option<(&Kept, &[(usize, Forced)])>,
    ) -> Result<PairResult, String> {
        let (here, states, lambda) = match keep {
            Some((kept, forced)) => {
                let kept = (kept.get::<Decided>()).ok_or("inner solve without mortar decisions")?;
                let mut states = kept.states.clone();
                for &(j, f) in forced {
                    states[j] = if f == Forced::Open {
                        NodeState::Open
                    } else {
                        NodeState::Slip
                    };
                }
                kept.at.weightless_follow(&mut states);
                (kept.at.clone(), states, kept.lambda.clone())
            }
            None => {
                let here = PairAt::new(at, pair)?;
                let was_closed: Vec<bool> = (mem.nodes.iter())
                    .map(|n| n.state != NodeState::Open)
                    .collect();
                let lambda = here.multipliers(&was_closed, at.r);
                let mut states = decide(at, pair, mem, &here, &lambda, flips, log, out)?;
                here.weightless_follow(&mut states);
                (std::sync::Arc::new(here), states, lambda)
            }
        };
        // The multipliers of the nodes kept in contact; a node that closes
        // carries none yet.
        let lambda: Vec<f64> = (0..states.len())
            .map(|j| {
                if states[j] != NodeState::Open {
                    lambda[j]
                } else {
                    0.0
                }
            })
            .collect();
        add_rows(pair, &here, &states, out);
        let force = add_forces(&here, &lambda, out);
        for (node, &state) in mem.nodes.iter_mut().zip(&states) {
            node.state = state;
        }
        let result = if keep.is_none() {
            report(pair, &here, &states, &lambda, &force)
        } else {
            PairResult::default()
        };
        out.kept.push(Kept::new(Decided {
            at: here,
            states,
            lambda,
        }));
        Ok(result)
    }

    fn inner_solves(&self) -> bool {
        true
    }

    /// The nodes the linearised problem decides otherwise: a node in
    /// contact whose multiplier after the solve (fitted to the predicted
    /// out-of-balance force) pulls by more than the force tolerance opens;
    /// an open node whose gap weighted by its hat function the solve
    /// takes below minus the length tolerance (over its area) closes.
    fn predict(
        &self,
        at: &Prediction,
        _pair: (usize, &ContactPair),
        _mem: &PairMemory,
        kept: &Kept,
        _cache: &mut SearchCache,
    ) -> Result<Option<Vec<(usize, Forced)>>, String> {
        let Some(kept) = kept.get::<Decided>() else {
            return Ok(None);
        };
        let here = &kept.at;
        let closed: Vec<bool> = kept.states.iter().map(|&s| s != NodeState::Open).collect();
        let lambda = here.multipliers(&closed, at.force_new);
        let [force_tol, length_tol] = at.tolerance;
        let mut switched = Vec::new();
        for (j, gap) in here.gaps.iter().enumerate() {
            if here.weightless[j] || !gap.touched {
                continue;
            }
            let a = here.area[j];
            if closed[j] {
                if lambda[j] * a < -force_tol && !at.settling {
                    switched.push((j, Forced::Open));
                }
            } else {
                let (value, gradient) = &gap.hat_weighted;
                let moved: f64 = (gradient.iter())
                    .map(|&(d, v)| v * (at.u_new[d] - at.u_now[d]))
                    .sum();
                let overlap = -(value + moved) / a;
                if overlap > length_tol {
                    switched.push((j, Forced::Close { j: 0, overlap }));
                }
            }
        }
        Ok(Some(switched))
    }

    fn sensitivities(&self) -> bool {
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
            "pair '{}': the sensitivities of mortar contact are not available",
            pair.name
        ))
    }
}

/// The longest side of a surface at positions `x`.
fn longest_side(surface: &Surface, x: &[[f64; 2]]) -> f64 {
    (surface.sides.iter())
        .map(|s| {
            let (a, b) = (x[s[0]], x[s[s.len() - 1]]);
            (b[0] - a[0]).hypot(b[1] - a[1])
        })
        .fold(0.0, f64::max)
}

/// Each contactor node's weighted gap from the side pairs' parts.
fn gather(parts: &[Part], m: usize) -> Vec<NodeGap> {
    type Sum = (f64, BTreeMap<usize, f64>);
    let mut sums: Vec<(Sum, Sum, bool)> = vec![Default::default(); m];
    let add = |sum: &mut Sum, value: f64, dofs: &[usize], gradient: &[f64]| {
        sum.0 += value;
        for (&d, &v) in dofs.iter().zip(gradient) {
            *sum.1.entry(d).or_default() += v;
        }
    };
    for part in parts {
        for ((k, value, gradient, _), (mean, mean_gradient)) in
            part.gaps.iter().zip(&part.hat_weighted)
        {
            let s = &mut sums[*k];
            add(&mut s.0, *value, &part.dofs, gradient);
            add(&mut s.1, *mean, &part.dofs, mean_gradient);
            s.2 = true;
        }
    }
    let entries = |m: BTreeMap<usize, f64>| m.into_iter().filter(|e| e.1 != 0.0).collect();
    sums.into_iter()
        .map(|(gap, hat_weighted, touched)| NodeGap {
            value: gap.0,
            gradient: entries(gap.1),
            hat_weighted: (hat_weighted.0, entries(hat_weighted.1)),
            touched,
        })
        .collect()
}

/// `argmin |A l - b|` for the sparse columns of A, by conjugate gradients
/// on the normal equations (CGLS) to round-off.
fn least_squares(columns: &[Vec<(usize, f64)>], b: &[f64]) -> Vec<f64> {
    let n = columns.len();
    let apply = |p: &[f64]| {
        let mut q = vec![0.0; b.len()];
        for (c, &pj) in columns.iter().zip(p) {
            for &(i, v) in c {
                q[i] += v * pj;
            }
        }
        q
    };
    let transposed = |r: &[f64]| -> Vec<f64> {
        (columns.iter())
            .map(|c| c.iter().map(|&(i, v)| v * r[i]).sum())
            .collect()
    };
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let mut x = vec![0.0; n];
    let mut r = b.to_vec();
    let mut s = transposed(&r);
    let mut p = s.clone();
    let mut gamma = dot(&s, &s);
    let gamma0 = gamma;
    for _ in 0..(4 * n + 20) {
        if gamma <= 1e-30 * gamma0 || gamma == 0.0 {
            break;
        }
        let q = apply(&p);
        let qq = dot(&q, &q);
        if qq == 0.0 {
            break;
        }
        let alpha = gamma / qq;
        for (xi, pi) in x.iter_mut().zip(&p) {
            *xi += alpha * pi;
        }
        for (ri, qi) in r.iter_mut().zip(&q) {
            *ri -= alpha * qi;
        }
        s = transposed(&r);
        let next = dot(&s, &s);
        let beta = next / gamma;
        gamma = next;
        for (pi, si) in p.iter_mut().zip(&s) {
            *pi = si + beta * *pi;
        }
    }
    x
}

/// Each node's state from its multiplier and weighted gap: a node in
/// contact opens when its traction pulls (kept while the iterate settles,
/// counted as pending); an open node closes when its gap weighted by its
/// hat function is negative (or zero, when touching closes). Changes between open and
/// contact are counted and releases logged.
#[allow(clippy::too_many_arguments)]
fn decide(
    at: &Iterate,
    pair: &ContactPair,
    mem: &PairMemory,
    here: &PairAt,
    lambda: &[f64],
    flips: &mut [usize],
    log: &mut dyn FnMut(&str),
    out: &mut ContactSystem,
) -> Result<Vec<NodeState>, String> {
    let scale = lambda.iter().fold(0.0f64, |a, l| a.max(l.abs()));
    let tension = TENSION_TOLERANCE * scale;
    let mut states = Vec::with_capacity(here.gaps.len());
    for (j, gap) in here.gaps.iter().enumerate() {
        let old = mem.nodes[j].state;
        if here.weightless[j] {
            // Set by its side afterwards, not counted.
            states.push(old);
            continue;
        }
        let state = if !gap.touched {
            NodeState::Open
        } else if old != NodeState::Open {
            if lambda[j] >= -tension {
                NodeState::Slip
            } else if at.start.settling {
                out.pending += 1;
                NodeState::Slip
            } else {
                NodeState::Open
            }
        } else if gap.hat_weighted.0 < 0.0 || (gap.hat_weighted.0 == 0.0 && at.start.touching) {
            NodeState::Slip
        } else {
            NodeState::Open
        };
        if (state == NodeState::Open) != (old == NodeState::Open) {
            out.changes += 1;
            count_flip(pair, j, flips)?;
            if state == NodeState::Open {
                log(&format!(
                    "pair '{}' node {j}: released (traction {:.3e})",
                    pair.name, lambda[j]
                ));
            }
        }
        states.push(state);
    }
    Ok(states)
}

/// A row per node in contact: its weighted gap closed to first order,
/// `grad g_j du = -g_j`, divided by the node's area so that the row reads
/// in lengths (its multiplier a force) as a node-to-segment row does.
fn add_rows(pair: &ContactPair, here: &PairAt, states: &[NodeState], out: &mut ContactSystem) {
    for (j, gap) in here.gaps.iter().enumerate() {
        if states[j] == NodeState::Open || !gap.touched {
            continue;
        }
        let a = here.area[j];
        let entries: Vec<(usize, f64)> = gap.gradient.iter().map(|&(d, v)| (d, v / a)).collect();
        let row = out.rows.len();
        out.rows.push(Row {
            dofs: super::Entries::from_slice(&entries),
            rhs: -gap.value / a,
            column: Default::default(),
        });
        out.groups.push((pair.contactor[j], row..row + 1));
        out.max_overlap = out.max_overlap.max((gap.value / a).abs());
    }
}

/// The contact forces `sum lambda_j grad g_j` into `out.force` and the
/// tangent `-sum lambda_j hess g_j` into `out.k`; returns the forces per
/// dof.
fn add_forces(here: &PairAt, lambda: &[f64], out: &mut ContactSystem) -> BTreeMap<usize, f64> {
    let mut force: BTreeMap<usize, f64> = BTreeMap::new();
    for (gap, &l) in here.gaps.iter().zip(lambda).filter(|(_, l)| **l != 0.0) {
        for &(d, v) in &gap.gradient {
            *force.entry(d).or_default() += l * v;
        }
    }
    out.force.extend(force.iter().map(|(&d, &f)| (d, f)));
    for part in &here.parts {
        let count = part.dofs.len();
        let mut h = vec![0.0; count * count];
        let mut any = false;
        for (k, _, _, hessian) in &part.gaps {
            let l = lambda[*k];
            if l != 0.0 {
                any = true;
                for (hi, v) in h.iter_mut().zip(hessian) {
                    *hi -= l * v;
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
                    out.k.push((da, db, v));
                }
            }
        }
    }
    force
}

/// The pair's results: per node its state, normal force (its traction
/// times its area) and traction; the resultants of the contact forces on
/// the contactor, normal (compression positive) and tangential parts along
/// each node's frame.
fn report(
    pair: &ContactPair,
    here: &PairAt,
    states: &[NodeState],
    lambda: &[f64],
    force: &BTreeMap<usize, f64>,
) -> PairResult {
    let (contactor, x, area) = (&here.contactor, &here.x, &here.area);
    let xv: Vec<Vector2<f64>> = x.iter().map(|p| Vector2::new(p[0], p[1])).collect();
    let mut report = Report::new(x.len());
    let mut tn = vec![0.0; x.len()];
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
        if states[j] != NodeState::Open {
            tn[j] = lambda[j];
        }
        report.node(xv[j], states[j], [lambda[j] * area[j], 0.0]);
    }
    // A node of no weight reports the traction field's value there.
    for j in (0..x.len()).filter(|&j| here.weightless[j] && states[j] != NodeState::Open) {
        let (e, l) = contactor.on[j][0];
        tn[j] = field_at_node(&here.setting(), e, l, lambda);
    }
    let mut result = report.result;
    result.nodes.tn = tn;
    result.nodes.tt = vec![0.0; x.len()];
    result
}
