//! Everything an increment changes, cloneable: rollback after a failed
//! increment and (later) the FMU state.

use crate::problem::Problem;
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct State {
    /// Time of the last converged increment.
    pub time: f64,
    /// Nodal displacements, two per node (x, y), merged mesh numbering.
    pub u: Vec<f64>,
    /// Material history per Gauss point (empty for history-free laws).
    pub history: Vec<f64>,
    /// The history the increment that reached this state started from:
    /// the consistent tangent of the state (its sensitivities) is taken
    /// from it. Empty before the first increment (then `history`).
    #[serde(default)]
    pub step_start_history: Vec<f64>,
    /// The displacements and the rigid targets' poses the increment that
    /// reached this state started from: the weighted slips of mortar
    /// friction are measured from there, in the sensitivities as in the
    /// increment. Empty before the first increment (then `u`, `rigid`).
    #[serde(default)]
    pub step_start_u: Vec<f64>,
    #[serde(default)]
    pub step_start_rigid: Vec<[f64; 3]>,
    /// Contact memory per pair, each in its formulation's own type, in
    /// scene order.
    pub contact: Vec<crate::contact::PairMemory>,
    /// Pose [ux, uy, theta] of each rigid target at `time`, in scene order.
    pub rigid: Vec<[f64; 3]>,
    /// Lagrange multipliers of the tie rows (`Problem::ties` in order, each
    /// tie's rows in order): the tie forces.
    #[serde(default)]
    pub ties: Vec<f64>,
    /// Force [x, y] each driver applies at `time` on its force components
    /// (the set's resultant; 0 on displacement components), in scene order.
    #[serde(default)]
    pub driver_forces: Vec<[f64; 2]>,
    /// Value of each edge pressure at `time`, in scene order.
    #[serde(default)]
    pub pressures: Vec<f64>,
    /// What each running strip carries (`crate::running`), in body order.
    #[serde(default)]
    pub running: Vec<RunningMemory>,
}

/// What a running strip carries from step to step.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RunningMemory {
    /// Elements shifted in at the supply end, less those shifted back.
    pub shifts: i64,
    /// Material speed at the supply and take-up ends over the last step.
    pub speed: [f64; 2],
}

impl State {
    pub fn displacement(&self, node: usize) -> [f64; 2] {
        [self.u[2 * node], self.u[2 * node + 1]]
    }

    /// Whether this state (restored from elsewhere) has the shape of
    /// `like`, a state of `problem`: every array as long, every contact
    /// pair's memory its pair's. The error names the first that is not.
    pub fn fits(&self, like: &State, problem: &Problem) -> Result<(), String> {
        let lengths = [
            ("displacements", self.u.len(), like.u.len()),
            ("material history", self.history.len(), like.history.len()),
            ("contact pairs", self.contact.len(), like.contact.len()),
            ("rigid targets", self.rigid.len(), like.rigid.len()),
            ("tie multipliers", self.ties.len(), like.ties.len()),
            (
                "driver forces",
                self.driver_forces.len(),
                like.driver_forces.len(),
            ),
            ("pressures", self.pressures.len(), like.pressures.len()),
            ("running strips", self.running.len(), like.running.len()),
        ];
        // Empty before the first increment.
        let starts = [
            (
                "increment-start history",
                self.step_start_history.len(),
                like.history.len(),
            ),
            (
                "increment-start displacements",
                self.step_start_u.len(),
                like.u.len(),
            ),
            (
                "increment-start poses",
                self.step_start_rigid.len(),
                like.rigid.len(),
            ),
        ];
        for (what, has, wants) in lengths {
            if has != wants {
                return Err(format!("it has {has} {what}, this model {wants}"));
            }
        }
        for (what, has, wants) in starts {
            if has != 0 && has != wants {
                return Err(format!("it has {has} {what}, this model {wants} (or none)"));
            }
        }
        for (memory, pair) in self.contact.iter().zip(&problem.contacts) {
            if !memory.fits(pair) {
                return Err(format!(
                    "contact pair '{}': its memory does not fit the pair's {} contactor nodes under its formulation",
                    pair.name,
                    pair.contactor.len()
                ));
            }
        }
        Ok(())
    }
}
