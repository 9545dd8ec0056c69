//! Increments, Newton-Raphson iterations and automatic bisection. Residuals
//! are measured against the problem's force scale (never the first residual
//! alone: a held input converges at iteration 0) and logged with the
//! observed convergence rate; a failed increment leaves the last converged
//! state untouched.

use crate::assembly::{Model, PRESCRIBED, Workspace};
use crate::constraint::TieResult;
use crate::contact::{self, ContactSystem, Flips, PairMemory, Switched};
use crate::linsolve::{Augmented, LinearError, LinearSolver, LinearTimes};
use crate::problem::Problem;
use crate::results::{DriverResult, LogCategory, StepResult};
use crate::state::State;
use std::time::{Duration, Instant};

mod rest;
mod sensitivity;
pub use rest::rest_step;
pub use sensitivity::{Input, Response, provides_derivatives};

/// A constraint row whose coefficients on free dofs are below this fraction
/// of those on prescribed dofs (root sum of squares) acts on prescribed dofs
/// only: the contact search's own tolerance on `beta` (pairs.rs).
const NEGLIGIBLE_ROW: f64 = 1e-6;

/// Solves of one Newton iteration's linearised problem while its stick/slip
/// decisions change (see `increment`).
const MAX_INNER: usize = 50;

/// Times a node may open or close in one iteration's inner solves.
const INNER_FLIPS: usize = 1;

/// The inner solves of one correction: how many were made, the sets of
/// states met (`contact::state_key`), and per pair and node how often one
/// opened or closed.
#[derive(Default)]
struct InnerSolves {
    count: usize,
    seen: Vec<u64>,
    flipped: Vec<Vec<usize>>,
    /// The nodes (pair, node) each inner solve's states changed.
    changed: Vec<Vec<(usize, usize)>>,
    /// The states met a second time after changes at every node of a
    /// pair's contact zone: the decisions wander.
    wandered: bool,
}

/// A solve before the decisions the linearised problem took from it: its
/// solution, the contact memory and rows it was made with, and, when it
/// was left partial (`Augmented::solve_watching`), its right-hand side and
/// entries.
#[derive(Clone)]
struct KeptSolve {
    full: Vec<f64>,
    memory: Vec<PairMemory>,
    system: Option<ContactSystem>,
    deferred: Option<Deferred>,
}

/// A partial solve's right-hand side and entries beside the tangent.
type Deferred = (Vec<f64>, Vec<(usize, usize, f64)>);

/// An iterate is still settling while the correction that reached it is
/// above this fraction of the increment's first correction (and always
/// right after the predictor): its nodes in contact are not released on
/// their forces then (`contact::Start::settling`). Measured on the capstan
/// pulled 6 mm in one increment: holding only after the predictor, every
/// node was released at the second iterate and the increment bisected;
/// 0.5 and 0.1 both take it in 7 iterations.
const SETTLING: f64 = 0.5;

#[derive(Debug, thiserror::Error)]
pub enum SolveError {
    #[error("invalid problem: {0}")]
    Invalid(String),
    #[error("increment to t = {time} failed: {reason}")]
    NotConverged { time: f64, reason: String },
}

/// A prescribed degree of freedom: which driver and component drive it.
#[derive(Clone, Copy, Debug)]
struct Prescribed {
    dof: usize,
    driver: usize,
    component: usize,
}

/// An iterate's equilibrium residual against the problem's forces.
struct Measure {
    /// |r| / F.
    rho: f64,
    /// F: element forces, reactions, contact forces, or the tangent over
    /// the motion at a strain of 1e-6 when nothing else has a scale.
    f_ref: f64,
    /// |r| is at round-off: the residual sums element forces of size F,
    /// and K u of a body that moves without stress.
    at_roundoff: bool,
}

/// What the correction of one Newton iteration needs to know of it.
struct Step<'a> {
    t: f64,
    it: usize,
    u: &'a [f64],
    dup: &'a [f64],
    poses: &'a [[f64; 3]],
    /// The iteration's equilibrium tolerances [force, length]: the inner
    /// solves' stick/slip decisions do not change a node for less.
    tolerance: [f64; 2],
    /// The iterate's geometry is not settled (`Start::settling`).
    settling: bool,
}

/// The step an increment lies in: its inputs ramp from the converged state
/// at t0 (displacements, rigid target poses, driver forces and pressures)
/// toward their values at t1.
struct Ramp<'a> {
    t0: f64,
    t1: f64,
    u0: &'a [f64],
    rigid0: &'a [[f64; 3]],
    forces0: &'a [[f64; 2]],
    pressures0: &'a [f64],
}

/// What the iterations of one increment carry from one to the next.
struct Increment {
    t: f64,
    /// Rigid target poses at t.
    poses: Vec<[f64; 3]>,
    /// The iterate.
    u: Vec<f64>,
    /// The prescribed increment (carried through the tangent at iteration 0).
    dup: Vec<f64>,
    /// The motion's scale (`Measure::f_ref`).
    u_max: f64,
    /// K du_p of the predictor.
    kdu: Vec<f64>,
    /// Material history at the iterate.
    history: Vec<f64>,
    /// The right-hand side, then the correction, per free dof.
    rhs: Vec<f64>,
    /// Norm and energy of the first correction.
    du1: f64,
    e1: f64,
    /// |r|/F per iteration, for the rate.
    ratios: Vec<f64>,
    /// The last correction (-r_0 before the first).
    last_du: Vec<f64>,
    memory: Vec<PairMemory>,
    flips: Flips,
    solves: usize,
    /// Constraint triplets beside K.
    extra: Vec<(usize, usize, f64)>,
    /// Tie multipliers, total.
    lambda: Vec<f64>,
    /// How far the prescribed motion moves a node in this increment
    /// (`contact_slots`).
    reach: f64,
    /// The contact slots of this increment's solves without contact rows
    /// (`contact_slots`): per multiplier slot, the free equations of its
    /// node; made at the first such solve, empty when it takes `linear`.
    slots: Option<Vec<Vec<usize>>>,
}

/// What one iteration's residual and contact update give its convergence
/// test and its correction.
struct Evaluated {
    contact: Option<ContactSystem>,
    /// The right-hand side without the contact forces (`measure`).
    rhs_base: Option<Vec<f64>>,
    measure: Measure,
    need_k: bool,
    /// `Step::settling`.
    settling: bool,
    /// The gap tolerance, a length.
    gap_tol: f64,
}

/// What one Newton solve of an increment did.
struct Converged {
    iterations: usize,
    solves: usize,
    residual: f64,
}

/// Where a solver's time went since it was made, by phase (the benchmarks'
/// split, issue 14). `total` is the wall time inside `advance`; what the
/// phases leave of it is the iteration's own work (residual norms,
/// convergence tests, copies of the iterate).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Phases {
    /// Element internal forces and tangents.
    pub assembly: Duration,
    /// Contact search, force recovery, decisions and rows, and the inner
    /// solves' predictions of the linearised problem's states.
    pub contact: Duration,
    /// Building, ordering, factoring and solving the linear systems.
    pub linear: LinearTimes,
    pub total: Duration,
    /// Numeric factorizations of the increments' systems (the
    /// sensitivities' not counted).
    pub factorizations: usize,
    /// Symbolic analyses of bordered systems (a new contact pattern).
    pub analyses: usize,
    /// Bordered systems solved by LDLT, by LU, by the unpivoted LDU, and
    /// without a factorization of their own, on the last LDLT factor's
    /// trailing block (`linsolve::Augmented::trailing_solves`).
    pub ldlt: usize,
    pub lu: usize,
    pub ldu: usize,
    pub trailing: usize,
    /// Of those, the ones whose interior waited until an inner solve was
    /// accepted (`linsolve::Augmented::deferred_solves`).
    pub deferred: usize,
    /// Newton iterations whose first solve took the last factor's trailing
    /// block instead of a factorization (a constant tangent, its contact
    /// rows changed on the trailing set alone).
    pub reused: usize,
    /// Assemblies of the tangent (one per solver for a constant one).
    pub tangents: usize,
}

impl Phases {
    /// The phases as percentages of the time inside `advance`, one line.
    pub fn split(&self) -> String {
        let total = self.total.as_secs_f64().max(f64::MIN_POSITIVE);
        let parts = [
            ("assembly", self.assembly),
            ("contact", self.contact),
            ("system", self.linear.system),
            ("symbolic", self.linear.symbolic),
            ("numeric", self.linear.numeric),
            ("solve", self.linear.solve),
        ];
        let named: Duration = parts.iter().map(|(_, d)| *d).sum();
        let rest = self.total.saturating_sub(named);
        (parts.iter().chain([&("rest", rest)]))
            .map(|(name, d)| format!("{name} {:.1}", 100.0 * d.as_secs_f64() / total))
            .collect::<Vec<_>>()
            .join("  ")
    }

    /// `split` and the counts, one line (the CLI's `-v` and the benchmark).
    pub fn summary(&self) -> String {
        format!(
            "{}; {} factorizations ({} LDLT, {} LU, {} LDU), {} solves on the trailing block ({} deferred, {} first of an iteration), {} symbolic analyses",
            self.split(),
            self.factorizations,
            self.ldlt,
            self.lu,
            self.ldu,
            self.trailing,
            self.deferred,
            self.reused,
            self.analyses
        )
    }
}

/// The solver's own part of [`Phases`].
#[derive(Clone, Copy, Debug, Default)]
struct SolverTimes {
    tangents: usize,
    reused: usize,
    assembly: Duration,
    contact: Duration,
    total: Duration,
}

/// The dofs the drivers prescribe (a flag per dof) and each one's driver
/// and component, a later driver on a dof taking it over; an error names a
/// driver's node beyond the mesh.
fn prescribed_dofs(
    problem: &Problem,
    ndof: usize,
) -> Result<(Vec<bool>, Vec<Prescribed>), SolveError> {
    let mut is_prescribed = vec![false; ndof];
    let mut prescribed = Vec::new();
    for (d, driver) in problem.drivers.iter().enumerate() {
        for (c, comp) in [&driver.ux, &driver.uy].into_iter().enumerate() {
            if comp.is_none() {
                continue;
            }
            for &n in &driver.nodes {
                let dof = 2 * n + c;
                if dof >= ndof {
                    return Err(SolveError::Invalid(format!(
                        "driver '{}' names node {n} beyond the mesh",
                        driver.name
                    )));
                }
                if is_prescribed[dof] {
                    prescribed.retain(|p: &Prescribed| p.dof != dof);
                }
                is_prescribed[dof] = true;
                prescribed.push(Prescribed {
                    dof,
                    driver: d,
                    component: c,
                });
            }
        }
    }
    Ok((is_prescribed, prescribed))
}

