//! Mortar (segment-to-segment) contact between two bodies (`formulation =
//! "mortar"`): the contact conditions hold on weighted gaps, one per
//! contactor node, integrated over the contactor against the target's
//! interpolation (`integrate`), and the multipliers are the tractions at
//! the contactor's nodes, interpolated by the dual basis of its sides. A
//! uniform pressure between non-matching meshes is carried exactly (the
//! contact patch test), and a target node between two contactor nodes no
//! longer slips through.
//!
//! Per iteration: the weighted gaps with their gradients and Hessians
//! (with friction also the weighted slips since the start of the
//! increment); the multipliers recovered from the contactor's
//! out-of-balance forces (the least-squares fit of the gradients, exact at
//! equilibrium); each node decided on its own multipliers, weighted gap
//! and weighted slip (`decide`); per node in contact a row `grad g_j du =
//! -g_j` scaled by its area, a second one on its weighted slip while it
//! sticks, its friction `mu_d` against the slip in its multiplier's column
//! while it slides; the contact forces and their tangent (`rows`). Against
//! a deformable target. The derivation is in docs/contact.md section 11.

mod decide;
mod dual;
mod integrate;
mod linearise;
mod memory;
mod rows;
mod surface;

use super::outputs::nearest_point;
use super::report::geometry;
use super::search::{SearchCache, target_segments};
use super::sensitivity::{At, Linearised};
use super::system::{ContactSystem, Forced, Iterate};
use super::{Formulation, Kept, PairMemory, Prediction, StartData, mismatch};
use crate::assembly::PRESCRIBED;
use crate::problem::{ContactPair, Kinematics};
use crate::results::{NodeState, PairResult};
use decide::Decision;
use integrate::{Coupling, Order, Part, Setting, couplings, integrate, slip_from};
use nalgebra::Vector2;
use std::collections::BTreeMap;
use std::sync::Arc;
use surface::Surface;

pub use memory::Memory;

/// Mortar contact (`formulation = "mortar"`).
pub(super) struct Mortar;

/// A sum of mesh-dof entries (dof, coefficient).
type Gradient = Vec<(usize, f64)>;

/// One contactor node's weighted gap summed over its side pairs: value and
/// gradient (mesh dof, coefficient); `touched`: some target side meets one
/// of its sides.
#[derive(Clone, Debug, Default)]
struct NodeGap {
    value: f64,
    gradient: Gradient,
    /// The gap weighted by the node's hat function (`integrate::hat`):
    /// value and gradient. The dual basis (and an 8-node side's quadratic
    /// shape functions) take negative values, so a node whose gap grows
    /// along its sides may show a negative weighted gap while clear of the
    /// target everywhere; a node closes on this one, negative only where
    /// the target is entered near the node.
    hat_weighted: (f64, Gradient),
    /// The integral of its hat function where the target covers its sides
    /// (`Part::covered`): value and gradient. `hat_weighted` over it is
    /// its mean gap there (`mean_gap`), which a shrinking cover leaves
    /// finite.
    covered: (f64, Gradient),
    touched: bool,
    /// With friction, the node's weighted slip since the start of the
    /// increment along its tangent (`integrate::slip_from` less the parts'
    /// `slips`): value and gradient, and the Hessian entries of its
    /// `slip_from` term (the parts hold the rest).
    slip: (f64, Gradient),
    slip_hessian: Vec<(usize, usize, f64)>,
}

/// A pair at an iterate: its surfaces and positions, the weighted gaps
/// with their side pairs' parts (to the first order; the second where a
/// solve needs the tangent), each contactor node's area and whether it has
/// none, and the free dofs of both surfaces (the rows of the multipliers'
/// least-squares fit). Kept for the inner solves at the same iterate.
struct PairAt {
    contactor: Surface,
    target: Surface,
    x: Vec<[f64; 2]>,
    y: Vec<[f64; 2]>,
    x_ref: Vec<[f64; 2]>,
    reference_measure: bool,
    geometry: crate::contact::report::Geometry,
    friction: bool,
    parts: Vec<Part>,
    /// The parts with their Hessians (`second_order`).
    second: std::sync::OnceLock<Vec<Part>>,
    gaps: Vec<NodeGap>,
    area: Vec<f64>,
    weightless: Vec<bool>,
    free: BTreeMap<usize, usize>,
    /// The longest side of either surface.
    h: f64,
}

