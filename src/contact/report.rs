//! A pair's reported results: its resultants, the reaction on a rigid
//! target, the node states and forces; and what the formulations' reports
//! share: the analysis' area weights (`Geometry`) and a contactor node's
//! frame.

use super::search::rigid_reference;
use super::segment::ContactPoint;
use super::system::Iterate;
use crate::problem::{AnalysisKind, ContactPair, Problem, Target};
use crate::results::{NodeState, PairResult};
use nalgebra::Vector2;

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
        let (normal, tangent) = (cp.normal(), cp.tangent());
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

/// Planar (plane stress, plane strain) or axisymmetric analysis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Geometry {
    /// Uniform thickness `h` (plane strain uses the solver's thickness, 1 by default).
    Planar { thickness: f64 },
    /// x is the radius; weights are taken over the full circle (`2 pi x ds`).
    Axisymmetric,
}

/// The analysis' geometry, as the contact kernels weigh areas.
pub(super) fn geometry(problem: &Problem) -> Geometry {
    match problem.analysis {
        AnalysisKind::PlaneStrain { thickness } | AnalysisKind::PlaneStress { thickness } => {
            Geometry::Planar { thickness }
        }
        AnalysisKind::Axisymmetric => Geometry::Axisymmetric,
    }
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
