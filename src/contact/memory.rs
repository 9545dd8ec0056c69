//! What contact carries from one iteration, and one increment, to the
//! next, as the shared phases see it: each formulation keeps a pair's
//! memory in its own type (a variant of `PairMemory`, part of the solver's
//! `State`: rollback, FMU state); `Remembered` is what every one answers,
//! and what a `PairMemory` dereferences to.

use super::PairMemory;
use crate::results::NodeState;

/// What the shared phases read of a formulation's memory of a pair, and
/// what they do to it.
pub trait Remembered {
    /// How many contactor nodes it remembers.
    fn nodes(&self) -> usize;

    /// Node k's state and, in contact, where it meets the target (target
    /// segment, beta): the outputs' gap and slip are measured there.
    fn contact(&self, k: usize) -> (NodeState, usize, f64);

    /// Node k's state.
    fn state(&self, k: usize) -> NodeState {
        self.contact(k).0
    }

    /// Node k's slip direction while it slides (+-1), else 0: part of the
    /// set of states the inner solves stop on meeting again (`state_key`).
    fn slip_sign(&self, k: usize) -> f64;

    /// The start of an increment from the converged state it holds.
    fn begin_increment(&mut self);

    /// The contactor's material moved along its chain (a running strip's
    /// recycled material): node k takes over what node `sources[k]`
    /// remembered, or starts afresh (None).
    fn shift(&mut self, sources: &[Option<usize>]);
}

/// The start of an increment from the converged state `memory` holds.
pub fn begin_increment(memory: &mut [PairMemory]) {
    for m in memory {
        m.begin_increment();
    }
}