/// What `update` keeps for `predict` and the inner solves' `update`: the
/// pair at the iterate, and the decisions and multipliers (normal and
/// tangential tractions) its rows were built from.
pub(crate) struct Decided {
    at: Arc<PairAt>,
    decisions: Vec<Decision>,
    lambda: Vec<f64>,
    lambda_t: Vec<f64>,
}

/// Both surfaces' nodes and their positions.
type StartKey = (Vec<usize>, Vec<usize>, Vec<[f64; 2]>, Vec<[f64; 2]>);

/// Where the contactor's points met the target at the start of the
/// increment (`integrate::couplings`), with the key they were made from:
/// both surfaces' nodes and positions there (`StartCache`).
pub(crate) struct AtStart {
    key: StartKey,
    couplings: Vec<Coupling>,
}

impl Decided {
    /// The contact tangent of the decisions' rows (`ContactSystem::defer_tangent`).
    pub(crate) fn add_tangent(&self, k: &mut Vec<(usize, usize, f64)>) {
        rows::add_tangent(&self.at, [&self.lambda, &self.lambda_t], k);
    }
}

impl PairAt {
    fn new(at: &Iterate, (p, pair): (usize, &ContactPair)) -> Result<Self, String> {
        let problem = at.problem;
        let mut contactor = Surface::contactor(problem, pair)?;
        let target = Surface::target(problem, pair)?.ok_or_else(|| {
            format!(
                "pair '{}': mortar contact needs a body as target",
                pair.name
            )
        })?;
        contactor.hold_symmetry_planes(&target, &problem.mesh.nodes, &|d| at.eq[d] == PRESCRIBED);
        let point = |n: usize, u: Option<&[f64]>| {
            let p = problem.mesh.nodes[n];
            u.map_or(p, |u| [p[0] + u[2 * n], p[1] + u[2 * n + 1]])
        };
        let positions =
            |s: &Surface, u: Option<&[f64]>| s.nodes.iter().map(|&n| point(n, u)).collect();
        // The contactor's and the target's surface dofs that no driver
        // holds: where a contactor node's tangential dof is held (a
        // symmetry plane), the target's side of its weighted slip still
        // sets its tangential traction.
        let mut free = BTreeMap::new();
        for &n in pair.contactor.iter().chain(&target.nodes) {
            for d in [2 * n, 2 * n + 1]
                .into_iter()
                .filter(|&d| at.eq[d] != PRESCRIBED)
            {
                let next = free.len();
                free.entry(d).or_insert(next);
            }
        }
        let mut pair_at = PairAt {
            x: positions(&contactor, Some(at.u)),
            y: positions(&target, Some(at.u)),
            x_ref: positions(&contactor, None),
            contactor,
            target,
            reference_measure: matches!(
                problem.kinematics,
                Kinematics::SmallStrain | Kinematics::MaterialNonlinearOnly
            ),
            geometry: geometry(problem),
            friction: pair.mu_s != 0.0 || pair.mu_d != 0.0,
            parts: Vec::new(),
            second: std::sync::OnceLock::new(),
            gaps: Vec::new(),
            area: Vec::new(),
            weightless: Vec::new(),
            free,
            h: 0.0,
        };
        pair_at.h = longest_side(&pair_at.contactor, &pair_at.x)
            .max(longest_side(&pair_at.target, &pair_at.y));
        let (parts, area) = integrate(&pair_at.setting(&pair_at.x, &pair_at.y), Order::First);
        let mut gaps = gather(&parts, pair_at.x.len());
        if pair_at.friction {
            // Where the contactor's points met the target at the start of
            // the increment: the weighted slips are measured from there.
            // They depend on the start alone: made at the increment's first
            // iterate, kept for the others (`StartCache`).
            let (x0, y0): (Vec<[f64; 2]>, Vec<[f64; 2]>) = (
                positions(&pair_at.contactor, Some(at.start.u)),
                positions(&pair_at.target, Some(at.start.u)),
            );
            let key = (
                pair_at.contactor.nodes.clone(),
                pair_at.target.nodes.clone(),
                x0.clone(),
                y0.clone(),
            );
            let start = match at.start.cache.get(p) {
                Some(StartData::Mortar(kept)) if kept.key == key => kept,
                _ => {
                    // Their reach is the start's own (`PairAt::h` there).
                    let h0 = longest_side(&pair_at.contactor, &x0)
                        .max(longest_side(&pair_at.target, &y0));
                    let couplings = couplings(&Setting {
                        reach: 2.0 * h0,
                        ..pair_at.setting(&x0, &y0)
                    });
                    let made = Arc::new(AtStart { key, couplings });
                    at.start.cache.set(p, StartData::Mortar(made.clone()));
                    made
                }
            };
            pair_at.add_slips(&mut gaps, &parts, &start.couplings);
        }
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

    /// The side pairs' parts with their Hessians, integrated on the first
    /// call: the contact tangent is formed only at an iterate a solve
    /// starts from (`ContactSystem::defer_tangent`). Their values and
    /// gradients are the first-order parts', bit for bit.
    fn second_order(&self) -> &[Part] {
        self.second.get_or_init(|| {
            let (parts, _) = integrate(&self.setting(&self.x, &self.y), Order::Second);
            debug_assert!(
                parts.len() == self.parts.len()
                    && (parts.iter().zip(&self.parts)).all(|(a, b)| a.dofs == b.dofs
                        && (a.gaps.iter().zip(&b.gaps))
                            .all(|(p, q)| p.0 == q.0 && p.1.to_bits() == q.1.to_bits()))
            );
            parts
        })
    }

    /// The pair's setting with the contactor at `x` and the target at `y`.
    fn setting<'a>(&'a self, x: &'a [[f64; 2]], y: &'a [[f64; 2]]) -> Setting<'a> {
        Setting {
            contactor: &self.contactor,
            target: &self.target,
            x,
            y,
            x_ref: &self.x_ref,
            reference_measure: self.reference_measure,
            geometry: self.geometry,
            reach: 2.0 * self.h,
            friction: self.friction,
        }
    }

    /// Each touched node's weighted slip: its `slip_from` the increment's
    /// start coupling `start` less its parts' `slips`.
    fn add_slips(&self, gaps: &mut [NodeGap], parts: &[Part], start: &[Coupling]) {
        let setting = self.setting(&self.x, &self.y);
        let mut sums: Vec<(f64, BTreeMap<usize, f64>)> = vec![Default::default(); gaps.len()];
        for part in parts {
            for ((k, ..), (value, gradient, _)) in part.gaps.iter().zip(&part.slips) {
                let sum = &mut sums[*k];
                sum.0 -= value;
                for (&d, &v) in part.dofs.iter().zip(gradient) {
                    *sum.1.entry(d).or_default() -= v;
                }
            }
        }
        for (k, (gap, (value, mut gradient))) in gaps.iter_mut().zip(sums).enumerate() {
            if !gap.touched {
                continue;
            }
            let from = slip_from(&setting, k, &start[k]);
            for &(d, v) in &from.gradient {
                *gradient.entry(d).or_default() += v;
            }
            gap.slip = (
                value + from.value,
                gradient.into_iter().filter(|e| e.1 != 0.0).collect(),
            );
            gap.slip_hessian = from.hessian.into_iter().filter(|e| e.2 != 0.0).collect();
        }
    }

    /// The multipliers of the nodes in contact under `decisions` from the
    /// out-of-balance force `force` (per mesh dof): the least-squares fit
    /// of the contact force to it over both surfaces' free dofs (the
    /// contact force there at equilibrium; the out-of-balance force of a
    /// surface node that another pair also touches carries that pair's
    /// force as well). Per node its normal traction
    /// (column `grad g_j`) and, with friction, its tangential traction
    /// (column `grad u_j`, its weighted slip), each its own unknown whatever
    /// the node's state, so that the force decides; zero for the nodes not
    /// in contact.
    fn multipliers(&self, decisions: &[Decision], force: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let mut b = vec![0.0; self.free.len()];
        for (&d, &i) in &self.free {
            b[i] = force[d];
        }
        let on_free = |entries: &[(usize, f64)]| -> Gradient {
            (entries.iter())
                .filter_map(|&(d, v)| self.free.get(&d).map(|&i| (i, v)))
                .collect()
        };
        // Per unknown: its node and whether it is a tangential traction.
        let mut unknowns: Vec<(usize, bool)> = Vec::new();
        let mut columns: Vec<Gradient> = Vec::new();
        for (j, (gap, d)) in self.gaps.iter().zip(decisions).enumerate() {
            if d.state == NodeState::Open || !gap.touched {
                continue;
            }
            columns.push(on_free(&gap.gradient));
            unknowns.push((j, false));
            if self.friction && !self.on_symmetry_plane(j) {
                columns.push(on_free(&gap.slip.1));
                unknowns.push((j, true));
            }
        }
        let mut lambda = vec![0.0; self.gaps.len()];
        let mut lambda_t = vec![0.0; self.gaps.len()];
        for (&(j, tangential), l) in unknowns.iter().zip(least_squares(&columns, &b)) {
            if tangential {
                lambda_t[j] = l;
            } else {
                lambda[j] = l;
            }
        }
        (lambda, lambda_t)
    }

    /// Whether contactor node `j` lies on a symmetry plane both surfaces
    /// end on (`Surface::hold_symmetry_planes`): its tangential motion is
    /// the symmetry drivers', and by symmetry the shear across the plane,
    /// its tangential traction, is zero. It sticks, with no slip row and no
    /// tangential multiplier.
    fn on_symmetry_plane(&self, j: usize) -> bool {
        self.contactor.mirror[j].is_some()
    }

    /// A node of no weight takes its side's state: that of a node of
    /// weight on its side in contact (`followed`), or open.
    fn weightless_follow(&self, decisions: &mut [Decision]) {
        for j in (0..decisions.len()).filter(|&j| self.weightless[j]) {
            decisions[j] = self
                .followed(j, decisions)
                .map_or(Decision::OPEN, |k| Decision {
                    sign: 0.0,
                    ..decisions[k]
                });
        }
    }

    /// The node of weight in contact on weightless node j's side, nearest
    /// to it first: whose state node j takes, and whose tractions it
    /// reports.
    fn followed(&self, j: usize, decisions: &[Decision]) -> Option<usize> {
        let side = &self.contactor.sides[self.contactor.on[j][0].0];
        let distance = |k: usize| (self.x[k][0] - self.x[j][0]).hypot(self.x[k][1] - self.x[j][1]);
        (side.iter().copied())
            .filter(|&k| !self.weightless[k] && decisions[k].state != NodeState::Open)
            .min_by(|&a, &b| distance(a).total_cmp(&distance(b)))
    }
}

