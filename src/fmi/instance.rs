//! One FMU instance: the FMI 2.0 co-simulation state machine over a solver,
//! in plain Rust (`ffi` maps the C calls onto it). It holds no physics: it
//! maps variables onto the problem, the solver's inputs and the last step's
//! results, and calls the solver.

use super::description::{LOG_CATEGORIES, guid};
use super::variables::{
    Binding, Causality, NodeField, PairField, Start, Type, Variable, output, variables,
};
use crate::newton::{Input, Response, SolveError, Solver, rest_step};
use crate::problem::{
    Problem, SolverSettings, check_coefficient, check_modulus, check_poisson, check_range,
};
use crate::results::{LogCategory, StepResult};
use crate::state::State;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// The FMI status an instance call ends with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    Ok,
    Warning,
    Discard,
    Error,
}

/// Where the instance is in the FMI 2.0 co-simulation state machine.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Mode {
    Instantiated,
    Initialization,
    StepComplete,
    Terminated,
    /// An internal failure (a caught panic): only reset, a saved state,
    /// getters and free are accepted.
    Error,
}

/// The logger: (status, category, message).
pub type LogFn = Box<dyn FnMut(Status, &str, &str) + Send>;

/// A saved FMU state: everything a step depends on, so that a restored
/// state continues bit for bit as the original did.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Snapshot {
    guid: String,
    /// Values of every variable that is not an output, by variable index
    /// (parameters, to check against the instance's; inputs, to restore).
    reals: Vec<f64>,
    ints: Vec<i32>,
    /// The instance's `stepped`.
    #[serde(default)]
    stepped: Vec<f64>,
    output_dir: String,
    state: State,
    last: StepResult,
    steps: usize,
}

const SNAPSHOT_MAGIC: &[u8] = b"contact2d FMU state 1\n";

pub struct Instance {
    name: String,
    guid: String,
    /// The problem as the scene gives it (reset returns to it).
    base: Problem,
    /// The scene file, read again when its `[parameters]` are set.
    scene: PathBuf,
    vars: Vec<Variable>,
    by_vr: HashMap<u32, usize>,
    /// Current value of each Real / Integer variable that is not an output,
    /// by variable index (unused entries stay 0).
    reals: Vec<f64>,
    ints: Vec<i32>,
    /// `reals` as the last step (or initialisation) left them: the inputs
    /// the converged state was solved for.
    stepped: Vec<f64>,
    /// First time derivative of each Real input for the next step
    /// (`fmi2SetRealInputDerivatives`), by variable index; zero after each
    /// step.
    derivatives: Vec<f64>,
    output_dir: String,
    /// The VTK series written into `output_dir` so far (its `.pvd`).
    vtk: Option<crate::output::VtkSeries>,
    start_time: f64,
    solver: Option<Solver>,
    /// Outputs of the last converged step (at rest before the first).
    last: StepResult,
    /// Steps taken (names the VTK files).
    steps: usize,
    mode: Mode,
    logging_on: bool,
    /// Enabled categories, in `LOG_CATEGORIES` order.
    categories: [bool; 4],
    log: LogFn,
}

impl Instance {
    /// Reads the scene and checks the GUID the master expects against the
    /// one this scene's interface has.
    pub fn new(
        name: &str,
        scene: &Path,
        expected_guid: &str,
        logging_on: bool,
        log: LogFn,
    ) -> Result<Instance, String> {
        let problem = crate::scene::load(scene).map_err(|e| e.to_string())?;
        let guid = guid(&problem);
        if guid != expected_guid {
            return Err(format!(
                "GUID {expected_guid} does not match the scene's interface {guid} ({}): the FMU's resources and modelDescription.xml disagree",
                scene.display()
            ));
        }
        let vars = variables(&problem);
        let by_vr = vars.iter().enumerate().map(|(i, v)| (v.vr, i)).collect();
        let n = vars.len();
        let last = rest_step(&problem);
        let mut instance = Instance {
            name: name.to_string(),
            guid,
            base: problem,
            scene: scene.to_path_buf(),
            vars,
            by_vr,
            reals: vec![0.0; n],
            ints: vec![0; n],
            stepped: vec![0.0; n],
            derivatives: vec![0.0; n],
            output_dir: String::new(),
            vtk: None,
            start_time: 0.0,
            solver: None,
            last,
            steps: 0,
            mode: Mode::Instantiated,
            logging_on,
            categories: [true; 4],
            log,
        };
        instance.load_starts();
        for w in instance.base.warnings.clone() {
            instance.log(LogCategory::Warning, &w);
        }
        Ok(instance)
    }

    /// Start values of the parameters and inputs.
    fn load_starts(&mut self) {
        self.derivatives.fill(0.0);
        for (i, v) in self.vars.iter().enumerate() {
            match &v.start {
                Some(Start::Real(x)) => self.reals[i] = *x,
                Some(Start::Integer(x)) => self.ints[i] = *x,
                Some(Start::String(s)) => self.output_dir = s.clone(),
                None => {}
            }
        }
    }

