//! What one increment produced, in the names of the FMU and summary file
//! (SPEC section 5). Plain data: the CLI serializes it, the FMU reads it.

use serde::{Deserialize, Serialize};

/// Force that a driver exerts on the body to impose its motion.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct DriverResult {
    #[serde(rename = "Rx")]
    pub rx: f64,
    #[serde(rename = "Ry")]
    pub ry: f64,
    /// Moment about the reference point (rigid targets only).
    #[serde(rename = "Mz", default, skip_serializing_if = "Option::is_none")]
    pub mz: Option<f64>,
    /// On a force component: the mean displacement of the driver's nodes
    /// (what the force produced); `Rx`/`Ry` are then the applied force.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ux: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uy: Option<f64>,
}

/// Contact state of a contactor node (the summary's and the FMU's codes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(into = "i32", try_from = "i32")]
pub enum NodeState {
    #[default]
    Open,
    Stick,
    Slip,
}

impl TryFrom<i32> for NodeState {
    type Error = String;
    fn try_from(v: i32) -> Result<Self, String> {
        match v {
            0 => Ok(NodeState::Open),
            1 => Ok(NodeState::Stick),
            2 => Ok(NodeState::Slip),
            _ => Err(format!("contact node state {v} is not 0, 1 or 2")),
        }
    }
}

impl From<NodeState> for i32 {
    /// 0 open, 1 sticking, 2 sliding.
    fn from(s: NodeState) -> i32 {
        match s {
            NodeState::Open => 0,
            NodeState::Stick => 1,
            NodeState::Slip => 2,
        }
    }
}

/// Per contactor node, in contactor order: current position, the normal
/// traction (positive in compression) and the tangential traction (positive
/// from a node toward the next), and the state.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PairNodes {
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub tn: Vec<f64>,
    pub tt: Vec<f64>,
    pub state: Vec<NodeState>,
    /// Normal gap to the target (positive clear of it, negative into it):
    /// zero to Newton's tolerance at a node in contact
    /// (`contact::outputs::gaps_and_slips`).
    #[serde(default)]
    pub gap: Vec<f64>,
    /// Slip over the last step relative to the target, along the contactor
    /// (the direction of `tt`: friction opposes it); zero for a node not in
    /// contact at both ends of the step.
    #[serde(default)]
    pub slip: Vec<f64>,
    /// On a strip's contactor: each node's angle along the wrap from the
    /// take-up side's tangent point (`StripPath::angle_from_exit`); empty
    /// elsewhere.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub angle: Vec<f64>,
    /// The normal contact force on each node (compression positive): the
    /// multiplier the contact conditions hold on, whose sign the reported
    /// traction of an 8-node side (a quadratic fit of these forces) need
    /// not keep. Not written to the summary.
    #[serde(skip)]
    pub pn: Vec<f64>,
    /// The tangential contact force on each node, in `tt`'s direction.
    #[serde(skip)]
    pub pt: Vec<f64>,
}

/// Resultants of one contact pair: the force the target exerts on the
/// contactor (global Fx, Fy; Fn, Ft its normal and tangential parts summed
/// over the contactor segments), node counts by state, and the nodes.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PairResult {
    #[serde(rename = "Fx")]
    pub fx: f64,
    #[serde(rename = "Fy")]
    pub fy: f64,
    #[serde(rename = "Fn")]
    pub fn_: f64,
    #[serde(rename = "Ft")]
    pub ft: f64,
    pub n_stick: usize,
    pub n_slip: usize,
    pub n_open: usize,
    /// Length of the contactor surface that sticks, and that slides, in the
    /// current configuration ([`PairResult::zone_lengths`]).
    #[serde(default)]
    pub stick_length: f64,
    #[serde(default)]
    pub slip_length: f64,
    pub nodes: PairNodes,
}

impl PairResult {
    /// The contactor's stick and slip zone lengths from its nodes' states
    /// and current positions, segment by segment (`closed`: the last node
    /// joins the first): a segment whose two nodes share a state counts
    /// whole to it; one between a sticking and a sliding node half to each;
    /// one between a node in contact and an open node half to the node in
    /// contact (the zone's edge lies within it, at its midpoint on
    /// average); one between two open nodes to neither.
    pub fn zone_lengths(nodes: &PairNodes, closed: bool) -> (f64, f64) {
        let m = nodes.state.len();
        let segments = if closed { m } else { m.saturating_sub(1) };
        let (mut stick, mut slip) = (0.0, 0.0);
        for a in 0..segments {
            let b = (a + 1) % m;
            let length = (nodes.x[b] - nodes.x[a]).hypot(nodes.y[b] - nodes.y[a]);
            for k in [a, b] {
                match nodes.state[k] {
                    NodeState::Stick => stick += 0.5 * length,
                    NodeState::Slip => slip += 0.5 * length,
                    NodeState::Open => {}
                }
            }
        }
        (stick, slip)
    }
}

/// What a running strip reports after a step.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RunningResult {
    /// Reference length of strip that has run in at the supply end.
    pub fed: f64,
    /// Material speed along the path at the supply and take-up ends over
    /// the last step (lab frame).
    pub speed_in: f64,
    pub speed_out: f64,
    /// Strain of the mid-line at the supply and take-up ends.
    pub strain_in: f64,
    pub strain_out: f64,
}

