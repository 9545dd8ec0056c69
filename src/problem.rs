//! The solver's input: a fully resolved problem (one merged mesh, materials,
//! drivers, loads, load history, solver settings). The scene reader builds
//! it from TOML; the FMU edits its parameters. It holds indices, not names,
//! except where results are reported by name.

use crate::mesh::{Edge, Mesh};
use std::ops::RangeInclusive;

/// Analysis kind (the paper's planar and axisymmetric cases). In the
/// axisymmetric case x is the radius and y the axis of revolution; forces and
/// volumes are taken over the full circle (2 pi r).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AnalysisKind {
    PlaneStrain { thickness: f64 },
    PlaneStress { thickness: f64 },
    Axisymmetric,
}

/// Kinematic description (the paper's "M.N.O." and "T.L.").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kinematics {
    /// Linear strain-displacement relation, linear material: one solve.
    SmallStrain,
    /// Materially-nonlinear-only: small strain, Newton on the material law.
    MaterialNonlinearOnly,
    /// Total Lagrangian: Green-Lagrange strain, second Piola-Kirchhoff stress.
    TotalLagrangian,
}

/// Material constants as given in the scene.
#[derive(Clone, Debug, PartialEq)]
pub enum MaterialSpec {
    LinearElastic {
        e: f64,
        nu: f64,
    },
    /// Incompressible rubber in plane stress, total Lagrangian only.
    MooneyRivlin {
        c1: f64,
        c2: f64,
    },
    /// Von Mises plasticity with linear isotropic hardening modulus `h`
    /// (small strain: materially-nonlinear-only analysis).
    VonMises {
        e: f64,
        nu: f64,
        sigma_y: f64,
        h: f64,
    },
}

#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
    pub spec: MaterialSpec,
}

/// A body: its elements and nodes are contiguous ranges of the merged mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    pub name: String,
    pub material: usize,
    pub elements: std::ops::Range<usize>,
    pub nodes: std::ops::Range<usize>,
    /// A strip's path: its reference mesh is straight and it starts laid
    /// along this path (`Problem::initial_u`).
    pub strip: Option<crate::strip::StripPath>,
    /// Material runs through the strip from its supply end to its take-up
    /// end (`crate::running`, docs/contact.md section 12).
    pub running: bool,
}

/// Piecewise linear time function; constant beyond its ends.
#[derive(Clone, Debug, PartialEq)]
pub struct TimeFunction {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

impl TimeFunction {
    pub fn value(&self, t: f64) -> f64 {
        let p = &self.points;
        if p.is_empty() {
            return 0.0;
        }
        if t <= p[0].0 {
            return p[0].1;
        }
        for w in p.windows(2) {
            let ((t0, v0), (t1, v1)) = (w[0], w[1]);
            if t <= t1 {
                if t1 == t0 {
                    return v1;
                }
                return v0 + (v1 - v0) * (t - t0) / (t1 - t0);
            }
        }
        p[p.len() - 1].1
    }
}

/// A scalar that follows a time function: `scale * f(t)`, or `scale` when
/// there is no function.
#[derive(Clone, Debug, PartialEq)]
pub struct Scaled {
    pub scale: f64,
    pub function: Option<usize>,
}

impl Scaled {
    pub fn constant(v: f64) -> Self {
        Scaled {
            scale: v,
            function: None,
        }
    }
    pub fn at(&self, t: f64, functions: &[TimeFunction]) -> f64 {
        match self.function {
            Some(f) => self.scale * functions[f].value(t),
            None => self.scale,
        }
    }
}

/// Prescribed components of a node set: a displacement (`ux`, `uy`) or a
/// force (`fx`, `fy`: the set's resultant, acting on the set as
/// `distribution` says), at most one of the two per component. A component
/// with neither is free. Its reaction (or its applied force) is reported
/// under the driver's name.
#[derive(Clone, Debug, PartialEq)]
pub struct Driver {
    pub name: String,
    pub nodes: Vec<usize>,
    pub ux: Option<Scaled>,
    pub uy: Option<Scaled>,
    pub fx: Option<Scaled>,
    pub fy: Option<Scaled>,
    pub distribution: Distribution,
}

/// How a force driver's resultant acts on its node set.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Distribution {
    /// Each node carries an equal share (a dead load); the nodes move
    /// apart as the body lets them.
    #[default]
    Equal,
    /// The set moves as one in each force component (a rigid clamp, the
    /// plane end of a wire or strip): its nodes share one unknown per
    /// component, which takes the whole resultant, and the body decides
    /// how the force spreads over the set.
    Rigid,
}

