//! The scene file as serde sees it: every table denies unknown keys, and every
//! value that is validated later keeps its span so errors can name its line.
//! Tables whose keys depend on a tag (`model`, `generator`) are read in two
//! passes from the parsed document: a head with the tag, then the variant.

use crate::mesh::ElementKind;
use serde::Deserialize;
use serde::de::{self, IgnoredAny, MapAccess, SeqAccess, Visitor, value::MapAccessDeserializer};
use std::fmt;
use std::marker::PhantomData;
use toml::Spanned;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Scene {
    pub title: Option<String>,
    pub analysis: Spanned<Analysis>,
    /// Read per entry by `MaterialHead` and the model's own table.
    pub material: Spanned<Vec<IgnoredAny>>,
    pub body: Spanned<Vec<Spanned<Body>>>,
    #[serde(default)]
    pub node_set: Vec<Spanned<NodeSet>>,
    #[serde(default)]
    pub function: Vec<Spanned<Function>>,
    #[serde(default)]
    pub driver: Vec<Spanned<Driver>>,
    #[serde(default)]
    pub rigid: Vec<Spanned<Rigid>>,
    #[serde(default)]
    pub contact: Vec<Contact>,
    #[serde(default)]
    pub tie: Vec<Tie>,
    #[serde(default)]
    pub pressure: Vec<Pressure>,
    #[serde(default)]
    pub force: Vec<Spanned<Force>>,
    #[serde(default)]
    pub body_force: Vec<BodyForce>,
    #[serde(default)]
    pub initial_stress: Vec<InitialStress>,
    pub steps: Spanned<Steps>,
    pub solver: Option<Solver>,
    pub units: Option<Units>,
    /// Read before the rest (`params`): named numbers for expressions.
    #[allow(dead_code)]
    pub parameters: Option<IgnoredAny>,
}

/// The units the scene's numbers are in (declared in the FMU).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Units {
    pub length: Option<crate::problem::LengthUnit>,
    pub force: Option<crate::problem::ForceUnit>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Analysis {
    pub kind: Spanned<AnalysisName>,
    pub thickness: Option<Spanned<f64>>,
    pub kinematics: Option<Spanned<KinematicsName>>,
}

#[derive(Deserialize, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub(super) enum AnalysisName {
    PlaneStrain,
    PlaneStress,
    Axisymmetric,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
pub(super) enum KinematicsName {
    SmallStrain,
    Mno,
    TotalLagrangian,
}

/// The keys every material has; the model's own keys are read by its table.
#[derive(Deserialize)]
pub(super) struct MaterialHead {
    pub name: Spanned<String>,
    pub model: Spanned<ModelName>,
}

