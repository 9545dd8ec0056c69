//! Sensitivities of the converged state: how the reactions, the force
//! drivers' displacements and the contact resultants would change had the
//! increment that reached the state been given other input values. The
//! equilibrium at the state is linearised with its contact states held
//! (`contact::sensitivity`), the bordered tangent factored once and kept
//! until the state changes, and each seed costs one solve and two products
//! of the element tangents with a motion:
//!
//! `[K - dF_c/du, -C_col; C, 0] [du; dlambda] = [-(K du_p + dr/dx dx) +
//! dF_c/dpose dpose; -C_p du_p - C_pose dpose]`
//!
//! with `du_p` the prescribed motion, `dx` the load inputs (driver forces,
//! pressures) and `dpose` the rigid targets' motion; then the outputs
//! follow from `dr = K du + dr/dx dx - T^T dlambda_ties` and the contact
//! forces' change.

use super::{Solver, acts_on_free, subtract_loads};
use crate::assembly::{PRESCRIBED, Workspace};
use crate::contact::sensitivity::{self, Linearised};
use crate::contact::{self, Flips};
use crate::linsolve::FactoredLu;

/// Whether a converged state of `problem` has sensitivities (the FMU's
/// directional derivatives): every contact pair's formulation linearises
/// its converged state.
pub fn provides_derivatives(problem: &crate::problem::Problem) -> bool {
    contact::sensitivities(problem)
}

/// An input whose change the sensitivities follow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Input {
    /// Prescribed component (0 x, 1 y) of a driver: its displacement, or
    /// the resultant force of a component the scene prescribes as a force.
    Driver { driver: usize, component: usize },
    /// Value of edge pressure `pressure`.
    Pressure { pressure: usize },
    /// Pose component (0 ux, 1 uy, 2 theta) of a rigid target.
    Rigid { rigid: usize, component: usize },
}

/// A result whose change the sensitivities give.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Response {
    /// Component (0 Rx, 1 Ry, 2 Mz) of entry `index` of
    /// `StepResult::drivers`: the drivers, then the rigid targets.
    Reaction { index: usize, component: usize },
    /// Mean displacement (0 x, 1 y) of a driver's nodes on a component it
    /// prescribes as a force.
    DriverDisplacement { driver: usize, component: usize },
    /// Resultant (0 Fx, 1 Fy, 2 Fn, 3 Ft) of a contact pair.
    Pair { pair: usize, component: usize },
}

/// The converged state's linearisation, factored.
pub(super) struct Linearization {
    factor: FactoredLu,
    contact: Linearised,
    /// Rows whose free coefficients are round-off beside their prescribed
    /// ones (`NEGLIGIBLE_ROW`): their multiplier is held at zero.
    negligible: Vec<bool>,
    /// The history the state's increment started from (the products with
    /// the element tangents are taken from it, as the state's were).
    history: Vec<f64>,
    ws: Workspace,
}

impl Solver {
    /// The change of each of `responses` at the converged state for the
    /// input changes `seeds`: the directional derivative of the results of
    /// the increment that reached the state with respect to the values its
    /// inputs reached, the contact states held. The first call at a state
    /// factors its tangent; later ones reuse it.
    pub fn sensitivity(
        &mut self,
        seeds: &[(Input, f64)],
        responses: &[Response],
    ) -> Result<Vec<f64>, String> {
        self.check_seeds(seeds)?;
        let mut lin = match self.linearization.take() {
            Some(lin) => lin,
            None => self.linearize()?,
        };
        let result = self.solve_sensitivity(&mut lin, seeds, responses);
        self.linearization = Some(lin);
        result
    }

    fn check_seeds(&self, seeds: &[(Input, f64)]) -> Result<(), String> {
        let p = &self.problem;
        for &(input, value) in seeds {
            let ok = match input {
                Input::Driver { driver, component } => {
                    component < 2
                        && p.drivers.get(driver).is_some_and(|d| {
                            d.force(component).is_some() || d.displacement(component).is_some()
                        })
                }
                Input::Pressure { pressure } => pressure < p.pressures.len(),
                Input::Rigid { rigid, component } => rigid < p.rigids.len() && component < 3,
            };
            if !ok {
                return Err(format!("{input:?} is not an input of this problem"));
            }
            if !value.is_finite() {
                return Err(format!("the change of {input:?} is {value}, not finite"));
            }
        }
        Ok(())
    }

