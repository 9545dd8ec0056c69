//! The scene file: parse a TOML scene, validate every value, and resolve names
//! (materials, bodies, sets, functions) into the solver's `Problem`. Every
//! error names the file, line, key and value it is about.

mod contact;
mod locate;
mod mesh;
mod params;
pub use params::evaluate;
mod raw;
mod tie;

use crate::mesh::{Edge, Mesh};
use crate::problem::{
    self, AnalysisKind, Body, BodyForce, Distribution, Driver, InitialStress, Kinematics, Material,
    MaterialSpec, NodalForce, Pressure, Problem, Scaled, SolverSettings, TimeFunction, Units,
};
use locate::Source;
use raw::{AnalysisName, KinematicsName, ModelName, ValueSpec};
use serde::Deserialize;
use serde::de::DeserializeOwned;
use std::ops::Range;
use std::path::{Path, PathBuf};
use toml::Spanned;
use toml::de::{DeTable, ValueDeserializer};

/// More increments than this in `[steps]` is taken as a mistake in dt.
const MAX_INCREMENTS: usize = 1_000_000;

/// Elements a scene may have unless its `[solver] max_elements` says more:
/// a mistyped division count must be an error, not an allocation that
/// brings the process (or an FMU's host) down. A million 4-node elements is
/// about two million unknowns, more than a 24 GiB machine factorises.
pub const MAX_ELEMENTS: usize = 1_000_000;

/// What kind of mistake a scene error reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneErrorKind {
    /// The scene file could not be read.
    Io,
    /// Not valid TOML.
    Syntax,
    UnknownKey,
    MissingKey,
    WrongType,
    /// Out of range, not one of the allowed words, or badly formed.
    InvalidValue,
    /// A name (material, body, set, function, group) that does not exist.
    UnknownReference,
    Duplicate,
    /// A mesh file that cannot be read, or a mesh that fails its check.
    Mesh,
}

/// A mistake in a scene file, located by file, 1-based line and dotted key.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{}:{line}: {key} = {value}: {message}", file.display())]
pub struct SceneError {
    pub kind: SceneErrorKind,
    pub file: PathBuf,
    pub line: usize,
    /// Dotted path of the key, e.g. `material[0].nu`.
    pub key: String,
    /// The value as written in the file, `(missing)` for an absent key.
    pub value: String,
    pub message: String,
}

/// Reads and resolves the scene file at `path`.
pub fn load(path: &Path) -> Result<Problem, SceneError> {
    parse(&read(path)?, path)
}

fn read(path: &Path) -> Result<String, SceneError> {
    // Only a regular file: reading a FIFO or a device would wait forever
    // (an FMU's host with it).
    if let Ok(meta) = std::fs::metadata(path)
        && !meta.is_file()
    {
        return Err(SceneError {
            kind: SceneErrorKind::Io,
            file: path.to_path_buf(),
            line: 1,
            key: "(file)".into(),
            value: path.display().to_string(),
            message: "not a regular file (a FIFO, device or folder is not read)".into(),
        });
    }
    std::fs::read_to_string(path).map_err(|e| SceneError {
        kind: SceneErrorKind::Io,
        file: path.to_path_buf(),
        line: 1,
        key: "(file)".into(),
        value: path.display().to_string(),
        message: format!("cannot read the scene file: {e}"),
    })
}

/// Resolves scene `text`; `path` names it in errors and is where relative
/// mesh file paths start from.
pub fn parse(text: &str, path: &Path) -> Result<Problem, SceneError> {
    parse_with(text, path, &[])
}

/// Reads the scene file at `path` with some of its `[parameters]` set to
/// other values (name, value).
pub fn load_with(path: &Path, overrides: &[(String, f64)]) -> Result<Problem, SceneError> {
    parse_with(&read(path)?, path, overrides)
}

/// [`parse`] with some of the scene's `[parameters]` set to other values:
/// the expressions that use them (`"= 2 * r"`, [`params`]) are evaluated
/// and written into the text as numbers, which is then read as usual.
pub fn parse_with(
    text: &str,
    path: &Path,
    overrides: &[(String, f64)],
) -> Result<Problem, SceneError> {
    let doc = DeTable::parse(text).map_err(|e| locate::syntax_error(path, text, &e))?;
    let src = Source {
        file: path,
        text,
        doc: &doc,
    };
    locate::check_finite(&src)?;
    let (text, parameters, subs) = params::substitute(&src, overrides)?;
    if subs.is_empty() {
        let mut problem = resolve(src)?;
        problem.parameters = parameters;
        return Ok(problem);
    }
    let doc = DeTable::parse(&text).map_err(|e| locate::syntax_error(path, &text, &e))?;
    let src = Source {
        file: path,
        text: &text,
        doc: &doc,
    };
    let mut problem = resolve(src).map_err(|e| params::annotate(e, &subs))?;
    problem.parameters = parameters;
    Ok(problem)
}

fn resolve(src: Source) -> Result<Problem, SceneError> {
    let scene = raw::Scene::deserialize(toml::de::Deserializer::from(src.doc.clone()))
        .map_err(|e| src.toml(&e))?;
    Resolver::new(src).resolve(&scene)
}