    /// The FMU's variables, in value-reference order.
    pub fn variables(&self) -> &[Variable] {
        &self.vars
    }

    pub fn mode(&self) -> Mode {
        self.mode
    }

    pub fn guid(&self) -> &str {
        &self.guid
    }

    /// Logs a message; errors and warnings always reach the logger, Newton
    /// and contact lines only when logging is on for their category.
    pub fn log(&mut self, category: LogCategory, msg: &str) {
        emit(
            &mut self.log,
            self.logging_on,
            &self.categories,
            category,
            msg,
        );
    }

    /// Puts `log` in place of the instance's logger; the one it had.
    pub fn replace_logger(&mut self, log: LogFn) -> LogFn {
        std::mem::replace(&mut self.log, log)
    }

    fn error(&mut self, msg: impl AsRef<str>) -> Status {
        self.log(LogCategory::Error, msg.as_ref());
        Status::Error
    }

    /// Refuses a call made in a mode that does not allow it.
    fn require(&mut self, call: &str, allowed: &[Mode]) -> Result<(), Status> {
        if allowed.contains(&self.mode) {
            Ok(())
        } else {
            Err(self.error(format!(
                "{call} is not allowed in mode {:?} (allowed: {allowed:?})",
                self.mode
            )))
        }
    }

    pub fn set_debug_logging(&mut self, on: bool, categories: &[String]) -> Status {
        if categories.is_empty() {
            self.categories = [on; 4];
        } else {
            // Listed categories on: only those; listed off: those off.
            let mut set = if on { [false; 4] } else { self.categories };
            for c in categories {
                match LOG_CATEGORIES.iter().position(|(n, _)| n == c) {
                    Some(i) => set[i] = on,
                    None => {
                        return self.error(format!(
                            "fmi2SetDebugLogging: unknown log category '{c}' (known: logStatusError, logStatusWarning, logNewton, logContact)"
                        ));
                    }
                }
            }
            self.categories = set;
        }
        self.logging_on = on || self.categories.iter().any(|&c| c);
        Status::Ok
    }

    pub fn setup_experiment(&mut self, start_time: f64) -> Status {
        if let Err(s) = self.require("fmi2SetupExperiment", &[Mode::Instantiated]) {
            return s;
        }
        if !start_time.is_finite() {
            return self.error(format!(
                "fmi2SetupExperiment: startTime = {start_time} is not finite"
            ));
        }
        self.start_time = start_time;
        Status::Ok
    }

    pub fn enter_initialization(&mut self) -> Status {
        if let Err(s) = self.require("fmi2EnterInitializationMode", &[Mode::Instantiated]) {
            return s;
        }
        self.mode = Mode::Initialization;
        Status::Ok
    }

    /// Applies the parameters, checks them together, and builds the solver.
    pub fn exit_initialization(&mut self) -> Status {
        if let Err(s) = self.require("fmi2ExitInitializationMode", &[Mode::Initialization]) {
            return s;
        }
        let problem = match self.configured_problem() {
            Ok(p) => p,
            Err(msg) => return self.error(format!("fmi2ExitInitializationMode: {msg}")),
        };
        if problem.parameters != self.base.parameters {
            // The scene read with other parameter values: the parameters and
            // inputs the master left at their start values take the values
            // this scene gives them (an input's load, a material constant
            // written as an expression).
            for (i, v) in variables(&problem).into_iter().enumerate() {
                match (&self.vars[i].start, v.start) {
                    (Some(Start::Real(old)), Some(Start::Real(new)))
                        if self.reals[i].to_bits() == old.to_bits() =>
                    {
                        self.reals[i] = new;
                    }
                    (Some(Start::Integer(old)), Some(Start::Integer(new)))
                        if self.ints[i] == *old =>
                    {
                        self.ints[i] = new;
                    }
                    _ => {}
                }
            }
        }
        let mut solver = match Solver::new(problem) {
            Ok(s) => s,
            Err(e) => return self.error(format!("fmi2ExitInitializationMode: {e}")),
        };
        let mut state = solver.state().clone();
        state.time = self.start_time;
        solver.restore(state);
        self.last = solver.rest_step();
        self.solver = Some(solver);
        self.stepped.clone_from(&self.reals);
        self.mode = Mode::StepComplete;
        Status::Ok
    }

