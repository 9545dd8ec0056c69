//! The scene reader: a good scene resolves to exact numbers, and every class
//! of mistake is reported with file, line, key and value.

use contact2d::mesh::{Edge, ElementKind, Mesh, generators};
use contact2d::problem::{
    AnalysisKind, ContactFormulation, FrictionRule, Kinematics, MaterialSpec, Recovery, Scaled,
    Target,
};
use contact2d::scene::{self, SceneError, SceneErrorKind};
use std::path::Path;

/// A valid scene; the error tests each change one thing in it.
const BASE: &str = r#"title = "base"

[analysis]
kind = "plane_strain"

[[material]]
name = "steel"
model = "linear_elastic"
E = 200000.0
nu = 0.3

[[body]]
name = "block"
material = "steel"
mesh = { generator = "rectangle", origin = [0.0, 0.0], size = [2.0, 1.0], divisions = [2, 1] }

[[body]]
name = "wheel"
material = "steel"
mesh = { generator = "disk", center = [1.0, 3.0], radius = 2.0, divisions = 2, ratio = 1.0 }

[[function]]
name = "ramp"
points = [[0.0, 0.0], [1.0, 1.0]]

[[driver]]
name = "base"
set = "block.bottom"
ux = 0.0
uy = 0.0

[[driver]]
name = "press"
set = "wheel.top"
uy = { function = "ramp", scale = -0.1 }

[[pressure]]
set = "block.top"
value = 1.0

[[body_force]]
body = "block"
by = -1.0

[[initial_stress]]
body = "wheel"
yy = 5.0

[steps]
dt = 0.5
t_end = 1.0

[solver]
force_tolerance = 1e-8
max_iterations = 20
"#;

const FILE: &str = "scenes/t.toml";

/// Two bodies and every kind of load; `steps` given as dt and t_end.
const TWO_BODIES: &str = r#"
[analysis]
kind = "plane_stress"
thickness = 2.0
kinematics = "mno"

[[material]]
name = "steel"
model = "linear_elastic"
E = 200000.0
nu = 0.3

[[material]]
name = "rubber"
model = "linear_elastic"
E = 10
nu = 0.5

[[body]]
name = "block"
material = "rubber"
mesh = { generator = "rectangle", origin = [0.0, -1.0], size = [4.0, 1.0], divisions = [4, 2] }

[[body]]
name = "wheel"
material = "steel"
element = "q8"
mesh = { generator = "disk", center = [0.0, 3.0], radius = 3.0, divisions = 4, ratio = 2.0 }

[[function]]
name = "ramp"
points = [[0.0, 0.0], [1.0, 1.0]]

[[function]]
name = "hold"
points = [[0.0, 0.0], [0.5, 1.0], [2.0, 1.0]]

[[driver]]
name = "base"
set = "block.bottom"
ux = 0.0
uy = 0

[[driver]]
name = "press"
set = "wheel.top"
uy = { function = "ramp", scale = -0.1 }

[[driver]]
name = "side"
set = "block.left"
ux = { function = "hold" }

[[pressure]]
set = "block.right"
value = { function = "ramp", scale = 5.0 }
follower = false

[[pressure]]
set = "wheel.arc"
value = 2.5

[[body_force]]
body = "block"
by = -9.81

[[initial_stress]]
body = "wheel"
yy = 300.0
xy = 1.5

[steps]
dt = 0.3
t_end = 1.0

[solver]
force_tolerance = 1e-6
max_iterations = 40
"#;

/// The edges of a body's own mesh, numbered as in the merged mesh.
fn shifted(edges: &[Edge], nodes: usize, elements: usize) -> Vec<Edge> {
    let shift = |e: &Edge| Edge {
        element: e.element + elements,
        face: e.face,
        nodes: e.nodes.iter().map(|n| n + nodes).collect(),
    };
    edges.iter().map(shift).collect()
}

fn set(mesh: &Mesh, name: &str, offset: usize) -> Vec<usize> {
    mesh.node_sets[name].iter().map(|n| n + offset).collect()
}

#[test]
fn two_bodies_resolve_to_exact_numbers() {
    let p = scene::parse(TWO_BODIES, Path::new("scenes/two_bodies.toml")).unwrap();
    let block = generators::rectangle(ElementKind::Q4, [0.0, -1.0], [4.0, 1.0], [4, 2], [1.0, 1.0])
        .unwrap();
    let wheel = generators::disk(ElementKind::Q8, [0.0, 3.0], 3.0, 4, 2.0, false).unwrap();
    let (nb, eb) = (block.nodes.len(), block.elements.len());
    let (nw, ew) = (wheel.nodes.len(), wheel.elements.len());
    assert_eq!((nb, eb), (15, 8));

    assert_eq!(p.name, "two_bodies");
    assert_eq!(p.analysis, AnalysisKind::PlaneStress { thickness: 2.0 });
    assert_eq!(p.kinematics, Kinematics::MaterialNonlinearOnly);
    assert_eq!(
        p.materials[1].spec,
        MaterialSpec::LinearElastic { e: 10.0, nu: 0.5 }
    );

    assert_eq!(p.mesh.nodes.len(), nb + nw);
    assert_eq!(p.mesh.elements.len(), eb + ew);
    assert_eq!(
        (p.bodies[0].nodes.clone(), p.bodies[0].elements.clone()),
        (0..nb, 0..eb)
    );
    assert_eq!(
        (p.bodies[1].nodes.clone(), p.bodies[1].elements.clone()),
        (nb..nb + nw, eb..eb + ew)
    );
    assert_eq!((p.bodies[0].material, p.bodies[1].material), (1, 0));
    assert_eq!(p.element_material, [vec![1; eb], vec![0; ew]].concat());
    assert_eq!(p.mesh.nodes[nb], wheel.nodes[0]);
    assert_eq!(p.mesh.elements[eb].kind, ElementKind::Q8);
    assert_eq!(
        p.mesh.elements[eb].nodes,
        wheel.elements[0]
            .nodes
            .iter()
            .map(|n| n + nb)
            .collect::<Vec<_>>()
    );
    for name in [
        "block.bottom",
        "block.top_left",
        "wheel.contact_point",
        "wheel.top",
    ] {
        assert!(p.mesh.node_sets.contains_key(name), "{name}");
    }
    assert!(p.mesh.edge_sets.contains_key("wheel.arc"));
    assert_eq!(
        p.mesh.element_sets["wheel.all"],
        (eb..eb + ew).collect::<Vec<_>>()
    );

    let names: Vec<&str> = p.functions.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(names, ["ramp", "hold"]);
    assert_eq!(
        p.functions[1].points,
        vec![(0.0, 0.0), (0.5, 1.0), (2.0, 1.0)]
    );

    let [base, press, side] = &p.drivers[..] else {
        panic!("three drivers")
    };
    assert_eq!(
        (base.name.as_str(), press.name.as_str(), side.name.as_str()),
        ("base", "press", "side")
    );
    assert_eq!(base.nodes, set(&block, "bottom", 0));
    assert_eq!(
        (base.ux.clone(), base.uy.clone()),
        (Some(Scaled::constant(0.0)), Some(Scaled::constant(0.0)))
    );
    assert_eq!(press.nodes, set(&wheel, "top", nb));
    assert_eq!(press.ux, None);
    assert_eq!(
        press.uy,
        Some(Scaled {
            scale: -0.1,
            function: Some(0)
        })
    );
    assert_eq!(side.nodes, set(&block, "left", 0));
    assert_eq!(
        side.ux,
        Some(Scaled {
            scale: 1.0,
            function: Some(1)
        })
    );
    assert_eq!(side.uy, None);

    assert_eq!(p.pressures.len(), 2);
    assert_eq!(p.pressures[0].edges, block.edge_sets["right"]);
    assert_eq!(
        p.pressures[0].value,
        Scaled {
            scale: 5.0,
            function: Some(0)
        }
    );
    assert!(!p.pressures[0].follower);
    assert_eq!(
        p.pressures[1].edges,
        shifted(&wheel.edge_sets["arc"], nb, eb)
    );
    assert_eq!(p.pressures[1].value, Scaled::constant(2.5));
    assert!(p.pressures[1].follower);

    assert_eq!(p.body_forces.len(), 1);
    assert_eq!(p.body_forces[0].body, 0);
    assert_eq!(
        (p.body_forces[0].bx.clone(), p.body_forces[0].by.clone()),
        (Scaled::constant(0.0), Scaled::constant(-9.81))
    );
    assert_eq!(p.initial_stresses.len(), 1);
    assert_eq!(
        (p.initial_stresses[0].body, p.initial_stresses[0].stress),
        (1, [0.0, 300.0, 0.0, 1.5])
    );
    assert!(p.forces.is_empty());

    // dt = 0.3 up to 1.0: the last increment is the shorter 0.1.
    assert_eq!(p.times, vec![0.3, 0.6, 3.0 * 0.3, 1.0]);
    assert_eq!(p.solver.force_tolerance, 1e-6);
    assert_eq!(p.solver.max_iterations, 40);
    assert_eq!(p.solver.displacement_tolerance, 1e-8);
    assert_eq!(p.solver.max_bisections, 6);
}