impl Driver {
    /// The prescribed displacement of component c (0 x, 1 y).
    pub fn displacement(&self, c: usize) -> Option<&Scaled> {
        [&self.ux, &self.uy][c].as_ref()
    }

    /// The prescribed force (the set's resultant) of component c.
    pub fn force(&self, c: usize) -> Option<&Scaled> {
        [&self.fx, &self.fy][c].as_ref()
    }
}

/// Edge pressure (positive pushes into the body). A follower pressure acts
/// on the current edge normal; a dead one on the reference normal.
#[derive(Clone, Debug, PartialEq)]
pub struct Pressure {
    pub edges: Vec<Edge>,
    pub value: Scaled,
    pub follower: bool,
    /// A named pressure is an FMU input, `<name>.p`.
    pub name: Option<String>,
}

/// Concentrated force applied at each node of a set (dead load).
#[derive(Clone, Debug, PartialEq)]
pub struct NodalForce {
    pub nodes: Vec<usize>,
    pub fx: Scaled,
    pub fy: Scaled,
}

/// Body force per unit reference volume, on the elements of one body.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyForce {
    pub body: usize,
    pub bx: Scaled,
    pub by: Scaled,
}

/// Initial stress [xx, yy, zz, xy] in the elements of one body, present from
/// t = 0 (it is in equilibrium only where the scene makes it so).
#[derive(Clone, Debug, PartialEq)]
pub struct InitialStress {
    pub body: usize,
    pub stress: [f64; 4],
}

/// A rigid target: a polyline with no degrees of freedom, its points in the
/// order that puts the target on the left (the contact kernel's convention),
/// moved as a rigid body about `reference` by `ux`, `uy` and a rotation
/// `theta` (radians, counter-clockwise). Its reaction (Rx, Ry, Mz about the
/// moved reference point) is reported under its name, like a driver's.
#[derive(Clone, Debug, PartialEq)]
pub struct Rigid {
    pub name: String,
    pub points: Vec<[f64; 2]>,
    pub reference: [f64; 2],
    pub ux: Scaled,
    pub uy: Scaled,
    pub theta: Scaled,
}

impl Rigid {
    /// Its points at pose [ux, uy, theta]: rotated by theta about the
    /// reference and translated by (ux, uy); and the moved reference point.
    pub fn points_at(&self, pose: [f64; 3]) -> (Vec<[f64; 2]>, [f64; 2]) {
        let [ux, uy, th] = pose;
        let (s, c) = th.sin_cos();
        let [cx, cy] = self.reference;
        let points = (self.points.iter())
            .map(|p| {
                let (dx, dy) = (p[0] - cx, p[1] - cy);
                [cx + c * dx - s * dy + ux, cy + s * dx + c * dy + uy]
            })
            .collect();
        (points, [cx + ux, cy + uy])
    }
}

/// What a contactor surface is pressed against.
#[derive(Clone, Debug, PartialEq)]
pub enum Target {
    /// Segments `[A, B]` between consecutive surface nodes of a deformable
    /// body, each with the target body on its left.
    Body {
        body: usize,
        segments: Vec<[usize; 2]>,
        /// A smoothed target (`smooth_target`, node-to-segment): each
        /// segment's outer neighbours `[P, Q]`, the nodes before A and after
        /// B along the surface (None at an end of the target), through which
        /// its curve runs (`contact::segment::Segment::smoothed`).
        smooth: Option<Vec<[Option<usize>; 2]>>,
    },
    /// A rigid target (index into `Problem::rigids`); its segments join
    /// consecutive points.
    Rigid(usize),
}

/// Which static coefficient a segment that is sticking uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrictionRule {
    /// mu_s until the segment first slides, mu_d from then on for good (the
    /// paper's usual algorithm).
    MuDAfterSlip,
    /// mu_s throughout (the paper's experiment).
    AlwaysMuS,
}

