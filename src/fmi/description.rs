//! `modelDescription.xml` of a scene's FMU (FMI 2.0 co-simulation), and its
//! GUID: a hash of the interface (model identifier, and each variable's
//! name, value reference, type, causality and unit), so it changes when the
//! interface does and not when only a start value does.

use super::variables::{Causality, Start, Type, Variable, base_unit, unit, variables};
use crate::problem::Problem;
use std::collections::BTreeSet;
use std::fmt::Write;

/// The shared library's name inside the FMU; the same for every scene.
pub const MODEL_IDENTIFIER: &str = "contact2d";

/// Logger categories (SPEC section 4).
pub const LOG_CATEGORIES: [(&str, &str); 4] = [
    ("logStatusError", "errors: rejected inputs, failed steps"),
    (
        "logStatusWarning",
        "warnings: bisections, stagnating residuals",
    ),
    (
        "logNewton",
        "Newton iterations: residual norms and convergence rate",
    ),
    (
        "logContact",
        "contact: NEQC, state changes, overlap per iteration",
    ),
];

/// GUID of the FMU of `problem`.
pub fn guid(problem: &Problem) -> String {
    guid_of(&variables(problem), problem)
}

fn guid_of(vars: &[Variable], problem: &Problem) -> String {
    let mut text = format!("{MODEL_IDENTIFIER}\n");
    for v in vars {
        let _ = writeln!(
            text,
            "{} {} {:?} {:?} {}",
            v.name,
            v.vr,
            v.ty,
            v.causality,
            unit_of(v, problem).unwrap_or("-")
        );
    }
    let a = fnv1a64(text.as_bytes(), 0xcbf2_9ce4_8422_2325);
    let b = fnv1a64(text.as_bytes(), 0x6c62_272e_07bb_0142);
    format!(
        "{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}",
        a >> 32,
        (a >> 16) & 0xffff,
        a & 0xffff,
        b >> 48,
        b & 0xffff_ffff_ffff
    )
}

/// FNV-1a, 64 bit, from `seed`.
fn fnv1a64(bytes: &[u8], seed: u64) -> u64 {
    bytes.iter().fold(seed, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

pub(super) fn unit_of(v: &Variable, problem: &Problem) -> Option<&'static str> {
    match v.ty {
        Type::Real => unit(v.quantity, problem.units.length, problem.units.force),
        _ => None,
    }
}

/// XML attribute text.
pub(super) fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if (c as u32) < 0x20 => {
                let _ = write!(out, "&#{};", c as u32);
            }
            c => out.push(c),
        }
    }
    out
}

/// A Real start value written so that it reads back to the same f64.
pub(super) fn real(v: f64) -> String {
    // -0.0 reads as 0.0.
    format!("{:?}", v + 0.0)
}

/// Whether fmi2GetDirectionalDerivative answers for this scene: every
/// contact pair's formulation linearises its converged state (node-to-
/// segment with the nodal decisions; the paper's decisions make the
/// friction a fixed point of recovered resultants, without a derivative).
pub fn provides_directional_derivative(problem: &Problem) -> bool {
    crate::newton::provides_derivatives(problem)
}

