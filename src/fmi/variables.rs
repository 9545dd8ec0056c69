//! The FMU's variables, made from a problem (SPEC section 4): their names,
//! value references, causality, units, and what each one reads or writes.
//! Value references run 1, 2, ... over all types, parameters first, then
//! inputs, then outputs, in scene order: unique across types.

use crate::problem::{Distribution, ForceUnit, LengthUnit, MaterialSpec, Problem};
use crate::results::StepResult;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Type {
    Real,
    Integer,
    String,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Causality {
    Parameter,
    Input,
    Output,
}

/// What a Real variable measures; its unit follows from the scene's units.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    Length,
    Angle,
    Force,
    Moment,
    Stress,
    Speed,
    None,
}

/// A scalar of a contact pair's result.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PairField {
    Fx,
    Fy,
    Fn,
    Ft,
    NStick,
    NSlip,
    NOpen,
    StickLength,
    SlipLength,
}

/// A per-node array of a contact pair's result.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NodeField {
    State,
    Tn,
    Tt,
    X,
    Y,
    Gap,
    Slip,
    /// A node's angle along a strip's wrap (contactors on strips only).
    Angle,
}

/// A running strip's output.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RunningField {
    Fed,
    SpeedIn,
    SpeedOut,
    StrainIn,
    StrainOut,
}

