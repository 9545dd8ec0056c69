//! What a node-to-segment pair carries from one iteration, and one
//! increment, to the next: per contactor node its state, target segment,
//! contact point and anchor; per contactor segment its state (the paper's
//! decisions). The pair's variant of `contact::PairMemory`.

use crate::contact::memory::Remembered;
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

/// A node-to-segment pair's memory.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Memory {
    pub nodes: Vec<NodeMemory>,
    pub segments: Vec<SegmentMemory>,
}

impl Memory {
    pub fn new(pair: &ContactPair) -> Self {
        let m = pair.contactor.len();
        let segments = if pair.closed { m } else { m.saturating_sub(1) };
        Memory {
            nodes: vec![NodeMemory::default(); m],
            segments: vec![SegmentMemory::default(); segments],
        }
    }
}

impl Remembered for Memory {
    fn nodes(&self) -> usize {
        self.nodes.len()
    }

    fn contact(&self, k: usize) -> (NodeState, usize, f64) {
        let node = &self.nodes[k];
        (node.state, node.segment, node.beta)
    }

    fn slip_sign(&self, k: usize) -> f64 {
        self.nodes[k].nodal.slip_sign
    }

    /// Every closed node's anchor at its converged contact point.
    fn begin_increment(&mut self) {
        for node in &mut self.nodes {
            node.anchor = (node.state != NodeState::Open).then_some((node.segment, node.beta));
            node.crossed = None;
            node.nodal.slid = false;
            node.nodal.corner_leaves = 0;
        }
    }

    /// A segment keeps its memory when both its nodes come from one
    /// segment's two nodes.
    fn shift(&mut self, sources: &[Option<usize>]) {
        let old = self.clone();
        let m = sources.len();
        for (node, src) in self.nodes.iter_mut().zip(sources) {
            *node = src.map_or_else(NodeMemory::default, |f| old.nodes[f]);
        }
        for (j, segment) in self.segments.iter_mut().enumerate() {
            *segment = match (sources[j], sources[(j + 1) % m]) {
                (Some(a), Some(b)) if a.abs_diff(b) == 1 => old.segments[a.min(b)],
                _ => SegmentMemory::default(),
            };
        }
    }
}