/// The contact pairs at rest (`contact::checks`): a pair whose contactor and
/// target face away from each other is refused, an overlap noted.
fn check_pairs(
    src: &Source,
    mut problem: Problem,
    raw: &[raw::Contact],
) -> Result<Problem, SceneError> {
    for (i, (pair, r)) in problem.contacts.iter().zip(raw).enumerate() {
        let key = format!("contact[{i}]");
        let invalid = |msg: String| {
            src.at(
                SceneErrorKind::InvalidValue,
                r.name.span(),
                key.clone(),
                msg,
            )
        };
        let found = crate::contact::checks::at_rest(&problem, pair).map_err(invalid)?;
        if let Some(msg) = found.facing_away {
            return Err(invalid(msg));
        }
        problem.warnings.extend(found.overlap);
    }
    Ok(problem)
}

/// Builds the problem section by section; later sections refer to the names
/// resolved by earlier ones.
struct Resolver<'a> {
    src: Source<'a>,
    analysis: AnalysisKind,
    kinematics: Kinematics,
    materials: Vec<Material>,
    functions: Vec<TimeFunction>,
    bodies: Vec<Body>,
    mesh: Mesh,
    element_material: Vec<usize>,
    /// The scene's element limit (`[solver] max_elements`).
    max_elements: usize,
}

impl<'a> Resolver<'a> {
    fn new(src: Source<'a>) -> Self {
        Resolver {
            src,
            // Set first of all, by `analysis`.
            analysis: AnalysisKind::Axisymmetric,
            kinematics: Kinematics::SmallStrain,
            materials: Vec::new(),
            functions: Vec::new(),
            bodies: Vec::new(),
            mesh: Mesh::default(),
            element_material: Vec::new(),
            max_elements: MAX_ELEMENTS,
        }
    }

    fn resolve(mut self, scene: &raw::Scene) -> Result<Problem, SceneError> {
        let kinematics = self.analysis(scene.analysis.get_ref())?;
        self.kinematics = kinematics;
        self.materials(&scene.material, kinematics)?;
        self.functions(&scene.function)?;
        if let Some(n) = scene.solver.as_ref().and_then(|s| s.max_elements.as_ref()) {
            if *n.get_ref() == 0 {
                return Err(self.invalid(n.span(), "solver.max_elements", "must be at least 1"));
            }
            self.max_elements = *n.get_ref();
        }
        self.bodies(&scene.body)?;
        self.node_sets(&scene.node_set)?;
        let drivers = self.drivers(&scene.driver)?;
        let rigids = self.rigids(&scene.rigid, &drivers)?;
        let contacts = self.contacts(&scene.contact, &rigids)?;
        let ties = self.ties(&scene.tie)?;
        let pressures = self.pressures(&scene.pressure)?;
        let forces = self.forces(&scene.force)?;
        let body_forces = self.body_forces(&scene.body_force)?;
        let initial_stresses = self.initial_stresses(&scene.initial_stress)?;
        let times = self.times(&scene.steps)?;
        let solver = self.solver(scene.solver.as_ref())?;
        let name = match &scene.title {
            Some(title) => title.clone(),
            None => self
                .src
                .file
                .file_stem()
                .map_or_else(String::new, |s| s.to_string_lossy().into_owned()),
        };
        let problem = Problem {
            name,
            analysis: self.analysis,
            kinematics,
            mesh: self.mesh,
            element_material: self.element_material,
            materials: self.materials,
            bodies: self.bodies,
            functions: self.functions,
            drivers,
            rigids,
            contacts,
            ties,
            pressures,
            forces,
            body_forces,
            initial_stresses,
            times,
            solver,
            parameters: Vec::new(),
            warnings: Vec::new(),
            units: scene.units.as_ref().map_or_else(Units::default, |u| Units {
                length: u.length.unwrap_or_default(),
                force: u.force.unwrap_or_default(),
            }),
        };
        check_pairs(&self.src, problem, &scene.contact)
    }

    /// Deserializes the table at `path` of the document again, as `T`: for
    /// tables whose keys depend on a tag read first.
    fn table_at<T: DeserializeOwned>(&self, path: &[&str]) -> Result<T, SceneError> {
        let value = locate::lookup(self.src.doc, path).expect("table read in the first pass");
        T::deserialize(ValueDeserializer::from(value.clone())).map_err(|e| self.src.toml(&e))
    }

    fn invalid(
        &self,
        span: Range<usize>,
        key: impl Into<String>,
        message: impl Into<String>,
    ) -> SceneError {
        self.src
            .at(SceneErrorKind::InvalidValue, span, key, message)
    }

    fn positive(
        &self,
        value: &Spanned<f64>,
        key: impl Into<String>,
        what: &str,
    ) -> Result<f64, SceneError> {
        let v = *value.get_ref();
        if v > 0.0 {
            Ok(v)
        } else {
            Err(self.invalid(value.span(), key, format!("{what} must be positive")))
        }
    }

    /// A `[solver]` setting within its range (`SolverSettings`).
    fn in_range<T: PartialOrd + std::fmt::Debug + Copy>(
        &self,
        value: &Spanned<T>,
        name: &str,
        range: &std::ops::RangeInclusive<T>,
    ) -> Result<T, SceneError> {
        let v = *value.get_ref();
        crate::problem::check_range(v, range)
            .map(|()| v)
            .map_err(|msg| {
                self.invalid(
                    value.span(),
                    format!("solver.{name}"),
                    format!("{name} {msg}"),
                )
            })
    }