#[test]
fn steps_as_a_list_of_times() {
    let text = TWO_BODIES.replace("dt = 0.3\nt_end = 1.0", "times = [0.25, 1, 2.5]");
    let p = scene::parse(&text, Path::new("two_bodies.toml")).unwrap();
    assert_eq!(p.times, vec![0.25, 1.0, 2.5]);
    // dt dividing t_end: no extra step.
    let text = TWO_BODIES.replace("dt = 0.3", "dt = 0.25");
    let p = scene::parse(&text, Path::new("two_bodies.toml")).unwrap();
    assert_eq!(p.times, vec![0.25, 0.5, 0.75, 1.0]);
}

#[test]
fn defaults() {
    let text = r#"
[analysis]
kind = "axisymmetric"
[[material]]
name = "m"
model = "linear_elastic"
E = 1.0
nu = 0.0
[[body]]
name = "b"
material = "m"
[body.mesh]
generator = "ring"
center = [0.0, 0.0]
r_inner = 1.0
r_outer = 2.0
angles = [0.0, 90.0]
divisions = [2, 3]
[steps]
times = [1.0]
"#;
    let p = scene::parse(text, Path::new("dir/ring.toml")).unwrap();
    let ring = generators::ring(
        ElementKind::Q4,
        [0.0, 0.0],
        1.0,
        2.0,
        [0.0, 90.0],
        [2, 3],
        1.0,
    )
    .unwrap();
    assert_eq!(p.name, "ring");
    assert_eq!(p.analysis, AnalysisKind::Axisymmetric);
    assert_eq!(p.kinematics, Kinematics::SmallStrain);
    assert_eq!(p.mesh.nodes, ring.nodes);
    assert_eq!(p.mesh.elements[0].kind, ElementKind::Q4);
    assert_eq!(p.solver, contact2d::problem::SolverSettings::default());
    assert!(p.drivers.is_empty());
}

/// BASE with the first `old` replaced by `new`, parsed; it must fail.
fn bad(old: &str, new: &str) -> SceneError {
    assert!(BASE.contains(old), "BASE has no {old:?}");
    let text = BASE.replacen(old, new, 1);
    match scene::parse(&text, Path::new(FILE)) {
        Ok(_) => panic!("scene with {new:?} was accepted"),
        Err(e) => e,
    }
}

fn assert_error(e: &SceneError, kind: SceneErrorKind, expected: &str) {
    assert_eq!(e.to_string(), expected);
    assert_eq!(e.kind, kind, "{e}");
}

#[test]
fn base_scene_is_valid() {
    let p = scene::parse(BASE, Path::new(FILE)).unwrap();
    assert_eq!(p.name, "base");
    assert_eq!(p.times, vec![0.5, 1.0]);
    assert_eq!(p.solver.max_iterations, 20);
}

#[test]
fn syntax_error() {
    let e = bad("nu = 0.3", "nu = 0.3.1");
    assert_error(
        &e,
        SceneErrorKind::Syntax,
        "scenes/t.toml:10: material[0].nu = 0.3.1: TOML syntax: invalid float",
    );
    let e = bad(r#"name = "wheel""#, r#"name = "wheel"#);
    assert_error(
        &e,
        SceneErrorKind::Syntax,
        r#"scenes/t.toml:18: body[1].name = "wheel: TOML syntax: invalid basic string, expected `"`"#,
    );
    let e = bad("dt = 0.5", "dt = 0.5\ndt = 0.25");
    assert_error(
        &e,
        SceneErrorKind::Syntax,
        "scenes/t.toml:51: steps.dt = 0.25: TOML syntax: duplicate key",
    );
}

#[test]
fn unknown_key_lists_the_allowed_keys() {
    let e = bad("nu = 0.3", "nu = 0.3\nmu = 0.2");
    assert_error(
        &e,
        SceneErrorKind::UnknownKey,
        "scenes/t.toml:11: material[0].mu = 0.2: unknown key; allowed keys: name, model, E, nu",
    );
    // A generator's own keys are listed, not every generator's.
    let e = bad("ratio = 1.0 }", "ratio = 1.0, size = [1.0, 1.0] }");
    assert_error(
        &e,
        SceneErrorKind::UnknownKey,
        "scenes/t.toml:20: body[1].mesh.size = [1.0, 1.0]: unknown key; \
         allowed keys: generator, center, radius, divisions, ratio, half",
    );
    let e = bad("[steps]", "[[gap]]\nwidth = 1\n\n[steps]");
    assert_error(
        &e,
        SceneErrorKind::UnknownKey,
        "scenes/t.toml:49: gap = [[gap]]: unknown key; allowed keys: title, analysis, material, body, \
         node_set, function, driver, rigid, contact, tie, pressure, force, body_force, initial_stress, \
         steps, solver, units, parameters",
    );
    let e = bad(
        "uy = { function = \"ramp\", scale = -0.1 }",
        "uy = { function = \"ramp\", factor = -0.1 }",
    );
    assert_error(
        &e,
        SceneErrorKind::UnknownKey,
        "scenes/t.toml:35: driver[1].uy.factor = -0.1: unknown key; allowed keys: function, scale",
    );
}

#[test]
fn missing_key() {
    let e = bad("nu = 0.3\n", "");
    assert_error(
        &e,
        SceneErrorKind::MissingKey,
        "scenes/t.toml:6: material[0].nu = (missing): required key is missing",
    );
    let e = bad("radius = 2.0, ", "");
    assert_error(
        &e,
        SceneErrorKind::MissingKey,
        "scenes/t.toml:20: body[1].mesh.radius = (missing): required key is missing",
    );
    let e = bad("[steps]\ndt = 0.5\nt_end = 1.0\n", "");
    assert_error(
        &e,
        SceneErrorKind::MissingKey,
        "scenes/t.toml:1: steps = (missing): required key is missing",
    );
    let e = bad("kind = \"plane_strain\"", "kinematics = \"mno\"");
    assert_error(
        &e,
        SceneErrorKind::MissingKey,
        "scenes/t.toml:3: analysis.kind = (missing): required key is missing",
    );
    let e = bad("t_end = 1.0", "");
    assert_error(
        &e,
        SceneErrorKind::MissingKey,
        "scenes/t.toml:49: steps.t_end = (missing): dt needs t_end",
    );
    let e = bad("ux = 0.0\nuy = 0.0\n", "");
    assert_error(
        &e,
        SceneErrorKind::MissingKey,
        "scenes/t.toml:26: driver[0].ux = (missing): a driver prescribes at least one component: ux or fx, uy or fy",
    );
    let e = bad("generator = \"disk\", ", "");
    assert_error(
        &e,
        SceneErrorKind::MissingKey,
        "scenes/t.toml:20: body[1].mesh.generator = (missing): \
         a mesh needs `generator` (rectangle, disk, ring, plate_with_hole, strip) or `file`",
    );
}

#[test]
fn wrong_type() {
    let e = bad("E = 200000.0", "E = \"stiff\"");
    assert_error(
        &e,
        SceneErrorKind::WrongType,
        r#"scenes/t.toml:9: material[0].E = "stiff": expected a number, found string "stiff""#,
    );
    let e = bad("divisions = 2,", "divisions = [2, 2],");
    assert_error(
        &e,
        SceneErrorKind::WrongType,
        "scenes/t.toml:20: body[1].mesh.divisions = [2, 2]: expected a non-negative integer, found an array",
    );
    let e = bad("divisions = [2, 1]", "divisions = [2, -1]");
    assert_error(
        &e,
        SceneErrorKind::WrongType,
        "scenes/t.toml:15: body[0].mesh.divisions[1] = -1: expected a non-negative integer, found integer `-1`",
    );
    let e = bad("value = 1.0", "value = \"high\"");
    assert_error(
        &e,
        SceneErrorKind::WrongType,
        r#"scenes/t.toml:39: pressure[0].value = "high": expected a number or a table { function = "name", scale = number }, found string "high""#,
    );
    let e = bad("kind = \"plane_strain\"", "kind = 2");
    assert_error(
        &e,
        SceneErrorKind::WrongType,
        "scenes/t.toml:4: analysis.kind = 2: expected a string",
    );
    let e = bad("size = [2.0, 1.0]", "size = [2.0, 1.0, 3.0]");
    assert_error(
        &e,
        SceneErrorKind::WrongType,
        "scenes/t.toml:15: body[0].mesh.size = [2.0, 1.0, 3.0]: expected an array of 2 values, found 3 values",
    );
}

#[test]
fn unknown_word() {
    let e = bad("kind = \"plane_strain\"", "kind = \"plane\"");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        r#"scenes/t.toml:4: analysis.kind = "plane": must be one of: plane_strain, plane_stress, axisymmetric"#,
    );
    let e = bad("model = \"linear_elastic\"", "model = \"elastic\"");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        r#"scenes/t.toml:8: material[0].model = "elastic": must be one of: linear_elastic, mooney_rivlin, von_mises"#,
    );
    let e = bad("generator = \"disk\"", "generator = \"circle\"");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        r#"scenes/t.toml:20: body[1].mesh.generator = "circle": must be one of: rectangle, disk, ring, plate_with_hole, strip"#,
    );
    let e = bad(
        "name = \"wheel\"\nmaterial = \"steel\"",
        "name = \"wheel\"\nmaterial = \"steel\"\nelement = \"q9\"",
    );
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        r#"scenes/t.toml:20: body[1].element = "q9": must be one of: q4, q8"#,
    );
}