/// Adding a material model: one arm here, one table below, one match arm in
/// `Resolver::materials`.
#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
pub(super) enum ModelName {
    LinearElastic,
    MooneyRivlin,
    VonMises,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct LinearElastic {
    #[serde(rename = "name")]
    _name: IgnoredAny,
    #[serde(rename = "model")]
    _model: IgnoredAny,
    #[serde(rename = "E")]
    pub e: Spanned<f64>,
    pub nu: Spanned<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MooneyRivlin {
    #[serde(rename = "name")]
    _name: IgnoredAny,
    #[serde(rename = "model")]
    _model: IgnoredAny,
    #[serde(rename = "C1")]
    pub c1: Spanned<f64>,
    #[serde(rename = "C2")]
    pub c2: Spanned<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct VonMises {
    #[serde(rename = "name")]
    _name: IgnoredAny,
    #[serde(rename = "model")]
    _model: IgnoredAny,
    #[serde(rename = "E")]
    pub e: Spanned<f64>,
    pub nu: Spanned<f64>,
    pub sigma_y: Spanned<f64>,
    #[serde(rename = "H")]
    pub h: Spanned<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Body {
    pub name: Spanned<String>,
    pub material: Spanned<String>,
    pub element: Option<Spanned<ElementKind>>,
    /// Read by `MeshHead` and the generator's own table.
    pub mesh: Spanned<IgnoredAny>,
    /// Material runs through the body (a `strip` mesh only).
    pub running: Option<Spanned<bool>>,
}

/// The tag of a body's mesh table: a generator, or a file.
#[derive(Deserialize)]
pub(super) struct MeshHead {
    pub generator: Option<Spanned<GeneratorName>>,
    pub file: Option<Spanned<String>>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
pub(super) enum GeneratorName {
    Rectangle,
    Disk,
    Ring,
    PlateWithHole,
    Strip,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Rectangle {
    #[serde(rename = "generator")]
    _generator: IgnoredAny,
    pub origin: Pair<f64>,
    pub size: Spanned<Pair<f64>>,
    pub divisions: Spanned<Pair<usize>>,
    pub ratio: Option<Spanned<Pair<f64>>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Disk {
    #[serde(rename = "generator")]
    _generator: IgnoredAny,
    pub center: Pair<f64>,
    pub radius: Spanned<f64>,
    pub divisions: Spanned<usize>,
    pub ratio: Option<Spanned<f64>>,
    pub half: Option<bool>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Ring {
    #[serde(rename = "generator")]
    _generator: IgnoredAny,
    pub center: Pair<f64>,
    pub r_inner: Spanned<f64>,
    pub r_outer: Spanned<f64>,
    pub angles: Spanned<Pair<f64>>,
    pub divisions: Spanned<Pair<usize>>,
    pub ratio: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Strip {
    #[serde(rename = "generator")]
    _generator: IgnoredAny,
    pub center: Pair<f64>,
    pub radius: Spanned<f64>,
    pub thickness: Spanned<f64>,
    pub angles: Spanned<Pair<f64>>,
    pub spans: Spanned<Pair<usize>>,
    pub divisions: Spanned<Pair<usize>>,
    pub strain: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PlateWithHole {
    #[serde(rename = "generator")]
    _generator: IgnoredAny,
    pub hole_radius: Spanned<f64>,
    pub width: Spanned<f64>,
    pub y_range: Spanned<Pair<f64>>,
    pub divisions: Spanned<Pair<usize>>,
    pub ratio: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MeshFile {
    pub file: Spanned<String>,
    pub group: Option<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Function {
    pub name: Spanned<String>,
    pub points: Spanned<Vec<Spanned<Pair<f64>>>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Driver {
    pub name: Spanned<String>,
    pub set: Spanned<String>,
    pub ux: Option<ValueSpec>,
    pub uy: Option<ValueSpec>,
    pub fx: Option<ValueSpec>,
    pub fy: Option<ValueSpec>,
    pub distribution: Option<Spanned<DistributionName>>,
}

/// How a force driver's resultant acts on its set.
#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
pub(super) enum DistributionName {
    Equal,
    Rigid,
}

/// A rigid target: a polyline given by its points, or an arc.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Rigid {
    pub name: Spanned<String>,
    pub points: Option<Spanned<Vec<Spanned<Pair<f64>>>>>,
    pub arc: Option<Spanned<Arc>>,
    pub reference: Option<Pair<f64>>,
    pub ux: Option<ValueSpec>,
    pub uy: Option<ValueSpec>,
    pub theta: Option<ValueSpec>,
}

/// A rigid arc: `segments` chords from `angles[0]` to `angles[1]` (degrees).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Arc {
    pub center: Pair<f64>,
    pub radius: Spanned<f64>,
    pub angles: Spanned<Pair<f64>>,
    pub segments: Spanned<usize>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Contact {
    pub name: Spanned<String>,
    pub contactor: Spanned<String>,
    pub target: Spanned<String>,
    pub mu_s: Option<Spanned<f64>>,
    pub mu_d: Option<Spanned<f64>>,
    pub rule: Option<RuleName>,
    pub recovery: Option<RecoveryName>,
    pub decisions: Option<DecisionsName>,
    pub formulation: Option<Spanned<FormulationName>>,
    pub smooth_target: Option<Spanned<bool>>,
}

#[derive(Deserialize, Clone, Copy, PartialEq)]
#[serde(rename_all = "snake_case")]
pub(super) enum FormulationName {
    NodeToSegment,
    Mortar,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
pub(super) enum DecisionsName {
    Nodal,
    Paper,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Tie {
    pub name: Spanned<String>,
    pub nodes: Spanned<String>,
    pub to: Spanned<String>,
    pub kind: TieKindName,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
pub(super) enum TieKindName {
    Normal,
    Full,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
pub(super) enum RuleName {
    MuDAfterSlip,
    AlwaysMuS,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
pub(super) enum RecoveryName {
    Consistent,
    Lumped,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Pressure {
    pub name: Option<Spanned<String>>,
    pub set: Spanned<String>,
    pub value: ValueSpec,
    pub follower: Option<bool>,
}

/// A node set picked by location: the node nearest a point, or every node
/// inside a box.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct NodeSet {
    pub name: Spanned<String>,
    pub nearest: Option<Spanned<Pair<f64>>>,
    #[serde(rename = "box")]
    pub bounds: Option<Spanned<Pair<Pair<f64>>>>,
}

/// A dead force on every node of a set (per node, per unit thickness in
/// plane strain, total over the circle in axisymmetry).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Force {
    pub set: Spanned<String>,
    pub fx: Option<ValueSpec>,
    pub fy: Option<ValueSpec>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct BodyForce {
    pub body: Spanned<String>,
    pub bx: Option<ValueSpec>,
    pub by: Option<ValueSpec>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct InitialStress {
    pub body: Spanned<String>,
    pub xx: Option<f64>,
    pub yy: Option<f64>,
    pub zz: Option<f64>,
    pub xy: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Steps {
    pub dt: Option<Spanned<f64>>,
    pub t_end: Option<Spanned<f64>>,
    pub times: Option<Spanned<Vec<Spanned<f64>>>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Solver {
    pub force_tolerance: Option<Spanned<f64>>,
    pub displacement_tolerance: Option<Spanned<f64>>,
    pub energy_tolerance: Option<Spanned<f64>>,
    pub max_iterations: Option<Spanned<usize>>,
    pub max_bisections: Option<Spanned<usize>>,
    pub max_elements: Option<Spanned<usize>>,
}

/// A number, or `{ function = "name", scale = s }` meaning `s * f(t)`.
pub(super) enum ValueSpec {
    Number(f64),
    Function(FunctionRef),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FunctionRef {
    pub function: Spanned<String>,
    pub scale: Option<f64>,
}

impl<'de> Deserialize<'de> for ValueSpec {
    fn deserialize<D: de::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct SpecVisitor;
        impl<'de> Visitor<'de> for SpecVisitor {
            type Value = ValueSpec;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number or a table { function = \"name\", scale = number }")
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<ValueSpec, E> {
                Ok(ValueSpec::Number(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<ValueSpec, E> {
                Ok(ValueSpec::Number(v as f64))
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<ValueSpec, E> {
                Ok(ValueSpec::Number(v))
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<ValueSpec, A::Error> {
                FunctionRef::deserialize(MapAccessDeserializer::new(map)).map(ValueSpec::Function)
            }
        }
        deserializer.deserialize_any(SpecVisitor)
    }
}

/// Exactly two values (serde's `[T; 2]` lets a third one pass unseen).
#[derive(Clone, Copy)]
pub(super) struct Pair<T>(pub [T; 2]);

impl<'de, T: Deserialize<'de>> Deserialize<'de> for Pair<T> {
    fn deserialize<D: de::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct PairVisitor<T>(PhantomData<T>);
        impl<'de, T: Deserialize<'de>> Visitor<'de> for PairVisitor<T> {
            type Value = Pair<T>;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("an array of 2 values")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Pair<T>, A::Error> {
                let first = seq
                    .next_element()?
                    .ok_or_else(|| de::Error::invalid_length(0, &self))?;
                let second = seq
                    .next_element()?
                    .ok_or_else(|| de::Error::invalid_length(1, &self))?;
                let mut count = 2;
                while seq.next_element::<IgnoredAny>()?.is_some() {
                    count += 1;
                }
                if count > 2 {
                    return Err(de::Error::invalid_length(count, &self));
                }
                Ok(Pair([first, second]))
            }
        }
        deserializer.deserialize_seq(PairVisitor(PhantomData))
    }
}