/// One converged (or failed) increment.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StepResult {
    pub time: f64,
    pub converged: bool,
    /// Newton iterations summed over the sub-increments of this step.
    pub iterations: usize,
    /// Number of bisections used (0: the increment was taken whole).
    pub substeps: usize,
    /// Linear solves summed over the sub-increments (one per Newton
    /// iteration, and one more per change of the linearised problem's
    /// contact states within an iteration). Not written to the summary.
    #[serde(skip)]
    pub solves: usize,
    /// Numeric factorizations summed over the sub-increments (an inner
    /// solve done with its iteration's factorization adds none). Not
    /// written to the summary.
    #[serde(skip)]
    pub factorizations: usize,
    /// Increments the inner solves failed and the iterate's decisions
    /// alone then solved or failed too (`Solver::advance`). Not written to
    /// the summary.
    #[serde(skip)]
    pub fallbacks: usize,
    /// Final relative force residual.
    pub residual: f64,
    /// Number of contact equations (0 until contact exists).
    pub neqc: usize,
    /// Per driver, by name, in scene order; rigid targets follow the
    /// drivers, with their moment.
    pub drivers: Vec<(String, DriverResult)>,
    /// Per contact pair, by name, in scene order.
    pub pairs: Vec<(String, PairResult)>,
    /// Per tie, by name, in scene order: its forces on the tied nodes.
    #[serde(default)]
    pub ties: Vec<(String, crate::constraint::TieResult)>,
    /// Per running strip, by body name, in body order.
    #[serde(default)]
    pub running: Vec<(String, RunningResult)>,
}

/// Log categories; they are the FMU logger's categories.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LogCategory {
    Error,
    Warning,
    Newton,
    Contact,
}

impl LogCategory {
    pub fn fmi_name(self) -> &'static str {
        match self {
            LogCategory::Error => "logStatusError",
            LogCategory::Warning => "logStatusWarning",
            LogCategory::Newton => "logNewton",
            LogCategory::Contact => "logContact",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Five nodes 1 apart on a line, open-stick-stick-slip-open: the
    /// stick zone is the segment between the sticking nodes plus half a
    /// segment to each neighbour (2.0), the slip zone half a segment to
    /// each of its neighbours (1.0); closing the chain adds the segment
    /// from the last node back to the first (both open: nothing).
    #[test]
    fn zone_lengths_by_half_segments() {
        use NodeState::*;
        let nodes = PairNodes {
            x: vec![0.0, 1.0, 2.0, 3.0, 4.0],
            y: vec![0.0; 5],
            state: vec![Open, Stick, Stick, Slip, Open],
            ..Default::default()
        };
        assert_eq!(PairResult::zone_lengths(&nodes, false), (2.0, 1.0));
        assert_eq!(PairResult::zone_lengths(&nodes, true), (2.0, 1.0));
        // A ring of three sliding nodes: its whole perimeter slides.
        let ring = PairNodes {
            x: vec![0.0, 3.0, 0.0],
            y: vec![0.0, 0.0, 4.0],
            state: vec![Slip; 3],
            ..Default::default()
        };
        assert_eq!(PairResult::zone_lengths(&ring, true), (0.0, 12.0));
        assert_eq!(PairResult::zone_lengths(&ring, false), (0.0, 8.0));
    }
}

/// Wall time of the linear algebra by phase, summed over its calls (the
/// benchmark's split, issue 14).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LinearTimes {
    /// Building the bordered matrix (contact rows sorted into the tangent's
    /// columns) and its symmetry check.
    pub system: std::time::Duration,
    /// Fill-reducing ordering and symbolic factorization.
    pub symbolic: std::time::Duration,
    /// Numeric factorization.
    pub numeric: std::time::Duration,
    /// Triangular solves, refinement and backward errors, trailing solves.
    pub solve: std::time::Duration,
}

impl LinearTimes {
    /// The sum of two tallies.
    pub fn plus(self, o: LinearTimes) -> LinearTimes {
        LinearTimes {
            system: self.system + o.system,
            symbolic: self.symbolic + o.symbolic,
            numeric: self.numeric + o.numeric,
            solve: self.solve + o.solve,
        }
    }
}

/// What a run's linear solves cost and how they went, summed (the
/// solver's counters, `linsolve::Linear::counts`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LinearCounts {
    pub times: LinearTimes,
    /// Numeric factorizations (failed LDLT attempts included).
    pub factorizations: usize,
    /// Symbolic analyses of bordered systems (a new contact pattern).
    pub analyses: usize,
    /// Bordered systems solved by LDLT, by LU, by the unpivoted LDU, and
    /// without a factorization of their own, on the last LDLT factor's
    /// trailing block.
    pub ldlt: usize,
    pub lu: usize,
    pub ldu: usize,
    pub trailing: usize,
    /// Of the trailing solves, the ones whose interior waited until an
    /// inner solve was accepted.
    pub deferred: usize,
    /// Iterations whose first solve took the trailing block instead of a
    /// factorization (a constant tangent, its contact rows changed on the
    /// trailing set alone).
    pub reused: usize,
}