#[test]
fn material_constants_out_of_range() {
    let e = bad("nu = 0.3", "nu = 0.5");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:10: material[0].nu = 0.5: Poisson's ratio must satisfy -1 < nu < 0.5 in plane strain",
    );
    let e = bad("nu = 0.3", "nu = -1.0");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:10: material[0].nu = -1.0: Poisson's ratio must satisfy -1 < nu < 0.5 in plane strain",
    );
    let plane_stress = BASE.replace("kind = \"plane_strain\"", "kind = \"plane_stress\"");
    assert!(
        scene::parse(
            &plane_stress.replace("nu = 0.3", "nu = 0.5"),
            Path::new(FILE)
        )
        .is_ok()
    );
    let e = scene::parse(
        &plane_stress.replace("nu = 0.3", "nu = 0.51"),
        Path::new(FILE),
    )
    .unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:10: material[0].nu = 0.51: Poisson's ratio must satisfy -1 < nu <= 0.5 in plane stress",
    );
    let e = bad(
        "kind = \"plane_strain\"\n\n[[material]]\nname = \"steel\"\nmodel = \"linear_elastic\"\nE = 200000.0\nnu = 0.3",
        "kind = \"axisymmetric\"\n\n[[material]]\nname = \"steel\"\nmodel = \"linear_elastic\"\nE = 200000.0\nnu = 0.5",
    );
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:10: material[0].nu = 0.5: Poisson's ratio must satisfy -1 < nu < 0.5 in axisymmetric analysis",
    );
    let e = bad("E = 200000.0", "E = 0");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:9: material[0].E = 0: Young's modulus must be positive",
    );
}

/// BASE's material as `material` (the lines after `model =`), under the
/// analysis lines `analysis`, parsed.
fn with_material(
    analysis: &str,
    model: &str,
    constants: &str,
) -> Result<contact2d::problem::Problem, SceneError> {
    let old = "kind = \"plane_strain\"\n\n[[material]]\nname = \"steel\"\nmodel = \"linear_elastic\"\nE = 200000.0\nnu = 0.3\n";
    assert!(BASE.contains(old));
    let new =
        format!("{analysis}\n\n[[material]]\nname = \"steel\"\nmodel = \"{model}\"\n{constants}\n");
    scene::parse(&BASE.replacen(old, &new, 1), Path::new(FILE))
}

#[test]
fn nonlinear_material_models() {
    let rubber_analysis = "kind = \"plane_stress\"\nkinematics = \"total_lagrangian\"";
    let rubber = "C1 = 0.3\nC2 = 0.1";
    let p = with_material(rubber_analysis, "mooney_rivlin", rubber).unwrap();
    assert_eq!(
        p.materials[0].spec,
        MaterialSpec::MooneyRivlin { c1: 0.3, c2: 0.1 }
    );
    assert_eq!(p.materials[0].constants(), vec![("C1", 0.3), ("C2", 0.1)]);
    let plastic_analysis = "kind = \"plane_strain\"\nkinematics = \"mno\"";
    let steel = "E = 200000.0\nnu = 0.3\nsigma_y = 250.0\nH = 1000.0";
    let p = with_material(plastic_analysis, "von_mises", steel).unwrap();
    assert_eq!(
        p.materials[0].spec,
        MaterialSpec::VonMises {
            e: 200000.0,
            nu: 0.3,
            sigma_y: 250.0,
            h: 1000.0
        }
    );
    // Each law only where it applies, reported at the `model` line.
    for (analysis, model, constants, rule) in [
        (
            "kind = \"plane_strain\"\nkinematics = \"total_lagrangian\"",
            "mooney_rivlin",
            rubber,
            "mooney_rivlin needs",
        ),
        (
            "kind = \"plane_stress\"\nkinematics = \"mno\"",
            "mooney_rivlin",
            rubber,
            "mooney_rivlin needs",
        ),
        (
            "kind = \"plane_strain\"",
            "von_mises",
            steel,
            "von_mises needs",
        ),
        (
            "kind = \"plane_strain\"\nkinematics = \"total_lagrangian\"",
            "von_mises",
            steel,
            "von_mises needs",
        ),
    ] {
        let e = with_material(analysis, model, constants).unwrap_err();
        let line = 8 + analysis.lines().count() - 1;
        let head =
            format!("scenes/t.toml:{line}: material[0].model = \"{model}\": {rule} analysis.");
        assert!(e.to_string().starts_with(&head), "{e}");
        assert_eq!(e.kind, SceneErrorKind::InvalidValue);
    }
    // Constants out of range, at their own lines.
    for (model, analysis, constants, old, new, expected) in [
        (
            "mooney_rivlin",
            rubber_analysis,
            rubber,
            "C1 = 0.3",
            "C1 = 0.0",
            "10: material[0].C1 = 0.0: C1 must be positive and finite",
        ),
        (
            "mooney_rivlin",
            rubber_analysis,
            rubber,
            "C2 = 0.1",
            "C2 = -0.1",
            "11: material[0].C2 = -0.1: C2 must be finite and not negative",
        ),
        (
            "von_mises",
            plastic_analysis,
            steel,
            "nu = 0.3",
            "nu = 0.5",
            "11: material[0].nu = 0.5: Poisson's ratio must satisfy -1 < nu < 0.5 for von_mises",
        ),
        (
            "von_mises",
            plastic_analysis,
            steel,
            "sigma_y = 250.0",
            "sigma_y = 0.0",
            "12: material[0].sigma_y = 0.0: the yield stress must be positive and finite",
        ),
        (
            "von_mises",
            plastic_analysis,
            steel,
            "H = 1000.0",
            "H = -1.0",
            "13: material[0].H = -1.0: the hardening modulus must be finite and not negative",
        ),
    ] {
        let e = with_material(analysis, model, &constants.replace(old, new)).unwrap_err();
        assert_error(
            &e,
            SceneErrorKind::InvalidValue,
            &format!("scenes/t.toml:{expected}"),
        );
    }
    // A model's own keys, no others.
    let e = with_material(
        rubber_analysis,
        "mooney_rivlin",
        "C1 = 0.3\nC2 = 0.1\nE = 1.0",
    )
    .unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::UnknownKey,
        "scenes/t.toml:12: material[0].E = 1.0: unknown key; allowed keys: name, model, C1, C2",
    );
    let e = with_material(plastic_analysis, "von_mises", "E = 1.0\nnu = 0.3\nH = 1.0").unwrap_err();
    assert_eq!(e.kind, SceneErrorKind::MissingKey, "{e}");
    assert!(
        e.to_string().contains("material[0].sigma_y = (missing)"),
        "{e}"
    );
}

#[test]
fn analysis_out_of_range() {
    let e = bad(
        "kind = \"plane_strain\"",
        "kind = \"plane_strain\"\nthickness = 0.0",
    );
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:5: analysis.thickness = 0.0: thickness must be positive",
    );
    let e = bad(
        "kind = \"plane_strain\"",
        "kind = \"axisymmetric\"\nthickness = 1.0",
    );
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:5: analysis.thickness = 1.0: axisymmetric analysis has no thickness (it works on the full circle)",
    );
}

#[test]
fn mesh_values_out_of_range() {
    let e = bad("radius = 2.0", "radius = -2.0");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:20: body[1].mesh.radius = -2.0: radius must be positive",
    );
    let e = bad("divisions = 2,", "divisions = 0,");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:20: body[1].mesh.divisions = 0: divisions must be at least 1",
    );
    let e = bad("divisions = [2, 1]", "divisions = [0, 1]");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:15: body[0].mesh.divisions = [0, 1]: divisions must be at least 1",
    );
    let e = bad("ratio = 1.0", "ratio = 0.0");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:20: body[1].mesh.ratio = 0.0: ratio must be positive",
    );
    let e = bad(
        "divisions = [2, 1]",
        "divisions = [2, 1], ratio = [1.0, -2.0]",
    );
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:15: body[0].mesh.ratio = [1.0, -2.0]: both ratio components must be positive",
    );
    let e = bad("size = [2.0, 1.0]", "size = [2.0, 0.0]");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:15: body[0].mesh.size = [2.0, 0.0]: both size components must be positive",
    );
}