/// How nodal tractions are recovered from the out-of-balance forces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Recovery {
    /// The tridiagonal systems of Eqs. (26)/(27).
    Consistent,
    /// Each node's force over its tributary length (area in axisymmetry).
    Lumped,
}

/// How the contact states (open, stick, slip) are decided in each iteration.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Decisions {
    /// Each node from the current iterate: its own contact force, gap and
    /// slip from where it was at the start of the increment (a semismooth
    /// Newton on the nodal complementarity conditions), friction of a
    /// sliding node consistently linearised (`contact::nodal`).
    #[default]
    Nodal,
    /// The paper's Section 3: traction recovery, segment resultants and
    /// Table 1, friction of a sliding segment held over the iteration.
    Paper,
}

/// How a pair's contact conditions are written.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ContactFormulation {
    /// The paper's: each contactor node held on the target segment it
    /// meets (`contact::node_to_segment`), its states decided by
    /// `decisions`.
    #[default]
    NodeToSegment,
    /// Weighted gaps integrated over the contactor against the target's
    /// interpolation, the multipliers its nodal tractions
    /// (`contact::mortar`), against a body.
    Mortar,
}

/// A contactor surface against a target (Section 2 of the paper).
#[derive(Clone, Debug, PartialEq)]
pub struct ContactPair {
    pub name: String,
    /// The body the contactor nodes belong to.
    pub body: usize,
    /// Contactor surface nodes in order, the body on the left from one to
    /// the next (8-node sides contribute their mid-side nodes).
    pub contactor: Vec<usize>,
    /// The contactor surface is a closed loop: a last segment joins the last
    /// node back to the first (no node is listed twice).
    pub closed: bool,
    pub target: Target,
    pub mu_s: f64,
    pub mu_d: f64,
    pub rule: FrictionRule,
    pub recovery: Recovery,
    pub decisions: Decisions,
    pub formulation: ContactFormulation,
}

impl ContactPair {
    /// The coefficient that holds a sticking node (`ever_slid`: it has
    /// slid before): under the usual rule mu_s until it first slides and
    /// mu_d from then on; under the experiment's, mu_s throughout.
    pub fn sticking_mu(&self, ever_slid: bool) -> f64 {
        match self.rule {
            FrictionRule::MuDAfterSlip if ever_slid => self.mu_d,
            _ => self.mu_s,
        }
    }
}

/// Newton control. The force tolerance is relative to the problem's force
/// scale (element forces, reactions, contact forces), the displacement and
/// energy tolerances to the first correction of the increment
/// (docs/contact.md section 8).
#[derive(Clone, Debug, PartialEq)]
pub struct SolverSettings {
    pub force_tolerance: f64,
    pub displacement_tolerance: f64,
    pub energy_tolerance: f64,
    pub max_iterations: usize,
    pub max_bisections: usize,
}

impl SolverSettings {
    /// The force and displacement tolerances are ratios of norms summed
    /// over the unknowns. Below 1e-14 (about 50 units of f64's round-off,
    /// 2.2e-16) they ask for less than the round-off of those norms, which
    /// Newton cannot reach (an increment then fails after every bisection);
    /// above 0.1 an iterate 10% out of balance passes as converged.
    pub const RELATIVE_TOLERANCE: RangeInclusive<f64> = 1e-14..=1e-1;
    /// The energy tolerance is the product of a force and a displacement
    /// ratio (docs/contact.md section 8): the squares of their bounds.
    pub const ENERGY_TOLERANCE: RangeInclusive<f64> = 1e-28..=1e-2;
    /// Newton converging quadratically needs fewer than 10 iterations; a
    /// linear rate as slow as 0.97 per iteration (the paper's fixed-point
    /// friction is far faster) gains the 13 orders from the first residual
    /// to round-off within 1000 (0.97^1000 = 6e-14). More only turns an
    /// increment that does not converge into one that runs for hours.
    pub const MAX_ITERATIONS: RangeInclusive<usize> = 1..=1000;
    /// 52 halvings take an increment down to the resolution of f64 relative
    /// to it; 12 more leave room for sub-increments that fail later. Each
    /// bisection costs a failed Newton solve, so a larger budget only
    /// multiplies the time a failing step takes.
    pub const MAX_BISECTIONS: RangeInclusive<usize> = 0..=64;