    /// A new name for a `what`: not empty, unique among `seen`, and free of
    /// '.' where `no_dots` gives the reason (names joined with others by '.').
    /// A name in the FMU's variable names (`fmi`: materials, drivers, rigid
    /// targets, contact pairs) is also checked against FMI 2.0's structured
    /// naming convention, which the model description declares.
    fn new_name<'n>(
        &self,
        name: &Spanned<String>,
        key: String,
        what: &str,
        seen: impl IntoIterator<Item = &'n str>,
        no_dots: Option<&str>,
        fmi: bool,
    ) -> Result<(), SceneError> {
        let n = name.get_ref();
        if n.is_empty() {
            return Err(self.invalid(name.span(), key, format!("a {what} name must not be empty")));
        }
        if let Some(reason) = no_dots.filter(|_| n.contains('.')) {
            return Err(self.invalid(
                name.span(),
                key,
                format!("a {what} name must not contain '.'{reason}"),
            ));
        }
        if fmi && !n.split('.').all(fmi_identifier) {
            return Err(self.invalid(
                name.span(),
                key,
                format!(
                    "a {what} name begins the FMU's variable names ('{n}.<key>'), so by FMI 2.0's \
                     structured naming each part between '.' must be a letter or '_' followed by \
                     letters, digits or '_'"
                ),
            ));
        }
        if seen.into_iter().any(|s| s == n) {
            return Err(self.src.at(
                SceneErrorKind::Duplicate,
                name.span(),
                key,
                format!("duplicate {what} name"),
            ));
        }
        Ok(())
    }

    fn analysis(&mut self, a: &raw::Analysis) -> Result<Kinematics, SceneError> {
        let name = *a.kind.get_ref();
        let thickness = match &a.thickness {
            Some(t) if name == AnalysisName::Axisymmetric => {
                return Err(self.invalid(
                    t.span(),
                    "analysis.thickness",
                    "axisymmetric analysis has no thickness (it works on the full circle)",
                ));
            }
            Some(t) => self.positive(t, "analysis.thickness", "thickness")?,
            None => 1.0,
        };
        self.analysis = match name {
            AnalysisName::PlaneStrain => AnalysisKind::PlaneStrain { thickness },
            AnalysisName::PlaneStress => AnalysisKind::PlaneStress { thickness },
            AnalysisName::Axisymmetric => AnalysisKind::Axisymmetric,
        };
        Ok(match a.kinematics.as_ref().map(|k| *k.get_ref()) {
            None | Some(KinematicsName::SmallStrain) => Kinematics::SmallStrain,
            Some(KinematicsName::Mno) => Kinematics::MaterialNonlinearOnly,
            Some(KinematicsName::TotalLagrangian) => Kinematics::TotalLagrangian,
        })
    }

    fn materials(
        &mut self,
        list: &Spanned<Vec<serde::de::IgnoredAny>>,
        kinematics: Kinematics,
    ) -> Result<(), SceneError> {
        if list.get_ref().is_empty() {
            return Err(self.invalid(
                list.span(),
                "material",
                "at least one [[material]] is required",
            ));
        }
        for i in 0..list.get_ref().len() {
            let index = i.to_string();
            let path = ["material", index.as_str()];
            let head: raw::MaterialHead = self.table_at(&path)?;
            let seen: Vec<&str> = self.materials.iter().map(|m| m.name.as_str()).collect();
            self.new_name(
                &head.name,
                format!("material[{i}].name"),
                "material",
                seen,
                None,
                true,
            )?;
            let spec = match head.model.get_ref() {
                ModelName::LinearElastic => {
                    let m: raw::LinearElastic = self.table_at(&path)?;
                    let e = *m.e.get_ref();
                    if e <= 0.0 {
                        return Err(self.invalid(
                            m.e.span(),
                            format!("material[{i}].E"),
                            "Young's modulus must be positive",
                        ));
                    }
                    MaterialSpec::LinearElastic {
                        e,
                        nu: self.poisson(&m.nu, format!("material[{i}].nu"))?,
                    }
                }
                ModelName::MooneyRivlin => {
                    let m: raw::MooneyRivlin = self.table_at(&path)?;
                    MaterialSpec::MooneyRivlin {
                        c1: self.checked(&m.c1, format!("material[{i}].C1"), problem::check_c1)?,
                        c2: self.checked(&m.c2, format!("material[{i}].C2"), problem::check_c2)?,
                    }
                }
                ModelName::VonMises => {
                    let m: raw::VonMises = self.table_at(&path)?;
                    let key = |k: &str| format!("material[{i}].{k}");
                    MaterialSpec::VonMises {
                        e: self.checked(&m.e, key("E"), problem::check_modulus)?,
                        nu: self.checked(&m.nu, key("nu"), problem::check_plastic_poisson)?,
                        sigma_y: self.checked(
                            &m.sigma_y,
                            key("sigma_y"),
                            problem::check_yield_stress,
                        )?,
                        h: self.checked(&m.h, key("H"), problem::check_hardening)?,
                    }
                }
            };
            problem::check_model_analysis(&spec, self.analysis, kinematics).map_err(|msg| {
                self.invalid(head.model.span(), format!("material[{i}].model"), msg)
            })?;
            self.materials.push(Material {
                name: head.name.into_inner(),
                spec,
            });
        }
        Ok(())
    }

    /// A number that `check` accepts, or an error at its line.
    fn checked(
        &self,
        value: &Spanned<f64>,
        key: String,
        check: fn(f64) -> Result<(), String>,
    ) -> Result<f64, SceneError> {
        let v = *value.get_ref();
        check(v)
            .map(|()| v)
            .map_err(|message| self.invalid(value.span(), key, message))
    }

    /// Poisson's ratio; 0.5 (incompressible) only where the thickness is free
    /// to change.
    fn poisson(&self, nu: &Spanned<f64>, key: String) -> Result<f64, SceneError> {
        let v = *nu.get_ref();
        crate::problem::check_poisson(self.analysis, v)
            .map(|()| v)
            .map_err(|message| self.invalid(nu.span(), key, message))
    }

    fn functions(&mut self, list: &[Spanned<raw::Function>]) -> Result<(), SceneError> {
        for (i, f) in list.iter().enumerate() {
            let f = f.get_ref();
            let seen: Vec<&str> = self.functions.iter().map(|f| f.name.as_str()).collect();
            self.new_name(
                &f.name,
                format!("function[{i}].name"),
                "function",
                seen,
                None,
                false,
            )?;
            let points = f.points.get_ref();
            if points.is_empty() {
                return Err(self.invalid(
                    f.points.span(),
                    format!("function[{i}].points"),
                    "a function needs at least one point",
                ));
            }
            let times: Vec<_> = points
                .iter()
                .map(|p| (p.span(), p.get_ref().0[0]))
                .collect();
            self.strictly_increasing(&times, |j| format!("function[{i}].points[{j}]"))?;
            let points = points
                .iter()
                .map(|p| (p.get_ref().0[0], p.get_ref().0[1]))
                .collect();
            self.functions.push(TimeFunction {
                name: f.name.get_ref().clone(),
                points,
            });
        }
        Ok(())
    }

    /// Times (with their spans) that must increase strictly; `key` names
    /// the j-th.
    fn strictly_increasing(
        &self,
        times: &[(Range<usize>, f64)],
        key: impl Fn(usize) -> String,
    ) -> Result<(), SceneError> {
        for (j, w) in times.windows(2).enumerate() {
            let ((_, t0), (span, t1)) = (&w[0], &w[1]);
            if t1 <= t0 {
                let message = format!("times must be strictly increasing ({t1:?} follows {t0:?})");
                return Err(self.invalid(span.clone(), key(j + 1), message));
            }
        }
        Ok(())
    }

    fn bodies(&mut self, list: &Spanned<Vec<Spanned<raw::Body>>>) -> Result<(), SceneError> {
        if list.get_ref().is_empty() {
            return Err(self.invalid(list.span(), "body", "at least one [[body]] is required"));
        }
        for (i, b) in list.get_ref().iter().enumerate() {
            let b = b.get_ref();
            let seen: Vec<&str> = self.bodies.iter().map(|b| b.name.as_str()).collect();
            self.new_name(
                &b.name,
                format!("body[{i}].name"),
                "body",
                seen,
                Some(" (sets are named <body>.<set>)"),
                false,
            )?;
            let Some(material) = self
                .materials
                .iter()
                .position(|m| &m.name == b.material.get_ref())
            else {
                let names: Vec<&str> = self.materials.iter().map(|m| m.name.as_str()).collect();
                return Err(self.src.at(
                    SceneErrorKind::UnknownReference,
                    b.material.span(),
                    format!("body[{i}].material"),
                    format!("no material of that name; materials: {}", names.join(", ")),
                ));
            };
            let (body_mesh, strip) = self.body_mesh(i, b)?;
            let running = self.running(i, b, strip.as_ref())?;
            let (nodes0, elements0) = (self.mesh.nodes.len(), self.mesh.elements.len());
            self.mesh
                .append(&body_mesh, &format!("{}.", b.name.get_ref()));
            self.mesh.check().map_err(|e| {
                self.src.at(
                    SceneErrorKind::Mesh,
                    b.mesh.span(),
                    format!("body[{i}].mesh"),
                    e.to_string(),
                )
            })?;
            self.element_material
                .resize(self.mesh.elements.len(), material);
            self.bodies.push(Body {
                name: b.name.get_ref().clone(),
                material,
                elements: elements0..self.mesh.elements.len(),
                nodes: nodes0..self.mesh.nodes.len(),
                strip,
                running,
            });
        }
        Ok(())
    }

    /// Whether body `i` runs: only a strip, laid along its path in total
    /// Lagrangian kinematics, with free spans of at least two elements
    /// (its end columns stay off the drum).
    fn running(
        &self,
        i: usize,
        b: &raw::Body,
        strip: Option<&crate::strip::StripPath>,
    ) -> Result<bool, SceneError> {
        let Some(flag) = &b.running else {
            return Ok(false);
        };
        if !*flag.get_ref() {
            return Ok(false);
        }
        let key = format!("body[{i}].running");
        let Some(path) = strip else {
            return Err(self.invalid(
                flag.span(),
                key,
                "only a body meshed with `generator = \"strip\"` can run",
            ));
        };
        if path.spans[0].min(path.spans[1])
            < 2.0 * path.element * (1.0 + path.strain) * (1.0 - 1e-9)
        {
            return Err(self.invalid(
                flag.span(),
                key,
                "a running strip needs free spans (`spans`) of at least 2 elements each",
            ));
        }
        Ok(true)
    }

    /// The body a `name` refers to.
    fn body(&self, name: &Spanned<String>, key: String) -> Result<usize, SceneError> {
        self.bodies
            .iter()
            .position(|b| &b.name == name.get_ref())
            .ok_or_else(|| {
                let names: Vec<&str> = self.bodies.iter().map(|b| b.name.as_str()).collect();
                self.src.at(
                    SceneErrorKind::UnknownReference,
                    name.span(),
                    key,
                    format!("no body of that name; bodies: {}", names.join(", ")),
                )
            })
    }

    /// The body of a set reference `<body>.<set>`, and the set's name within it.
    fn set_ref<'s>(
        &self,
        set: &'s Spanned<String>,
        key: &str,
    ) -> Result<(&str, &'s str), SceneError> {
        let Some((body, name)) = set.get_ref().split_once('.') else {
            return Err(self.invalid(set.span(), key, "a set is named <body>.<set>"));
        };
        let b = self.body(&Spanned::new(set.span(), body.to_string()), key.to_string())?;
        Ok((self.bodies[b].name.as_str(), name))
    }

    /// The set names of `body` without its prefix: edge sets, or all sets.
    fn set_names(&self, body: &str, edges_only: bool) -> String {
        let prefix = format!("{body}.");
        let edge = self.mesh.edge_sets.keys();
        let node = self.mesh.node_sets.keys().filter(|_| !edges_only);
        let mut names: Vec<&str> = edge
            .chain(node)
            .filter_map(|k| k.strip_prefix(&prefix))
            .collect();
        names.sort_unstable();
        names.dedup();
        if names.is_empty() {
            "(none)".into()
        } else {
            names.join(", ")
        }
    }

    /// The nodes of a node set, or of an edge set.
    fn node_set(&self, set: &Spanned<String>, key: &str) -> Result<Vec<usize>, SceneError> {
        let (body, name) = self.set_ref(set, key)?;
        let full = set.get_ref();
        if let Some(nodes) = self.mesh.node_sets.get(full) {
            return Ok(nodes.clone());
        }
        self.mesh.edge_set_nodes(full).ok_or_else(|| {
            self.src.at(
                SceneErrorKind::UnknownReference,
                set.span(),
                key,
                format!(
                    "body `{body}` has no set `{name}`; available sets: {}",
                    self.set_names(body, false)
                ),
            )
        })
    }

    fn edge_set(&self, set: &Spanned<String>, key: &str) -> Result<Vec<Edge>, SceneError> {
        let (body, name) = self.set_ref(set, key)?;
        let full = set.get_ref();
        if let Some(edges) = self.mesh.edge_sets.get(full) {
            return Ok(edges.clone());
        }
        let message = if self.mesh.node_sets.contains_key(full) {
            format!(
                "`{name}` is a node set; this needs an edge set; edge sets of `{body}`: {}",
                self.set_names(body, true)
            )
        } else {
            format!(
                "body `{body}` has no edge set `{name}`; available edge sets: {}",
                self.set_names(body, true)
            )
        };
        Err(self
            .src
            .at(SceneErrorKind::UnknownReference, set.span(), key, message))
    }

    /// A number, or `scale * f(t)` of a named function.
    fn scaled(&self, spec: &ValueSpec, key: &str) -> Result<Scaled, SceneError> {
        match spec {
            ValueSpec::Number(v) => Ok(Scaled::constant(*v)),
            ValueSpec::Function(f) => {
                let name = &f.function;
                let Some(index) = self
                    .functions
                    .iter()
                    .position(|g| &g.name == name.get_ref())
                else {
                    let names: Vec<&str> = self.functions.iter().map(|g| g.name.as_str()).collect();
                    let known = if names.is_empty() {
                        "none defined".into()
                    } else {
                        names.join(", ")
                    };
                    return Err(self.src.at(
                        SceneErrorKind::UnknownReference,
                        name.span(),
                        format!("{key}.function"),
                        format!("no function of that name; functions: {known}"),
                    ));
                };
                Ok(Scaled {
                    scale: f.scale.unwrap_or(1.0),
                    function: Some(index),
                })
            }
        }
    }

    fn optional_scaled(
        &self,
        spec: Option<&ValueSpec>,
        key: &str,
    ) -> Result<Option<Scaled>, SceneError> {
        spec.map(|s| self.scaled(s, key)).transpose()
    }

    fn drivers(&self, list: &[Spanned<raw::Driver>]) -> Result<Vec<Driver>, SceneError> {
        let mut drivers: Vec<Driver> = Vec::new();
        for (i, d) in list.iter().enumerate() {
            let span = d.span();
            let d = d.get_ref();
            let seen = list[..i]
                .iter()
                .map(|d| d.get_ref().name.get_ref().as_str());
            self.new_name(
                &d.name,
                format!("driver[{i}].name"),
                "driver",
                seen,
                Some(""),
                true,
            )?;
            let nodes = self.node_set(&d.set, &format!("driver[{i}].set"))?;
            let ux = self.optional_scaled(d.ux.as_ref(), &format!("driver[{i}].ux"))?;
            let uy = self.optional_scaled(d.uy.as_ref(), &format!("driver[{i}].uy"))?;
            let fx = self.optional_scaled(d.fx.as_ref(), &format!("driver[{i}].fx"))?;
            let fy = self.optional_scaled(d.fy.as_ref(), &format!("driver[{i}].fy"))?;
            if ux.is_none() && uy.is_none() && fx.is_none() && fy.is_none() {
                return Err(self.src.missing(
                    span,
                    format!("driver[{i}].ux"),
                    "a driver prescribes at least one component: ux or fx, uy or fy",
                ));
            }
            for (u, f, c) in [(&ux, &fx, 'x'), (&uy, &fy, 'y')] {
                if u.is_some() && f.is_some() {
                    return Err(self.invalid(
                        span,
                        format!("driver[{i}].f{c}"),
                        format!(
                            "u{c} and f{c} both given: a component is prescribed as a displacement or as a force, not both"
                        ),
                    ));
                }
            }
            let distribution = match d.distribution.as_ref() {
                None => Distribution::Equal,
                Some(s) if fx.is_none() && fy.is_none() => {
                    return Err(self.invalid(
                        s.span(),
                        format!("driver[{i}].distribution"),
                        "distribution says how a force acts on the set, and this driver prescribes no force (fx or fy)",
                    ));
                }
                Some(s) => match s.get_ref() {
                    raw::DistributionName::Equal => Distribution::Equal,
                    raw::DistributionName::Rigid => Distribution::Rigid,
                },
            };
            let rigid = matches!(distribution, Distribution::Rigid);
            if ux.is_some() || uy.is_some() || rigid {
                self.off_strips(&nodes, span, i)?;
            }
            drivers.push(Driver {
                name: d.name.get_ref().clone(),
                nodes,
                ux,
                uy,
                fx,
                fy,
                distribution,
            });
        }
        self.rigid_sets_apart(list, &drivers)?;
        Ok(drivers)
    }

    /// A strip starts laid along its path by a displacement from its
    /// straight reference, which a prescribed displacement or a rigid set
    /// (its nodes one unknown) would undo: driver `i` on `nodes` may only
    /// apply forces shared equally there.
    fn off_strips(&self, nodes: &[usize], span: Range<usize>, i: usize) -> Result<(), SceneError> {
        for b in self.bodies.iter().filter(|b| b.strip.is_some()) {
            if nodes.iter().any(|n| b.nodes.contains(n)) {
                return Err(self.invalid(
                    span,
                    format!("driver[{i}].set"),
                    format!(
                        "body `{}` is a strip, laid along its path from a straight reference: \
                         drive it by forces (`fx`, `fy`) with `distribution = \"equal\"`",
                        b.name
                    ),
                ));
            }
        }
        Ok(())
    }

    /// A rigid force component makes its set's nodes one unknown: none of
    /// them may be prescribed in that component by a displacement, nor
    /// belong to another rigid set of the same component.
    fn rigid_sets_apart(
        &self,
        list: &[Spanned<raw::Driver>],
        drivers: &[Driver],
    ) -> Result<(), SceneError> {
        let mut owner: std::collections::HashMap<(usize, usize), (usize, bool)> =
            std::collections::HashMap::new();
        for (i, d) in drivers.iter().enumerate() {
            for c in 0..2 {
                let rigid = d.force(c).is_some() && d.distribution == Distribution::Rigid;
                if !rigid && d.displacement(c).is_none() {
                    continue;
                }
                for &n in &d.nodes {
                    let Some(&(j, other_rigid)) = owner.get(&(n, c)) else {
                        owner.insert((n, c), (i, rigid));
                        continue;
                    };
                    if !(rigid || other_rigid) || j == i {
                        continue;
                    }
                    let axis = ['x', 'y'][c];
                    let how = |r: bool| {
                        if r {
                            format!("a rigid force f{axis}")
                        } else {
                            format!("a displacement u{axis}")
                        }
                    };
                    return Err(self.invalid(
                        list[i].span(),
                        format!("driver[{i}].set"),
                        format!(
                            "node {n} gets {} here and {} from driver `{}`: a rigid force set moves as one, so none of its nodes may be driven in that component by another driver",
                            how(rigid),
                            how(other_rigid),
                            drivers[j].name
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    /// Node sets picked by location, added to the mesh as `<body>.<name>`.
    fn node_sets(&mut self, list: &[Spanned<raw::NodeSet>]) -> Result<(), SceneError> {
        for (i, s) in list.iter().enumerate() {
            let span = s.span();
            let s = s.get_ref();
            let key = format!("node_set[{i}].name");
            let (body, _) = self.set_ref(&s.name, &key)?;
            let b = &self.bodies[self.bodies.iter().position(|b| b.name == body).unwrap_or(0)];
            let full = s.name.get_ref();
            if self.mesh.node_sets.contains_key(full) || self.mesh.edge_sets.contains_key(full) {
                return Err(self.src.at(
                    SceneErrorKind::Duplicate,
                    s.name.span(),
                    key,
                    "a set of that name already exists",
                ));
            }
            let coords = |n: usize| self.mesh.nodes[n];
            let nodes: Vec<usize> = match (&s.nearest, &s.bounds) {
                (Some(p), None) => {
                    let [x, y] = p.get_ref().0;
                    let d2 = |n: usize| (coords(n)[0] - x).powi(2) + (coords(n)[1] - y).powi(2);
                    let nearest = b.nodes.clone().min_by(|&m, &n| d2(m).total_cmp(&d2(n)));
                    nearest.into_iter().collect()
                }
                (None, Some(bounds)) => {
                    let [lo, hi] = bounds.get_ref().0.each_ref().map(|p| p.0);
                    let bkey = format!("node_set[{i}].box");
                    if lo[0] > hi[0] || lo[1] > hi[1] {
                        return Err(self.invalid(
                            bounds.span(),
                            bkey,
                            "a box is [[xmin, ymin], [xmax, ymax]] with min <= max",
                        ));
                    }
                    // Nodes on the box's sides belong to it: a tolerance of
                    // 1e-9 of the body's extent absorbs generator round-off.
                    let (mut min, mut max) = ([f64::MAX; 2], [f64::MIN; 2]);
                    for n in b.nodes.clone() {
                        let p = coords(n);
                        min = [min[0].min(p[0]), min[1].min(p[1])];
                        max = [max[0].max(p[0]), max[1].max(p[1])];
                    }
                    let tol = 1e-9 * (max[0] - min[0]).max(max[1] - min[1]);
                    let inside = |n: &usize| {
                        let p = coords(*n);
                        p[0] >= lo[0] - tol
                            && p[0] <= hi[0] + tol
                            && p[1] >= lo[1] - tol
                            && p[1] <= hi[1] + tol
                    };
                    let nodes: Vec<usize> = b.nodes.clone().filter(inside).collect();
                    if nodes.is_empty() {
                        return Err(self.invalid(
                            bounds.span(),
                            bkey,
                            format!(
                                "no node of body `{body}` lies in this box; the body spans \
                                 [[{}, {}], [{}, {}]]",
                                min[0], min[1], max[0], max[1]
                            ),
                        ));
                    }
                    nodes
                }
                _ => {
                    return Err(self.src.missing(
                        span,
                        format!("node_set[{i}].nearest"),
                        "a node set gives exactly one of `nearest = [x, y]` or \
                         `box = [[xmin, ymin], [xmax, ymax]]`",
                    ));
                }
            };
            self.mesh.node_sets.insert(full.clone(), nodes);
        }
        Ok(())
    }

    fn forces(&self, list: &[Spanned<raw::Force>]) -> Result<Vec<NodalForce>, SceneError> {
        let resolve = |(i, f): (usize, &Spanned<raw::Force>)| {
            let span = f.span();
            let f = f.get_ref();
            let fx = self.optional_scaled(f.fx.as_ref(), &format!("force[{i}].fx"))?;
            let fy = self.optional_scaled(f.fy.as_ref(), &format!("force[{i}].fy"))?;
            if fx.is_none() && fy.is_none() {
                return Err(self.src.missing(
                    span,
                    format!("force[{i}].fx"),
                    "a force gives fx, fy or both",
                ));
            }
            Ok(NodalForce {
                nodes: self.node_set(&f.set, &format!("force[{i}].set"))?,
                fx: fx.unwrap_or(Scaled::constant(0.0)),
                fy: fy.unwrap_or(Scaled::constant(0.0)),
            })
        };
        list.iter().enumerate().map(resolve).collect()
    }

    fn pressures(&self, list: &[raw::Pressure]) -> Result<Vec<Pressure>, SceneError> {
        let mut pressures: Vec<Pressure> = Vec::new();
        for (i, p) in list.iter().enumerate() {
            if let Some(name) = &p.name {
                self.new_name(
                    name,
                    format!("pressure[{i}].name"),
                    "pressure",
                    pressures.iter().filter_map(|p| p.name.as_deref()),
                    Some(""),
                    true,
                )?;
            }
            pressures.push(Pressure {
                edges: self.edge_set(&p.set, &format!("pressure[{i}].set"))?,
                value: self.scaled(&p.value, &format!("pressure[{i}].value"))?,
                follower: p.follower.unwrap_or(true),
                name: p.name.as_ref().map(|n| n.get_ref().clone()),
            });
        }
        Ok(pressures)
    }

    fn body_forces(&self, list: &[raw::BodyForce]) -> Result<Vec<BodyForce>, SceneError> {
        let resolve = |(i, f): (usize, &raw::BodyForce)| {
            let component = |spec: Option<&ValueSpec>, c: &str| {
                Ok(self
                    .optional_scaled(spec, &format!("body_force[{i}].{c}"))?
                    .unwrap_or(Scaled::constant(0.0)))
            };
            Ok(BodyForce {
                body: self.body(&f.body, format!("body_force[{i}].body"))?,
                bx: component(f.bx.as_ref(), "bx")?,
                by: component(f.by.as_ref(), "by")?,
            })
        };
        list.iter().enumerate().map(resolve).collect()
    }

    fn initial_stresses(
        &self,
        list: &[raw::InitialStress],
    ) -> Result<Vec<InitialStress>, SceneError> {
        let resolve = |(i, s): (usize, &raw::InitialStress)| {
            let stress = [s.xx, s.yy, s.zz, s.xy].map(|c| c.unwrap_or(0.0));
            Ok(InitialStress {
                body: self.body(&s.body, format!("initial_stress[{i}].body"))?,
                stress,
            })
        };
        list.iter().enumerate().map(resolve).collect()
    }

    /// End times of the increments: `times` as given, or dt, 2 dt, ... t_end
    /// with a shorter last step where dt does not divide t_end.
    fn times(&self, steps: &Spanned<raw::Steps>) -> Result<Vec<f64>, SceneError> {
        let s = steps.get_ref();
        match (&s.times, &s.dt, &s.t_end) {
            (Some(times), None, None) => {
                let list = times.get_ref();
                if list.is_empty() {
                    return Err(self.invalid(
                        times.span(),
                        "steps.times",
                        "at least one time is required",
                    ));
                }
                if *list[0].get_ref() <= 0.0 {
                    let message = "times must be positive";
                    return Err(self.invalid(list[0].span(), "steps.times[0]", message));
                }
                let pairs: Vec<_> = list.iter().map(|t| (t.span(), *t.get_ref())).collect();
                self.strictly_increasing(&pairs, |j| format!("steps.times[{j}]"))?;
                Ok(list.iter().map(|t| *t.get_ref()).collect())
            }
            (Some(times), _, _) => Err(self.invalid(
                times.span(),
                "steps.times",
                "give either times, or dt and t_end, not both",
            )),
            (None, Some(dt), Some(t_end)) => {
                let h = self.positive(dt, "steps.dt", "dt")?;
                let end = self.positive(t_end, "steps.t_end", "t_end")?;
                if end / h > MAX_INCREMENTS as f64 {
                    return Err(self.invalid(
                        dt.span(),
                        "steps.dt",
                        format!(
                            "t_end / dt = {:.0} increments; at most {MAX_INCREMENTS}",
                            end / h
                        ),
                    ));
                }
                let mut times = Vec::new();
                for k in 1.. {
                    let t = k as f64 * h;
                    // A last step shorter than 1e-9 dt is merged into the one before.
                    if end - t <= 1e-9 * h {
                        times.push(end);
                        break;
                    }
                    times.push(t);
                }
                Ok(times)
            }
            (None, Some(_), None) => {
                Err(self
                    .src
                    .missing(steps.span(), "steps.t_end", "dt needs t_end"))
            }
            (None, None, Some(_)) => {
                Err(self.src.missing(steps.span(), "steps.dt", "t_end needs dt"))
            }
            (None, None, None) => Err(self.src.missing(
                steps.span(),
                "steps.dt",
                "[steps] needs dt and t_end, or times",
            )),
        }
    }

    fn solver(&self, raw: Option<&raw::Solver>) -> Result<SolverSettings, SceneError> {
        let mut settings = SolverSettings::default();
        let Some(s) = raw else { return Ok(settings) };
        let tolerances = [
            (
                &s.force_tolerance,
                "force_tolerance",
                &mut settings.force_tolerance,
            ),
            (
                &s.displacement_tolerance,
                "displacement_tolerance",
                &mut settings.displacement_tolerance,
            ),
            (
                &s.energy_tolerance,
                "energy_tolerance",
                &mut settings.energy_tolerance,
            ),
        ];
        for (value, name, target) in tolerances {
            if let Some(v) = value {
                let range = match name {
                    "energy_tolerance" => SolverSettings::ENERGY_TOLERANCE,
                    _ => SolverSettings::RELATIVE_TOLERANCE,
                };
                *target = self.in_range(v, name, &range)?;
            }
        }
        if let Some(n) = &s.max_iterations {
            settings.max_iterations =
                self.in_range(n, "max_iterations", &SolverSettings::MAX_ITERATIONS)?;
        }
        if let Some(n) = &s.max_bisections {
            settings.max_bisections =
                self.in_range(n, "max_bisections", &SolverSettings::MAX_BISECTIONS)?;
        }
        Ok(settings)
    }
}

/// The mesh files a scene reads (`body.mesh.file`), as written in it:
/// relative to the scene's folder.
pub fn mesh_files(path: &Path) -> Result<Vec<std::path::PathBuf>, SceneError> {
    let text = read(path)?;
    // A scene that loads parses; this reads only the file names.
    let doc: toml::Table = toml::from_str(&text).unwrap_or_default();
    let bodies = doc.get("body").and_then(|b| b.as_array());
    Ok(bodies
        .into_iter()
        .flatten()
        .filter_map(|b| b.get("mesh")?.get("file")?.as_str())
        .map(std::path::PathBuf::from)
        .collect())
}

/// An identifier of FMI 2.0's structured naming convention (its `BaseName`;
/// quoted names are not used): a letter or '_', then letters, digits or '_'.
fn fmi_identifier(part: &str) -> bool {
    let mut chars = part.chars();
    chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}