#[test]
fn ring_and_plate_bounds() {
    let disk =
        r#"generator = "disk", center = [1.0, 3.0], radius = 2.0, divisions = 2, ratio = 1.0"#;
    let ring = r#"generator = "ring", center = [0.0, 0.0], r_inner = 2.0, r_outer = 2.0, angles = [0, 90], divisions = [2, 4]"#;
    let e = bad(disk, ring);
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:20: body[1].mesh.r_outer = 2.0: must exceed r_inner = 2.0",
    );
    let e = bad(
        disk,
        &ring
            .replace("r_outer = 2.0", "r_outer = 3.0")
            .replace("[0, 90]", "[90, 0]"),
    );
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:20: body[1].mesh.angles = [90, 0]: the second value must exceed the first",
    );
    let plate = r#"generator = "plate_with_hole", hole_radius = 1.0, width = 0.5, y_range = [0, 5], divisions = [4, 4], ratio = 2.0"#;
    let e = bad(disk, plate);
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:20: body[1].mesh.width = 0.5: must exceed hole_radius = 1.0",
    );
}

#[test]
fn non_finite_numbers_anywhere() {
    let e = bad("radius = 2.0", "radius = nan");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:20: body[1].mesh.radius = nan: numbers must be finite",
    );
    let e = bad(
        "points = [[0.0, 0.0], [1.0, 1.0]]",
        "points = [[0.0, 0.0], [1.0, inf]]",
    );
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:24: function[0].points[1][1] = inf: numbers must be finite",
    );
    let e = bad("yy = 5.0", "yy = -inf");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:47: initial_stress[0].yy = -inf: numbers must be finite",
    );
    let e = bad("scale = -0.1", "scale = 1e999");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:35: driver[1].uy.scale = 1e999: numbers must be finite",
    );
}

#[test]
fn times_out_of_order() {
    let e = bad(
        "points = [[0.0, 0.0], [1.0, 1.0]]",
        "points = [[0.0, 0.0], [1.0, 1.0], [1.0, 2.0]]",
    );
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:24: function[0].points[2] = [1.0, 2.0]: times must be strictly increasing (1.0 follows 1.0)",
    );
    let e = bad("dt = 0.5\nt_end = 1.0", "times = [0.5, 1.5, 1.0]");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:50: steps.times[2] = 1.0: times must be strictly increasing (1.0 follows 1.5)",
    );
    let e = bad("dt = 0.5\nt_end = 1.0", "times = [0.0, 1.0]");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:50: steps.times[0] = 0.0: times must be positive",
    );
    let e = bad("dt = 0.5\nt_end = 1.0", "times = []");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:50: steps.times = []: at least one time is required",
    );
    let e = bad("dt = 0.5", "dt = 0.5\ntimes = [1.0]");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:51: steps.times = [1.0]: give either times, or dt and t_end, not both",
    );
}

/// Newton settings outside their ranges (issue 35, item 5; the ranges and
/// their reasons are `contact2d::problem::SolverSettings`'s): refused with
/// the key, the value and the range; the ends of each range are accepted.
#[test]
fn solver_settings_outside_their_ranges() {
    let cases = [
        (
            "force_tolerance = 5e-324",
            54,
            "force_tolerance",
            "[1e-14, 0.1]",
        ),
        (
            "force_tolerance = 0.5",
            54,
            "force_tolerance",
            "[1e-14, 0.1]",
        ),
        (
            "displacement_tolerance = 1e-15",
            54,
            "displacement_tolerance",
            "[1e-14, 0.1]",
        ),
        (
            "energy_tolerance = 1e-30",
            54,
            "energy_tolerance",
            "[1e-28, 0.01]",
        ),
        (
            "energy_tolerance = 0.1",
            54,
            "energy_tolerance",
            "[1e-28, 0.01]",
        ),
    ];
    for (line, at, key, range) in cases {
        let e = bad("force_tolerance = 1e-8", line);
        let value = line.split(" = ").nth(1).unwrap();
        assert_error(
            &e,
            SceneErrorKind::InvalidValue,
            &format!("scenes/t.toml:{at}: solver.{key} = {value}: {key} must lie in {range}"),
        );
    }
    for (line, key, range) in [
        ("max_iterations = 1000000", "max_iterations", "[1, 1000]"),
        (
            "max_iterations = 20\nmax_bisections = 65",
            "max_bisections",
            "[0, 64]",
        ),
    ] {
        let e = bad("max_iterations = 20", line);
        let (at, value) = match line.split_once('\n') {
            Some((_, second)) => (56, second.split(" = ").nth(1).unwrap()),
            None => (55, line.split(" = ").nth(1).unwrap()),
        };
        assert_error(
            &e,
            SceneErrorKind::InvalidValue,
            &format!("scenes/t.toml:{at}: solver.{key} = {value}: {key} must lie in {range}"),
        );
    }
    let edges = BASE
        .replacen(
            "force_tolerance = 1e-8",
            "force_tolerance = 1e-14\ndisplacement_tolerance = 0.1\nenergy_tolerance = 1e-28",
            1,
        )
        .replacen(
            "max_iterations = 20",
            "max_iterations = 1000\nmax_bisections = 64",
            1,
        );
    let p = scene::parse(&edges, Path::new(FILE)).unwrap();
    assert_eq!(
        (
            p.solver.force_tolerance,
            p.solver.displacement_tolerance,
            p.solver.energy_tolerance
        ),
        (1e-14, 0.1, 1e-28)
    );
    assert_eq!(
        (p.solver.max_iterations, p.solver.max_bisections),
        (1000, 64)
    );
}

#[test]
fn steps_and_solver_out_of_range() {
    let e = bad("dt = 0.5", "dt = 0.0");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:50: steps.dt = 0.0: dt must be positive",
    );
    let e = bad("t_end = 1.0", "t_end = -1");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:51: steps.t_end = -1: t_end must be positive",
    );
    let e = bad("dt = 0.5", "dt = 1e-9");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:50: steps.dt = 1e-9: t_end / dt = 1000000000 increments; at most 1000000",
    );
    let e = bad("force_tolerance = 1e-8", "force_tolerance = 0.0");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:54: solver.force_tolerance = 0.0: force_tolerance must lie in [1e-14, 0.1]",
    );
    let e = bad("force_tolerance = 1e-8", "energy_tolerance = -1e-16");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:54: solver.energy_tolerance = -1e-16: energy_tolerance must lie in [1e-28, 0.01]",
    );
    let e = bad("max_iterations = 20", "max_iterations = 0");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:55: solver.max_iterations = 0: max_iterations must lie in [1, 1000]",
    );
}

#[test]
fn unknown_references() {
    let e = bad("material = \"steel\"", "material = \"iron\"");
    assert_error(
        &e,
        SceneErrorKind::UnknownReference,
        r#"scenes/t.toml:14: body[0].material = "iron": no material of that name; materials: steel"#,
    );
    let e = bad("body = \"block\"", "body = \"brick\"");
    assert_error(
        &e,
        SceneErrorKind::UnknownReference,
        r#"scenes/t.toml:42: body_force[0].body = "brick": no body of that name; bodies: block, wheel"#,
    );
    let e = bad("function = \"ramp\"", "function = \"rmap\"");
    assert_error(
        &e,
        SceneErrorKind::UnknownReference,
        r#"scenes/t.toml:35: driver[1].uy.function = "rmap": no function of that name; functions: ramp"#,
    );
    let e = bad("set = \"wheel.top\"", "set = \"tyre.top\"");
    assert_error(
        &e,
        SceneErrorKind::UnknownReference,
        r#"scenes/t.toml:34: driver[1].set = "tyre.top": no body of that name; bodies: block, wheel"#,
    );
    let e = bad("set = \"block.top\"", "set = \"block.lid\"");
    assert_error(
        &e,
        SceneErrorKind::UnknownReference,
        r#"scenes/t.toml:38: pressure[0].set = "block.lid": body `block` has no edge set `lid`; available edge sets: bottom, left, right, top"#,
    );
    let e = bad("set = \"block.bottom\"", "set = \"block.base\"");
    let block_sets = "bottom, bottom_left, bottom_right, left, right, top, top_left, top_right";
    assert_error(
        &e,
        SceneErrorKind::UnknownReference,
        &format!(
            r#"scenes/t.toml:28: driver[0].set = "block.base": body `block` has no set `base`; available sets: {block_sets}"#
        ),
    );
    let e = bad("set = \"block.top\"", "set = \"block.top_left\"");
    assert_error(
        &e,
        SceneErrorKind::UnknownReference,
        r#"scenes/t.toml:38: pressure[0].set = "block.top_left": `top_left` is a node set; this needs an edge set; edge sets of `block`: bottom, left, right, top"#,
    );
    let e = bad("set = \"block.bottom\"", "set = \"bottom\"");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        r#"scenes/t.toml:28: driver[0].set = "bottom": a set is named <body>.<set>"#,
    );
}