    /// The out-of-balance forces at the converged state (contact
    /// excluded) and, with `k`, the tangent over the free dofs, from the
    /// history its increment started from.
    fn state_residual(
        &self,
        history: &[f64],
        ws: &mut Workspace,
        k: Option<&mut [f64]>,
    ) -> Result<Vec<f64>, String> {
        let s = &self.state;
        let mut r = vec![0.0; s.u.len()];
        let mut trial = history.to_vec();
        (self.model)
            .assemble(
                &self.problem,
                s.time,
                &s.u,
                &mut trial,
                &mut r,
                k,
                None,
                None,
                ws,
            )
            .map_err(|e| e.to_string())?;
        subtract_loads(&self.problem, &s.driver_forces, &s.ties, &mut r);
        Ok(r)
    }

    /// Linearises the converged state and factors its bordered tangent.
    fn linearize(&mut self) -> Result<Linearization, String> {
        let s = &self.state;
        let history = if s.step_start_history.len() == s.history.len() {
            s.step_start_history.clone()
        } else {
            s.history.clone()
        };
        let mut ws = Workspace::new();
        ws.pressures.clone_from(&s.pressures);
        let mut k = vec![0.0; self.model.pattern.row_idx.len()];
        let r = self.state_residual(&history, &mut ws, Some(&mut k))?;
        let eq = &self.model.eq;
        let contact = if self.problem.contacts.is_empty() {
            Linearised::default()
        } else {
            // The contact states as the state holds them: deciding again at
            // the converged iterate from its memory, with the increment's
            // start, gives the same states (and mortar's weighted slips
            // measured from where the increment started).
            let mut memory = s.contact.clone();
            let (start_u, start_poses) = if s.step_start_u.len() == s.u.len() {
                (&s.step_start_u, &s.step_start_rigid)
            } else {
                (&s.u, &s.rigid)
            };
            let start = contact::Start {
                u: start_u,
                poses: start_poses,
                settling: false,
                touching: false,
                cache: &contact::StartCache::default(),
            };
            let system = contact::update(
                &self.problem,
                &self.targets,
                &s.rigid,
                &s.u,
                &r,
                eq,
                &start,
                &mut memory,
                &mut Flips::default(),
                &mut |_| {},
                None,
            )?;
            if system.changes > 0 || system.pending > 0 {
                return Err(format!(
                    "the contact states at t = {:?} are not those of a converged state \
                     ({} would change)",
                    s.time,
                    system.changes + system.pending
                ));
            }
            sensitivity::linearise(
                &sensitivity::At {
                    problem: &self.problem,
                    poses: &s.rigid,
                    r: &r,
                    eq,
                },
                &system,
            )?
        };
        let n = self.model.free_dofs();
        let mut extra: Vec<(usize, usize, f64)> = Vec::new();
        for &(i, j, v) in &contact.k {
            if eq[i] != PRESCRIBED && eq[j] != PRESCRIBED {
                extra.push((eq[i] as usize, eq[j] as usize, -v));
            }
        }
        let contact_rows = contact.rows.iter().map(|r| (&r.dofs[..], &r.column[..]));
        let tie_rows =
            (self.problem.ties.iter().flat_map(|t| &t.rows)).map(|r| (&r.dofs[..], &r.dofs[..]));
        let mut negligible = Vec::new();
        for (i, (dofs, column)) in contact_rows.chain(tie_rows).enumerate() {
            // As in Newton's rows: one acting on prescribed dofs alone holds
            // nothing the drivers do not.
            let free = acts_on_free(dofs, eq);
            negligible.push(!free);
            if !free {
                extra.push((n + i, n + i, 1.0));
                continue;
            }
            for &(d, v) in dofs.iter().filter(|e| eq[e.0] != PRESCRIBED) {
                extra.push((n + i, eq[d] as usize, v));
            }
            for &(d, v) in column.iter().filter(|e| eq[e.0] != PRESCRIBED) {
                extra.push((eq[d] as usize, n + i, -v));
            }
        }
        let order = n + negligible.len();
        self.sensitivity_factorizations += 1;
        let factor = FactoredLu::new(&self.model.pattern, &k, &mut extra, order)
            .map_err(|e| format!("the tangent of the state at t = {:?}: {e}", s.time))?;
        Ok(Linearization {
            factor,
            contact,
            negligible,
            history,
            ws,
        })
    }