/// The free equations of every contactor node, ascending.
fn contact_equations(problem: &Problem, model: &Model) -> Vec<usize> {
    let mut eqs: Vec<usize> = (problem.contacts.iter())
        .flat_map(|p| &p.contactor)
        .flat_map(|&node| [2 * node, 2 * node + 1])
        .filter(|&d| model.eq[d] != PRESCRIBED)
        .map(|d| model.eq[d] as usize)
        .collect();
    eqs.sort_unstable();
    eqs.dedup();
    eqs
}

/// The diagonal of the bounding box of the mesh and the rigid targets
/// (1 when it is not finite).
fn model_size(problem: &Problem) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    let rigid_points = problem.rigids.iter().flat_map(|r| r.points.iter());
    for p in problem.mesh.nodes.iter().chain(rigid_points) {
        for c in 0..2 {
            lo[c] = lo[c].min(p[c]);
            hi[c] = hi[c].max(p[c]);
        }
    }
    let size = (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
    if size.is_finite() { size } else { 1.0 }
}

/// Where each equation's diagonal entry sits in the tangent's pattern.
fn diagonal_positions(pattern: &crate::assembly::Pattern) -> Result<Vec<usize>, SolveError> {
    (0..pattern.n)
        .map(|q| {
            (pattern.col_ptr[q]..pattern.col_ptr[q + 1])
                .find(|&i| pattern.row_idx[i] == q)
                .ok_or_else(|| SolveError::Invalid(format!("no diagonal entry for equation {q}")))
        })
        .collect()
}

/// Overrides of the scene's loads (the FMU's inputs), each the value to
/// reach at the end of the next `advance`, linearly in time from its
/// converged value; None: the scene's.
struct Inputs {
    /// Per driver, its [ux, uy] (a displacement or a force component).
    drivers: Vec<[Option<f64>; 2]>,
    /// Per rigid target, its pose [ux, uy, theta].
    rigids: Vec<[Option<f64>; 3]>,
    /// Per edge pressure, its value (`<name>.p`).
    pressures: Vec<Option<f64>>,
}

pub struct Solver {
    problem: Problem,
    /// Driver forces of the increment being solved (`driver_forces`).
    step_forces: Vec<[f64; 2]>,
    model: Model,
    linear: LinearSolver,
    prescribed: Vec<Prescribed>,
    /// The FMU's inputs: values to reach at the end of the next `advance`.
    inputs: Inputs,
    state: State,
    ws: Workspace,
    r: Vec<f64>,
    k: Vec<f64>,
    /// `k` holds the tangent of a model whose tangent is constant
    /// (`Model::constant_tangent`: small strain, linear laws), assembled
    /// once: later iterations assemble the forces alone.
    k_constant: bool,
    /// The factorization in `linear` is of the current constant tangent.
    factor_valid: bool,
    /// The bordered system of Eq. (18), used while contact rows exist.
    augmented: Augmented,
    /// The contact part of the last converged iteration (for results).
    contact: Option<ContactSystem>,
    /// Diagonal of the model's bounding box: the length scale of gap tests.
    size: f64,
    /// Position of each free dof's diagonal entry in `k`.
    diagonal_at: Vec<usize>,
    /// Largest diagonal entry of the last assembled tangent.
    k_max: f64,
    /// The converged state's linearisation, factored once and kept until
    /// the state changes (a step, a restore, new tunable parameters).
    linearization: Option<sensitivity::Linearization>,
    /// Factorizations of converged tangents for the sensitivities.
    sensitivity_factorizations: usize,
    /// The increment being solved leaves opening and closing to the
    /// iterate's decisions: its inner solves change stick and slip only
    /// (the fallback of `advance`).
    iterate_opens: bool,
    /// Wall time of assembly and contact, summed (`phases`).
    times: SolverTimes,
    /// Free nodes touching a target close too (`contact::Start::touching`;
    /// the second fallback of `advance`).
    close_touching: bool,
    /// Every contact pair's target is rigid: only then do the inner solves
    /// border the iteration's factor (`constrained_correction`) and the
    /// multipliers keep slots (`Augmented::slots`). Against a deformable
    /// target a sliding node's row changes key with its segment, and the
    /// buried pipe (a steel pipe in soft soil, held by contact alone, its
    /// LU solves good to about 1e-9 of the right-hand side) stalled at
    /// |r|/F = 4.8e-4 in its first increment and bisected under either:
    /// its stick/slip path depends on round-off (docs/contact.md section 8).
    rigid_targets: bool,
    /// The free equations of every contactor node (with rigid targets):
    /// what the linearised problem's decisions read of an inner solve's
    /// displacements (`contact::predict`), so its solve may be deferred
    /// (`Augmented::solve_watching`).
    contact_eqs: Vec<usize>,
    /// The last increment failed at its first solve because nothing held
    /// a body (`correction`).
    free_at_first_solve: bool,
    /// The free nodes' search candidates of the inner solves' decisions
    /// (`contact::SearchCache`), for the increment.
    search_cache: contact::SearchCache,
    /// What the contact formulations derive from an increment's start
    /// (`contact::StartCache`).
    start_cache: contact::StartCache,
    /// The rigid targets' segments, built once per pose
    /// (`contact::RigidSegments`).
    targets: contact::RigidSegments,
    /// Nodes the inner solves opened or closed since `advance` last reset
    /// it (an increment they did not touch gains nothing from the fallback).
    inner_flips: usize,
    /// The running strips (`crate::running`), in body order.
    running: Vec<crate::running::Strip>,
}

impl Solver {
    pub fn new(problem: Problem) -> Result<Self, SolveError> {
        let rigid_targets =
            (problem.contacts.iter()).all(|p| matches!(p.target, crate::problem::Target::Rigid(_)));
        let ndof = 2 * problem.mesh.nodes.len();
        if problem.element_material.len() != problem.mesh.elements.len() {
            return Err(SolveError::Invalid(
                "element_material does not match the elements".into(),
            ));
        }
        for m in &problem.materials {
            crate::problem::check_model_analysis(&m.spec, problem.analysis, problem.kinematics)
                .map_err(|e| SolveError::Invalid(format!("material '{}': {e}", m.name)))?;
        }
        let (is_prescribed, prescribed) = prescribed_dofs(&problem, ndof)?;
        let model = Model::new(&problem, &is_prescribed);
        let mut augmented = Augmented::with_slots(rigid_targets);
        augmented.symmetric_tangent = model.symmetric;
        let contact_eqs = if rigid_targets {
            contact_equations(&problem, &model)
        } else {
            Vec::new()
        };
        let linear = LinearSolver::new(&model.pattern, model.symmetric)
            .map_err(|e| SolveError::Invalid(e.to_string()))?;
        let nnz = model.pattern.row_idx.len();
        let running: Vec<crate::running::Strip> = (0..problem.bodies.len())
            .filter(|&b| problem.bodies[b].running)
            .map(|b| crate::running::Strip::new(&problem, b))
            .collect();
        let state = State {
            time: 0.0,
            u: problem.initial_u(),
            history: vec![0.0; model.history_len],
            step_start_history: Vec::new(),
            step_start_u: Vec::new(),
            step_start_rigid: Vec::new(),
            contact: problem.contacts.iter().map(PairMemory::new).collect(),
            rigid: contact::scene_poses(&problem, 0.0),
            ties: vec![0.0; problem.ties.iter().map(|t| t.rows.len()).sum()],
            driver_forces: scene_forces(&problem, 0.0),
            pressures: scene_pressures(&problem, 0.0),
            running: vec![Default::default(); running.len()],
        };
        let size = model_size(&problem);
        let diagonal_at = diagonal_positions(&model.pattern)?;
        let inputs = Inputs {
            drivers: vec![[None, None]; problem.drivers.len()],
            rigids: vec![[None; 3]; problem.rigids.len()],
            pressures: vec![None; problem.pressures.len()],
        };
        let step_forces = state.driver_forces.clone();
        Ok(Solver {
            step_forces,
            problem,
            model,
            linear,
            prescribed,
            inputs,
            state,
            ws: Workspace::new(),
            r: vec![0.0; ndof],
            k: vec![0.0; nnz],
            k_constant: false,
            factor_valid: false,
            augmented,
            rigid_targets,
            contact_eqs,
            contact: None,
            size,
            diagonal_at,
            k_max: 0.0,
            linearization: None,
            sensitivity_factorizations: 0,
            iterate_opens: false,
            inner_flips: 0,
            search_cache: contact::SearchCache::default(),
            start_cache: contact::StartCache::default(),
            targets: contact::RigidSegments::default(),
            times: SolverTimes::default(),
            close_touching: false,
            free_at_first_solve: false,
            running,
        })
    }

    pub fn problem(&self) -> &Problem {
        &self.problem
    }

    /// Takes the tunable parameters of `from` (each pair's friction
    /// coefficients, the solver settings) for the increments to come; the
    /// converged state is kept. `from` is this solver's problem with only
    /// those changed, checked (`Problem::check_parameters`).
    pub fn set_tunables(&mut self, from: &Problem) {
        for (c, f) in self.problem.contacts.iter_mut().zip(&from.contacts) {
            (c.mu_s, c.mu_d) = (f.mu_s, f.mu_d);
        }
        self.problem.solver = from.solver.clone();
        self.linearization = None;
    }

    pub fn state(&self) -> &State {
        &self.state
    }

    /// Newton control, changeable between increments.
    pub fn settings_mut(&mut self) -> &mut crate::problem::SolverSettings {
        &mut self.problem.solver
    }

    pub fn restore(&mut self, state: State) {
        self.state = state;
        self.linearization = None;
    }

    /// Number of unknowns of the linear system.
    pub fn dofs(&self) -> usize {
        self.model.free_dofs()
    }

    /// Number of numeric factorizations done so far.
    /// Where the time of every `advance` so far went.
    pub fn phases(&self) -> Phases {
        Phases {
            assembly: self.times.assembly,
            contact: self.times.contact,
            linear: self.linear.times.plus(self.augmented.times),
            total: self.times.total,
            factorizations: self.linear.factorizations + self.augmented.factorizations,
            analyses: self.augmented.analyses,
            ldlt: self.augmented.ldlt,
            lu: self.augmented.lu,
            ldu: self.augmented.ldu,
            trailing: self.augmented.trailing_solves,
            deferred: self.augmented.deferred_solves,
            reused: self.times.reused,
            tangents: self.times.tangents,
        }
    }

    pub fn factorizations(&self) -> usize {
        self.linear.factorizations + self.augmented.factorizations + self.sensitivity_factorizations
    }

    /// Override a driver component: reach `value` at the end of the next
    /// `advance`, linearly in time from its current value (None: back to the
    /// scene's time function).
    pub fn set_input(&mut self, driver: usize, component: usize, value: Option<f64>) {
        self.inputs.drivers[driver][component] = value;
    }