#[test]
fn duplicate_and_bad_names() {
    let e = bad("name = \"wheel\"", "name = \"block\"");
    assert_error(
        &e,
        SceneErrorKind::Duplicate,
        r#"scenes/t.toml:18: body[1].name = "block": duplicate body name"#,
    );
    let e = bad("name = \"press\"", "name = \"base\"");
    assert_error(
        &e,
        SceneErrorKind::Duplicate,
        r#"scenes/t.toml:33: driver[1].name = "base": duplicate driver name"#,
    );
    let e = bad(
        "[[driver]]",
        "[[function]]\nname = \"ramp\"\npoints = [[0.0, 1.0]]\n\n[[driver]]",
    );
    assert_error(
        &e,
        SceneErrorKind::Duplicate,
        r#"scenes/t.toml:27: function[1].name = "ramp": duplicate function name"#,
    );
    let e = bad(
        "[[body]]",
        "[[material]]\nname = \"steel\"\nmodel = \"linear_elastic\"\nE = 1.0\nnu = 0.0\n\n[[body]]",
    );
    assert_error(
        &e,
        SceneErrorKind::Duplicate,
        r#"scenes/t.toml:13: material[1].name = "steel": duplicate material name"#,
    );
    let e = bad("name = \"wheel\"", "name = \"big.wheel\"");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        r#"scenes/t.toml:18: body[1].name = "big.wheel": a body name must not contain '.' (sets are named <body>.<set>)"#,
    );
    let e = bad("name = \"press\"", "name = \"press.y\"");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        r#"scenes/t.toml:33: driver[1].name = "press.y": a driver name must not contain '.'"#,
    );
    // Names that begin FMU variable names follow FMI 2.0's structured
    // naming (model descriptions declare it): identifiers between dots.
    let fmi = "so by FMI 2.0's structured naming each part between '.' must be a letter or '_' followed by letters, digits or '_'";
    let e = bad("name = \"press\"", "name = \"press-1\"");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        &format!(
            r#"scenes/t.toml:33: driver[1].name = "press-1": a driver name begins the FMU's variable names ('press-1.<key>'), {fmi}"#
        ),
    );
    let e = bad("name = \"steel\"", "name = \"steel.2a\"");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        &format!(
            r#"scenes/t.toml:7: material[0].name = "steel.2a": a material name begins the FMU's variable names ('steel.2a.<key>'), {fmi}"#
        ),
    );
    // Bodies, functions and ties are not in variable names: no such rule.
    let ok = scene::parse(&BASE.replace("\"wheel", "\"wheel-2"), Path::new(FILE));
    assert!(ok.is_ok(), "{ok:?}");
}

#[test]
fn scene_files_on_disk() {
    let e = scene::load(Path::new("tests/data/scenes/syntax.toml")).unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::Syntax,
        "tests/data/scenes/syntax.toml:9: material[0].nu = [0.3: TOML syntax: unclosed array, expected `]`",
    );
    let e = scene::load(Path::new("tests/data/scenes/element_with_file.toml")).unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        r#"tests/data/scenes/element_with_file.toml:14: body[0].element = "q8": a mesh file brings its own element kind; remove `element`"#,
    );
    let e = scene::load(Path::new("tests/data/scenes/no_such_scene.toml")).unwrap_err();
    assert_eq!(e.kind, SceneErrorKind::Io);
    assert!(
        e.to_string()
            .starts_with("tests/data/scenes/no_such_scene.toml:1: (file) = "),
        "{e}"
    );
}

#[test]
fn unreadable_mesh_file_names_the_scene_line() {
    let e = scene::load(Path::new("tests/data/scenes/missing_mesh.toml")).unwrap_err();
    assert_eq!(e.kind, SceneErrorKind::Mesh);
    let prefix =
        r#"tests/data/scenes/missing_mesh.toml:14: body[0].mesh.file = "meshes/none.msh": "#;
    let text = e.to_string();
    assert!(text.starts_with(prefix), "{text}");
    // The mesh reader's own message, with the resolved path.
    assert!(
        e.message.contains("tests/data/scenes/meshes/none.msh"),
        "{text}"
    );
}

/// Two unit quads side by side: physical surfaces "left_block" and
/// "right_block", physical curve "base" under both.
const TWO_QUADS_MSH: &str = "$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
3
1 1 \"base\"
2 2 \"left_block\"
2 3 \"right_block\"
$EndPhysicalNames
$Entities
0 1 2 0
1 0 0 0 2 0 0 1 1 0
1 0 0 0 1 1 0 1 2 0
2 1 0 0 2 1 0 1 3 0
$EndEntities
$Nodes
1 6 1 6
2 1 0 6
1
2
3
4
5
6
0 0 0
1 0 0
2 0 0
0 1 0
1 1 0
2 1 0
$EndNodes
$Elements
3 4 1 4
1 1 1 2
1 1 2
2 2 3
2 1 3 1
3 1 2 5 4
2 2 3 1
4 2 3 6 5
$EndElements
";

#[test]
fn gmsh_file_and_group() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("scene_gmsh");
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    std::fs::write(dir.join("meshes/quads.msh"), TWO_QUADS_MSH).unwrap();
    let scene_text = |group: &str| {
        format!(
            "[analysis]\nkind = \"plane_strain\"\n\n[[material]]\nname = \"m\"\nmodel = \"linear_elastic\"\n\
             E = 1.0\nnu = 0.25\n\n[[body]]\nname = \"b\"\nmaterial = \"m\"\n\
             mesh = {{ file = \"meshes/quads.msh\"{group} }}\n\n[steps]\ntimes = [1.0]\n"
        )
    };
    let path = dir.join("quads.toml");
    std::fs::write(&path, scene_text("")).unwrap();
    let p = scene::load(&path).unwrap();
    assert_eq!((p.mesh.nodes.len(), p.mesh.elements.len()), (6, 2));
    assert_eq!(p.bodies[0].elements, 0..2);
    assert!(p.mesh.element_sets.contains_key("b.right_block"));
    assert_eq!(p.mesh.edge_sets["b.base"].len(), 2);

    std::fs::write(&path, scene_text(", group = \"right_block\"")).unwrap();
    let p = scene::load(&path).unwrap();
    assert_eq!(p.mesh.elements.len(), 1);
    assert_eq!(p.element_material, vec![0]);

    std::fs::write(&path, scene_text(", group = \"lid\"")).unwrap();
    let e = scene::load(&path).unwrap_err();
    let expected = format!(
        "{}:13: body[0].mesh.group = \"lid\": the mesh file has no 2D physical group of that name; \
         groups: left_block, right_block",
        path.display()
    );
    assert_error(&e, SceneErrorKind::UnknownReference, &expected);
}

/// BASE with `extra` appended before `[steps]`, parsed.
fn with(extra: &str) -> Result<contact2d::problem::Problem, SceneError> {
    let text = BASE.replacen("[steps]", &format!("{extra}\n[steps]"), 1);
    scene::parse(&text, Path::new(FILE))
}

#[test]
fn node_sets_by_location_and_nodal_forces() {
    // block: 2 x 1 Q4 elements over [0, 2] x [0, 1], nodes on a 3 x 2 grid.
    let p = with(
        "[[node_set]]\nname = \"block.corner\"\nnearest = [2.1, 1.05]\n\n\
         [[node_set]]\nname = \"block.right_side\"\nbox = [[1.5, -1.0], [2.0, 2.0]]\n\n\
         [[force]]\nset = \"block.corner\"\nfy = { function = \"ramp\", scale = -3.0 }\n\n\
         [[force]]\nset = \"block.right_side\"\nfx = 2.0\n",
    )
    .unwrap();
    let corner = &p.mesh.node_sets["block.corner"];
    assert_eq!(corner.len(), 1);
    assert_eq!(p.mesh.nodes[corner[0]], [2.0, 1.0]);
    let mut side: Vec<[f64; 2]> = p.mesh.node_sets["block.right_side"]
        .iter()
        .map(|&n| p.mesh.nodes[n])
        .collect();
    side.sort_by(|a, b| a[1].total_cmp(&b[1]));
    assert_eq!(side, vec![[2.0, 0.0], [2.0, 1.0]]);
    assert_eq!(p.forces.len(), 2);
    assert_eq!(p.forces[0].nodes, *corner);
    assert_eq!(p.forces[0].fx, Scaled::constant(0.0));
    assert_eq!(p.forces[0].fy.scale, -3.0);
    assert_eq!(p.forces[0].fy.function, Some(0));
    assert_eq!(p.forces[1].fx, Scaled::constant(2.0));

    let e =
        with("[[node_set]]\nname = \"block.empty\"\nbox = [[5.0, 5.0], [6.0, 6.0]]\n").unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:51: node_set[0].box = [[5.0, 5.0], [6.0, 6.0]]: no node of body `block` \
         lies in this box; the body spans [[0, 0], [2, 1]]",
    );
    let e = with("[[node_set]]\nname = \"block.top\"\nnearest = [0.0, 0.0]\n").unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::Duplicate,
        r#"scenes/t.toml:50: node_set[0].name = "block.top": a set of that name already exists"#,
    );
    let e = with("[[node_set]]\nname = \"block.p\"\n").unwrap_err();
    assert_eq!(e.kind, SceneErrorKind::MissingKey, "{e}");
    assert!(e.to_string().contains("node_set[0].nearest"), "{e}");
    let e = with("[[force]]\nset = \"block.nowhere\"\nfx = 1.0\n").unwrap_err();
    assert_eq!(e.kind, SceneErrorKind::UnknownReference, "{e}");
    assert!(
        e.to_string().starts_with("scenes/t.toml:50: force[0].set"),
        "{e}"
    );
    let e = with("[[force]]\nset = \"block.top\"\n").unwrap_err();
    assert_eq!(e.kind, SceneErrorKind::MissingKey, "{e}");
    assert!(e.to_string().contains("force[0].fx"), "{e}");
}