impl Formulation for Mortar {
    /// One pair's update, in phases: the pair at the iterate (weighted gaps
    /// and slips, `PairAt::new`), the multipliers recovered
    /// (`PairAt::multipliers`), each node's decision (`decide`; with `keep`,
    /// the kept decisions but for the forced nodes'), the rows, forces and
    /// tangent (`rows::add_rows`, `rows::add_forces`) and the reported
    /// results (`rows::report`; none for an inner solve's system, which
    /// serves its rows alone).
    fn update(
        &self,
        at: &Iterate,
        (p, pair): (usize, &ContactPair),
        mem: &mut PairMemory,
        counters: [&mut [usize]; 2],
        log: &mut dyn FnMut(&str),
        out: &mut ContactSystem,
        keep: Option<(&Kept, &[(usize, Forced)])>,
    ) -> Result<PairResult, String> {
        let PairMemory::Mortar(mem) = mem else {
            return Err(mismatch(pair, "memory"));
        };
        let (here, decisions, lambda, lambda_t) = match keep {
            Some((kept, forced)) => {
                let Kept::Mortar(kept) = kept else {
                    return Err(mismatch(pair, "inner solve's decisions"));
                };
                let mut decisions = kept.decisions.clone();
                for &(j, f) in forced {
                    decisions[j] = decide::forced(pair, &kept.at, mem, j, f);
                }
                kept.at.weightless_follow(&mut decisions);
                let (lambda, lambda_t) = (kept.lambda.clone(), kept.lambda_t.clone());
                (kept.at.clone(), decisions, lambda, lambda_t)
            }
            None => {
                let here = PairAt::new(at, (p, pair))?;
                let was: Vec<Decision> = mem.nodes.iter().map(Decision::of).collect();
                let (lambda, lambda_t) = here.multipliers(&was, at.r);
                let mut decisions = decide::decide(
                    at,
                    pair,
                    mem,
                    &here,
                    [&lambda, &lambda_t],
                    counters,
                    log,
                    out,
                )?;
                here.weightless_follow(&mut decisions);
                (Arc::new(here), decisions, lambda, lambda_t)
            }
        };
        // The multipliers of the nodes kept in contact (a node that closes
        // carries none yet), a sliding node's friction against its slip.
        let keep_closed = |l: &[f64], j: usize| {
            if decisions[j].state != NodeState::Open {
                l[j]
            } else {
                0.0
            }
        };
        let lambda: Vec<f64> = (0..decisions.len())
            .map(|j| keep_closed(&lambda, j))
            .collect();
        let lambda_t: Vec<f64> = (0..decisions.len())
            .map(|j| match decisions[j].state {
                NodeState::Slip => -decisions[j].friction(pair) * lambda[j],
                _ => keep_closed(&lambda_t, j),
            })
            .collect();
        rows::add_rows(pair, &here, &decisions, out);
        let force = rows::add_forces(&here, [&lambda, &lambda_t], out);
        out.defer_tangent(p);
        for (node, d) in mem.nodes.iter_mut().zip(&decisions) {
            d.remember(node, here.friction);
        }
        let result = if keep.is_none() {
            remember_feet(at, pair, &here, mem)?;
            rows::report(pair, &here, &decisions, [&lambda, &lambda_t], &force)
        } else {
            PairResult::default()
        };
        out.kept.push(Kept::Mortar(Arc::new(Decided {
            at: here,
            decisions,
            lambda,
            lambda_t,
        })));
        Ok(result)
    }

