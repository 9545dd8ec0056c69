//! The outputs before the first increment, as every reader of the solver's
//! results (the command line, the FMU) sees them: forces zero, every
//! contactor node open at its position, running strips laid along their
//! paths with nothing fed yet.

use super::Solver;
use crate::contact::outputs;
use crate::problem::Problem;
use crate::results::StepResult;

/// A problem at rest at t = 0, before any solver is made.
pub fn rest_step(problem: &Problem) -> StepResult {
    let mut rest = outputs::rest_step(problem, 0.0, &problem.initial_u());
    rest.running = crate::running::at_rest(problem);
    rest
}

impl Solver {
    /// The solver's state as a step at rest: its time and displacements,
    /// its running strips' figures, no contact force.
    pub fn rest_step(&self) -> StepResult {
        let state = self.state();
        let mut rest = outputs::rest_step(self.problem(), state.time, &state.u);
        rest.running = self.running_results();
        rest
    }
}
