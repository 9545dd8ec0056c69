//! What contact carries from one iteration, and one increment, to the next:
//! per contactor node its state, target segment, contact point and anchor;
//! per contactor segment its state (the paper's decisions). Part of the
//! solver's `State` (rollback, FMU state).

use crate::problem::ContactPair;
use crate::results::NodeState;
use serde::{Deserialize, Serialize};

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
    /// What the nodal decisions alone keep of the node.
    #[serde(default)]
    pub nodal: NodalMemory,
}

/// What the nodal decisions keep of a contactor node besides its contact.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct NodalMemory {
    /// The direction of its slip along the target's tangent (A to B) while
    /// it slides, +-1.
    pub slip_sign: f64,
    /// It has slid in this increment (sticks with mu_d).
    pub slid: bool,
    /// It has ever slid (mu_d for good under the usual rule).
    pub ever_slid: bool,
    /// How many times it left a corner hold in this increment (after
    /// `CORNER_LEAVES`, held again only from the wedge itself).
    pub corner_leaves: u32,
}

/// A contactor segment's memory (segment j joins contactor nodes j, j+1),
/// the paper's decisions' own.
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
        node.nodal.slid = false;
        node.nodal.corner_leaves = 0;
    }
}