/// Two bodies in contact and two rigids: a Q8 half disk ("wheel") on a Q4
/// block, the block on a rigid floor, the wheel in a rigid cup (an arc).
const CONTACT: &str = r#"
[analysis]
kind = "plane_strain"

[[material]]
name = "steel"
model = "linear_elastic"
E = 200000.0
nu = 0.3

[[body]]
name = "block"
material = "steel"
mesh = { generator = "rectangle", origin = [0.0, 0.0], size = [2.0, 1.0], divisions = [2, 1] }

[[body]]
name = "wheel"
material = "steel"
element = "q8"
mesh = { generator = "disk", center = [1.0, 3.0], radius = 2.0, divisions = 2, ratio = 1.0, half = true }

[[function]]
name = "ramp"
points = [[0.0, 0.0], [1.0, 1.0]]

[[driver]]
name = "press"
set = "wheel.top"
uy = { function = "ramp", scale = -0.1 }

[[rigid]]
name = "floor"
points = [[3.0, 0.0], [-1.0, 0.0]]

[[rigid]]
name = "cup"
arc = { center = [1.0, 3.0], radius = 2.5, angles = [0.0, -180.0], segments = 4 }
reference = [1.0, 0.5]
ux = { function = "ramp", scale = 0.5 }
uy = -0.25
theta = 0.1

[[contact]]
name = "wheel_on_block"
contactor = "wheel.arc"
target = "block.top"
mu_s = 0.3
mu_d = 0.2
rule = "always_mu_s"
recovery = "lumped"

[[contact]]
name = "block_on_floor"
contactor = "block.bottom"
target = "floor"

[[contact]]
name = "block_under_wheel"
contactor = "block.top"
target = "wheel.arc"
mu_s = 0.25

[[contact]]
name = "wheel_in_cup"
contactor = "wheel.arc"
target = "cup"

[steps]
times = [1.0]
"#;

fn cross(o: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
}

fn assert_points_near(actual: &[[f64; 2]], expected: &[[f64; 2]]) {
    assert_eq!(actual.len(), expected.len(), "{actual:?}");
    for (a, e) in actual.iter().zip(expected) {
        assert!(
            (a[0] - e[0]).abs() <= 1e-12 && (a[1] - e[1]).abs() <= 1e-12,
            "{actual:?} != {expected:?}"
        );
    }
}

