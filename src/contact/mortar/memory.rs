//! What a mortar pair carries from one iteration, and one increment, to
//! the next: per contactor node its decision, whether it has slid, and
//! where it meets the target. The pair's variant of `contact::PairMemory`.

use crate::contact::memory::Remembered;
use crate::problem::ContactPair;
use crate::results::NodeState;
use serde::{Deserialize, Serialize};

/// What a contactor node remembers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Node {
    pub state: NodeState,
    /// Where it meets the target's polyline (segment, beta), for the
    /// outputs' gap and slip (`remember_feet`).
    pub segment: usize,
    pub beta: f64,
    /// The direction of its slip along its tangent while it slides with
    /// friction, +-1; 0 otherwise.
    pub slip_sign: f64,
    /// It has slid with friction in this increment (sticks with mu_s
    /// again under the rule `AlwaysMuS` only when it has not).
    pub slid: bool,
    /// It has ever slid with friction (mu_d for good under the usual rule).
    pub ever_slid: bool,
}

/// A mortar pair's memory.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Memory {
    pub nodes: Vec<Node>,
}

impl Memory {
    pub fn new(pair: &ContactPair) -> Self {
        Memory {
            nodes: vec![Node::default(); pair.contactor.len()],
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
        self.nodes[k].slip_sign
    }

    fn begin_increment(&mut self) {
        for node in &mut self.nodes {
            node.slid = false;
        }
    }

    fn shift(&mut self, sources: &[Option<usize>]) {
        let old = self.nodes.clone();
        for (node, src) in self.nodes.iter_mut().zip(sources) {
            *node = src.map_or_else(Node::default, |f| old[f]);
        }
    }
}