    /// Each setting within its range; the error names the scene key, the
    /// value and the range.
    pub fn check(&self) -> Result<(), String> {
        let reals = [
            (
                "force_tolerance",
                self.force_tolerance,
                Self::RELATIVE_TOLERANCE,
            ),
            (
                "displacement_tolerance",
                self.displacement_tolerance,
                Self::RELATIVE_TOLERANCE,
            ),
            (
                "energy_tolerance",
                self.energy_tolerance,
                Self::ENERGY_TOLERANCE,
            ),
        ];
        for (key, value, range) in reals {
            check_range(value, &range).map_err(|msg| format!("solver.{key} = {value:?}: {msg}"))?;
        }
        let counts = [
            ("max_iterations", self.max_iterations, Self::MAX_ITERATIONS),
            ("max_bisections", self.max_bisections, Self::MAX_BISECTIONS),
        ];
        for (key, value, range) in counts {
            check_range(value, &range).map_err(|msg| format!("solver.{key} = {value}: {msg}"))?;
        }
        Ok(())
    }
}

/// `value` within `range`, or why not (NaN is in no range).
pub fn check_range<T: PartialOrd + std::fmt::Debug>(
    value: T,
    range: &RangeInclusive<T>,
) -> Result<(), String> {
    if range.contains(&value) {
        Ok(())
    } else {
        Err(format!(
            "must lie in [{:?}, {:?}]",
            range.start(),
            range.end()
        ))
    }
}

impl Default for SolverSettings {
    fn default() -> Self {
        SolverSettings {
            force_tolerance: 1e-8,
            displacement_tolerance: 1e-8,
            energy_tolerance: 1e-16,
            max_iterations: 25,
            max_bisections: 6,
        }
    }
}

/// Everything the solver needs.
#[derive(Clone, Debug)]
pub struct Problem {
    pub name: String,
    pub analysis: AnalysisKind,
    pub kinematics: Kinematics,
    pub mesh: Mesh,
    /// Material index of each element of `mesh`.
    pub element_material: Vec<usize>,
    pub materials: Vec<Material>,
    pub bodies: Vec<Body>,
    pub functions: Vec<TimeFunction>,
    pub drivers: Vec<Driver>,
    pub rigids: Vec<Rigid>,
    pub contacts: Vec<ContactPair>,
    /// Multi-point constraints tying one body's nodes to another's surface.
    pub ties: Vec<crate::constraint::Tie>,
    pub pressures: Vec<Pressure>,
    pub forces: Vec<NodalForce>,
    pub body_forces: Vec<BodyForce>,
    pub initial_stresses: Vec<InitialStress>,
    /// End times of the increments of the scene's own load history.
    pub times: Vec<f64>,
    pub solver: SolverSettings,
    pub units: Units,
    /// The scene's `[parameters]` (FMU parameters; the scene already
    /// carries their values wherever its expressions use them).
    pub parameters: Vec<Parameter>,
    /// What the scene reader noticed and did not refuse (a contact pair
    /// that starts overlapped): the command line prints them, the FMU logs
    /// them as warnings.
    pub warnings: Vec<String>,
}

/// A scene parameter: its name (an FMU parameter of that name) and value.
#[derive(Clone, Debug, PartialEq)]
pub struct Parameter {
    pub name: String,
    pub value: f64,
    /// The value the scene file gives (before any override).
    pub default: f64,
}

/// Length unit of a scene's coordinates and displacements.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize)]
pub enum LengthUnit {
    #[default]
    #[serde(rename = "m")]
    Metre,
    #[serde(rename = "mm")]
    Millimetre,
}

/// Force unit of a scene's loads and results.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize)]
pub enum ForceUnit {
    #[default]
    #[serde(rename = "N")]
    Newton,
    #[serde(rename = "kN")]
    Kilonewton,
}

/// The units a scene is written in: stresses are force / length^2. The
/// solver does not use them; the FMU declares them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Units {
    pub length: LengthUnit,
    pub force: ForceUnit,
}

/// Young's modulus must be positive.
pub fn check_modulus(e: f64) -> Result<(), String> {
    if e > 0.0 && e.is_finite() {
        Ok(())
    } else {
        Err("Young's modulus must be positive and finite".into())
    }
}

