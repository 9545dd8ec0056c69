//! SKELETON (being written): increments, Newton iterations, bisection.
use crate::problem::Problem;
use crate::results::{LogCategory, StepResult};
use crate::state::State;

#[derive(Debug, thiserror::Error)]
pub enum SolveError {
    #[error("invalid problem: {0}")]
    Invalid(String),
    #[error("increment to t = {time} failed: {reason}")]
    NotConverged { time: f64, reason: String },
}

pub struct Solver {
    problem: Problem,
    state: State,
}

impl Solver {
    pub fn new(problem: Problem) -> Result<Self, SolveError> {
        let n = problem.mesh.nodes.len();
        Ok(Solver { problem, state: State { time: 0.0, u: vec![0.0; 2 * n], history: vec![] } })
    }
    pub fn problem(&self) -> &Problem {
        &self.problem
    }
    pub fn state(&self) -> &State {
        &self.state
    }
    pub fn restore(&mut self, state: State) {
        self.state = state;
    }
    /// Solve equilibrium at `t_end`, bisecting on failure; on error the
    /// state stays at the last converged time.
    pub fn advance(
        &mut self,
        _t_end: f64,
        _log: &mut dyn FnMut(LogCategory, &str),
    ) -> Result<StepResult, SolveError> {
        todo!()
    }
    /// Element-average Cauchy stress [xx, yy, zz, xy] of each element.
    pub fn element_stresses(&self) -> Vec<[f64; 4]> {
        todo!()
    }
    /// Number of unknowns of the linear system.
    pub fn dofs(&self) -> usize {
        todo!()
    }
}