#[test]
fn contact_pairs_and_rigids_resolve() {
    let p = scene::parse(CONTACT, Path::new("scenes/contact.toml")).unwrap();
    let wheel = generators::disk(ElementKind::Q8, [1.0, 3.0], 2.0, 2, 1.0, true).unwrap();
    let nb = 6; // block: 3 x 2 nodes
    assert_eq!(p.bodies[1].nodes.start, nb);
    let x = |n: usize| p.mesh.nodes[n];

    // Rigids: a polyline as given, an arc from 0 to -180 degrees clockwise.
    let [floor, cup] = &p.rigids[..] else {
        panic!("two rigids")
    };
    assert_eq!(floor.name, "floor");
    assert_eq!(floor.points, vec![[3.0, 0.0], [-1.0, 0.0]]);
    assert_eq!(floor.reference, [3.0, 0.0]);
    for c in [&floor.ux, &floor.uy, &floor.theta] {
        assert_eq!(*c, Scaled::constant(0.0));
    }
    assert_eq!(cup.name, "cup");
    let h = 2.5 * std::f64::consts::FRAC_1_SQRT_2;
    assert_points_near(
        &cup.points,
        &[
            [3.5, 3.0],
            [1.0 + h, 3.0 - h],
            [1.0, 0.5],
            [1.0 - h, 3.0 - h],
            [-1.5, 3.0],
        ],
    );
    assert_eq!(cup.reference, [1.0, 0.5]);
    assert_eq!(
        cup.ux,
        Scaled {
            scale: 0.5,
            function: Some(0)
        }
    );
    assert_eq!(cup.uy, Scaled::constant(-0.25));
    assert_eq!(cup.theta, Scaled::constant(0.1));

    let [
        wheel_on_block,
        block_on_floor,
        block_under_wheel,
        wheel_in_cup,
    ] = &p.contacts[..]
    else {
        panic!("four pairs")
    };

    // The Q8 arc walked with increasing x (the wheel above it, on the left),
    // each side start, mid-side, end.
    let arc = shifted(&wheel.edge_sets["arc"], nb, 2);
    let c = &wheel_on_block.contactor;
    assert_eq!(wheel_on_block.name, "wheel_on_block");
    assert_eq!(wheel_on_block.body, 1);
    assert!(!wheel_on_block.closed);
    assert_eq!(c.len(), 2 * arc.len() + 1);
    let mut sorted = c.clone();
    sorted.sort_unstable();
    assert_eq!(sorted, set(&wheel, "arc", nb));
    assert_eq!((x(c[0]), x(c[c.len() - 1])), ([-1.0, 3.0], [3.0, 3.0]));
    for w in c.windows(2) {
        assert!(x(w[1])[0] > x(w[0])[0], "{:?} then {:?}", x(w[0]), x(w[1]));
        assert!(
            cross(x(w[0]), x(w[1]), [1.0, 3.0]) > 0.0,
            "wheel not on the left"
        );
    }
    for k in 0..arc.len() {
        let side = [c[2 * k], c[2 * k + 2], c[2 * k + 1]];
        assert!(arc.iter().any(|e| e.nodes == side), "side {k}: {side:?}");
    }
    assert_eq!(
        wheel_on_block.target,
        Target::Body {
            body: 0,
            segments: vec![[5, 4], [4, 3]],
            smooth: None,
        }
    );
    assert_eq!((x(5), x(4), x(3)), ([2.0, 1.0], [1.0, 1.0], [0.0, 1.0]));
    assert_eq!((wheel_on_block.mu_s, wheel_on_block.mu_d), (0.3, 0.2));
    assert_eq!(wheel_on_block.rule, FrictionRule::AlwaysMuS);
    assert_eq!(wheel_on_block.recovery, Recovery::Lumped);

    // Defaults; the block's bottom in +x (the block above, on its left).
    assert_eq!(block_on_floor.body, 0);
    let bottom: Vec<[f64; 2]> = block_on_floor.contactor.iter().map(|&n| x(n)).collect();
    assert_eq!(bottom, vec![[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]);
    assert!(!block_on_floor.closed);
    assert_eq!(block_on_floor.target, Target::Rigid(0));
    assert_eq!((block_on_floor.mu_s, block_on_floor.mu_d), (0.0, 0.0));
    assert_eq!(block_on_floor.rule, FrictionRule::MuDAfterSlip);
    assert_eq!(block_on_floor.recovery, Recovery::Consistent);

    // The block's top walked in -x; a Q8 target side gives two segments,
    // start to mid-side and mid-side to end, the wheel on their left.
    let top: Vec<[f64; 2]> = block_under_wheel.contactor.iter().map(|&n| x(n)).collect();
    assert_eq!(top, vec![[2.0, 1.0], [1.0, 1.0], [0.0, 1.0]]);
    assert_eq!(
        (block_under_wheel.mu_s, block_under_wheel.mu_d),
        (0.25, 0.25)
    );
    let Target::Body { body, segments, .. } = &block_under_wheel.target else {
        panic!("a body target")
    };
    assert_eq!(*body, 1);
    let expected: Vec<[usize; 2]> = arc
        .iter()
        .flat_map(|e| [[e.nodes[0], e.nodes[2]], [e.nodes[2], e.nodes[1]]])
        .collect();
    assert_eq!(*segments, expected);
    for s in segments {
        assert!(cross(x(s[0]), x(s[1]), [1.0, 3.0]) > 0.0);
    }
    assert_eq!(wheel_in_cup.target, Target::Rigid(1));
    assert_eq!(wheel_in_cup.contactor, *c);
}

#[test]
fn closed_contactor_loop_lists_each_node_once() {
    let ring = r#"mesh = { generator = "ring", center = [1.0, 3.0], r_inner = 1.0, r_outer = 2.0, angles = [0.0, 360.0], divisions = [1, 6] }"#;
    let text = CONTACT
        .replace(
            r#"mesh = { generator = "disk", center = [1.0, 3.0], radius = 2.0, divisions = 2, ratio = 1.0, half = true }"#,
            ring,
        )
        .replace("\"wheel.top\"", "\"wheel.inner\"")
        .replace("\"wheel.arc\"", "\"wheel.outer\"");
    let p = scene::parse(&text, Path::new("ring.toml")).unwrap();
    let mesh = generators::ring(
        ElementKind::Q8,
        [1.0, 3.0],
        1.0,
        2.0,
        [0.0, 360.0],
        [1, 6],
        1.0,
    )
    .unwrap();
    let outer = shifted(&mesh.edge_sets["outer"], 6, 2);
    let pair = &p.contacts[0];
    assert!(pair.closed);
    // Six Q8 sides: six corners and six mid-side nodes, none repeated,
    // counter-clockwise (the ring inside, on the left), from the set's
    // first side on.
    let c = &pair.contactor;
    assert_eq!(c.len(), 12);
    let mut sorted = c.clone();
    sorted.sort_unstable();
    assert_eq!(sorted, set(&mesh, "outer", 6));
    assert_eq!(
        c[..3],
        [outer[0].nodes[0], outer[0].nodes[2], outer[0].nodes[1]]
    );
    for k in 0..12 {
        let (a, b) = (p.mesh.nodes[c[k]], p.mesh.nodes[c[(k + 1) % 12]]);
        assert!(cross([1.0, 3.0], a, b) > 0.0, "{a:?} then {b:?}");
    }
    // An open chain is not closed.
    assert!(!p.contacts[1].closed);
}

#[test]
fn contact_reference_errors() {
    let pair = |contactor: &str, target: &str| {
        with(&format!(
            "[[rigid]]\nname = \"floor\"\npoints = [[3.0, 0.0], [-1.0, 0.0]]\n\n\
             [[contact]]\nname = \"c\"\ncontactor = \"{contactor}\"\ntarget = \"{target}\"\n"
        ))
        .unwrap_err()
    };
    let e = pair("block.lid", "floor");
    assert_error(
        &e,
        SceneErrorKind::UnknownReference,
        r#"scenes/t.toml:55: contact[0].contactor = "block.lid": body `block` has no edge set `lid`; available edge sets: bottom, left, right, top"#,
    );
    let e = pair("tyre.arc", "floor");
    assert_error(
        &e,
        SceneErrorKind::UnknownReference,
        r#"scenes/t.toml:55: contact[0].contactor = "tyre.arc": no body of that name; bodies: block, wheel"#,
    );
    let e = pair("arc", "floor");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        r#"scenes/t.toml:55: contact[0].contactor = "arc": a set is named <body>.<set>"#,
    );
    let e = pair("block.top_left", "floor");
    assert_error(
        &e,
        SceneErrorKind::UnknownReference,
        r#"scenes/t.toml:55: contact[0].contactor = "block.top_left": `top_left` is a node set; this needs an edge set; edge sets of `block`: bottom, left, right, top"#,
    );
    let e = pair("wheel.arc", "block.lid");
    assert_error(
        &e,
        SceneErrorKind::UnknownReference,
        r#"scenes/t.toml:56: contact[0].target = "block.lid": body `block` has no edge set `lid`; available edge sets: bottom, left, right, top"#,
    );
    let e = pair("wheel.arc", "brick.top");
    assert_error(
        &e,
        SceneErrorKind::UnknownReference,
        r#"scenes/t.toml:56: contact[0].target = "brick.top": no body of that name; bodies: block, wheel"#,
    );
    let e = pair("wheel.arc", "block.bottom_left");
    assert_error(
        &e,
        SceneErrorKind::UnknownReference,
        r#"scenes/t.toml:56: contact[0].target = "block.bottom_left": `bottom_left` is a node set; this needs an edge set; edge sets of `block`: bottom, left, right, top"#,
    );
    let e = pair("wheel.arc", "flor");
    assert_error(
        &e,
        SceneErrorKind::UnknownReference,
        r#"scenes/t.toml:56: contact[0].target = "flor": no rigid of that name (a body's edge set is written <body>.<set>); rigids: floor"#,
    );
    let e = pair("wheel.arc", "block");
    assert_error(
        &e,
        SceneErrorKind::UnknownReference,
        r#"scenes/t.toml:56: contact[0].target = "block": `block` is a body, not a rigid; a body target is one of its edge sets, `block.<set>` (edge sets: bottom, left, right, top); rigids: floor"#,
    );
    let e = pair("block.top", "block.bottom");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        r#"scenes/t.toml:56: contact[0].target = "block.bottom": the target must belong to another body than the contactor (`block`)"#,
    );
    // Without rigids.
    let e = with("[[contact]]\nname = \"c\"\ncontactor = \"wheel.arc\"\ntarget = \"floor\"\n")
        .unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::UnknownReference,
        r#"scenes/t.toml:52: contact[0].target = "floor": no rigid of that name (a body's edge set is written <body>.<set>); rigids: (none)"#,
    );
}

#[test]
fn contactor_must_be_one_chain() {
    // The plate's `axis` is two pieces, above and below the hole.
    let e = with(
        "[[body]]\nname = \"plate\"\nmaterial = \"steel\"\nmesh = { generator = \"plate_with_hole\", \
         hole_radius = 1.0, width = 3.0, y_range = [-3.0, 3.0], divisions = [2, 4] }\n\n\
         [[contact]]\nname = \"c\"\ncontactor = \"plate.axis\"\ntarget = \"block.top\"\n",
    )
    .unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        r#"scenes/t.toml:56: contact[0].contactor = "plate.axis": edge set `plate.axis` falls apart into 2 separate pieces: a chain from (0, 3) to (0, 1); a chain from (0, -1) to (0, -3); a contactor surface must be one chain or one closed loop"#,
    );
    // Two squares touching at a corner: their boundary branches there.
    let e = scene::load(Path::new("tests/data/scenes/pinched.toml")).unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        r#"tests/data/scenes/pinched.toml:23: contact[0].contactor = "pair.rim": edge set `pair.rim` branches at (1, 1): two of its edges start there; a contactor surface must be one chain or one closed loop"#,
    );
}

/// BASE with a floor and a pair `wheel.arc` on it, with `extra` lines in
/// the pair.
fn pair_with(extra: &str) -> Result<contact2d::problem::Problem, SceneError> {
    with(&format!(
        "[[rigid]]\nname = \"floor\"\npoints = [[3.0, 0.0], [-1.0, 0.0]]\n\n\
         [[contact]]\nname = \"c\"\ncontactor = \"wheel.arc\"\ntarget = \"floor\"\n{extra}"
    ))
}

#[test]
fn friction_coefficients_and_words() {
    let p = pair_with("mu_s = 0.5\nmu_d = 0.5\n").unwrap();
    assert_eq!((p.contacts[0].mu_s, p.contacts[0].mu_d), (0.5, 0.5));
    let p =
        pair_with("mu_s = 1\nmu_d = 0\nrule = \"mu_d_after_slip\"\nrecovery = \"consistent\"\n")
            .unwrap();
    assert_eq!((p.contacts[0].mu_s, p.contacts[0].mu_d), (1.0, 0.0));
    assert_eq!(p.contacts[0].rule, FrictionRule::MuDAfterSlip);
    assert_eq!(p.contacts[0].recovery, Recovery::Consistent);

    let e = pair_with("mu_s = -0.1\n").unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:57: contact[0].mu_s = -0.1: mu_s must not be negative",
    );
    let e = pair_with("mu_s = 0.2\nmu_d = -0.1\n").unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:58: contact[0].mu_d = -0.1: mu_d must not be negative",
    );
    let e = pair_with("mu_s = 0.2\nmu_d = 0.3\n").unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:58: contact[0].mu_d = 0.3: mu_d must not exceed mu_s = 0.2",
    );
    let e = pair_with("mu_d = 0.1\n").unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:57: contact[0].mu_d = 0.1: mu_d must not exceed mu_s = 0.0 (mu_s defaults to 0)",
    );
    let e = pair_with("mu_s = nan\n").unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:57: contact[0].mu_s = nan: numbers must be finite",
    );
    let e = pair_with("rule = \"coulomb\"\n").unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        r#"scenes/t.toml:57: contact[0].rule = "coulomb": must be one of: mu_d_after_slip, always_mu_s"#,
    );
    let e = pair_with("recovery = \"exact\"\n").unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        r#"scenes/t.toml:57: contact[0].recovery = "exact": must be one of: consistent, lumped"#,
    );
    let e = pair_with("friction = 0.3\n").unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::UnknownKey,
        "scenes/t.toml:57: contact[0].friction = 0.3: unknown key; \
         allowed keys: name, contactor, target, mu_s, mu_d, rule, recovery, decisions, formulation, smooth_target",
    );
    let e = pair_with("formulation = \"mortar\"\n").unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        r#"scenes/t.toml:57: contact[0].formulation = "mortar": mortar contact needs a body's edge set as target, not a rigid"#,
    );
    let e = pair_with("formulation = \"segment\"\n").unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        r#"scenes/t.toml:57: contact[0].formulation = "segment": must be one of: node_to_segment, mortar"#,
    );
    let p = pair_with("formulation = \"node_to_segment\"\n").unwrap();
    assert_eq!(p.contacts[0].formulation, ContactFormulation::NodeToSegment);
    let e = with("[[contact]]\nname = \"c\"\ncontactor = \"wheel.arc\"\n").unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::MissingKey,
        "scenes/t.toml:49: contact[0].target = (missing): required key is missing",
    );
}