/// Poisson's ratio; 0.5 (incompressible) only where the thickness is free to
/// change (plane stress).
pub fn check_poisson(kind: AnalysisKind, nu: f64) -> Result<(), String> {
    let (ok, rule) = match kind {
        AnalysisKind::PlaneStress { .. } => {
            (nu > -1.0 && nu <= 0.5, "-1 < nu <= 0.5 in plane stress")
        }
        AnalysisKind::PlaneStrain { .. } => {
            (nu > -1.0 && nu < 0.5, "-1 < nu < 0.5 in plane strain")
        }
        AnalysisKind::Axisymmetric => (
            nu > -1.0 && nu < 0.5,
            "-1 < nu < 0.5 in axisymmetric analysis",
        ),
    };
    if ok {
        Ok(())
    } else {
        Err(format!("Poisson's ratio must satisfy {rule}"))
    }
}

/// Mooney-Rivlin C1 (half the initial shear modulus when C2 = 0).
pub fn check_c1(c1: f64) -> Result<(), String> {
    if c1 > 0.0 && c1.is_finite() {
        Ok(())
    } else {
        Err("C1 must be positive and finite".into())
    }
}

/// Mooney-Rivlin C2.
pub fn check_c2(c2: f64) -> Result<(), String> {
    if c2 >= 0.0 && c2.is_finite() {
        Ok(())
    } else {
        Err("C2 must be finite and not negative".into())
    }
}

/// Poisson's ratio of the von Mises law: its elastic part is 3D (the plane
/// stress condition is met by iteration), so nu = 0.5 is excluded everywhere.
pub fn check_plastic_poisson(nu: f64) -> Result<(), String> {
    if nu > -1.0 && nu < 0.5 {
        Ok(())
    } else {
        Err("Poisson's ratio must satisfy -1 < nu < 0.5 for von_mises".into())
    }
}

/// Initial yield stress of the von Mises law.
pub fn check_yield_stress(sigma_y: f64) -> Result<(), String> {
    if sigma_y > 0.0 && sigma_y.is_finite() {
        Ok(())
    } else {
        Err("the yield stress must be positive and finite".into())
    }
}

/// Linear isotropic hardening modulus (0: perfectly plastic).
pub fn check_hardening(h: f64) -> Result<(), String> {
    if h >= 0.0 && h.is_finite() {
        Ok(())
    } else {
        Err("the hardening modulus must be finite and not negative".into())
    }
}

/// The analysis a material model needs, if it is restricted.
pub fn check_model_analysis(
    spec: &MaterialSpec,
    kind: AnalysisKind,
    kinematics: Kinematics,
) -> Result<(), String> {
    match spec {
        MaterialSpec::LinearElastic { .. } => Ok(()),
        MaterialSpec::MooneyRivlin { .. } => {
            if matches!(kind, AnalysisKind::PlaneStress { .. })
                && kinematics == Kinematics::TotalLagrangian
            {
                Ok(())
            } else {
                Err("mooney_rivlin needs analysis.kind = \"plane_stress\" and analysis.kinematics = \"total_lagrangian\" (incompressible rubber thins freely only in plane stress; it is a large-strain law)".into())
            }
        }
        MaterialSpec::VonMises { .. } => {
            if kinematics == Kinematics::MaterialNonlinearOnly {
                Ok(())
            } else {
                Err("von_mises needs analysis.kinematics = \"mno\" (a small-strain, nonlinear law: \"small_strain\" is for linear laws, and it is not a large-strain law for \"total_lagrangian\")".into())
            }
        }
    }
}

/// A friction coefficient must be finite and not negative.
pub fn check_coefficient(mu: f64) -> Result<(), String> {
    if mu >= 0.0 && mu.is_finite() {
        Ok(())
    } else {
        Err("a friction coefficient must be finite and not negative".into())
    }
}

impl Material {
    /// The model's constants by name, in the scene's order.
    pub fn constants(&self) -> Vec<(&'static str, f64)> {
        match self.spec {
            MaterialSpec::LinearElastic { e, nu } => vec![("E", e), ("nu", nu)],
            MaterialSpec::MooneyRivlin { c1, c2 } => vec![("C1", c1), ("C2", c2)],
            MaterialSpec::VonMises { e, nu, sigma_y, h } => {
                vec![("E", e), ("nu", nu), ("sigma_y", sigma_y), ("H", h)]
            }
        }
    }