/// Where a variable's value lives.
#[derive(Clone, Debug, PartialEq)]
pub enum Binding {
    /// Prescribed component (0 x, 1 y) of a driver: a displacement
    /// (`<driver>.ux`) or a force (`<driver>.Fx`), as the scene prescribes it.
    DriverInput {
        driver: usize,
        component: usize,
    },
    /// Value of a named edge pressure (`problem.pressures[pressure]`).
    PressureInput {
        pressure: usize,
    },
    /// Pose component (0 ux, 1 uy, 2 theta) of a rigid target.
    RigidInput {
        rigid: usize,
        component: usize,
    },
    /// Mean displacement (0 ux, 1 uy) of a driver's nodes on a component
    /// it prescribes as a force.
    DriverDisplacement {
        driver: usize,
        component: usize,
    },
    /// Reaction (0 Rx, 1 Ry, 2 Mz) of entry `index` of `StepResult::drivers`.
    Reaction {
        index: usize,
        component: usize,
    },
    Pair {
        pair: usize,
        field: PairField,
    },
    Node {
        pair: usize,
        field: NodeField,
        k: usize,
    },
    /// Entry `index` of `StepResult::running`.
    Running {
        index: usize,
        field: RunningField,
    },
    MaterialConstant {
        material: usize,
        name: &'static str,
    },
    Friction {
        pair: usize,
        dynamic: bool,
    },
    /// Entry `index` of the scene's `[parameters]`.
    SceneParameter {
        index: usize,
    },
    Tolerance,
    MaxIterations,
    MaxSubsteps,
    Iterations,
    Substeps,
    Residual,
    OutputDir,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Start {
    Real(f64),
    Integer(i32),
    String(String),
}

#[derive(Clone, Debug, PartialEq)]
pub struct Variable {
    pub name: String,
    pub vr: u32,
    pub ty: Type,
    pub causality: Causality,
    pub quantity: Quantity,
    pub description: String,
    /// Start value: required for parameters and inputs, absent for outputs.
    pub start: Option<Start>,
    pub binding: Binding,
}

impl Variable {
    /// A parameter a master may change between steps (`variability =
    /// "tunable"`): the friction coefficients and the solver settings. The
    /// material constants and the output folder are fixed once the solver
    /// is built.
    pub fn tunable(&self) -> bool {
        self.causality == Causality::Parameter
            && matches!(
                self.binding,
                Binding::Friction { .. }
                    | Binding::Tolerance
                    | Binding::MaxIterations
                    | Binding::MaxSubsteps
            )
    }
}

/// The variables as they are made, each given the next value reference.
struct List(Vec<Variable>);

impl List {
    fn add(
        &mut self,
        name: String,
        ty: Type,
        causality: Causality,
        quantity: Quantity,
        description: String,
        start: Option<Start>,
        binding: Binding,
    ) {
        let vr = self.0.len() as u32 + 1;
        self.0.push(Variable {
            name,
            vr,
            ty,
            causality,
            quantity,
            description,
            start,
            binding,
        });
    }
}

/// The variables of a problem, in value-reference order: parameters,
/// inputs, outputs.
pub fn variables(problem: &Problem) -> Vec<Variable> {
    let mut list = List(Vec::new());
    parameters(&mut list, problem);
    inputs(&mut list, problem);
    outputs(&mut list, problem);
    list.0
}

/// The scene's parameters, the materials' constants, the friction
/// coefficients and the solver's settings.
fn parameters(list: &mut List, problem: &Problem) {
    use Causality::*;
    for (index, p) in problem.parameters.iter().enumerate() {
        list.add(
            p.name.clone(),
            Type::Real,
            Parameter,
            Quantity::None,
            format!(
                "scene parameter '{}' ([parameters]; set before initialisation, it changes every value of the scene that uses it)",
                p.name
            ),
            Some(Start::Real(p.value)),
            Binding::SceneParameter { index },
        );
    }
    for (m, material) in problem.materials.iter().enumerate() {
        for (name, value) in material.constants() {
            let (quantity, what) = match (&material.spec, name) {
                (MaterialSpec::LinearElastic { .. } | MaterialSpec::VonMises { .. }, "E") => {
                    (Quantity::Stress, "Young's modulus")
                }
                (MaterialSpec::VonMises { .. }, "sigma_y") => {
                    (Quantity::Stress, "initial yield stress")
                }
                (MaterialSpec::VonMises { .. }, "H") => {
                    (Quantity::Stress, "linear isotropic hardening modulus")
                }
                (MaterialSpec::MooneyRivlin { .. }, "C1") => {
                    (Quantity::Stress, "Mooney-Rivlin constant C1")
                }
                (MaterialSpec::MooneyRivlin { .. }, "C2") => {
                    (Quantity::Stress, "Mooney-Rivlin constant C2")
                }
                _ => (Quantity::None, "Poisson's ratio"),
            };
            list.add(
                format!("{}.{name}", material.name),
                Type::Real,
                Parameter,
                quantity,
                format!("{what} of material '{}'", material.name),
                Some(Start::Real(value)),
                Binding::MaterialConstant { material: m, name },
            );
        }
    }
    for (p, pair) in problem.contacts.iter().enumerate() {
        for (dynamic, key, value, what) in [
            (false, "mu_s", pair.mu_s, "static"),
            (true, "mu_d", pair.mu_d, "dynamic"),
        ] {
            list.add(
                format!("{}.{key}", pair.name),
                Type::Real,
                Parameter,
                Quantity::None,
                format!(
                    "{what} friction coefficient of contact pair '{}'",
                    pair.name
                ),
                Some(Start::Real(value)),
                Binding::Friction { pair: p, dynamic },
            );
        }
    }
    let s = &problem.solver;
    list.add(
        "solver.tolerance".into(),
        Type::Real,
        Parameter,
        Quantity::None,
        "Newton tolerance on the relative force (and displacement) norm".into(),
        Some(Start::Real(s.force_tolerance)),
        Binding::Tolerance,
    );
    list.add(
        "solver.max_iterations".into(),
        Type::Integer,
        Parameter,
        Quantity::None,
        "Newton iterations allowed per increment".into(),
        Some(Start::Integer(clamp_i32(s.max_iterations))),
        Binding::MaxIterations,
    );
    list.add(
        "solver.max_substeps".into(),
        Type::Integer,
        Parameter,
        Quantity::None,
        "bisections allowed within one step before it is discarded".into(),
        Some(Start::Integer(clamp_i32(s.max_bisections))),
        Binding::MaxSubsteps,
    );
    list.add(
        "output_dir".into(),
        Type::String,
        Parameter,
        Quantity::None,
        "folder for one VTK file per step; empty: none".into(),
        Some(Start::String(String::new())),
        Binding::OutputDir,
    );
}

/// The prescribed components at the end of the step, named pressures and
/// the rigid targets' motion.
fn inputs(list: &mut List, problem: &Problem) {
    use Causality::*;
    let f = &problem.functions;
    for (d, driver) in problem.drivers.iter().enumerate() {
        for component in 0..2 {
            let (key, what, quantity, value) = match (
                driver.displacement(component),
                driver.force(component),
            ) {
                (Some(v), _) => (
                    ["ux", "uy"][component],
                    "prescribed displacement",
                    Quantity::Length,
                    v,
                ),
                (None, Some(v)) => (
                    ["Fx", "Fy"][component],
                    match driver.distribution {
                        Distribution::Equal => {
                            "prescribed force (the set's resultant, shared equally by its nodes)"
                        }
                        Distribution::Rigid => {
                            "prescribed force (the set's resultant; the set moves as one)"
                        }
                    },
                    Quantity::Force,
                    v,
                ),
                (None, None) => continue,
            };
            list.add(
                format!("{}.{key}", driver.name),
                Type::Real,
                Input,
                quantity,
                format!("{what} {key} of driver '{}'", driver.name),
                Some(Start::Real(value.at(0.0, f))),
                Binding::DriverInput {
                    driver: d,
                    component,
                },
            );
        }
    }
    for (i, pressure) in problem.pressures.iter().enumerate() {
        let Some(name) = &pressure.name else { continue };
        list.add(
            format!("{name}.p"),
            Type::Real,
            Input,
            Quantity::Stress,
            format!("edge pressure '{name}' (positive pushes into the body)"),
            Some(Start::Real(pressure.value.at(0.0, f))),
            Binding::PressureInput { pressure: i },
        );
    }
    for (r, rigid) in problem.rigids.iter().enumerate() {
        for (component, (key, value, quantity)) in [
            ("ux", &rigid.ux, Quantity::Length),
            ("uy", &rigid.uy, Quantity::Length),
            ("theta", &rigid.theta, Quantity::Angle),
        ]
        .into_iter()
        .enumerate()
        {
            list.add(
                format!("{}.{key}", rigid.name),
                Type::Real,
                Input,
                quantity,
                format!("rigid-body motion {key} of rigid target '{}'", rigid.name),
                Some(Start::Real(value.at(0.0, f))),
                Binding::RigidInput {
                    rigid: r,
                    component,
                },
            );
        }
    }
}

/// Reactions (drivers, then rigid targets, as in StepResult), the drivers'
/// displacements and the contact pairs' results.
fn outputs(list: &mut List, problem: &Problem) {
    use Causality::*;
    let reacting = problem
        .drivers
        .iter()
        .map(|d| (d.name.as_str(), false))
        .chain(problem.rigids.iter().map(|r| (r.name.as_str(), true)));
    for (index, (name, rigid)) in reacting.enumerate() {
        let n = if rigid { 3 } else { 2 };
        for (component, key) in ["Rx", "Ry", "Mz"].into_iter().enumerate().take(n) {
            let quantity = if component == 2 {
                Quantity::Moment
            } else {
                Quantity::Force
            };
            list.add(
                format!("{name}.{key}"),
                Type::Real,
                Output,
                quantity,
                format!("{key} exerted by '{name}' on the body to impose its motion"),
                None,
                Binding::Reaction { index, component },
            );
        }
    }
    for (d, driver) in problem.drivers.iter().enumerate() {
        for component in (0..2).filter(|&c| driver.force(c).is_some()) {
            let key = ["ux", "uy"][component];
            list.add(
                format!("{}.{key}", driver.name),
                Type::Real,
                Output,
                Quantity::Length,
                match driver.distribution {
                    Distribution::Equal => format!(
                        "mean displacement {key} of the nodes of driver '{}' under its force",
                        driver.name
                    ),
                    Distribution::Rigid => format!(
                        "displacement {key} of the set of driver '{}', which moves as one under its force",
                        driver.name
                    ),
                },
                None,
                Binding::DriverDisplacement {
                    driver: d,
                    component,
                },
            );
        }
    }
    pair_outputs(list, problem);
    running_outputs(list, problem);
    list.add(
        "solver.iterations".into(),
        Type::Integer,
        Output,
        Quantity::None,
        "Newton iterations of the last step (all its substeps)".into(),
        None,
        Binding::Iterations,
    );
    list.add(
        "solver.substeps".into(),
        Type::Integer,
        Output,
        Quantity::None,
        "bisections used in the last step".into(),
        None,
        Binding::Substeps,
    );
    list.add(
        "solver.residual".into(),
        Type::Real,
        Output,
        Quantity::None,
        "final relative force residual of the last step".into(),
        None,
        Binding::Residual,
    );
}

/// Each contact pair's resultants, state counts, zone lengths and per-node
/// results.
/// Per pair: its resultant and count outputs (`<pair>.<key>`), by field,
/// key, type, quantity and meaning.
const PAIR_OUTPUTS: [(PairField, &str, Type, Quantity, &str); 9] = [
    (
        PairField::Fx,
        "Fx",
        Type::Real,
        Quantity::Force,
        "resultant contact force on the contactor, x",
    ),
    (
        PairField::Fy,
        "Fy",
        Type::Real,
        Quantity::Force,
        "resultant contact force on the contactor, y",
    ),
    (
        PairField::Fn,
        "Fn",
        Type::Real,
        Quantity::Force,
        "sum of the segment normal resultants T_n",
    ),
    (
        PairField::Ft,
        "Ft",
        Type::Real,
        Quantity::Force,
        "sum of the segment tangential resultants T_t",
    ),
    (
        PairField::NStick,
        "n_stick",
        Type::Integer,
        Quantity::None,
        "number of sticking contactor nodes",
    ),
    (
        PairField::NSlip,
        "n_slip",
        Type::Integer,
        Quantity::None,
        "number of sliding contactor nodes",
    ),
    (
        PairField::NOpen,
        "n_open",
        Type::Integer,
        Quantity::None,
        "number of open contactor nodes",
    ),
    (
        PairField::StickLength,
        "stick_length",
        Type::Real,
        Quantity::Length,
        "length of the contactor surface that sticks (current configuration)",
    ),
    (
        PairField::SlipLength,
        "slip_length",
        Type::Real,
        Quantity::Length,
        "length of the contactor surface that slides (current configuration)",
    ),
];

/// Per contactor node: its outputs (`<pair>.<key>[k]`), likewise.
const NODE_OUTPUTS: [(NodeField, &str, Type, Quantity, &str); 7] = [
    (
        NodeField::State,
        "state",
        Type::Integer,
        Quantity::None,
        "state: 0 open, 1 stick, 2 slip",
    ),
    (
        NodeField::Tn,
        "tn",
        Type::Real,
        Quantity::Stress,
        "normal traction (compression positive)",
    ),
    (
        NodeField::Tt,
        "tt",
        Type::Real,
        Quantity::Stress,
        "tangential traction",
    ),
    (NodeField::X, "x", Type::Real, Quantity::Length, "current x"),
    (NodeField::Y, "y", Type::Real, Quantity::Length, "current y"),
    (
        NodeField::Gap,
        "gap",
        Type::Real,
        Quantity::Length,
        "normal gap to the target (positive clear of it, negative into it; 0 in contact)",
    ),
    (
        NodeField::Slip,
        "slip",
        Type::Real,
        Quantity::Length,
        "slip over the last step relative to the target, along the contactor (tt's direction; friction opposes it); 0 unless in contact at both ends of the step",
    ),
];

/// Per contactor node on a strip: its place along the wrap.
const NODE_ANGLE: (NodeField, &str, Type, Quantity, &str) = (
    NodeField::Angle,
    "angle",
    Type::Real,
    Quantity::Angle,
    "angle along the strip's wrap from the take-up side's tangent point (0 where the strip leaves the drum, the wrap angle where it meets it; beyond, the free spans' lengths at the mid-line's radius)",
);

/// Per running strip: its outputs (`<body>.<key>`).
const RUNNING_OUTPUTS: [(RunningField, &str, Quantity, &str); 5] = [
    (
        RunningField::Fed,
        "fed",
        Quantity::Length,
        "reference length of strip that has run in at the supply end",
    ),
    (
        RunningField::SpeedIn,
        "speed_in",
        Quantity::Speed,
        "material speed along the path at the supply end over the last step",
    ),
    (
        RunningField::SpeedOut,
        "speed_out",
        Quantity::Speed,
        "material speed along the path at the take-up end over the last step",
    ),
    (
        RunningField::StrainIn,
        "strain_in",
        Quantity::None,
        "strain of the mid-line at the supply end",
    ),
    (
        RunningField::StrainOut,
        "strain_out",
        Quantity::None,
        "strain of the mid-line at the take-up end",
    ),
];

fn running_outputs(list: &mut List, problem: &Problem) {
    let running = problem.bodies.iter().filter(|b| b.running);
    for (index, body) in running.enumerate() {
        for (field, key, quantity, what) in RUNNING_OUTPUTS {
            list.add(
                format!("{}.{key}", body.name),
                Type::Real,
                Causality::Output,
                quantity,
                format!("{what} (running strip '{}')", body.name),
                None,
                Binding::Running { index, field },
            );
        }
    }
}

fn pair_outputs(list: &mut List, problem: &Problem) {
    use Causality::*;
    for (p, pair) in problem.contacts.iter().enumerate() {
        for (field, key, ty, quantity, what) in PAIR_OUTPUTS {
            list.add(
                format!("{}.{key}", pair.name),
                ty,
                Output,
                quantity,
                format!("{what} (pair '{}')", pair.name),
                None,
                Binding::Pair { pair: p, field },
            );
        }
        let on_strip = problem.contactor_strip(pair).is_some();
        let angle = on_strip.then_some(NODE_ANGLE);
        for (field, key, ty, quantity, what) in NODE_OUTPUTS.into_iter().chain(angle) {
            for k in 0..pair.contactor.len() {
                list.add(
                    format!("{}.{key}[{}]", pair.name, k + 1),
                    ty,
                    Output,
                    quantity,
                    format!("contactor node {} of pair '{}': {what}", k + 1, pair.name),
                    None,
                    Binding::Node { pair: p, field, k },
                );
            }
        }
    }
}

fn clamp_i32(v: usize) -> i32 {
    i32::try_from(v).unwrap_or(i32::MAX)
}

/// The unit of a quantity in the scene's units (None: dimensionless).
pub fn unit(quantity: Quantity, length: LengthUnit, force: ForceUnit) -> Option<&'static str> {
    use ForceUnit::*;
    use LengthUnit::*;
    Some(match (quantity, length, force) {
        (Quantity::None, _, _) => return None,
        (Quantity::Angle, _, _) => "rad",
        (Quantity::Length, Metre, _) => "m",
        (Quantity::Length, Millimetre, _) => "mm",
        (Quantity::Speed, Metre, _) => "m/s",
        (Quantity::Speed, Millimetre, _) => "mm/s",
        (Quantity::Force, _, Newton) => "N",
        (Quantity::Force, _, Kilonewton) => "kN",
        (Quantity::Moment, Metre, Newton) => "N.m",
        (Quantity::Moment, Millimetre, Newton) => "N.mm",
        (Quantity::Moment, Metre, Kilonewton) => "kN.m",
        (Quantity::Moment, Millimetre, Kilonewton) => "kN.mm",
        (Quantity::Stress, Metre, Newton) => "Pa",
        (Quantity::Stress, Millimetre, Newton) => "MPa",
        (Quantity::Stress, Metre, Kilonewton) => "kPa",
        (Quantity::Stress, Millimetre, Kilonewton) => "GPa",
    })
}

