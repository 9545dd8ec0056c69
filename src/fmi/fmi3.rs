//! The FMI 3.0 co-simulation face of the same FMU (`contact2d export --fmi
//! 3`): its variables and `modelDescription.xml`. The instance and the
//! solver are the FMI 2.0 ones; only the variables are grouped: a pair's
//! per-node outputs (`<pair>.tn[k]`, k = 1..n, in FMI 2.0) are one array
//! variable `<pair>.tn` of n elements, and the independent variable `time`
//! (value reference 0) is declared, as FMI 3.0 requires. Every other
//! variable keeps its FMI 2.0 name and value reference, so a master's
//! connections carry over.

use super::description::{
    MODEL_IDENTIFIER, categories_and_experiment, causality_variability, escape, guid,
    provides_directional_derivative, real, unit_definitions, unit_of,
};
use super::variables::{Binding, Causality, Start, Type, Variable, variables};
use crate::problem::Problem;
use std::fmt::Write;

/// Value reference of the independent variable `time`.
pub const TIME_VR: u32 = 0;

/// One FMI 3.0 variable: a scalar (one FMI 2.0 variable) or an array (the
/// FMI 2.0 variables of its elements, in order).
#[derive(Clone, Debug, PartialEq)]
pub struct Variable3 {
    pub name: String,
    pub vr: u32,
    /// The FMI 2.0 variables it stands for (indices into `variables()`);
    /// empty for `time`.
    pub members: Vec<usize>,
    /// Array length; None for a scalar.
    pub dimension: Option<usize>,
}

/// The FMI 3.0 variables of a problem: `time`, then the FMI 2.0 variables
/// in their order with each pair's per-node outputs grouped into arrays.
/// An array takes the value reference of its first element.
pub fn variables3(vars: &[Variable]) -> Vec<Variable3> {
    let mut out = vec![Variable3 {
        name: "time".into(),
        vr: TIME_VR,
        members: Vec::new(),
        dimension: None,
    }];
    let mut i = 0;
    while i < vars.len() {
        match vars[i].binding {
            Binding::Node { pair, field, k: 0 } => {
                let mut j = i + 1;
                while j < vars.len()
                    && matches!(vars[j].binding, Binding::Node { pair: p, field: f, .. } if p == pair && f == field)
                {
                    j += 1;
                }
                let name = vars[i].name.split('[').next().unwrap_or(&vars[i].name);
                out.push(Variable3 {
                    name: name.to_string(),
                    vr: vars[i].vr,
                    members: (i..j).collect(),
                    dimension: Some(j - i),
                });
                i = j;
            }
            _ => {
                out.push(Variable3 {
                    name: vars[i].name.clone(),
                    vr: vars[i].vr,
                    members: vec![i],
                    dimension: None,
                });
                i += 1;
            }
        }
    }
    out
}