    fn inner_solves(&self) -> bool {
        true
    }

    /// The nodes the linearised problem decides otherwise (`decide::predict`).
    fn predict(
        &self,
        at: &Prediction,
        (_, pair): (usize, &ContactPair),
        mem: &PairMemory,
        kept: &Kept,
        _cache: &mut SearchCache,
    ) -> Result<Option<Vec<(usize, Forced)>>, String> {
        let (PairMemory::Mortar(mem), Kept::Mortar(kept)) = (mem, kept) else {
            return Ok(None);
        };
        Ok(Some(decide::predict(at, pair, mem, kept)))
    }

    /// Every pair: the weighted slips of a frictional one are measured
    /// from where the increment started (`State::step_start_u`), as
    /// Newton's were.
    fn sensitivities(&self, _pair: &ContactPair) -> bool {
        true
    }

    fn linearise(
        &self,
        at: &At,
        (p, pair): (usize, &ContactPair),
        kept: &Kept,
        out: &mut Linearised,
    ) -> Result<(), String> {
        let Kept::Mortar(kept) = kept else {
            return Err(mismatch(pair, "converged state's decisions"));
        };
        linearise::linearise_pair(at, (p, pair), kept, out);
        Ok(())
    }
}

/// Where each node in contact meets the target: the nearest point of the
/// target's polyline, into its memory's segment and parameter (the
/// outputs' gap and slip read them, `outputs::gaps_and_slips`).
fn remember_feet(
    at: &Iterate,
    pair: &ContactPair,
    here: &PairAt,
    mem: &mut Memory,
) -> Result<(), String> {
    if mem.nodes.iter().all(|n| n.state == NodeState::Open) {
        return Ok(());
    }
    let segments = target_segments(at.targets, at.problem, pair, at.u, at.poses)?;
    for (node, x) in mem.nodes.iter_mut().zip(&here.x) {
        if node.state == NodeState::Open {
            continue;
        }
        if let Some(foot) = nearest_point(&segments, Vector2::new(x[0], x[1])) {
            (node.segment, node.beta) = (foot.segment, foot.beta);
        }
    }
    Ok(())
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
    let mut sums: Vec<(Sum, Sum, Sum, bool)> = vec![Default::default(); m];
    let add = |sum: &mut Sum, value: f64, dofs: &[usize], gradient: &[f64]| {
        sum.0 += value;
        for (&d, &v) in dofs.iter().zip(gradient) {
            *sum.1.entry(d).or_default() += v;
        }
    };
    for part in parts {
        for (((k, value, gradient, _), hat), weight) in (part.gaps.iter())
            .zip(&part.hat_weighted)
            .zip(&part.covered)
        {
            let s = &mut sums[*k];
            add(&mut s.0, *value, &part.dofs, gradient);
            add(&mut s.1, hat.0, &part.dofs, &hat.1);
            add(&mut s.2, weight.0, &part.dofs, &weight.1);
            s.3 = true;
        }
    }
    let entries = |m: BTreeMap<usize, f64>| m.into_iter().filter(|e| e.1 != 0.0).collect();
    sums.into_iter()
        .map(|(gap, hat_weighted, covered, touched)| NodeGap {
            value: gap.0,
            gradient: entries(gap.1),
            hat_weighted: (hat_weighted.0, entries(hat_weighted.1)),
            covered: (covered.0, entries(covered.1)),
            touched,
            ..Default::default()
        })
        .collect()
}

/// `argmin |A l - b|` for the sparse columns of A, by conjugate gradients
/// on the normal equations (CGLS) to round-off.
fn least_squares(columns: &[Vec<(usize, f64)>], b: &[f64]) -> Vec<f64> {
    // Each column scaled to unit length (a node whose own dof a driver
    // holds has a short slip column on the free dofs): CGLS on the scaled
    // columns converges to round-off where the unscaled ones stalled.
    let scale: Vec<f64> = (columns.iter())
        .map(|c| {
            let norm = c.iter().map(|e| e.1 * e.1).sum::<f64>().sqrt();
            if norm > 0.0 { 1.0 / norm } else { 0.0 }
        })
        .collect();
    let scaled: Vec<Vec<(usize, f64)>> = (columns.iter().zip(&scale))
        .map(|(c, s)| c.iter().map(|&(i, v)| (i, v * s)).collect())
        .collect();
    let x = cgls(&scaled, b);
    x.iter().zip(&scale).map(|(x, s)| x * s).collect()
}

/// `argmin |A l - b|` for the sparse columns of A by conjugate gradients
/// on the normal equations.
fn cgls(columns: &[Vec<(usize, f64)>], b: &[f64]) -> Vec<f64> {
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