/// SI base-unit exponents [kg, m, s, rad] and factor of a unit.
pub fn base_unit(unit: &str) -> ([i32; 4], f64) {
    match unit {
        "m" => ([0, 1, 0, 0], 1.0),
        "mm" => ([0, 1, 0, 0], 1e-3),
        "m/s" => ([0, 1, -1, 0], 1.0),
        "mm/s" => ([0, 1, -1, 0], 1e-3),
        "rad" => ([0, 0, 0, 1], 1.0),
        "s" => ([0, 0, 1, 0], 1.0),
        "N" => ([1, 1, -2, 0], 1.0),
        "kN" => ([1, 1, -2, 0], 1e3),
        "N.m" => ([1, 2, -2, 0], 1.0),
        "N.mm" => ([1, 2, -2, 0], 1e-3),
        "kN.m" => ([1, 2, -2, 0], 1e3),
        "kN.mm" => ([1, 2, -2, 0], 1.0),
        "Pa" => ([1, -1, -2, 0], 1.0),
        "kPa" => ([1, -1, -2, 0], 1e3),
        "MPa" => ([1, -1, -2, 0], 1e6),
        "GPa" => ([1, -1, -2, 0], 1e9),
        _ => ([0; 4], 1.0),
    }
}

/// The value an input takes at scene time `t` along the scene's own load
/// history (what a master feeds the FMU to replay the scene); `None` for a
/// binding that is not an input.
pub fn input(binding: &Binding, problem: &Problem, t: f64) -> Option<f64> {
    let f = &problem.functions;
    match *binding {
        Binding::DriverInput { driver, component } => {
            let d = &problem.drivers[driver];
            (d.displacement(component).or(d.force(component))).map(|c| c.at(t, f))
        }
        Binding::RigidInput { rigid, component } => {
            let r = &problem.rigids[rigid];
            Some([&r.ux, &r.uy, &r.theta][component].at(t, f))
        }
        Binding::PressureInput { pressure } => Some(problem.pressures[pressure].value.at(t, f)),
        _ => None,
    }
}