    /// `out += K du` over all dofs, with the state's tangent.
    fn tangent_product(
        &self,
        lin: &mut Linearization,
        du: &[f64],
        out: &mut [f64],
    ) -> Result<(), String> {
        let s = &self.state;
        let mut trial = lin.history.clone();
        let mut r = vec![0.0; du.len()];
        (self.model)
            .assemble(
                &self.problem,
                s.time,
                &s.u,
                &mut trial,
                &mut r,
                None,
                None,
                Some((du, out)),
                &mut lin.ws,
            )
            .map_err(|e| e.to_string())
    }

    fn solve_sensitivity(
        &self,
        lin: &mut Linearization,
        seeds: &[(Input, f64)],
        responses: &[Response],
    ) -> Result<Vec<f64>, String> {
        let p = &self.problem;
        let (eq, n) = (&self.model.eq, self.model.free_dofs());
        let ndof = self.state.u.len();
        let Seeds {
            mut du,
            load,
            dpose,
            dforce,
        } = self.seeds(lin, seeds);
        // Right-hand side: the prescribed motion through the tangent and
        // the contact forces, the load, the poses through the rows.
        let mut moved = load.clone();
        if du.iter().any(|&x| x != 0.0) {
            self.tangent_product(lin, &du, &mut moved)?;
        }
        let mut carried = vec![0.0; ndof];
        lin.contact.force_change(&du, &[], &dpose, &mut carried);
        let contact_rows = lin.contact.rows.iter().map(|r| (&r.dofs[..], &r.poses[..]));
        let tie_rows = (p.ties.iter().flat_map(|t| &t.rows)).map(|r| (&r.dofs[..], &[][..]));
        let mut x = vec![0.0; n + lin.negligible.len()];
        for (dof, &q) in eq.iter().enumerate() {
            if q != PRESCRIBED {
                // Summed: the dofs of a rigid force set share an equation.
                x[q as usize] += carried[dof] - moved[dof];
            }
        }
        for (i, (dofs, poses)) in contact_rows.chain(tie_rows).enumerate() {
            if lin.negligible[i] {
                continue;
            }
            let prescribed: f64 = (dofs.iter())
                .filter(|e| eq[e.0] == PRESCRIBED)
                .map(|&(d, c)| c * du[d])
                .sum();
            let posed: f64 = poses.iter().map(|&(r, c, v)| v * dpose[r][c]).sum();
            x[n + i] = -prescribed - posed;
        }
        lin.factor.solve(&mut x).map_err(|e| e.to_string())?;
        for (dof, &q) in eq.iter().enumerate() {
            if q != PRESCRIBED {
                du[dof] = x[q as usize];
            }
        }
        // The out-of-balance forces' change, and the contact forces'.
        let mut dr = load;
        self.tangent_product(lin, &du, &mut dr)?;
        let m = lin.contact.rows.len();
        let ties = (p.ties.iter().flat_map(|t| &t.rows)).zip(&x[n + m..]);
        for (row, &l) in ties {
            for &(d, v) in &row.dofs {
                dr[d] -= v * l;
            }
        }
        let mut dfc = vec![0.0; ndof];
        lin.contact
            .force_change(&du, &x[n..n + m], &dpose, &mut dfc);
        let (pairs, rigids) = lin.contact.resultant_changes(
            [p.contacts.len(), p.rigids.len()],
            &du,
            [&dr, &dfc],
            eq,
            &dpose,
        );
        let changes = Changes {
            du: &du,
            dr: &dr,
            dfc: &dfc,
            dforce: &dforce,
            pairs: &pairs,
            rigids: &rigids,
        };
        (responses.iter())
            .map(|&response| self.response_change(response, &changes))
            .collect()
    }
}