    /// The scene's problem with the parameter values set on this instance:
    /// the scene read again if any of its `[parameters]` was set (the
    /// interface must stay the one exported), then each parameter set away
    /// from its start value applied.
    fn configured_problem(&self) -> Result<Problem, String> {
        let changed = |i: usize| match self.vars[i].start {
            Some(Start::Real(x)) => self.reals[i].to_bits() != x.to_bits(),
            Some(Start::Integer(x)) => self.ints[i] != x,
            _ => false,
        };
        let overrides: Vec<(String, f64)> = (0..self.vars.len())
            .filter(|&i| {
                matches!(self.vars[i].binding, Binding::SceneParameter { .. }) && changed(i)
            })
            .map(|i| (self.vars[i].name.clone(), self.reals[i]))
            .collect();
        let mut p = if overrides.is_empty() {
            self.base.clone()
        } else if let Some(solver) = &self.solver {
            // Initialised: the scene parameters are fixed, the solver's
            // problem was read with them.
            solver.problem().clone()
        } else {
            let p = crate::scene::load_with(&self.scene, &overrides).map_err(|e| e.to_string())?;
            if guid(&p) != self.guid {
                let set: Vec<String> = overrides
                    .iter()
                    .map(|(n, v)| format!("{n} = {v}"))
                    .collect();
                return Err(format!(
                    "the scene parameters {} change the FMU's interface (the number of contactor nodes, \
                     drivers or variables it was exported with): export the scene again with these values",
                    set.join(", ")
                ));
            }
            p
        };
        for (i, v) in self.vars.iter().enumerate().filter(|&(i, _)| changed(i)) {
            match v.binding {
                Binding::MaterialConstant { material, name } => {
                    p.materials[material].set_constant(name, self.reals[i])?;
                }
                Binding::Friction { pair, dynamic } => {
                    let c = &mut p.contacts[pair];
                    if dynamic {
                        c.mu_d = self.reals[i];
                    } else {
                        c.mu_s = self.reals[i];
                    }
                }
                Binding::Tolerance => {
                    p.solver.force_tolerance = self.reals[i];
                    p.solver.displacement_tolerance = self.reals[i];
                }
                Binding::MaxIterations => p.solver.max_iterations = self.ints[i].max(0) as usize,
                Binding::MaxSubsteps => p.solver.max_bisections = self.ints[i].max(0) as usize,
                _ => {}
            }
        }
        p.check_parameters()?;
        Ok(p)
    }

    pub fn terminate(&mut self) -> Status {
        if let Err(s) = self.require("fmi2Terminate", &[Mode::StepComplete, Mode::Error]) {
            return s;
        }
        self.mode = Mode::Terminated;
        Status::Ok
    }

    /// Back to the state right after instantiation: start values, no solver.
    pub fn reset(&mut self) -> Status {
        self.solver = None;
        self.vtk = None;
        self.steps = 0;
        self.start_time = 0.0;
        self.load_starts();
        self.last = rest_step(&self.base);
        self.mode = Mode::Instantiated;
        Status::Ok
    }

    /// Looks a value reference up and checks its type.
    fn variable(&mut self, call: &str, vr: u32, ty: Type) -> Result<usize, Status> {
        match self.by_vr.get(&vr) {
            Some(&i) if self.vars[i].ty == ty => Ok(i),
            Some(&i) => {
                let v = &self.vars[i];
                let msg = format!(
                    "{call}: variable '{}' (valueReference {vr}) is {:?}, not {ty:?}",
                    v.name, v.ty
                );
                Err(self.error(msg))
            }
            None => Err(self.error(format!("{call}: no variable has valueReference {vr}"))),
        }
    }

    /// May variable `i` be set now? Parameters before the solver is built,
    /// tunable ones also between steps, inputs until the instance
    /// terminates, outputs never.
    fn settable(&mut self, call: &str, i: usize) -> Result<(), Status> {
        let v = &self.vars[i];
        let ok = match v.causality {
            Causality::Parameter if v.tunable() && self.mode == Mode::StepComplete => true,
            Causality::Parameter => matches!(self.mode, Mode::Instantiated | Mode::Initialization),
            Causality::Input => matches!(
                self.mode,
                Mode::Instantiated | Mode::Initialization | Mode::StepComplete
            ),
            Causality::Output => false,
        };
        if ok {
            Ok(())
        } else {
            let msg = format!(
                "{call}: '{}' ({:?}) cannot be set in mode {:?}",
                v.name, v.causality, self.mode
            );
            Err(self.error(msg))
        }
    }

    /// Checks all values first: a rejected call changes nothing.
    pub fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Status {
        let mut checked = Vec::with_capacity(vrs.len());
        for (&vr, &value) in vrs.iter().zip(values) {
            let i = match self.variable("fmi2SetReal", vr, Type::Real) {
                Ok(i) => i,
                Err(s) => return s,
            };
            if let Err(s) = self.settable("fmi2SetReal", i) {
                return s;
            }
            if let Err(msg) = self.check_real(i, value) {
                let name = self.vars[i].name.clone();
                return self.error(format!("fmi2SetReal: {name} = {value:?} rejected: {msg}"));
            }
            checked.push((i, value));
        }
        let before = self
            .tunes(checked.iter().map(|c| c.0))
            .then(|| self.reals.clone());
        for (i, value) in checked {
            self.reals[i] = value;
        }
        match before {
            Some(before) => self.retune("fmi2SetReal", |me| me.reals = before),
            None => Status::Ok,
        }
    }