/// Value of an output variable in a step result (Real and Integer outputs;
/// None for a binding that is not an output).
pub fn output(binding: &Binding, result: &StepResult) -> Option<f64> {
    Some(match *binding {
        Binding::DriverDisplacement { driver, component } => {
            let r = &result.drivers.get(driver)?.1;
            [r.ux, r.uy][component]?
        }
        Binding::Reaction { index, component } => {
            let r = &result.drivers.get(index)?.1;
            match component {
                0 => r.rx,
                1 => r.ry,
                _ => r.mz.unwrap_or(0.0),
            }
        }
        Binding::Pair { pair, field } => {
            let p = &result.pairs.get(pair)?.1;
            match field {
                PairField::Fx => p.fx,
                PairField::Fy => p.fy,
                PairField::Fn => p.fn_,
                PairField::Ft => p.ft,
                PairField::NStick => p.n_stick as f64,
                PairField::NSlip => p.n_slip as f64,
                PairField::NOpen => p.n_open as f64,
                PairField::StickLength => p.stick_length,
                PairField::SlipLength => p.slip_length,
            }
        }
        Binding::Node { pair, field, k } => {
            let n = &result.pairs.get(pair)?.1.nodes;
            match field {
                NodeField::State => i32::from(*n.state.get(k)?) as f64,
                NodeField::Tn => *n.tn.get(k)?,
                NodeField::Tt => *n.tt.get(k)?,
                NodeField::X => *n.x.get(k)?,
                NodeField::Y => *n.y.get(k)?,
                NodeField::Gap => *n.gap.get(k)?,
                NodeField::Slip => *n.slip.get(k)?,
                NodeField::Angle => *n.angle.get(k)?,
            }
        }
        Binding::Running { index, field } => {
            let r = &result.running.get(index)?.1;
            match field {
                RunningField::Fed => r.fed,
                RunningField::SpeedIn => r.speed_in,
                RunningField::SpeedOut => r.speed_out,
                RunningField::StrainIn => r.strain_in,
                RunningField::StrainOut => r.strain_out,
            }
        }
        Binding::Iterations => result.iterations as f64,
        Binding::Substeps => result.substeps as f64,
        Binding::Residual => result.residual,
        _ => return None,
    })
}