/// The FMI 3.0 `modelDescription.xml`; its instantiation token is the FMI
/// 2.0 GUID (a hash of the same interface).
pub fn model_description3(problem: &Problem) -> String {
    let vars = variables(problem);
    let list = variables3(&vars);
    let mut x = String::new();
    let _ = writeln!(x, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        x,
        r#"<fmiModelDescription fmiVersion="3.0" modelName="{}" instantiationToken="{}" description="{}" generationTool="contact2d {}" variableNamingConvention="structured">"#,
        escape(&problem.name),
        guid(problem),
        escape(
            "2D finite-element frictional contact (Bathe & Chaudhary 1984): one step is one quasi-static load increment"
        ),
        env!("CARGO_PKG_VERSION"),
    );
    let _ = writeln!(
        x,
        r#"  <CoSimulation modelIdentifier="{MODEL_IDENTIFIER}" needsExecutionTool="false" canBeInstantiatedOnlyOncePerProcess="false" canGetAndSetFMUState="true" canSerializeFMUState="true" providesDirectionalDerivatives="{}" canHandleVariableCommunicationStepSize="true" maxOutputDerivativeOrder="0" providesIntermediateUpdate="false" mightReturnEarlyFromDoStep="false" canReturnEarlyAfterIntermediateUpdate="false" hasEventMode="false"/>"#,
        provides_directional_derivative(problem)
    );
    unit_definitions(&mut x, &vars, problem);
    categories_and_experiment(&mut x, problem);
    let _ = writeln!(x, "  <ModelVariables>");
    let _ = writeln!(
        x,
        r#"    <Float64 name="time" valueReference="{TIME_VR}" description="simulation time: the end of the last converged step" causality="independent" variability="continuous" unit="s"/>"#
    );
    let mut outputs = Vec::new();
    for v3 in list.iter().skip(1) {
        let v = &vars[v3.members[0]];
        let (causality, variability) = causality_variability(v);
        if v.causality == Causality::Output {
            outputs.push(v3.vr);
        }
        let element = match v.ty {
            Type::Real => "Float64",
            Type::Integer => "Int32",
            Type::String => "String",
        };
        let description = match v3.dimension {
            // "contactor node 1 of pair 'wrap': ..." -> "per contactor node
            // of pair 'wrap': ...".
            Some(_) => v
                .description
                .replacen("contactor node 1 of", "per contactor node of", 1),
            None => v.description.clone(),
        };
        let mut attrs = format!(
            r#" name="{}" valueReference="{}" description="{}" causality="{causality}" variability="{variability}""#,
            escape(&v3.name),
            v3.vr,
            escape(&description)
        );
        match &v.start {
            Some(Start::Real(s)) => {
                let _ = write!(attrs, r#" start="{}""#, real(*s));
            }
            Some(Start::Integer(s)) => {
                let _ = write!(attrs, r#" start="{s}""#);
            }
            _ => {}
        }
        if let Some(u) = unit_of(v, problem) {
            let _ = write!(attrs, r#" unit="{}""#, escape(u));
        }
        let mut children = String::new();
        if let Some(n) = v3.dimension {
            let _ = write!(children, r#"<Dimension start="{n}"/>"#);
        }
        if let Some(Start::String(s)) = &v.start {
            let _ = write!(children, r#"<Start value="{}"/>"#, escape(s));
        }
        if children.is_empty() {
            let _ = writeln!(x, "    <{element}{attrs}/>");
        } else {
            let _ = writeln!(x, "    <{element}{attrs}>{children}</{element}>");
        }
    }
    let _ = writeln!(x, "  </ModelVariables>");
    // As in FMI 2.0: no direct feedthrough (docs/fmu.md).
    let _ = writeln!(x, "  <ModelStructure>");
    for vr in &outputs {
        let _ = writeln!(x, r#"    <Output valueReference="{vr}" dependencies=""/>"#);
    }
    for vr in &outputs {
        let _ = writeln!(x, r#"    <InitialUnknown valueReference="{vr}"/>"#);
    }
    let _ = writeln!(x, "  </ModelStructure>");
    let _ = writeln!(x, "</fmiModelDescription>");
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The capstan's per-node outputs become arrays of its 65 contactor
    /// nodes; every FMI 2.0 variable appears exactly once; value references
    /// are unique and `time` is 0.
    #[test]
    fn per_node_outputs_are_arrays() {
        let scene =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/capstan_drum_frame.toml");
        let problem = crate::scene::load(&scene).unwrap();
        let vars = variables(&problem);
        let list = variables3(&vars);
        assert_eq!((list[0].name.as_str(), list[0].vr), ("time", TIME_VR));
        let gap = list.iter().find(|v| v.name == "wrap.gap").unwrap();
        assert_eq!(gap.dimension, Some(65));
        assert_eq!(vars[gap.members[64]].name, "wrap.gap[65]");
        let mut seen: Vec<usize> = list.iter().flat_map(|v| v.members.clone()).collect();
        seen.sort_unstable();
        assert_eq!(seen, (0..vars.len()).collect::<Vec<_>>());
        let mut vrs: Vec<u32> = list.iter().map(|v| v.vr).collect();
        vrs.sort_unstable();
        vrs.dedup();
        assert_eq!(vrs.len(), list.len());
        assert!(
            list.iter()
                .any(|v| v.name == "back.Fy" && v.dimension.is_none())
        );
    }
}