    /// Does a call setting variables `set` change a tunable parameter of a
    /// built solver? Only then is the problem checked again (`retune`): an
    /// input set every step costs no more than storing it.
    fn tunes(&self, mut set: impl Iterator<Item = usize>) -> bool {
        self.mode == Mode::StepComplete && set.any(|i| self.vars[i].tunable())
    }

    /// `fmi2SetRealInputDerivatives`: first derivatives (order 1) of Real
    /// inputs, for the next step only. Checks all first: a rejected call
    /// changes nothing.
    pub fn set_real_input_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Status {
        const CALL: &str = "fmi2SetRealInputDerivatives";
        let mut checked = Vec::with_capacity(vrs.len());
        for ((&vr, &order), &value) in vrs.iter().zip(orders).zip(values) {
            let i = match self.variable(CALL, vr, Type::Real) {
                Ok(i) => i,
                Err(s) => return s,
            };
            let name = self.vars[i].name.clone();
            if self.vars[i].causality != Causality::Input {
                return self.error(format!("{CALL}: '{name}' is not an input"));
            }
            if let Err(s) = self.settable(CALL, i) {
                return s;
            }
            if order != 1 {
                return self.error(format!(
                    "{CALL}: {name} order {order} rejected: only first derivatives (order 1) are taken"
                ));
            }
            if !value.is_finite() {
                return self.error(format!(
                    "{CALL}: {name} derivative {value:?} rejected: not a finite number"
                ));
            }
            checked.push((i, value));
        }
        for (i, value) in checked {
            self.derivatives[i] = value;
        }
        Status::Ok
    }

    /// After tunable parameters were set between steps: checks them
    /// together (mu_d <= mu_s) and hands them to the solver for the steps
    /// to come, or undoes the call (`undo`) and refuses it.
    fn retune(&mut self, call: &str, undo: impl FnOnce(&mut Self)) -> Status {
        match self.configured_problem() {
            Ok(p) => {
                if let Some(solver) = self.solver.as_mut() {
                    solver.set_tunables(&p);
                }
                Status::Ok
            }
            Err(msg) => {
                undo(self);
                self.error(format!("{call}: rejected, the parameters kept: {msg}"))
            }
        }
    }

    /// Range check of one Real value.
    fn check_real(&self, i: usize, value: f64) -> Result<(), String> {
        if !value.is_finite() {
            return Err("not a finite number".into());
        }
        match self.vars[i].binding {
            Binding::MaterialConstant { name: "E", .. } => check_modulus(value),
            Binding::MaterialConstant { name: "nu", .. } => {
                check_poisson(self.base.analysis, value)
            }
            Binding::Friction { .. } => check_coefficient(value),
            Binding::Tolerance => check_range(value, &SolverSettings::RELATIVE_TOLERANCE),
            _ => Ok(()),
        }
    }

    pub fn set_integer(&mut self, vrs: &[u32], values: &[i32]) -> Status {
        let mut checked = Vec::with_capacity(vrs.len());
        for (&vr, &value) in vrs.iter().zip(values) {
            let i = match self.variable("fmi2SetInteger", vr, Type::Integer) {
                Ok(i) => i,
                Err(s) => return s,
            };
            if let Err(s) = self.settable("fmi2SetInteger", i) {
                return s;
            }
            let range = match self.vars[i].binding {
                Binding::MaxIterations => Some(SolverSettings::MAX_ITERATIONS),
                Binding::MaxSubsteps => Some(SolverSettings::MAX_BISECTIONS),
                _ => None,
            };
            // A negative count is outside every range (usize::MAX).
            let count = usize::try_from(value).unwrap_or(usize::MAX);
            if let Some(Err(msg)) = range.map(|r| check_range(count, &r)) {
                let name = self.vars[i].name.clone();
                return self.error(format!("fmi2SetInteger: {name} = {value} rejected: {msg}"));
            }
            checked.push((i, value));
        }
        let before = self
            .tunes(checked.iter().map(|c| c.0))
            .then(|| self.ints.clone());
        for (i, value) in checked {
            self.ints[i] = value;
        }
        match before {
            Some(before) => self.retune("fmi2SetInteger", |me| me.ints = before),
            None => Status::Ok,
        }
    }

    pub fn set_string(&mut self, vrs: &[u32], values: &[String]) -> Status {
        for (&vr, value) in vrs.iter().zip(values) {
            let i = match self.variable("fmi2SetString", vr, Type::String) {
                Ok(i) => i,
                Err(s) => return s,
            };
            if let Err(s) = self.settable("fmi2SetString", i) {
                return s;
            }
            self.output_dir = value.clone();
        }
        Status::Ok
    }

    /// Value of variable `i` as f64 (Real and Integer variables).
    fn value(&self, i: usize) -> f64 {
        let v = &self.vars[i];
        match v.causality {
            Causality::Output => output(&v.binding, &self.last).unwrap_or(0.0),
            _ if v.ty == Type::Integer => f64::from(self.ints[i]),
            _ => self.reals[i],
        }
    }