    /// Replace a constant (checked later, with the others, by
    /// `Problem::check_parameters`).
    pub fn set_constant(&mut self, name: &str, value: f64) -> Result<(), String> {
        match (&mut self.spec, name) {
            (MaterialSpec::LinearElastic { e, .. }, "E") => *e = value,
            (MaterialSpec::LinearElastic { nu, .. }, "nu") => *nu = value,
            (MaterialSpec::MooneyRivlin { c1, .. }, "C1") => *c1 = value,
            (MaterialSpec::MooneyRivlin { c2, .. }, "C2") => *c2 = value,
            (MaterialSpec::VonMises { e, .. }, "E") => *e = value,
            (MaterialSpec::VonMises { nu, .. }, "nu") => *nu = value,
            (MaterialSpec::VonMises { sigma_y, .. }, "sigma_y") => *sigma_y = value,
            (MaterialSpec::VonMises { h, .. }, "H") => *h = value,
            _ => return Err(format!("material '{}' has no constant '{name}'", self.name)),
        }
        Ok(())
    }
}

impl Problem {
    /// The path of the strip a pair's contactor lies on, if it does.
    pub fn contactor_strip(&self, pair: &ContactPair) -> Option<&crate::strip::StripPath> {
        let first = *pair.contactor.first()?;
        let body = self.bodies.iter().find(|b| b.nodes.contains(&first))?;
        body.strip.as_ref()
    }

    /// Nodal displacements at t = 0: zero, but a strip's nodes start laid
    /// along its path (its reference mesh is straight).
    pub fn initial_u(&self) -> Vec<f64> {
        let mut u = vec![0.0; 2 * self.mesh.nodes.len()];
        for b in &self.bodies {
            let Some(path) = &b.strip else { continue };
            for n in b.nodes.clone() {
                let x = self.mesh.nodes[n];
                let q = path.place(x);
                u[2 * n] = q[0] - x[0];
                u[2 * n + 1] = q[1] - x[1];
            }
        }
        u
    }

    /// Range checks of the values an FMU may override: material constants,
    /// friction coefficients, Newton control. The error names the value.
    pub fn check_parameters(&self) -> Result<(), String> {
        for m in &self.materials {
            match m.spec {
                MaterialSpec::LinearElastic { e, nu } => {
                    check_modulus(e).map_err(|msg| format!("{}.E = {e:?}: {msg}", m.name))?;
                    check_poisson(self.analysis, nu)
                        .map_err(|msg| format!("{}.nu = {nu:?}: {msg}", m.name))?;
                }
                MaterialSpec::MooneyRivlin { c1, c2 } => {
                    check_c1(c1).map_err(|msg| format!("{}.C1 = {c1:?}: {msg}", m.name))?;
                    check_c2(c2).map_err(|msg| format!("{}.C2 = {c2:?}: {msg}", m.name))?;
                }
                MaterialSpec::VonMises { e, nu, sigma_y, h } => {
                    check_modulus(e).map_err(|msg| format!("{}.E = {e:?}: {msg}", m.name))?;
                    check_plastic_poisson(nu)
                        .map_err(|msg| format!("{}.nu = {nu:?}: {msg}", m.name))?;
                    check_yield_stress(sigma_y)
                        .map_err(|msg| format!("{}.sigma_y = {sigma_y:?}: {msg}", m.name))?;
                    check_hardening(h).map_err(|msg| format!("{}.H = {h:?}: {msg}", m.name))?;
                }
            }
        }
        for c in &self.contacts {
            for (key, mu) in [("mu_s", c.mu_s), ("mu_d", c.mu_d)] {
                check_coefficient(mu).map_err(|msg| format!("{}.{key} = {mu:?}: {msg}", c.name))?;
            }
            if c.mu_d > c.mu_s {
                return Err(format!(
                    "{}.mu_d = {:?}: mu_d must not exceed mu_s = {:?}",
                    c.name, c.mu_d, c.mu_s
                ));
            }
        }
        self.solver.check()
    }
}