/// The whole `modelDescription.xml`.
pub fn model_description(problem: &Problem) -> String {
    let vars = variables(problem);
    let mut x = String::new();
    let _ = writeln!(x, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        x,
        r#"<fmiModelDescription fmiVersion="2.0" modelName="{}" guid="{}" description="{}" generationTool="contact2d {}" variableNamingConvention="structured" numberOfEventIndicators="0">"#,
        escape(&problem.name),
        guid_of(&vars, problem),
        escape(
            "2D finite-element frictional contact (Bathe & Chaudhary 1984): one step is one quasi-static load increment"
        ),
        env!("CARGO_PKG_VERSION"),
    );
    let _ = writeln!(
        x,
        r#"  <CoSimulation modelIdentifier="{MODEL_IDENTIFIER}" needsExecutionTool="false" canHandleVariableCommunicationStepSize="true" canInterpolateInputs="true" maxOutputDerivativeOrder="0" canRunAsynchronuously="false" canBeInstantiatedOnlyOncePerProcess="false" canNotUseMemoryManagementFunctions="true" canGetAndSetFMUstate="true" canSerializeFMUstate="true" providesDirectionalDerivative="{}"/>"#,
        provides_directional_derivative(problem)
    );
    unit_definitions(&mut x, &vars, problem);
    categories_and_experiment(&mut x, problem);
    let _ = writeln!(x, "  <ModelVariables>");
    let mut outputs = Vec::new();
    for (i, v) in vars.iter().enumerate() {
        let (causality, variability) = causality_variability(v);
        if v.causality == Causality::Output {
            outputs.push(i + 1);
        }
        let _ = writeln!(
            x,
            r#"    <ScalarVariable name="{}" valueReference="{}" description="{}" causality="{causality}" variability="{variability}">"#,
            escape(&v.name),
            v.vr,
            escape(&v.description)
        );
        let mut attrs = String::new();
        match &v.start {
            Some(Start::Real(s)) => {
                let _ = write!(attrs, r#" start="{}""#, real(*s));
            }
            Some(Start::Integer(s)) => {
                let _ = write!(attrs, r#" start="{s}""#);
            }
            Some(Start::String(s)) => {
                let _ = write!(attrs, r#" start="{}""#, escape(s));
            }
            None => {}
        }
        if let Some(u) = unit_of(v, problem) {
            let _ = write!(attrs, r#" unit="{}""#, escape(u));
        }
        let element = match v.ty {
            Type::Real => "Real",
            Type::Integer => "Integer",
            Type::String => "String",
        };
        let _ = writeln!(x, "      <{element}{attrs}/>");
        let _ = writeln!(x, "    </ScalarVariable>");
    }
    let _ = writeln!(x, "  </ModelVariables>");
    let _ = writeln!(x, "  <ModelStructure>");
    // No direct feedthrough: an output changes only in fmi2DoStep, never
    // when an input is set, so it depends on no input at the same instant
    // (a master needs no algebraic loop through this FMU). The directional
    // derivatives are of the step's results with respect to the inputs the
    // step reached (docs/fmu.md), not of a feedthrough.
    let _ = writeln!(x, "    <Outputs>");
    for i in &outputs {
        let _ = writeln!(x, r#"      <Unknown index="{i}" dependencies=""/>"#);
    }
    let _ = writeln!(x, "    </Outputs>");
    let _ = writeln!(x, "    <InitialUnknowns>");
    for i in &outputs {
        let _ = writeln!(x, r#"      <Unknown index="{i}"/>"#);
    }
    let _ = writeln!(x, "    </InitialUnknowns>");
    let _ = writeln!(x, "  </ModelStructure>");
    let _ = writeln!(x, "</fmiModelDescription>");
    x
}

/// `<UnitDefinitions>`: every unit the variables use, and seconds; the same
/// element in FMI 2.0 and 3.0.
pub(super) fn unit_definitions(x: &mut String, vars: &[Variable], problem: &Problem) {
    let units: BTreeSet<&str> = vars
        .iter()
        .filter_map(|v| unit_of(v, problem))
        .chain(["s"])
        .collect();
    let _ = writeln!(x, "  <UnitDefinitions>");
    for u in &units {
        let (exp, factor) = base_unit(u);
        let mut attrs = String::new();
        for (name, e) in ["kg", "m", "s", "rad"].iter().zip(exp) {
            if e != 0 {
                let _ = write!(attrs, r#" {name}="{e}""#);
            }
        }
        if factor != 1.0 {
            let _ = write!(attrs, r#" factor="{}""#, real(factor));
        }
        let _ = writeln!(
            x,
            "    <Unit name=\"{}\"><BaseUnit{attrs}/></Unit>",
            escape(u)
        );
    }
    let _ = writeln!(x, "  </UnitDefinitions>");
}

/// `<LogCategories>` and `<DefaultExperiment>` (the scene's own end time
/// and usual increment); the same elements in FMI 2.0 and 3.0.
pub(super) fn categories_and_experiment(x: &mut String, problem: &Problem) {
    let _ = writeln!(x, "  <LogCategories>");
    for (name, what) in LOG_CATEGORIES {
        let _ = writeln!(
            x,
            r#"    <Category name="{name}" description="{}"/>"#,
            escape(what)
        );
    }
    let _ = writeln!(x, "  </LogCategories>");
    let t_end = problem.times.last().copied().unwrap_or(1.0);
    let dt = usual_increment(&problem.times).unwrap_or(t_end);
    let _ = writeln!(
        x,
        r#"  <DefaultExperiment startTime="0.0" stopTime="{}" stepSize="{}"/>"#,
        real(t_end),
        real(dt)
    );
}

/// The increment a load history (increment end times from t = 0) takes
/// most often; on a tie, the one it takes first. Each increment is rounded
/// to 12 significant digits: the times are decimals, and their differences
/// carry the round-off of the operands (1.02 - 1.0 = 0.020000000000000018),
/// which must neither split equal increments nor reach the description.
fn usual_increment(times: &[f64]) -> Option<f64> {
    let mut counts: Vec<(f64, usize)> = Vec::new();
    let mut before = 0.0;
    for &t in times {
        let dt: f64 = format!("{:.11e}", t - before).parse().ok()?;
        before = t;
        match counts.iter_mut().find(|(d, _)| *d == dt) {
            Some((_, n)) => *n += 1,
            None => counts.push((dt, 1)),
        }
    }
    // max_by_key keeps the last of equal counts: search from the end.
    counts.iter().rev().max_by_key(|(_, n)| *n).map(|&(d, _)| d)
}

/// A variable's `causality` and `variability` attributes (the same in FMI
/// 2.0 and 3.0).
pub(super) fn causality_variability(v: &Variable) -> (&'static str, &'static str) {
    match (v.causality, v.ty) {
        (Causality::Parameter, _) if v.tunable() => ("parameter", "tunable"),
        (Causality::Parameter, _) => ("parameter", "fixed"),
        (Causality::Input, _) => ("input", "continuous"),
        (Causality::Output, Type::Real) => ("output", "continuous"),
        (Causality::Output, _) => ("output", "discrete"),
    }
}