    pub fn get_real(&mut self, vrs: &[u32], out: &mut [f64]) -> Status {
        for (&vr, o) in vrs.iter().zip(out.iter_mut()) {
            match self.variable("fmi2GetReal", vr, Type::Real) {
                Ok(i) => *o = self.value(i),
                Err(s) => return s,
            }
        }
        Status::Ok
    }

    pub fn get_integer(&mut self, vrs: &[u32], out: &mut [i32]) -> Status {
        for (&vr, o) in vrs.iter().zip(out.iter_mut()) {
            match self.variable("fmi2GetInteger", vr, Type::Integer) {
                // Integer outputs are counts and states, exact in f64.
                Ok(i) => *o = self.value(i) as i32,
                Err(s) => return s,
            }
        }
        Status::Ok
    }

    pub fn get_string(&mut self, vrs: &[u32]) -> Result<Vec<String>, Status> {
        let mut out = Vec::with_capacity(vrs.len());
        for &vr in vrs {
            self.variable("fmi2GetString", vr, Type::String)?;
            out.push(self.output_dir.clone());
        }
        Ok(out)
    }

    /// `fmi2GetDirectionalDerivative`: `out = (d unknown / d known) seed`
    /// at the current state, the unknowns being Real outputs (reactions,
    /// force drivers' displacements, pair resultants) and the knowns the
    /// Real inputs. The derivative is that of the outputs of the step that
    /// reached the state with respect to the input values the step reached
    /// (docs/fmu.md). From fmi2ExitInitializationMode on: the state is
    /// the solver's.
    pub fn directional_derivative(
        &mut self,
        unknown: &[u32],
        known: &[u32],
        seed: &[f64],
        out: &mut [f64],
    ) -> Status {
        const CALL: &str = "fmi2GetDirectionalDerivative";
        if let Err(s) = self.require(CALL, &[Mode::StepComplete, Mode::Terminated]) {
            return s;
        }
        let mut seeds = Vec::with_capacity(known.len());
        for (&vr, &dv) in known.iter().zip(seed) {
            let Some(&i) = self.by_vr.get(&vr) else {
                return self.error(format!(
                    "{CALL}: vKnown_ref: no variable has valueReference {vr}"
                ));
            };
            let v = &self.vars[i];
            let input = match v.binding {
                Binding::DriverInput { driver, component } => Input::Driver { driver, component },
                Binding::PressureInput { pressure } => Input::Pressure { pressure },
                Binding::RigidInput { rigid, component } => Input::Rigid { rigid, component },
                _ => {
                    let msg = format!(
                        "{CALL}: vKnown_ref: '{}' (valueReference {vr}) is not an input; the knowns are the continuous Real inputs",
                        v.name
                    );
                    return self.error(msg);
                }
            };
            if !dv.is_finite() {
                let msg = format!(
                    "{CALL}: dvKnown of '{}' (valueReference {vr}) is {dv}, not a finite number",
                    v.name
                );
                return self.error(msg);
            }
            seeds.push((input, dv));
        }
        let mut responses = Vec::with_capacity(unknown.len());
        for &vr in unknown {
            let Some(&i) = self.by_vr.get(&vr) else {
                return self.error(format!(
                    "{CALL}: vUnknown_ref: no variable has valueReference {vr}"
                ));
            };
            let v = &self.vars[i];
            let why = match v.binding {
                Binding::Reaction { index, component } => {
                    responses.push(Response::Reaction { index, component });
                    continue;
                }
                Binding::DriverDisplacement { driver, component } => {
                    responses.push(Response::DriverDisplacement { driver, component });
                    continue;
                }
                Binding::Pair { pair, field } => match field {
                    PairField::Fx | PairField::Fy | PairField::Fn | PairField::Ft => {
                        let component =
                            [PairField::Fx, PairField::Fy, PairField::Fn, PairField::Ft]
                                .iter()
                                .position(|&f| f == field)
                                .unwrap_or(0);
                        responses.push(Response::Pair { pair, component });
                        continue;
                    }
                    PairField::NStick | PairField::NSlip | PairField::NOpen => {
                        "a node count (Integer) changes only in steps"
                    }
                    PairField::StickLength | PairField::SlipLength => {
                        "the length of a stick or slip zone jumps when a node changes state"
                    }
                },
                Binding::Node {
                    field: NodeField::State,
                    ..
                } => "a node state (Integer) is discrete",
                Binding::Node { .. } => {
                    "per-node outputs have none; the reactions, the force drivers' displacements and the pair resultants Fx, Fy, Fn, Ft do"
                }
                Binding::Iterations | Binding::Substeps | Binding::Residual => {
                    "it describes the solver's work, not the physics"
                }
                _ => "it is not an output; the unknowns are outputs",
            };
            let msg = format!(
                "{CALL}: vUnknown_ref: '{}' (valueReference {vr}) has no directional derivative: {why}",
                v.name
            );
            return self.error(msg);
        }
        let Some(solver) = self.solver.as_mut() else {
            return self.error(format!("{CALL}: no solver (internal)"));
        };
        match solver.sensitivity(&seeds, &responses) {
            Ok(values) => {
                out.copy_from_slice(&values);
                Status::Ok
            }
            Err(msg) => self.error(format!("{CALL}: {msg}")),
        }
    }

