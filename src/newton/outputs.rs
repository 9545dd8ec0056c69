//! What a converged state reports: the drivers' reactions, the ties', the
//! contact pairs', the running strips' figures, the elements' stresses and
//! plastic strains.

use super::{SolveError, Solver};
use crate::assembly::Workspace;
use crate::constraint::TieResult;
use crate::contact::{self, PairMemory};
use crate::results::DriverResult;

impl Solver {
    /// Each running strip's figures in the converged state, by body name.
    pub fn running_results(&self) -> Vec<(String, crate::results::RunningResult)> {
        (self.running.iter().enumerate())
            .map(|(k, s)| (s.name.clone(), s.result(&self.problem, &self.state, k)))
            .collect()
    }

    /// Reactions per driver from the residual at the prescribed dofs.
    pub(super) fn driver_results(&self) -> Vec<(String, DriverResult)> {
        let mut out: Vec<(String, DriverResult)> = self
            .problem
            .drivers
            .iter()
            .map(|d| (d.name.clone(), DriverResult::default()))
            .collect();
        // Contact forces that land on prescribed dofs are part of the load
        // there, not of the reaction.
        let mut contact_force = std::collections::HashMap::new();
        if let Some(c) = &self.contact {
            for &(d, f) in &c.force {
                *contact_force.entry(d).or_insert(0.0) += f;
            }
        }
        for p in &self.prescribed {
            let f = self.r[p.dof] - contact_force.get(&p.dof).copied().unwrap_or(0.0);
            if p.component == 0 {
                out[p.driver].1.rx += f;
            } else {
                out[p.driver].1.ry += f;
            }
        }
        // Force components: the force applied, and the mean displacement it
        // produced.
        for (d, driver) in self.problem.drivers.iter().enumerate() {
            for c in (0..2).filter(|&c| driver.force(c).is_some()) {
                let f = self.state.driver_forces.get(d).map_or(0.0, |f| f[c]);
                let n = driver.nodes.len().max(1) as f64;
                let mean = driver
                    .nodes
                    .iter()
                    .map(|&k| self.state.u[2 * k + c])
                    .sum::<f64>()
                    / n;
                let r = &mut out[d].1;
                if c == 0 {
                    (r.rx, r.ux) = (f, Some(mean));
                } else {
                    (r.ry, r.uy) = (f, Some(mean));
                }
            }
        }
        if let Some(c) = &self.contact {
            for (rigid, f) in self.problem.rigids.iter().zip(&c.rigid) {
                out.push((
                    rigid.name.clone(),
                    DriverResult {
                        rx: f[0],
                        ry: f[1],
                        mz: Some(f[2]),
                        ..Default::default()
                    },
                ));
            }
        }
        out
    }

    /// Forces of each tie on its tied nodes in the converged state, by name.
    pub fn tie_results(&self) -> Vec<(String, TieResult)> {
        let mut offset = 0;
        self.problem
            .ties
            .iter()
            .map(|t| {
                let lambda = &self.state.ties[offset..offset + t.rows.len()];
                offset += t.rows.len();
                let mut result = t.result(lambda);
                let mesh = &self.problem.mesh;
                let u = &self.state.u;
                result.position = t
                    .nodes
                    .iter()
                    .map(|&n| [mesh.nodes[n][0] + u[2 * n], mesh.nodes[n][1] + u[2 * n + 1]])
                    .collect();
                (t.name.clone(), result)
            })
            .collect()
    }

    /// Contact pair results of the last converged increment (slip: none
    /// known, zero).
    pub fn last_pairs(&self) -> Result<Vec<(String, crate::results::PairResult)>, SolveError> {
        self.pair_results(None)
    }

    /// Contact pair results of the converged state, with each node's gap and
    /// its slip since `start` (the contact memory when the step began).
    pub(super) fn pair_results(
        &self,
        start: Option<&[PairMemory]>,
    ) -> Result<Vec<(String, crate::results::PairResult)>, SolveError> {
        let pairs = self
            .contact
            .as_ref()
            .map(|c| c.pairs.clone())
            .unwrap_or_default();
        let state = &self.state;
        (self.problem.contacts.iter().enumerate().zip(pairs))
            .map(|((i, p), mut result)| {
                (result.stick_length, result.slip_length) =
                    crate::results::PairResult::zone_lengths(&result.nodes, p.closed);
                let (gap, slip) = contact::outputs::gaps_and_slips(
                    &self.problem,
                    &self.targets,
                    p,
                    &state.u,
                    &state.rigid,
                    &state.contact[i],
                    start.and_then(|s| s.get(i)),
                )
                .map_err(SolveError::Invalid)?;
                (result.nodes.gap, result.nodes.slip) = (gap, slip);
                result.nodes.angle =
                    contact::outputs::angles(&self.problem, p, &result.nodes.x, &result.nodes.y);
                Ok((p.name.clone(), result))
            })
            .collect()
    }

    /// Element-average equivalent plastic strain of each element in the
    /// converged state; None when no material of the scene is plastic.
    pub fn element_plastic_strains(&self) -> Option<Vec<f64>> {
        (self.model).element_plastic_strains(&self.problem.mesh, &self.state.history)
    }

    /// Element-average Cauchy stress [xx, yy, zz, xy] of each element in the
    /// converged state.
    pub fn element_stresses(&self) -> Vec<[f64; 4]> {
        let mut stress = vec![[0.0; 4]; self.problem.mesh.elements.len()];
        let mut history = self.state.history.clone();
        let mut r = vec![0.0; self.r.len()];
        let mut ws = Workspace::new();
        // The converged state assembled before, so this cannot fail.
        let _ = self.model.assemble(
            &self.problem,
            self.state.time,
            &self.state.u,
            &mut history,
            &mut r,
            None,
            Some(&mut stress),
            None,
            &mut ws,
        );
        stress
    }
}