/// `smooth_target = true` smooths a node-to-segment pair's body target
/// (each segment's outer neighbours along the surface; none at its ends),
/// and is refused with mortar, a rigid target or the paper's decisions.
#[test]
fn smooth_target_is_node_to_segment_s_against_a_body() {
    let pair = "[[contact]]\nname = \"c\"\ncontactor = \"wheel.arc\"\ntarget = \"block.top\"\n";
    let p = with(&format!(
        "{pair}formulation = \"node_to_segment\"\nsmooth_target = true\n"
    ))
    .unwrap();
    let Target::Body {
        segments, smooth, ..
    } = &p.contacts[0].target
    else {
        panic!("a body target");
    };
    let smooth = smooth.as_ref().expect("smoothed");
    assert_eq!(smooth.len(), segments.len());
    let last = segments.len() - 1;
    assert_eq!(smooth[0][0], None);
    assert_eq!(smooth[last][1], None);
    for j in 0..last {
        assert_eq!(smooth[j][1], Some(segments[j + 1][1]));
        assert_eq!(smooth[j + 1][0], Some(segments[j][0]));
    }
    assert!(!contact2d::contact::sensitivities(&p));
    let p = with(&format!(
        "{pair}formulation = \"node_to_segment\"\nsmooth_target = false\n"
    ))
    .unwrap();
    assert!(matches!(
        p.contacts[0].target,
        Target::Body { smooth: None, .. }
    ));
    assert!(contact2d::contact::sensitivities(&p));

    let e = with(&format!("{pair}smooth_target = true\n")).unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        r#"scenes/t.toml:53: contact[0].smooth_target = true: smooth_target smooths node-to-segment's target; mortar's normals are already continuous (set formulation = "node_to_segment")"#,
    );
    let e = with(&format!(
        "{pair}decisions = \"paper\"\nsmooth_target = true\n"
    ))
    .unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        r#"scenes/t.toml:54: contact[0].smooth_target = true: smooth_target needs the nodal decisions (decisions = "nodal")"#,
    );
    let e = pair_with("smooth_target = true\n").unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:57: contact[0].smooth_target = true: smooth_target needs a body's edge set as target, not a rigid",
    );
}

#[test]
fn duplicate_contact_and_rigid_names() {
    let e =
        pair_with("\n[[contact]]\nname = \"c\"\ncontactor = \"block.top\"\ntarget = \"floor\"\n")
            .unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::Duplicate,
        r#"scenes/t.toml:59: contact[1].name = "c": duplicate contact name"#,
    );
    let e =
        with("[[contact]]\nname = \"c.1\"\ncontactor = \"wheel.arc\"\ntarget = \"block.top\"\n")
            .unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        r#"scenes/t.toml:50: contact[0].name = "c.1": a contact name must not contain '.'"#,
    );
    let e = with("[[rigid]]\nname = \"press\"\npoints = [[0.0, 0.0], [1.0, 0.0]]\n").unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::Duplicate,
        r#"scenes/t.toml:50: rigid[0].name = "press": driver[1] has that name; rigids and drivers need distinct names (both report their reactions by name)"#,
    );
    let e = with(
        "[[rigid]]\nname = \"floor\"\npoints = [[0.0, 0.0], [1.0, 0.0]]\n\n\
         [[rigid]]\nname = \"floor\"\npoints = [[0.0, 1.0], [1.0, 1.0]]\n",
    )
    .unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::Duplicate,
        r#"scenes/t.toml:54: rigid[1].name = "floor": duplicate rigid name"#,
    );
    let e =
        with("[[rigid]]\nname = \"big.floor\"\npoints = [[0.0, 0.0], [1.0, 0.0]]\n").unwrap_err();
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        r#"scenes/t.toml:50: rigid[0].name = "big.floor": a rigid name must not contain '.' (a contact target with '.' is a body's edge set)"#,
    );
}

/// BASE with one rigid named "floor" made of `lines`.
fn rigid(lines: &str) -> SceneError {
    with(&format!("[[rigid]]\nname = \"floor\"\n{lines}\n")).unwrap_err()
}

#[test]
fn rigid_shape_errors() {
    let e = rigid("points = [[0.0, 0.0]]");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:51: rigid[0].points = [[0.0, 0.0]]: a rigid polyline needs at least 2 points",
    );
    let e = rigid("points = [[0.0, 0.0], [1.0, 0.0], [1, 0]]");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:51: rigid[0].points[2] = [1, 0]: repeats the point before it; consecutive points must differ",
    );
    let e = rigid("points = [[0.0, 0.0], [inf, 0.0]]");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:51: rigid[0].points[1][0] = inf: numbers must be finite",
    );
    let e = rigid(
        "points = [[0.0, 0.0], [1.0, 0.0]]\n\
         arc = { center = [0.0, 0.0], radius = 1.0, angles = [0.0, 90.0], segments = 2 }",
    );
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:52: rigid[0].arc = { center = [0.0, 0.0], radius = 1.0, angles = [0.0, 90.0], s ...: \
         give either `points` or `arc`, not both",
    );
    let e = rigid("ux = 1.0");
    assert_error(
        &e,
        SceneErrorKind::MissingKey,
        "scenes/t.toml:49: rigid[0].points = (missing): a rigid gives exactly one of \
         `points = [[x, y], ...]` or `arc = { center, radius, angles, segments }`",
    );
    let arc = |radius: &str, angles: &str, segments: &str| {
        rigid(&format!(
            "arc = {{ center = [0.0, 0.0], radius = {radius}, angles = {angles}, segments = {segments} }}"
        ))
    };
    let e = arc("0.0", "[0.0, 90.0]", "2");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:51: rigid[0].arc.radius = 0.0: radius must be positive",
    );
    let e = arc("1.0", "[90, 90.0]", "2");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:51: rigid[0].arc.angles = [90, 90.0]: \
         the two angles must differ (the arc runs from the first to the second)",
    );
    let e = arc("1.0", "[0.0, -400.0]", "2");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:51: rigid[0].arc.angles = [0.0, -400.0]: an arc spans at most 360 degrees",
    );
    let e = arc("1.0", "[0.0, 90.0]", "0");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:51: rigid[0].arc.segments = 0: segments must be at least 1",
    );
    let e = arc("1.0", "[0.0, 360.0]", "1");
    assert_error(
        &e,
        SceneErrorKind::InvalidValue,
        "scenes/t.toml:51: rigid[0].arc.segments = 1: a full circle needs at least 2 segments",
    );
    let e = arc("1.0", "[0.0, 90.0]", "2, sweep = 1.0");
    assert_error(
        &e,
        SceneErrorKind::UnknownKey,
        "scenes/t.toml:51: rigid[0].arc.sweep = 1.0: unknown key; \
         allowed keys: center, radius, angles, segments",
    );
    let e = rigid("points = [[0.0, 0.0], [1.0, 0.0]]\ncenter = [0.0, 0.0]");
    assert_error(
        &e,
        SceneErrorKind::UnknownKey,
        "scenes/t.toml:52: rigid[0].center = [0.0, 0.0]: unknown key; \
         allowed keys: name, points, arc, reference, ux, uy, theta",
    );
    let e = rigid("points = [[0.0, 0.0], [1.0, 0.0]]\ntheta = { function = \"spin\" }");
    assert_error(
        &e,
        SceneErrorKind::UnknownReference,
        r#"scenes/t.toml:52: rigid[0].theta.function = "spin": no function of that name; functions: ramp"#,
    );
}