    /// Time of the last converged step.
    pub fn last_successful_time(&self) -> f64 {
        self.solver
            .as_ref()
            .map_or(self.start_time, |s| s.state().time)
    }

    /// Where the solver's time went since initialization (the benchmarks'
    /// split; None before `exit_initialization`).
    pub fn phases(&self) -> Option<crate::newton::Phases> {
        self.solver.as_ref().map(|s| s.phases())
    }

    /// One quasi-static increment from t to t + h with the inputs' current
    /// values as the prescribed values at t + h, or, for an input given a
    /// derivative, its value plus h times the derivative (then the input
    /// holds that value). A step that does not converge within
    /// `solver.max_substeps` bisections, or whose inputs make an output
    /// non-finite, returns Discard and leaves the state (and the inputs and
    /// their derivatives) at t.
    pub fn do_step(&mut self, t: f64, h: f64) -> Status {
        if let Err(s) = self.require("fmi2DoStep", &[Mode::StepComplete]) {
            return s;
        }
        let now = self.last_successful_time();
        let end = match self.step_end(t, h, now) {
            Ok(end) => end,
            Err(answer) => return answer,
        };
        let targets = match self.input_targets(h, now, end) {
            Ok(targets) => targets,
            Err(answer) => return answer,
        };
        let Some(solver) = self.solver.as_mut() else {
            return self.error("fmi2DoStep: no solver (internal)");
        };
        let before = solver.state().clone();
        for (binding, value) in targets {
            match binding {
                Binding::DriverInput { driver, component } => {
                    solver.set_input(driver, component, Some(value))
                }
                Binding::RigidInput { rigid, component } => {
                    solver.set_rigid_input(rigid, component, Some(value))
                }
                Binding::PressureInput { pressure } => {
                    solver.set_pressure_input(pressure, Some(value))
                }
                _ => {}
            }
        }
        let (log, on, cats) = (&mut self.log, self.logging_on, &self.categories);
        // To the master's t + h: the FMU's clock follows the master's.
        match solver.advance(end, &mut |cat, msg| emit(log, on, cats, cat, msg)) {
            Ok(step) => self.commit(step, before, h, now),
            Err(SolveError::NotConverged { time, reason }) => self.discard(&format!(
                "step to t = {time:?} discarded, the state stays at t = {now:?}: {reason}"
            )),
            Err(e) => self.error(format!("fmi2DoStep: {e}")),
        }
    }

    /// The end of a step from `t` by `h` with the FMU at `now`, or the
    /// call's answer without a solve (a held step is Ok; a step that cannot
    /// be taken is a logged error).
    fn step_end(&mut self, t: f64, h: f64, now: f64) -> Result<f64, Status> {
        if !(t.is_finite() && h.is_finite() && h > 0.0) {
            return Err(self.error(format!(
                "fmi2DoStep: currentCommunicationPoint = {t:?}, communicationStepSize = {h:?}: both must be finite and the step size positive"
            )));
        }
        // The master's clock and the FMU's agree to a few units in the last
        // place (a master may sum its steps or multiply them out; the FMU's
        // clock follows the master's): not to a fraction of t, which at
        // t = 1e9 let a clock off by a whole second through, nor of h.
        if (t - now).abs() > 16.0 * ulp(now.abs().max(t.abs())) {
            return Err(self.error(format!(
                "fmi2DoStep: currentCommunicationPoint = {t:?}, but the FMU is at t = {now:?} (restore a saved state to go back)"
            )));
        }
        let end = t + h;
        if !end.is_finite() {
            return Err(self.error(format!(
                "fmi2DoStep: currentCommunicationPoint + communicationStepSize = {t:?} + {h:?} overflows"
            )));
        }
        if end > now {
            return Ok(end);
        }
        // h is below the resolution of t: time cannot advance. With the
        // inputs as they are, there is nothing to do; a change of the
        // inputs needs a step that time can resolve.
        if self.changed_inputs().is_empty() {
            // A held step: no iteration, no slip.
            self.last.iterations = 0;
            self.last.substeps = 0;
            for (_, pair) in &mut self.last.pairs {
                pair.nodes.slip.fill(0.0);
            }
            return Err(Status::Ok);
        }
        Err(self.error(format!(
            "fmi2DoStep: t + h = {t:?} + {h:?} rounds to t (the resolution of t is {:?}): time cannot advance, and the inputs changed; take a larger step",
            ulp(t)
        )))
    }