    /// Override a rigid target's pose component (0 ux, 1 uy, 2 theta) the
    /// same way.
    pub fn set_rigid_input(&mut self, rigid: usize, component: usize, value: Option<f64>) {
        self.inputs.rigids[rigid][component] = value;
    }

    /// Poses of the rigid targets at time t within the step t0 -> t1: an
    /// overridden component runs linearly from its converged value.
    fn rigid_poses(&self, t: f64, t0: f64, t1: f64, rigid0: &[[f64; 3]]) -> Vec<[f64; 3]> {
        let scene = contact::scene_poses(&self.problem, t);
        (0..self.problem.rigids.len())
            .map(|r| {
                let (scene, start) = (scene[r], rigid0[r]);
                let mut pose = [0.0; 3];
                for c in 0..3 {
                    pose[c] = match self.inputs.rigids[r][c] {
                        Some(v) => toward(start[c], v, t, t0, t1),
                        None => scene[c],
                    };
                }
                pose
            })
            .collect()
    }

    /// Override edge pressure `i`'s value at the end of the step (None:
    /// the scene's); reached linearly from its converged value.
    pub fn set_pressure_input(&mut self, i: usize, value: Option<f64>) {
        self.inputs.pressures[i] = value;
    }

    /// Each edge pressure at time t within the step t0 -> t1: an overridden
    /// one runs linearly from its value at the start of the step, `start`.
    fn pressures_at(&self, t: f64, t0: f64, t1: f64, start: &[f64]) -> Vec<f64> {
        let scene = scene_pressures(&self.problem, t);
        (self.inputs.pressures.iter().zip(scene).enumerate())
            .map(|(i, (input, p))| match *input {
                Some(v) => toward(start.get(i).copied().unwrap_or(0.0), v, t, t0, t1),
                None => p,
            })
            .collect()
    }

    /// Force [x, y] of each driver at time t within the step t0 -> t1 (the
    /// set's resultant, on its force components): an overridden component
    /// runs linearly from its value at the start of the step, `start`.
    fn driver_forces(&self, t: f64, t0: f64, t1: f64, start: &[[f64; 2]]) -> Vec<[f64; 2]> {
        let scene = scene_forces(&self.problem, t);
        (0..self.problem.drivers.len())
            .map(|d| {
                let mut f = scene[d];
                for c in 0..2 {
                    if let (Some(v), Some(_)) =
                        (self.inputs.drivers[d][c], self.problem.drivers[d].force(c))
                    {
                        let s = start.get(d).map_or(0.0, |s| s[c]);
                        f[c] = toward(s, v, t, t0, t1);
                    }
                }
                f
            })
            .collect()
    }

    /// Value of a prescribed dof at time t within the step t0 -> t1.
    fn prescribed_value(&self, p: &Prescribed, t: f64, t0: f64, t1: f64, u0: &[f64]) -> f64 {
        match self.inputs.drivers[p.driver][p.component] {
            Some(v) => toward(u0[p.dof], v, t, t0, t1),
            None => {
                let d = &self.problem.drivers[p.driver];
                let comp = if p.component == 0 { &d.ux } else { &d.uy };
                comp.as_ref()
                    .map_or(0.0, |s| s.at(t, &self.problem.functions))
            }
        }
    }

    /// Solve equilibrium at `t_end`, bisecting a failed increment up to
    /// `solver.max_bisections` times; on error the state stays at the last
    /// converged time.
    pub fn advance(
        &mut self,
        t_end: f64,
        log: &mut dyn FnMut(LogCategory, &str),
    ) -> Result<StepResult, SolveError> {
        let clock = Instant::now();
        let result = self.advance_to(t_end, log);
        self.times.total += clock.elapsed();
        result
    }

    fn advance_to(
        &mut self,
        t_end: f64,
        log: &mut dyn FnMut(LogCategory, &str),
    ) -> Result<StepResult, SolveError> {
        let t0 = self.state.time;
        if !t_end.is_finite() || t_end <= t0 {
            return Err(SolveError::Invalid(format!(
                "step end time {t_end} must be finite and after t = {t0}"
            )));
        }
        // A running strip's state shifts by whole elements before the
        // step; a step that fails leaves the state as it was before that.
        let unshifted = (!self.running.is_empty()).then(|| self.state.clone());
        self.recycle();
        let start = self.state.clone();
        let u0 = start.u.clone();
        let factorizations = self.factorizations();
        let mut targets = vec![t_end];
        let mut bisections = 0;
        let mut iterations = 0;
        let mut solves = 0;
        let mut fallbacks = 0;
        let mut residual = 0.0;
        while let Some(&t) = targets.last() {
            let from = Ramp {
                t0,
                t1: t_end,
                u0: &u0,
                rigid0: &start.rigid,
                forces0: &start.driver_forces,
                pressures0: &start.pressures,
            };
            let attempt = self.attempt(t, &from, &mut fallbacks, log);
            match attempt {
                Ok(c) => {
                    iterations += c.iterations;
                    solves += c.solves;
                    residual = c.residual;
                    targets.pop();
                }
                Err(reason) => {
                    // Halving stops at the bisection budget, or where the
                    // midpoint would round onto an end of the increment (the
                    // same increment tried again).
                    let mid = 0.5 * (self.state.time + t);
                    let halvable = mid > self.state.time && mid < t;
                    if bisections >= self.problem.solver.max_bisections || !halvable {
                        self.state = unshifted.unwrap_or(start);
                        let why = if halvable {
                            format!("after {bisections} bisections")
                        } else {
                            format!(
                                "after {bisections} bisections (the increment cannot be halved further in floating point)"
                            )
                        };
                        let msg = format!(
                            "no convergence from t = {} to t = {t} {why}: {reason}",
                            self.state.time
                        );
                        log(LogCategory::Error, &msg);
                        return Err(SolveError::NotConverged {
                            time: t_end,
                            reason: msg,
                        });
                    }
                    bisections += 1;
                    log(
                        LogCategory::Warning,
                        &format!("increment to t = {t} failed ({reason}); bisecting at t = {mid}"),
                    );
                    targets.push(mid);
                }
            }
        }
        for (k, strip) in self.running.iter().enumerate() {
            self.state.running[k].speed =
                strip.speeds(&self.problem, &start.u, &self.state.u, t_end - t0);
        }
        Ok(StepResult {
            time: t_end,
            converged: true,
            iterations,
            solves,
            factorizations: self.factorizations() - factorizations,
            fallbacks,
            substeps: bisections,
            residual,
            neqc: self.contact.as_ref().map_or(0, |c| c.neqc()),
            drivers: self.driver_results(),
            pairs: self.pair_results(Some(&start.contact))?,
            ties: self.tie_results(),
            running: self.running_results(),
        })
    }

    /// Shifts each running strip's state by whole elements, so that its
    /// supply end lies within half an element of its home.
    fn recycle(&mut self) {
        for (k, strip) in self.running.iter().enumerate() {
            if strip.recycle(&self.problem, &self.model, &mut self.state, k) != 0 {
                self.linearization = None;
            }
        }
    }

    /// Each running strip's figures in the converged state, by body name.
    pub fn running_results(&self) -> Vec<(String, crate::results::RunningResult)> {
        (self.running.iter().enumerate())
            .map(|(k, s)| (s.name.clone(), s.result(&self.problem, &self.state, k)))
            .collect()
    }

    /// One increment to t (`increment`) and, if it fails, its fallbacks
    /// before `advance_to` halves it (docs/contact.md section 8, "Commit or
    /// fail"), each counted in `fallbacks`.
    fn attempt(
        &mut self,
        t: f64,
        from: &Ramp,
        fallbacks: &mut usize,
        log: &mut dyn FnMut(LogCategory, &str),
    ) -> Result<Converged, String> {
        self.inner_flips = 0;
        self.free_at_first_solve = false;
        let mut attempt = self.increment(t, from, log);
        // The inner solves open and close nodes on the linearised
        // problem, which can be far from the body's (a strip held on a
        // drum by its own tension has no stiffness across the drum
        // until it is stretched: the first solve pulls it off at many
        // nodes and the next turns its elements inside out). An
        // increment they fail is tried again, before it is halved,
        // with opening and closing decided on the iterate only (if they
        // opened or closed a node).
        if let Err(reason) = &attempt
            && self.inner_flips > 0
        {
            log(
                LogCategory::Warning,
                &format!(
                    "increment to t = {t} failed ({reason}); trying it again with \
                     opening and closing decided on the iterate only"
                ),
            );
            self.iterate_opens = true;
            attempt = self.increment(t, from, log);
            self.iterate_opens = false;
            *fallbacks += 1;
        }
        // A body resting on a target at gap 0 and loaded by forces
        // alone is held by nothing at its first solve: its touching
        // nodes are not penetrated, so they stay open. The increment is
        // tried again with them closed (a touching node the solve then
        // pulls off opens as any other). Only then: closing touching
        // nodes everywhere changes the first iteration of every scene
        // that starts in touch (the Hertz cylinder with mu = 10 took 8
        // iterations instead of 2, Cattaneo-Mindlin's stick zone split).
        if let Err(reason) = &attempt
            && self.free_at_first_solve
        {
            log(
                LogCategory::Warning,
                &format!(
                    "increment to t = {t} failed ({reason}); trying it again with the \
                 nodes that touch a target closed"
                ),
            );
            self.close_touching = true;
            attempt = self.increment(t, from, log);
            self.close_touching = false;
            *fallbacks += 1;
        }
        attempt
    }