/// What the inputs' changes are: the prescribed motion per dof, the load
/// (dr/dx dx), the rigid targets' pose changes and the drivers' force
/// changes.
struct Seeds {
    du: Vec<f64>,
    load: Vec<f64>,
    dpose: Vec<[f64; 3]>,
    dforce: Vec<[f64; 2]>,
}

/// A sensitivity solve's changes, from which each response is read:
/// displacements, out-of-balance and contact forces per dof, the drivers'
/// force changes, and the pairs' and rigid targets' resultant changes.
struct Changes<'a> {
    du: &'a [f64],
    dr: &'a [f64],
    dfc: &'a [f64],
    dforce: &'a [[f64; 2]],
    pairs: &'a [[f64; 4]],
    rigids: &'a [[f64; 3]],
}

impl Solver {
    /// The changes `seeds` make to the inputs.
    fn seeds(&self, lin: &mut Linearization, seeds: &[(Input, f64)]) -> Seeds {
        let p = &self.problem;
        let ndof = self.state.u.len();
        let mut du = vec![0.0; ndof];
        let mut load = vec![0.0; ndof];
        let mut dpose = vec![[0.0; 3]; p.rigids.len()];
        let mut dforce = vec![[0.0; 2]; p.drivers.len()];
        for &(input, v) in seeds {
            match input {
                Input::Driver { driver, component } => {
                    let d = &p.drivers[driver];
                    if d.force(component).is_some() {
                        // Each node carries an equal share of the resultant
                        // (summed into one equation on a rigid set).
                        let share = v / d.nodes.len().max(1) as f64;
                        for &node in &d.nodes {
                            load[2 * node + component] -= share;
                        }
                        dforce[driver][component] += v;
                    } else {
                        for q in &self.prescribed {
                            if (q.driver, q.component) == (driver, component) {
                                du[q.dof] += v;
                            }
                        }
                    }
                }
                Input::Pressure { pressure } => {
                    let mut unit = vec![0.0; ndof];
                    (self.model).pressure_load(p, pressure, &self.state.u, &mut unit, &mut lin.ws);
                    for (l, x) in load.iter_mut().zip(unit) {
                        *l += v * x;
                    }
                }
                Input::Rigid { rigid, component } => dpose[rigid][component] += v,
            }
        }
        Seeds {
            du,
            load,
            dpose,
            dforce,
        }
    }

    /// One response's change, read from the solve's `c`.
    fn response_change(&self, response: Response, c: &Changes) -> Result<f64, String> {
        let p = &self.problem;
        let missing = || format!("{response:?} is not a result of this problem");
        match response {
            Response::Reaction { index, component } if index < p.drivers.len() => {
                let d = &p.drivers[index];
                if component > 1 {
                    Err(missing())
                } else if d.force(component).is_some() {
                    Ok(c.dforce[index][component])
                } else {
                    // As `driver_results`: the residual at the
                    // driver's dofs less the contact forces there.
                    Ok((self.prescribed.iter())
                        .filter(|q| (q.driver, q.component) == (index, component))
                        .map(|q| c.dr[q.dof] - c.dfc[q.dof])
                        .sum())
                }
            }
            Response::Reaction { index, component } => (c.rigids)
                .get(index - p.drivers.len())
                .and_then(|r| r.get(component).copied())
                .ok_or_else(missing),
            Response::DriverDisplacement { driver, component } => {
                let d = p.drivers.get(driver).ok_or_else(missing)?;
                if component > 1 || d.force(component).is_none() {
                    return Err(missing());
                }
                let sum: f64 = d.nodes.iter().map(|&k| c.du[2 * k + component]).sum();
                Ok(sum / d.nodes.len().max(1) as f64)
            }
            Response::Pair { pair, component } => (c.pairs)
                .get(pair)
                .and_then(|r| r.get(component).copied())
                .ok_or_else(missing),
        }
    }
}