    /// The inputs changed since the last step (a new value or a
    /// derivative), by variable index.
    fn changed_inputs(&self) -> Vec<usize> {
        (0..self.vars.len())
            .filter(|&i| {
                self.vars[i].causality == Causality::Input
                    && (self.derivatives[i] != 0.0
                        || self.reals[i].to_bits() != self.stepped[i].to_bits())
            })
            .collect()
    }

    /// The value each input reaches at the end of a step of size `h`; a
    /// derivative that takes one beyond the range of f64 discards the step.
    fn input_targets(&mut self, h: f64, now: f64, end: f64) -> Result<Vec<(Binding, f64)>, Status> {
        let mut targets = Vec::new();
        for (i, v) in self.vars.iter().enumerate() {
            if v.causality != Causality::Input {
                continue;
            }
            let value = self.reals[i] + h * self.derivatives[i];
            if !value.is_finite() {
                let msg = format!(
                    "step to t = {end:?} discarded, the state stays at t = {now:?}: input {} = {:?} with derivative {:?} reaches {value:?} at the step's end, not a finite number",
                    v.name, self.reals[i], self.derivatives[i]
                );
                return Err(self.discard(&msg));
            }
            targets.push((v.binding.clone(), value));
        }
        Ok(targets)
    }

    /// A converged step: its outputs become the instance's when every one
    /// is finite; otherwise the state goes back to `before` and the step is
    /// discarded, naming the inputs that changed.
    fn commit(&mut self, step: StepResult, before: State, h: f64, now: f64) -> Status {
        let bad = self.vars.iter().find_map(|v| {
            let x = (v.causality == Causality::Output).then(|| output(&v.binding, &step))??;
            (!x.is_finite()).then(|| format!("{} = {x:?}", v.name))
        });
        if let Some(bad) = bad {
            if let Some(solver) = self.solver.as_mut() {
                solver.restore(before);
            }
            let inputs: Vec<String> = (self.changed_inputs().into_iter())
                .map(|i| {
                    let (v, d) = (self.reals[i], self.derivatives[i]);
                    match d {
                        0.0 => format!("{} = {v:?}", self.vars[i].name),
                        _ => format!("{} = {v:?} + h * {d:?}", self.vars[i].name),
                    }
                })
                .collect();
            let inputs = match inputs.is_empty() {
                true => "no input changed".to_string(),
                false => format!("the inputs set: {}", inputs.join(", ")),
            };
            return self.discard(&format!(
                "step to t = {:?} discarded, the state stays at t = {now:?}: output {bad} is not finite; {inputs}",
                step.time
            ));
        }
        self.last = step;
        self.steps += 1;
        for i in 0..self.vars.len() {
            self.reals[i] += h * self.derivatives[i];
        }
        self.derivatives.fill(0.0);
        self.stepped.clone_from(&self.reals);
        self.write_vtk()
    }

    /// Logs why a step was discarded; the state stays where it was.
    fn discard(&mut self, why: &str) -> Status {
        self.log(LogCategory::Error, &format!("fmi2DoStep: {why}"));
        Status::Discard
    }