    /// Reactions per driver from the residual at the prescribed dofs.
    fn driver_results(&self) -> Vec<(String, DriverResult)> {
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
    fn pair_results(
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

    /// Newton iterations for one increment to time t; commits on success.
    /// In phases: the predictor (`predictor`), then per iteration the
    /// residual and contact update (`evaluate`), the convergence test
    /// (`convergence_test`), and the correction (`correction`); the state
    /// is committed on convergence (`commit`) and left untouched on failure.
    fn increment(
        &mut self,
        t: f64,
        from: &Ramp,
        log: &mut dyn FnMut(LogCategory, &str),
    ) -> Result<Converged, String> {
        let max_iterations = self.problem.solver.max_iterations;
        // The multipliers' slots start afresh: an increment's round-off
        // depends on its start state alone (a restored state continues bit
        // for bit).
        self.augmented.restart();
        self.search_cache = contact::SearchCache::default();
        let mut inc = self.predictor(t, from);
        for it in 0..=max_iterations {
            let eval = self.evaluate(&mut inc, it, log)?;
            if self.convergence_test(&mut inc, it, &eval, log)? {
                let residual = eval.measure.rho;
                let solves = inc.solves;
                self.commit(inc, eval.contact);
                return Ok(Converged {
                    iterations: it,
                    solves,
                    residual,
                });
            }
            if it == max_iterations {
                break;
            }
            self.correction(&mut inc, it, eval, log)?;
        }
        Err(format!(
            "no convergence in {max_iterations} iterations{}",
            contact::failure_hints(&self.problem, &inc.memory)
        ))
    }

    /// The predictor: the increment's loads, pressures and rigid target
    /// poses at t, the prescribed increment `dup` (carried through the
    /// tangent at iteration 0, so a large boundary motion does not first
    /// distort the elements next to it), and the iteration's start from the
    /// converged state (contact anchors set: `contact::begin_increment`),
    /// a running strip's nodes carried along its path by its drum's turn
    /// (`running::Strip::carry`).
    fn predictor(&mut self, t: f64, from: &Ramp) -> Increment {
        let (t0, t1, u0) = (from.t0, from.t1, from.u0);
        let (rigid0, forces0, pressures0) = (from.rigid0, from.forces0, from.pressures0);
        let poses = self.rigid_poses(t, t0, t1, rigid0);
        self.step_forces = self.driver_forces(t, t0, t1, forces0);
        self.ws.pressures = self.pressures_at(t, t0, t1, pressures0);
        let mut u = self.state.u.clone();
        // A running strip starts where its drum's turn carries it.
        for strip in &self.running {
            if let Some(r) = strip.drum {
                let turn = poses[r][2] - self.state.rigid[r][2];
                if turn != 0.0 {
                    strip.carry(&self.problem, &mut u, turn);
                }
            }
        }
        let mut dup = vec![0.0; u.len()];
        for p in &self.prescribed {
            dup[p.dof] = self.prescribed_value(p, t, t0, t1, u0) - u[p.dof];
        }
        // The motion's scale: the start state and the prescribed motion (not
        // the iterate, which may run away past a limit load).
        let rigid_motion = (poses.iter().zip(&self.state.rigid))
            .map(|(p, q)| (p[0] - q[0]).abs().max((p[1] - q[1]).abs()))
            .fold(0.0, f64::max);
        let u_max = largest(&self.state.u) + largest(&dup) + rigid_motion;
        // The targets are at their poses at t already (the contact of
        // every iteration is found there): what may close the gap is the
        // nodes' own motion.
        let reach = largest(&dup);
        let n = self.model.free_dofs();
        let mut memory = self.state.contact.clone();
        contact::begin_increment(&mut memory);
        Increment {
            t,
            kdu: vec![0.0; u.len()],
            u,
            dup,
            poses,
            u_max,
            history: self.state.history.clone(),
            rhs: vec![0.0; n],
            du1: 0.0,
            e1: 0.0,
            ratios: Vec::new(),
            last_du: vec![0.0; n],
            memory,
            flips: Flips::default(),
            solves: 0,
            extra: Vec::new(),
            // Tie multipliers, total: their forces C^T lambda act as loads.
            lambda: self.state.ties.clone(),
            reach,
            slots: None,
        }
    }

    /// One iteration's residual and contact update at the iterate
    /// (`residual`: search, force recovery, decisions and rows, per pair),
    /// measured against the problem's forces (`measure`).
    fn evaluate(
        &mut self,
        inc: &mut Increment,
        it: usize,
        log: &mut dyn FnMut(LogCategory, &str),
    ) -> Result<Evaluated, String> {
        let with_contact = !self.problem.contacts.is_empty();
        inc.history.copy_from_slice(&self.state.history);
        let need_k = with_contact || !(self.model.constant_tangent && self.factor_valid);
        let settling = it == 1 || (it > 1 && norm(&inc.last_du) > SETTLING * inc.du1);
        let step = Step {
            t: inc.t,
            it,
            u: &inc.u,
            dup: &inc.dup,
            poses: &inc.poses,
            tolerance: [0.0; 2],
            settling,
        };
        let contact = self.residual(
            &step,
            need_k,
            &mut inc.history,
            &mut inc.kdu,
            &inc.lambda,
            &mut inc.memory,
            &mut inc.flips,
            log,
        )?;
        let (rhs_base, measure) = self.measure(
            it,
            &inc.kdu,
            contact.as_ref(),
            need_k,
            inc.u_max,
            &mut inc.rhs,
        )?;
        // Gaps are tested in lengths: to the displacement tolerance of
        // the first correction, or of 1e-3 of the model's size.
        let gap_tol = self.problem.solver.displacement_tolerance * inc.du1.max(1e-3 * self.size);
        Ok(Evaluated {
            contact,
            rhs_base,
            measure,
            need_k,
            settling,
            gap_tol,
        })
    }

    /// The convergence test (docs/contact.md section 8): true when the
    /// iterate is converged; logs the iteration, and fails a diverging
    /// increment.
    fn convergence_test(
        &self,
        inc: &mut Increment,
        it: usize,
        eval: &Evaluated,
        log: &mut dyn FnMut(LogCategory, &str),
    ) -> Result<bool, String> {
        let settings = &self.problem.solver;
        let (t, n) = (inc.t, self.model.free_dofs());
        let Measure {
            rho, at_roundoff, ..
        } = eval.measure;
        let contact = eval.contact.as_ref();
        let (neqc, changes, overlap) = contact.map_or((0, 0, 0.0), |c| {
            (c.neqc(), c.changes, closable_overlap(c, &self.model.eq))
        });
        let pending = contact.map_or(0, |c| c.pending);
        let contact_ok = changes == 0 && pending == 0 && overlap <= eval.gap_tol;
        let force_ok = rho <= settings.force_tolerance || at_roundoff;
        if it == 0 {
            // Nothing moved and the state is in equilibrium to the
            // tolerance: a held input converges without a solve.
            let held = inc.dup.iter().all(|v| *v == 0.0) && inc.poses == self.state.rigid;
            let converged = held && force_ok && contact_ok;
            if converged {
                log(
                    LogCategory::Newton,
                    &format!("t = {t:.6e} it 0: |r|/F = {rho:.3e}  held, in equilibrium"),
                );
            }
            return Ok(converged);
        }
        let (last_du, rhs) = (&inc.last_du, &inc.rhs);
        let energy = (0..n).map(|q| last_du[q] * rhs[q]).sum::<f64>().abs() / inc.e1;
        let dnorm = norm(last_du) / inc.du1;
        let ratios = &mut inc.ratios;
        ratios.push(rho);
        let rate = match ratios.len() {
            0..=2 => String::new(),
            m => {
                let (a, b, c) = (ratios[m - 3], ratios[m - 2], ratios[m - 1]);
                format!("  rate {:.2}", (c / b).ln() / (b / a).ln())
            }
        };
        let contact_text = if contact.is_some() {
            format!("  NEQC {neqc}  changed {changes}  overlap {overlap:.3e}")
        } else {
            String::new()
        };
        log(
            LogCategory::Newton,
            &format!(
                "t = {t:.6e} it {it}: |r|/F = {rho:.3e}  |du|/|du1| = {dnorm:.3e}  energy {energy:.3e}{rate}{contact_text}"
            ),
        );
        // A correction at the precision of the displacements cannot
        // improve the solution further.
        let stagnated = dnorm * inc.du1 <= 1e-14 * norm(&inc.u);
        let converged = contact_ok
            && (at_roundoff
                || (force_ok
                    && (energy <= settings.energy_tolerance
                        || dnorm <= settings.displacement_tolerance
                        || stagnated)));
        // Diverging: the residual is far above every force of the
        // problem and still growing.
        let m = ratios.len();
        if !converged
            && it >= 3
            && rho > 1e6
            && ratios[m - 1] > ratios[m - 2]
            && ratios[m - 2] > ratios[m - 3]
        {
            return Err(format!(
                "diverging: |r|/F = {rho:.3e} at iteration {it}, growing for two iterations"
            ));
        }
        Ok(converged)
    }

    /// The correction of one iteration (`solve`), failed at once when it
    /// has no equilibrium near, then added to the iterate.
    fn correction(
        &mut self,
        inc: &mut Increment,
        it: usize,
        eval: Evaluated,
        log: &mut dyn FnMut(LogCategory, &str),
    ) -> Result<(), String> {
        let n = self.model.free_dofs();
        if it == 0 {
            inc.last_du.copy_from_slice(&inc.rhs);
        }
        let first = it == 0 && !self.close_touching && !self.problem.contacts.is_empty();
        if let Err(e) = self.solve(inc, it, eval, log) {
            // A singular first system: a body held by nothing, perhaps.
            self.free_at_first_solve = first;
            return Err(e);
        }
        let (rhs, last_du) = (&inc.rhs, &mut inc.last_du);
        if it == 0 {
            // Energy of the first correction, |du_1 . r_0| (last_du holds -r_0).
            inc.e1 = (0..n)
                .map(|q| rhs[q] * last_du[q])
                .sum::<f64>()
                .abs()
                .max(f64::MIN_POSITIVE);
        }
        // A correction far beyond the model's size has no equilibrium
        // near it: the contact cannot hold the load (past a limit load,
        // e.g. a block that slides under a force it cannot resist) or
        // nothing holds the body. Fail now; a smaller step may converge.
        let du_max = largest(&rhs[..n]);
        if du_max.is_nan() || du_max > 1e3 * self.size {
            self.free_at_first_solve = first;
            return Err(format!(
                "no equilibrium near this state: iteration {it} moves a node by {du_max:.3e}, \
                 {:.1e} times the model's size (the load exceeds what the contact can hold, \
                 or nothing holds a body)",
                du_max / self.size
            ));
        }
        for (dof, &q) in self.model.eq.iter().enumerate() {
            if q != PRESCRIBED {
                inc.u[dof] += rhs[q as usize];
            } else if it == 0 {
                inc.u[dof] += inc.dup[dof];
            }
        }
        last_du.copy_from_slice(rhs);
        if it == 0 {
            inc.du1 = norm(last_du).max(f64::MIN_POSITIVE);
        }
        Ok(())
    }

    /// The residual and contact update: the out-of-balance forces `r =
    /// F_int - R_ext` at the iterate (with the tie forces; iteration 0 also
    /// carries the prescribed increment through the tangent into `kdu`),
    /// the tangent when `need_k`, and the contact system: search, forces,
    /// decisions, rows (`contact_update`).
    #[allow(clippy::too_many_arguments)]
    fn residual(
        &mut self,
        step: &Step,
        need_k: bool,
        history: &mut [f64],
        kdu: &mut [f64],
        lambda: &[f64],
        memory: &mut [PairMemory],
        flips: &mut Flips,
        log: &mut dyn FnMut(LogCategory, &str),
    ) -> Result<Option<ContactSystem>, String> {
        let (t, it) = (step.t, step.it);
        let pred = if it == 0 { Some((step.dup, kdu)) } else { None };
        let assemble_k = need_k && !self.k_constant;
        if assemble_k {
            // Said before K is written: an assembly that fails half way
            // has changed it too.
            self.augmented.new_tangent();
        }
        let k = if assemble_k {
            Some(&mut self.k[..])
        } else {
            None
        };
        let clock = Instant::now();
        let assembled = self
            .model
            .assemble(
                &self.problem,
                t,
                step.u,
                history,
                &mut self.r,
                k,
                None,
                pred,
                &mut self.ws,
            )
            .map_err(|e| e.to_string());
        self.times.assembly += clock.elapsed();
        assembled?;
        if assemble_k {
            self.k_constant = self.model.constant_tangent;
            self.times.tangents += 1;
        }
        subtract_loads(&self.problem, &self.step_forces, lambda, &mut self.r);
        let contact = if !self.problem.contacts.is_empty() {
            Some(self.contact_update(step, None, memory, flips, log)?)
        } else {
            None
        };
        Ok(contact)
    }

    /// The convergence test's figures: the right-hand side `-r` (with the predictor's
    /// `K du_p` at iteration 0) into `rhs`, returned without the contact
    /// forces and left in `rhs` with them, and the equilibrium residual
    /// against the problem's force scale (docs/contact.md section 8).
    fn measure(
        &mut self,
        it: usize,
        kdu: &[f64],
        contact: Option<&ContactSystem>,
        need_k: bool,
        u_max: f64,
        rhs: &mut [f64],
    ) -> Result<(Option<Vec<f64>>, Measure), String> {
        let mut react2 = 0.0;
        // Summed: the dofs of a rigid force set share an equation.
        rhs[..self.model.free_dofs()].fill(0.0);
        for (dof, &q) in self.model.eq.iter().enumerate() {
            if q == PRESCRIBED {
                react2 += self.r[dof] * self.r[dof];
            } else {
                let v = if it == 0 {
                    self.r[dof] + kdu[dof]
                } else {
                    self.r[dof]
                };
                rhs[q as usize] -= v;
            }
        }
        // The right-hand side without the contact forces: the inner solves
        // rebuild it with their own rows.
        let rhs_base = contact.map(|_| rhs.to_vec());
        let mut contact_force2 = 0.0;
        if let Some(c) = contact {
            for &(d, f) in &c.force {
                contact_force2 += f * f;
                let q = self.model.eq[d];
                if q != PRESCRIBED {
                    rhs[q as usize] += f;
                }
            }
        }
        // At a constrained node the multipliers take up the residual in
        // the constrained directions: measure what they cannot.
        let adjusted = match contact {
            Some(c) if c.neqc() > 0 => Some(equilibrium_residual(c, &self.model.eq, rhs)),
            _ => None,
        };
        let rnorm = norm(adjusted.as_deref().unwrap_or(rhs));
        if !rnorm.is_finite() {
            return Err(format!("non-finite residual at iteration {it}"));
        }
        // The force scale of the problem: element forces, reactions,
        // contact forces (never the first residual alone: a held input
        // has a first residual at round-off).
        // Below them, the round-off of K u: a body that moves without
        // stress has no other force to compare with.
        if need_k {
            self.k_max = (self.diagonal_at.iter())
                .map(|&i| self.k[i].abs())
                .fold(0.0, f64::max);
        }

        let f_phys = self
            .ws
            .force_scale
            .max(react2.sqrt())
            .max(contact_force2.sqrt());
        // The force of the tangent over the motion at a strain of 1e-6:
        // the scale when nothing else has one (a body moving unstressed).
        let f_motion = self.k_max * u_max;
        let f_ref = f_phys.max(1e-6 * f_motion).max(f64::MIN_POSITIVE);
        let f_round = 1e-13 * f_phys + 1e-14 * f_motion;
        let rho = rnorm / f_ref;
        Ok((
            rhs_base,
            Measure {
                rho,
                f_ref,
                at_roundoff: rnorm <= f_round,
            },
        ))
    }

    /// The correction into `inc.rhs`: the plain tangent solve, or Eq. (18)
    /// with contact rows or ties (`constrained_correction`, which updates
    /// the tie multipliers).
    fn solve(
        &mut self,
        inc: &mut Increment,
        it: usize,
        eval: Evaluated,
        log: &mut dyn FnMut(LogCategory, &str),
    ) -> Result<(), String> {
        let n = self.model.free_dofs();
        // The contact tangent a formulation deferred (a converged iterate,
        // which no solve starts from, never forms it).
        let clock = Instant::now();
        let contact = (eval.contact)
            .map(|mut c| {
                c.complete_tangent();
                c
            })
            .filter(|c| c.neqc() > 0 || !c.k.is_empty());
        self.times.contact += clock.elapsed();
        if contact.is_none() && inc.lambda.is_empty() {
            if self.solve_in_contact_slots(inc)? {
                inc.solves += 1;
                return Ok(());
            }
            if eval.need_k {
                // One AMD for the tangent and the bordered systems' block
                // where that block is the tangent's pattern (rigid targets;
                // against a deformable one the block has contact couplings
                // and its own order, as the buried pipe's round-off needs).
                if self.rigid_targets {
                    self.linear.share_order(self.augmented.order());
                }
                self.linear.factorize(&self.k).map_err(|e| e.to_string())?;
                if self.rigid_targets {
                    self.augmented.share_order(self.linear.order());
                }
                self.factor_valid = self.model.constant_tangent;
            }
            self.linear.solve(&mut inc.rhs).map_err(|e| e.to_string())?;
            inc.solves += 1;
        } else {
            let force_tolerance = self.problem.solver.force_tolerance;
            let step = Step {
                t: inc.t,
                it,
                u: &inc.u,
                dup: &inc.dup,
                poses: &inc.poses,
                tolerance: [force_tolerance * eval.measure.f_ref, eval.gap_tol],
                settling: eval.settling,
            };
            let (full, system) = self.constrained_correction(
                &step,
                contact,
                eval.rhs_base.as_deref(),
                &inc.rhs,
                &mut inc.memory,
                &mut inc.flips,
                &mut inc.extra,
                &mut inc.solves,
                log,
            )?;
            let contact_rows = system.as_ref().map_or(&[][..], |c| &c.rows[..]);
            inc.rhs.copy_from_slice(&full[..n]);
            // The system's multipliers are the change that removes the
            // tie forces' out-of-balance: K du = r + C^T lambda - C^T x.
            for (l, x) in inc.lambda.iter_mut().zip(&full[n + contact_rows.len()..]) {
                *l -= x;
            }
            self.factor_valid = false;
        }
        Ok(())
    }

    /// The contact nodes that may touch in this increment (`contact::near_target`,
    /// within its prescribed motion `Increment::reach`), as the multiplier
    /// slots their rows would take: one per node, two with friction (a
    /// sticking node's), each keyed by the node's free equations (the rows
    /// against a rigid target act on the node alone). The nearest nodes
    /// first, while the slots with their nodes' equations stay few enough
    /// for the dense solves on the factor's trailing block
    /// (`linsolve::trailing_fits`); a node left out that touches gives the
    /// contact system a pattern of its own (an analysis and a
    /// factorization, as without the slots). Empty when no node may touch
    /// or a target is a body.
    fn contact_slots(&self, inc: &Increment) -> Result<Vec<Vec<usize>>, String> {
        let n = self.model.free_dofs();
        let near = contact::near_target(
            &self.problem,
            &self.targets,
            &inc.poses,
            &self.state.u,
            &inc.memory,
            inc.reach,
        )?;
        let Some(near) = near else {
            return Ok(Vec::new());
        };
        let mut nodes: Vec<(f64, usize, usize)> = (near.iter().enumerate())
            .flat_map(|(p, near)| near.iter().map(move |&(k, d)| (d, p, k)))
            .collect();
        nodes.sort_by(|a, b| a.0.total_cmp(&b.0).then((a.1, a.2).cmp(&(b.1, b.2))));
        let mut slots = Vec::new();
        let mut dofs = 0;
        for (_, p, k) in nodes {
            let pair = &self.problem.contacts[p];
            let per_node = if pair.mu_s > 0.0 { 2 } else { 1 };
            let node = pair.contactor[k];
            let eqs: Vec<usize> = [2 * node, 2 * node + 1]
                .into_iter()
                .filter(|&d| self.model.eq[d] != PRESCRIBED)
                .map(|d| self.model.eq[d] as usize)
                .collect();
            // A row acting on prescribed dofs alone (a sticking node's
            // tangential row on a symmetry plane) is an identity row: its
            // key is empty.
            let empty = usize::from(eqs.len() < 2);
            let added = if eqs.is_empty() { 0 } else { per_node };
            // A node in two pairs counts its equations twice: the set is
            // overestimated, never under.
            let (t, m) = (dofs + eqs.len(), slots.len() + empty + added);
            if !crate::linsolve::trailing_fits(t + m, n + m) {
                break;
            }
            dofs = t;
            slots.extend(std::iter::repeat_n(Vec::new(), empty));
            slots.extend(std::iter::repeat_n(eqs, added));
        }
        Ok(slots)
    }

    /// A correction without contact rows (`inc.rhs` in, the correction
    /// out) against rigid targets: solved on the LDLT factor of the tangent
    /// bordered by the slots of the contact rows to come (`contact_slots`),
    /// every slot empty (an identity row, its entries on its node zero),
    /// their nodes and slots ordered last, so that the iterations with
    /// contact rows solve on the same factor's trailing block (under a
    /// constant tangent) or on its analysis: one symbolic analysis and one
    /// factorization where the plain tangent (`linear`) and then the
    /// contact system took two of each. False when this does not apply
    /// (no slots, comparisons forcing LU or no trailing set, a failed solve):
    /// `linear` solves then.
    fn solve_in_contact_slots(&mut self, inc: &mut Increment) -> Result<bool, String> {
        let augmented = &self.augmented;
        if !self.rigid_targets
            || self.problem.contacts.is_empty()
            || augmented.force_lu
            || augmented.no_trailing
            || !augmented.slots
        {
            return Ok(false);
        }
        if inc.slots.is_none() {
            inc.slots = Some(self.contact_slots(inc)?);
        }
        let slots = inc.slots.as_deref().unwrap_or_default();
        if slots.is_empty() {
            return Ok(false);
        }
        let n = self.model.free_dofs();
        let extra = &mut inc.extra;
        extra.clear();
        for (m, eqs) in slots.iter().enumerate() {
            for &q in eqs {
                extra.push((n + m, q, 0.0));
                extra.push((q, n + m, 0.0));
            }
            extra.push((n + m, n + m, 1.0));
        }
        let mut full = inc.rhs.clone();
        full.resize(n + slots.len(), 0.0);
        let (pattern, k) = (&self.model.pattern, &self.k);
        let trailing = self.augmented.trailing_solves;
        let solved = self.augmented.solve(pattern, k, extra, &mut full);
        self.times.reused += self.augmented.trailing_solves - trailing;
        if solved.is_err() {
            self.augmented.restart();
            inc.slots = Some(Vec::new());
            return Ok(false);
        }
        inc.rhs.copy_from_slice(&full[..n]);
        Ok(true)
    }

    /// The correction with contact rows or ties: Eq. (18), `[K + K_c, C^T;
    /// C, 0] [du; dlambda] = [r; overlap]`, the contact rows first, then the
    /// tie rows (`C u = 0`; `constraint_system`); under the nodal decisions
    /// solved again while the linearised problem decides a node's state
    /// otherwise than the iterate did (docs/contact.md section 8, inner
    /// solves: `next_inner_states`, `contact_update`), its rows changing,
    /// the tangent and the out-of-balance forces not. Returns `[du;
    /// multipliers]` and the contact system it solves.
    #[allow(clippy::too_many_arguments)]
    fn constrained_correction(
        &mut self,
        step: &Step,
        contact: Option<ContactSystem>,
        rhs_base: Option<&[f64]>,
        rhs: &[f64],
        memory: &mut Vec<PairMemory>,
        flips: &mut Flips,
        extra: &mut Vec<(usize, usize, f64)>,
        solves: &mut usize,
        log: &mut dyn FnMut(LogCategory, &str),
    ) -> Result<(Vec<f64>, Option<ContactSystem>), String> {
        let inner_solves = contact::inner_solves(&self.problem);
        let mut system: Option<ContactSystem> = contact;
        let mut rhs_now = rhs.to_vec();
        let mut inner = InnerSolves::default();
        // The solve before the decisions the linearised problem takes from
        // it, kept until the next solve shows those decisions hold.
        let mut kept: Option<KeptSolve> = None;
        // The solve of the iterate's own decisions, kept from the first
        // inner solve on where they may stand (`iterate_decides`): the
        // iteration goes on from it when the inner solves do not settle
        // (`unsettled`).
        let mut first: Option<KeptSolve> = None;
        let full = loop {
            let mut full = self.constraint_system(step, system.as_ref(), &rhs_now, extra);
            *solves += 1;
            let more =
                inner_solves && inner.count < MAX_INNER && system.is_some() && rhs_base.is_some();
            let neqc = system.as_ref().map_or(0, |c| c.rows.len());
            let b = more.then(|| full.clone());
            let (mut solved, mut partial) =
                self.solve_constraint_system(&mut full, extra, inner.count, more);
            if solved.is_ok()
                && !partial
                && let Some(sys) = system.as_ref()
                && self.contact_terms_turn_step(sys, &full)
            {
                // The pair's sliding gradient terms (Eq. 24) turn the
                // tangent's curvature along its own step non-positive: the
                // step heads for a saddle of the linearised problem, not
                // for an equilibrium. Solved again without them.
                log(LogCategory::Contact, &{
                    let (t, it) = (step.t, step.it);
                    format!(
                        "t = {t:.6e} it {it}: the contact's sliding gradient turns the \
                         tangent's curvature along the correction non-positive; solved \
                         without it"
                    )
                });
                // Its rows only: the contact's displacement block left out.
                full = self.constraint_system_with(step, system.as_ref(), &rhs_now, extra, false);
                (solved, partial) =
                    self.solve_constraint_system(&mut full, extra, inner.count, more);
            }
            let solved = solved.map_err(|e| format!("constraint system (NEQC {neqc}): {e}"));
            if let Some(previous) = kept.take()
                && let Some(x) =
                    self.rolled_back(previous, &solved, &full, memory, &mut system, extra)?
            {
                break x;
            }
            solved?;
            let Some((sys, rhs_base)) = system.as_ref().zip(rhs_base).filter(|_| more) else {
                if let Some(first) = first.take().filter(|_| inner.count >= MAX_INNER) {
                    break self.unsettled(first, step, memory, &mut system, extra, log)?;
                }
                break self.finish_inner(partial, full, extra)?;
            };
            let Some(switched) =
                self.next_inner_states(step, sys, &full, memory, &mut inner, log)?
            else {
                if let Some(first) = first.take().filter(|_| inner.wandered) {
                    break self.unsettled(first, step, memory, &mut system, extra, log)?;
                }
                break self.finish_inner(partial, full, extra)?;
            };
            let deferred = b.filter(|_| partial).map(|b| (b, extra.clone()));
            let states = memory.clone();
            let mut rebuilt =
                self.contact_update(step, Some((sys, &switched)), memory, flips, log)?;
            let clock = Instant::now();
            rebuilt.complete_tangent();
            self.times.contact += clock.elapsed();
            rhs_now.copy_from_slice(rhs_base);
            for &(d, f) in &rebuilt.force {
                if self.model.eq[d] != PRESCRIBED {
                    rhs_now[self.model.eq[d] as usize] += f;
                }
            }
            kept = Some(KeptSolve {
                full,
                memory: states,
                system: system.replace(rebuilt),
                deferred,
            });
            if first.is_none() && self.iterate_decides(step) {
                first = kept.clone();
            }
        };
        Ok((full, system))
    }

    /// One solve of the constraint system `full` (entries `extra` beside
    /// the tangent), the `inner`-th of its iteration (`Augmented::solve`
    /// decides how). With `more` (another inner solve may follow) it may be
    /// left partial, the contact nodes' motion solved alone until one is
    /// accepted (`finish_inner`). Returns the solve's outcome and whether
    /// it was left partial so.
    fn solve_constraint_system(
        &mut self,
        full: &mut [f64],
        extra: &mut [(usize, usize, f64)],
        inner: usize,
        more: bool,
    ) -> (Result<(), LinearError>, bool) {
        let watch = more.then_some(&self.contact_eqs[..]);
        let (pattern, k) = (&self.model.pattern, &self.k);
        let trailing = self.augmented.trailing_solves;
        let solved = (self.augmented).solve_watching(pattern, k, extra, full, watch);
        if inner == 0 {
            self.times.reused += self.augmented.trailing_solves - trailing;
        }
        match solved {
            Ok(whole) => (Ok(()), !whole),
            Err(e) => (Err(e), false),
        }
    }

    /// After an inner solve, whether the states the linearised problem chose
    /// before it leave no equilibrium near (every node of a free body
    /// sliding where the iterate's linearisation is poor: the solve failed,
    /// or moves a node by more than 1000 times the model's size). Then the
    /// solve before them (`previous`) is kept, its memory and rows restored
    /// (solved again in full if it was deferred), and the outer iteration
    /// decides: Some(that solve). None: the inner solve stands.
    fn rolled_back(
        &mut self,
        previous: KeptSolve,
        solved: &Result<(), String>,
        full: &[f64],
        memory: &mut Vec<PairMemory>,
        system: &mut Option<ContactSystem>,
        extra: &mut Vec<(usize, usize, f64)>,
    ) -> Result<Option<Vec<f64>>, String> {
        let n = self.model.free_dofs();
        let wild = solved.is_err()
            || largest(&full[..n]).is_nan()
            || largest(&full[..n]) > 1e3 * self.size;
        if !wild {
            return Ok(None);
        }
        self.restore_solve(previous, memory, system, extra)
            .map(Some)
    }

    /// The inner solves of an iteration where the iterate's decisions may
    /// stand (`iterate_decides`) cycled through every node of a pair's
    /// contact zone (`InnerSolves::wandered`), or `MAX_INNER` of them did
    /// not settle: the iteration
    /// goes on from its first solve, the iterate's own decisions
    /// (`first`), and the outer iteration decides. Keeping the last inner
    /// solve instead kept whichever state the wandering stopped at: a block
    /// of nu = 0.44 pressed with friction onto a stiffer strip moved its
    /// one-node stick zone four nodes and back at every iteration and
    /// failed its first increment (`scripts/press_sweep.py`,
    /// docs/performance-log.md, ninth session). Not at the predictor's
    /// iteration: there the iterate's decisions are the last increment's,
    /// which the new load may overturn at every node (the capstan of the
    /// stress suite, 2x: all 128 nodes alternated between stick and slip
    /// from iteration to iteration, and the increment bisected), and the
    /// linearised problem's last states are the better guess.
    fn unsettled(
        &mut self,
        first: KeptSolve,
        step: &Step,
        memory: &mut Vec<PairMemory>,
        system: &mut Option<ContactSystem>,
        extra: &mut Vec<(usize, usize, f64)>,
        log: &mut dyn FnMut(LogCategory, &str),
    ) -> Result<Vec<f64>, String> {
        let (t, it) = (step.t, step.it);
        log(
            LogCategory::Contact,
            &format!(
                "t = {t:.6e} it {it}: the inner solves did not settle; the iterate's own \
                 decisions stand"
            ),
        );
        self.restore_solve(first, memory, system, extra)
    }

    /// Whether the iterate's own decisions may stand when the inner solves
    /// do not settle (`unsettled`): past the predictor's iteration, and
    /// not in the fallback that leaves opening and closing to the iterate
    /// (`iterate_opens`). That fallback serves bodies far from
    /// equilibrium at their first iterates: the capstan's strip held on
    /// the drum by its end forces alone (`tests/force_driver.rs`) shows
    /// |r|/F of 0.2 to 1 there, its decisions are no guide, and going back
    /// to them failed the increment (13 stick/slip changes at a node,
    /// 6 bisections) where the last inner solve converges it in 7.
    fn iterate_decides(&self, step: &Step) -> bool {
        step.it > 0 && !self.iterate_opens
    }

    /// The solve `previous` with its memory and rows restored (solved again
    /// in full if it was left partial).
    fn restore_solve(
        &mut self,
        previous: KeptSolve,
        memory: &mut Vec<PairMemory>,
        system: &mut Option<ContactSystem>,
        extra: &mut Vec<(usize, usize, f64)>,
    ) -> Result<Vec<f64>, String> {
        *memory = previous.memory;
        *system = previous.system;
        let Some((rhs_prev, extra_prev)) = previous.deferred else {
            return Ok(previous.full);
        };
        // That solve was left partial: solved again in full.
        *extra = extra_prev;
        let mut x = rhs_prev;
        let (pattern, k) = (&self.model.pattern, &self.k);
        (self.augmented.solve(pattern, k, extra, &mut x))
            .map_err(|e| format!("constraint system: {e}"))?;
        Ok(x)
    }

    /// The nodes the linearised problem decides otherwise than `sys`'s rows
    /// did, after the solve `full` (`linearised_states`), for the next inner
    /// solve: None when none changes, when each change would open or close a
    /// node once too often in this iteration (`INNER_FLIPS`; none while the
    /// increment leaves opening and closing to the iterate), or when the
    /// states were met before in this iteration (the decisions cycle; when
    /// the cycle changed every node of a pair's contact zone,
    /// `inner.wandered`, the outer iteration decides from the first solve,
    /// `unsettled`).
    fn next_inner_states(
        &mut self,
        step: &Step,
        sys: &ContactSystem,
        full: &[f64],
        memory: &[PairMemory],
        inner: &mut InnerSolves,
        log: &mut dyn FnMut(LogCategory, &str),
    ) -> Result<Option<Switched>, String> {
        let clock = Instant::now();
        let predicted = self.linearised_states(step, sys, full, memory);
        self.times.contact += clock.elapsed();
        let Some(mut switched) = predicted? else {
            return Ok(None);
        };
        let flips_allowed = if self.iterate_opens { 0 } else { INNER_FLIPS };
        switched.limit_flips(&mut inner.flipped, flips_allowed);
        if switched.count() == 0 {
            return Ok(None);
        }
        let key = contact::state_key(memory, &switched);
        let nodes = switched.nodes();
        if let Some(at) = inner.seen.iter().position(|&k| k == key) {
            // The changes that lead round the cycle, from the states met
            // before (reached by `changed[at]`) back to them.
            let mut round: Vec<(usize, usize)> = inner.changed[at + 1..].concat();
            round.extend(&nodes);
            round.sort_unstable();
            round.dedup();
            // Every node of a pair's contact zone changed on the way.
            inner.wandered = memory.iter().enumerate().any(|(p, m)| {
                let mut zone = (0..m.nodes())
                    .filter(|&k| m.state(k) != crate::results::NodeState::Open)
                    .peekable();
                zone.peek().is_some() && zone.all(|k| round.binary_search(&(p, k)).is_ok())
            });
            return Ok(None);
        }
        inner.seen.push(key);
        inner.changed.push(nodes);
        inner.count += 1;
        let [opened, closed, slips] = switched.counts();
        self.inner_flips += opened + closed;
        let (t, it, count) = (step.t, step.it, inner.count);
        log(LogCategory::Contact, &{
            format!(
                "t = {t:.6e} it {it}: solve {count}: the linearised problem opens {opened}, \
                 closes {closed} and changes {slips} between stick and slip"
            )
        });
        Ok(Some(switched))
    }

    /// The accepted inner solve `full`: as solved, or, when it was left
    /// partial, finished (`Augmented::finish`; entries `extra`).
    fn finish_inner(
        &mut self,
        partial: bool,
        mut full: Vec<f64>,
        extra: &mut [(usize, usize, f64)],
    ) -> Result<Vec<f64>, String> {
        if partial {
            (self
                .augmented
                .finish(&self.model.pattern, &self.k, extra, &mut full))
            .map_err(|e| format!("constraint system: {e}"))?;
        }
        Ok(full)
    }

    /// The nodes whose stick/slip state the linearised problem decides
    /// otherwise than the rows of `sys` did (`contact::predict`), from where
    /// its solution `full` goes and the out-of-balance force it leaves at
    /// each dof (K du = r_c - C^T x - r).
    fn linearised_states(
        &mut self,
        step: &Step,
        sys: &ContactSystem,
        full: &[f64],
        memory: &[PairMemory],
    ) -> Result<Option<Switched>, String> {
        let (eq, n) = (&self.model.eq, self.model.free_dofs());
        let mut u_new = step.u.to_vec();
        let mut force_new = vec![0.0; step.u.len()];
        for (dof, &q) in eq.iter().enumerate() {
            if q != PRESCRIBED {
                u_new[dof] += full[q as usize];
            } else if step.it == 0 {
                u_new[dof] += step.dup[dof];
            }
        }
        for &(d, f) in &sys.force {
            if eq[d] != PRESCRIBED {
                force_new[d] += f;
            }
        }
        for (i, row) in sys.rows.iter().enumerate() {
            for &(d, v) in row.acting() {
                if eq[d] != PRESCRIBED {
                    force_new[d] -= full[n + i] * v;
                }
            }
        }
        contact::predict(
            &self.problem,
            &self.targets,
            step.poses,
            [step.u, &u_new],
            &force_new,
            memory,
            sys,
            step.tolerance,
            step.settling || step.it == 0,
            &mut self.search_cache,
        )
    }

    /// The contact system at the iterate, from `r` (`contact::update`); with
    /// `keep` (an inner solve), the rows rebuilt at the same iterate with
    /// the switched nodes' states and every other node's decision kept in
    /// the system given: the tangent and `r` do not change.
    fn contact_update(
        &mut self,
        step: &Step,
        keep: Option<(&ContactSystem, &Switched)>,
        memory: &mut [PairMemory],
        flips: &mut Flips,
        log: &mut dyn FnMut(LogCategory, &str),
    ) -> Result<ContactSystem, String> {
        let (t, it) = (step.t, step.it);
        let mut clog = |m: &str| log(LogCategory::Contact, &format!("t = {t:.6e} it {it}: {m}"));
        let start = contact::Start {
            u: &self.state.u,
            poses: &self.state.rigid,
            settling: step.settling,
            touching: self.close_touching,
            cache: &self.start_cache,
        };
        let clock = Instant::now();
        let updated = contact::update(
            &self.problem,
            &self.targets,
            step.poses,
            step.u,
            &self.r,
            &self.model.eq,
            &start,
            memory,
            flips,
            &mut clog,
            keep,
        );
        self.times.contact += clock.elapsed();
        updated
    }

    /// The constraint rows of Eq. (18) into `extra` (triplets beside K) and
    /// the full right-hand side `[rhs; row values]`: the contact system's
    /// sliding gradient entries and rows (a sliding node's multiplier with
    /// its own column), then the tie rows.
    fn constraint_system(
        &self,
        step: &Step,
        system: Option<&ContactSystem>,
        rhs_now: &[f64],
        extra: &mut Vec<(usize, usize, f64)>,
    ) -> Vec<f64> {
        self.constraint_system_with(step, system, rhs_now, extra, true)
    }

    /// Whether the contact's displacement block `sys.k` turns the
    /// curvature of the tangent along the solved correction `full`
    /// non-positive while the body's tangent alone keeps it positive:
    /// `du^T (K + K_c) du <= 0 < du^T K du`.
    fn contact_terms_turn_step(&self, sys: &ContactSystem, full: &[f64]) -> bool {
        if sys.k.is_empty() {
            return false;
        }
        let (eq, pattern, n) = (&self.model.eq, &self.model.pattern, self.model.free_dofs());
        let du = &full[..n];
        let mut body = 0.0;
        for (c, &du_c) in du.iter().enumerate().take(pattern.n) {
            for p in pattern.col_ptr[c]..pattern.col_ptr[c + 1] {
                body += du[pattern.row_idx[p]] * self.k[p] * du_c;
            }
        }
        let mut contact = 0.0;
        for &(a, b, v) in &sys.k {
            if eq[a] != PRESCRIBED && eq[b] != PRESCRIBED {
                contact += du[eq[a] as usize] * v * du[eq[b] as usize];
            }
        }
        body > 0.0 && body + contact <= 0.0
    }

    /// The constraint system, the contact's displacement block included
    /// (`gradient`) or not.
    fn constraint_system_with(
        &self,
        step: &Step,
        system: Option<&ContactSystem>,
        rhs_now: &[f64],
        extra: &mut Vec<(usize, usize, f64)>,
        gradient: bool,
    ) -> Vec<f64> {
        let (eq, n, it) = (&self.model.eq, self.model.free_dofs(), step.it);
        let (u, dup) = (step.u, step.dup);
        extra.clear();
        let mut full = rhs_now.to_vec();
        let contact_rows = system.map_or(&[][..], |c| &c.rows[..]);
        if let Some(c) = system.filter(|_| gradient) {
            for &(a, b, v) in &c.k {
                if eq[a] != PRESCRIBED && eq[b] != PRESCRIBED {
                    extra.push((eq[a] as usize, eq[b] as usize, v));
                }
            }
        }
        let ties = self.problem.ties.iter().flat_map(|t| &t.rows);
        let tie_rows = ties.map(|r| {
            let violation: f64 = r.dofs.iter().map(|&(d, v)| v * u[d]).sum();
            (&r.dofs[..], -violation)
        });
        let rows = contact_rows
            .iter()
            .map(|r| (&r.dofs[..], r.rhs, &r.column[..]));
        let tie_rows = tie_rows.map(|(dofs, b)| (dofs, b, &[][..]));
        for (i, (dofs, rhs_i, column)) in rows.chain(tie_rows).enumerate() {
            let mut b = rhs_i;
            let free = acts_on_free(dofs, eq);
            for &(d, v) in dofs {
                if eq[d] == PRESCRIBED {
                    if it == 0 {
                        b -= v * dup[d];
                    }
                } else if free {
                    extra.push((n + i, eq[d] as usize, v));
                    if column.is_empty() {
                        extra.push((eq[d] as usize, n + i, v));
                    }
                }
            }
            // A sliding node's friction: the multiplier's column
            // differs from its row.
            for &(d, v) in column.iter().filter(|_| free) {
                if eq[d] != PRESCRIBED {
                    extra.push((eq[d] as usize, n + i, v));
                }
            }
            if !free {
                // Every dof the row acts on is prescribed (a
                // sticking node on a symmetry plane against a
                // fixed target): the drivers already hold it; its
                // multiplier gets an identity row.
                extra.push((n + i, n + i, 1.0));
                b = 0.0;
            }
            full.push(b);
        }
        full
    }

    /// The converged increment becomes the state (the history, the
    /// displacements and the poses the step started from are kept for the
    /// sensitivities: the material tangent, mortar's weighted slips).
    fn commit(&mut self, inc: Increment, contact: Option<ContactSystem>) {
        self.state.time = inc.t;
        self.state.step_start_u = std::mem::replace(&mut self.state.u, inc.u);
        self.state.step_start_history = std::mem::replace(&mut self.state.history, inc.history);
        self.state.contact = inc.memory;
        self.state.step_start_rigid = std::mem::replace(&mut self.state.rigid, inc.poses);
        self.state.ties = inc.lambda;
        self.state.driver_forces.clone_from(&self.step_forces);
        self.state.pressures.clone_from(&self.ws.pressures);
        self.contact = contact;
        self.linearization = None;
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

/// The largest magnitude in `v`.
fn largest(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |a, x| a.max(x.abs()))
}

/// Whether a constraint row acts on free dofs. A row whose free
/// coefficients are round-off beside its prescribed ones (a node held at a
/// target node on a symmetry plane, its contact point a hair inside the
/// next segment: `beta` = 1e-8) would fix its tiny free part with a huge
/// multiplier; it is a row on prescribed dofs (`NEGLIGIBLE_ROW`).
fn acts_on_free(dofs: &[(usize, f64)], eq: &[u32]) -> bool {
    let square = |free: bool| -> f64 {
        (dofs.iter())
            .filter(|&&(d, _)| (eq[d] != PRESCRIBED) == free)
            .map(|&(_, v)| v * v)
            .sum()
    };
    square(true) > NEGLIGIBLE_ROW * NEGLIGIBLE_ROW * square(false)
}

/// The largest overlap of a constrained node that the solve can close: the
/// contact system's own (`max_overlap`), or, where a row acts on prescribed
/// dofs alone (a node its drivers place, against a rigid target: the row is
/// replaced by the identity row for its multiplier), each node's overlap in
/// the directions of its rows that act on free dofs. A driven node that
/// starts 1e-6 inside the drum by round-off keeps that overlap whatever the
/// solve does; counted, no iteration converged.
fn closable_overlap(c: &ContactSystem, eq: &[u32]) -> f64 {
    if c.rows.iter().all(|r| acts_on_free(&r.dofs, eq)) {
        return c.max_overlap;
    }
    (c.groups.iter())
        .map(|(_, rows)| {
            let free = c.rows[rows.clone()]
                .iter()
                .filter(|r| acts_on_free(&r.dofs, eq));
            free.map(|r| r.rhs * r.rhs).sum::<f64>().sqrt()
        })
        .fold(0.0, f64::max)
}

/// The loads beside the elements' in `r = F_int - R_ext`: each force
/// driver's resultant `forces`, shared equally by its nodes (a dead load;
/// on a rigid set the shares sum into the set's one equation, which takes
/// the whole resultant), and the tie forces `C^T lambda`.
fn subtract_loads(problem: &Problem, forces: &[[f64; 2]], lambda: &[f64], r: &mut [f64]) {
    for (driver, f) in problem.drivers.iter().zip(forces) {
        let share = 1.0 / driver.nodes.len().max(1) as f64;
        for c in (0..2).filter(|&c| driver.force(c).is_some()) {
            for &n in &driver.nodes {
                r[2 * n + c] -= share * f[c];
            }
        }
    }
    let tie_rows = problem.ties.iter().flat_map(|t| &t.rows);
    for (row, &l) in tie_rows.zip(lambda) {
        for &(d, v) in &row.dofs {
            r[d] -= v * l;
        }
    }
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// The residual left once each constrained node's multipliers take up its
/// out-of-balance force in the constrained directions (least squares at the
/// contactor node, the reactions spread to the target as the rows say).
/// Only the node's free components count: on a symmetry plane the prescribed
/// component is a reaction, and a row along a target normal tilted against
/// the plane takes up the free component alone (docs/contact.md item 10).
fn equilibrium_residual(c: &ContactSystem, eq: &[u32], rhs: &[f64]) -> Vec<f64> {
    let mut out = rhs.to_vec();
    let free = |d: usize| (eq[d] != PRESCRIBED).then(|| eq[d] as usize);
    for (node, rows) in &c.groups {
        let comps: Vec<(usize, usize)> = [2 * node, 2 * node + 1]
            .into_iter()
            .filter_map(|d| free(d).map(|q| (d, q)))
            .collect();
        if comps.is_empty() {
            continue;
        }
        let coeff = |row: &contact::Row, d: usize| {
            row.acting()
                .iter()
                .filter(|e| e.0 == d)
                .map(|e| e.1)
                .sum::<f64>()
        };
        let rs = &c.rows[rows.clone()];
        // C_k: the rows' coefficients at the node's free components
        // (components x rows); mu = pinv(C_k) r_k, singular values up to
        // 1e-12 of its largest entry taken as zero.
        let ck =
            nalgebra::DMatrix::from_fn(comps.len(), rs.len(), |i, j| coeff(&rs[j], comps[i].0));
        let rk = nalgebra::DVector::from_iterator(comps.len(), comps.iter().map(|&(_, q)| rhs[q]));
        let scale = ck.abs().max();
        if scale == 0.0 {
            continue;
        }
        let Some(mu) = node_multipliers(&ck, &rk, 1e-12 * scale) else {
            continue;
        };
        for (row, m) in rs.iter().zip(mu.iter()) {
            for &(d, v) in row.acting() {
                if let Some(q) = free(d) {
                    out[q] -= v * m;
                }
            }
        }
    }
    out
}

/// `pinv(C) r` with the singular values of `C` up to `eps` taken as zero:
/// in closed form for one column (a sliding node's row) and for a square
/// pair of rows well above `eps` (a sticking node's), by the SVD otherwise
/// (the closed forms spare a convergence test's residual the 1-2 dynamic
/// SVDs per contact node that took 4 % of the capstan FMU's time).
fn node_multipliers(
    c: &nalgebra::DMatrix<f64>,
    r: &nalgebra::DVector<f64>,
    eps: f64,
) -> Option<nalgebra::DVector<f64>> {
    match c.shape() {
        (_, 1) => {
            // One singular value, |c|.
            let norm2 = c.column(0).norm_squared();
            let sigma = norm2.sqrt();
            let mu = if sigma > eps {
                c.column(0).dot(r) / norm2
            } else {
                0.0
            };
            Some(nalgebra::DVector::from_element(1, mu))
        }
        (2, 2) => {
            let m = nalgebra::Matrix2::new(c[(0, 0)], c[(0, 1)], c[(1, 0)], c[(1, 1)]);
            let det = m.determinant();
            // The singular values' product is |det|, the larger at most the
            // Frobenius norm: the smaller is at least |det| / |C|_F.
            if det.abs() > eps * m.norm() {
                let inv = m.try_inverse()?;
                let mu = inv * nalgebra::Vector2::new(r[0], r[1]);
                Some(nalgebra::DVector::from_column_slice(mu.as_slice()))
            } else {
                c.clone().svd(true, true).solve(r, eps).ok()
            }
        }
        _ => c.clone().svd(true, true).solve(r, eps).ok(),
    }
}

/// An input's value at time t within the step t0 -> t1: linear from its
/// converged value `start` at t0 to the value `target` set for t1.
fn toward(start: f64, target: f64, t: f64, t0: f64, t1: f64) -> f64 {
    if t >= t1 {
        // The step's end: the input itself, not to the last bits.
        return target;
    }
    start + (target - start) * (t - t0) / (t1 - t0)
}

/// Value of each edge pressure at time t as the scene gives it.
fn scene_pressures(problem: &Problem, t: f64) -> Vec<f64> {
    (problem.pressures.iter())
        .map(|p| p.value.at(t, &problem.functions))
        .collect()
}

/// Force [x, y] of each driver's force components at time t as the scene
/// gives them (0 on the other components).
fn scene_forces(problem: &Problem, t: f64) -> Vec<[f64; 2]> {
    (problem.drivers.iter())
        .map(|d| [0, 1].map(|c| d.force(c).map_or(0.0, |s| s.at(t, &problem.functions))))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sliding node on a symmetry plane (x prescribed) against a target
    /// segment whose normal is tilted against the plane: the multiplier
    /// takes up the free component, and a force it can carry leaves no
    /// residual at the node or at the target.
    #[test]
    fn equilibrium_residual_on_a_symmetry_plane() {
        let (nx, ny) = (0.0654f64, 0.9979f64);
        let m = 300.0;
        let c = ContactSystem {
            rows: vec![contact::Row {
                dofs: contact::Entries::from_slice(&[(0, nx), (1, ny), (2, -nx), (3, -ny)]),
                rhs: 0.0,
                column: contact::Entries::default(),
            }],
            groups: vec![(0, 0..1)],
            ..Default::default()
        };
        let eq = [PRESCRIBED, 0, 1, 2];
        // The free entries of C^T m: node y, target x and y.
        let rhs = [ny * m, -nx * m, -ny * m];
        let out = equilibrium_residual(&c, &eq, &rhs);
        assert!(out.iter().all(|v| v.abs() <= 1e-12 * m), "{out:?}");
        // A force the row cannot carry (along the target, at the target
        // node) stays.
        let rhs = [ny * m, -nx * m + 5.0, -ny * m];
        let out = equilibrium_residual(&c, &eq, &rhs);
        assert!(
            (out[1] - 5.0).abs() <= 1e-9 && out[0].abs() <= 1e-9,
            "{out:?}"
        );
    }

    /// A node's multipliers in closed form (one row; two rows of a
    /// sticking node) agree with the SVD's pseudo-inverse to round-off,
    /// and singular cases (a zero column, two parallel rows, below the
    /// cut-off or not) take the SVD's cut-off.
    #[test]
    fn node_multipliers_are_the_pseudo_inverse() {
        use nalgebra::{DMatrix, DVector};
        let cases: Vec<(DMatrix<f64>, DVector<f64>)> = vec![
            (
                DMatrix::from_row_slice(2, 1, &[0.3, -0.95]),
                DVector::from_row_slice(&[2.0, 7.0]),
            ),
            (
                DMatrix::from_row_slice(1, 1, &[-0.4]),
                DVector::from_row_slice(&[3.0]),
            ),
            (
                DMatrix::from_row_slice(2, 1, &[0.0, 0.0]),
                DVector::from_row_slice(&[1.0, 1.0]),
            ),
            (
                DMatrix::from_row_slice(2, 2, &[0.3, -0.95, 0.95, 0.3]),
                DVector::from_row_slice(&[2.0, -7.0]),
            ),
            (
                DMatrix::from_row_slice(2, 2, &[1.0, 0.5, 2.0, 3.0]),
                DVector::from_row_slice(&[0.25, 4.0]),
            ),
            // Parallel rows: rank 1.
            (
                DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 0.5, 1.0]),
                DVector::from_row_slice(&[1.0, -3.0]),
            ),
            // Nearly parallel: the smaller singular value below the cut-off.
            (
                DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 0.5, 1.0 + 1e-14]),
                DVector::from_row_slice(&[1.0, -3.0]),
            ),
            // One component, two rows.
            (
                DMatrix::from_row_slice(1, 2, &[0.6, 0.8]),
                DVector::from_row_slice(&[5.0]),
            ),
        ];
        for (c, r) in cases {
            let eps = 1e-12 * c.abs().max();
            let svd = c.clone().svd(true, true).solve(&r, eps).unwrap();
            let mu = node_multipliers(&c, &r, eps).unwrap();
            let scale = svd.amax().max(1.0);
            assert!(
                (&mu - &svd).amax() <= 1e-14 * scale,
                "C {c} r {r}: {mu} against {svd}"
            );
        }
    }
}