    /// The VTK series into `output_dir`, when it is set: per step the solid,
    /// each pair's contactor surface with its contact values and each rigid
    /// target (`output::VtkSeries`, as the command line's `--vtk`), named
    /// after the instance, and the `.pvd` of the steps written so far.
    fn write_vtk(&mut self) -> Status {
        if self.output_dir.is_empty() {
            return Status::Ok;
        }
        let Some(solver) = &self.solver else {
            return Status::Ok;
        };
        let dir = PathBuf::from(&self.output_dir);
        let stem: String = self
            .name
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '-' {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        let series = self
            .vtk
            .get_or_insert_with(|| crate::output::VtkSeries::new(&dir, &stem));
        let stress = solver.element_stresses();
        let plastic = solver.element_plastic_strains();
        let frame = crate::output::Frame {
            time: self.last.time,
            u: &solver.state().u,
            stress: &stress,
            plastic_strain: plastic.as_deref(),
            pairs: &self.last.pairs,
            rigid_poses: &solver.state().rigid,
        };
        // After a restored state the steps from there on are written again.
        series.forget_from(frame.time);
        let written = std::fs::create_dir_all(&dir)
            .and_then(|()| series.write_frame(self.steps, solver.problem(), &frame))
            .and_then(|()| series.write_pvd().map(|_| ()));
        match written {
            Ok(()) => Status::Ok,
            Err(e) => {
                let msg = format!(
                    "output_dir: cannot write step {} into {}: {e} (the step itself converged)",
                    self.steps,
                    dir.display()
                );
                self.log(LogCategory::Warning, &msg);
                Status::Warning
            }
        }
    }

    pub fn get_state(&mut self) -> Result<Snapshot, Status> {
        let Some(solver) = &self.solver else {
            return Err(
                self.error("fmi2GetFMUstate: the state exists from fmi2ExitInitializationMode on")
            );
        };
        Ok(Snapshot {
            guid: self.guid.clone(),
            reals: self.reals.clone(),
            ints: self.ints.clone(),
            stepped: self.stepped.clone(),
            output_dir: self.output_dir.clone(),
            state: solver.state().clone(),
            last: self.last.clone(),
            steps: self.steps,
        })
    }

    /// Restores a state saved from an instance of the same FMU with the
    /// same fixed parameters (the tunable ones come back with the state);
    /// accepted after a failed step or an internal error.
    pub fn set_state(&mut self, snap: &Snapshot) -> Status {
        if let Err(s) = self.require(
            "fmi2SetFMUstate",
            &[Mode::StepComplete, Mode::Terminated, Mode::Error],
        ) {
            return s;
        }
        if snap.guid != self.guid {
            return self.error(format!(
                "fmi2SetFMUstate: the state belongs to an FMU with GUID {}, this one is {}",
                snap.guid, self.guid
            ));
        }
        // The mesh the solver has (scene parameters may have changed it).
        let nodes = (self.solver.as_ref())
            .map_or(&self.base, |s| s.problem())
            .mesh
            .nodes
            .len();
        if snap.reals.len() != self.reals.len() || snap.state.u.len() != nodes * 2 {
            return self.error("fmi2SetFMUstate: the state does not fit this FMU's variables");
        }
        // The fixed parameters must agree; the tunable ones are part of the
        // state and are restored with it.
        for (i, v) in self.vars.iter().enumerate() {
            if v.causality != Causality::Parameter || v.tunable() {
                continue;
            }
            let differs = match v.ty {
                Type::Real => snap.reals[i].to_bits() != self.reals[i].to_bits(),
                Type::Integer => snap.ints[i] != self.ints[i],
                Type::String => false,
            };
            if differs {
                let msg = format!(
                    "fmi2SetFMUstate: the state was saved with {} = {}, this instance has {}",
                    v.name,
                    if v.ty == Type::Real {
                        snap.reals[i]
                    } else {
                        f64::from(snap.ints[i])
                    },
                    if v.ty == Type::Real {
                        self.reals[i]
                    } else {
                        f64::from(self.ints[i])
                    },
                );
                return self.error(msg);
            }
        }
        let Some(solver) = self.solver.as_mut() else {
            return self.error("fmi2SetFMUstate: no solver (internal)");
        };
        if let Err(e) = snap.state.fits(solver.state(), solver.problem()) {
            return self.error(format!(
                "fmi2SetFMUstate: the state does not fit this instance's model ({e}); the instance keeps its own"
            ));
        }
        solver.restore(snap.state.clone());
        self.reals.clone_from(&snap.reals);
        self.ints.clone_from(&snap.ints);
        if snap.stepped.len() == snap.reals.len() {
            self.stepped.clone_from(&snap.stepped);
        } else {
            self.stepped.clone_from(&snap.reals);
        }
        self.derivatives.fill(0.0);
        self.output_dir.clone_from(&snap.output_dir);
        self.last = snap.last.clone();
        self.steps = snap.steps;
        self.mode = Mode::StepComplete;
        // Saved by this FMU, so its tunables passed the checks then.
        self.retune("fmi2SetFMUstate", |_| {})
    }

    /// Marks the instance failed after a caught panic.
    pub fn fail(&mut self, msg: &str) {
        self.mode = Mode::Error;
        self.log(LogCategory::Error, msg);
    }
}

/// The spacing of f64 at |x| (toward zero at the largest finite value):
/// finite for every finite x, so the clock check holds at any time.
fn ulp(x: f64) -> f64 {
    let a = x.abs();
    if a == f64::MAX {
        a - a.next_down()
    } else {
        a.next_up() - a
    }
}

fn emit(
    log: &mut LogFn,
    logging_on: bool,
    categories: &[bool; 4],
    category: LogCategory,
    msg: &str,
) {
    let (status, index) = match category {
        LogCategory::Error => (Status::Error, 0),
        LogCategory::Warning => (Status::Warning, 1),
        LogCategory::Newton => (Status::Ok, 2),
        LogCategory::Contact => (Status::Ok, 3),
    };
    let always = index < 2;
    if always || (logging_on && categories[index]) {
        log(status, category.fmi_name(), msg);
    }
}

impl Snapshot {
    pub fn guid(&self) -> &str {
        &self.guid
    }

    /// Bytes for fmi2SerializeFMUstate: a header line, then JSON whose
    /// numbers read back to the same f64 bits.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = SNAPSHOT_MAGIC.to_vec();
        // Serializing plain data with finite floats cannot fail.
        out.extend(serde_json::to_vec(self).unwrap_or_default());
        out
    }

    pub fn from_bytes(bytes: &[u8]) -> Result<Snapshot, String> {
        let body = bytes
            .strip_prefix(SNAPSHOT_MAGIC)
            .ok_or("fmi2DeSerializeFMUstate: the bytes are not a contact2d FMU state")?;
        serde_json::from_slice(body)
            .map_err(|e| format!("fmi2DeSerializeFMUstate: the state is damaged: {e}"))
    }
}
