//! Problems for the solver tests: built in code, or read from the shipped
//! scenes with text edits (a refined mesh, another coefficient).
#![allow(dead_code)]

pub mod mortar;
pub mod stress;

use contact2d::mesh::{Edge, Element, ElementKind, Mesh};
use contact2d::problem::*;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// The text of the shipped scene `name` (a path under scenes/) with each
/// `(old, new)` replaced once (each `old` must occur), and its path.
pub fn scene_text(name: &str, edits: &[(&str, &str)]) -> (String, PathBuf) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name);
    let mut text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
    for (old, new) in edits {
        assert!(text.contains(old), "{name} has no {old:?}");
        text = text.replacen(old, new, 1);
    }
    (text, path)
}

/// The shipped scene `name` (a path under scenes/) with each `(old, new)`
/// replaced once; each `old` must occur.
pub fn shipped_scene(name: &str, edits: &[(&str, &str)]) -> Problem {
    let (text, path) = scene_text(name, edits);
    contact2d::scene::parse(&text, &path).unwrap_or_else(|e| panic!("{e}"))
}

/// A problem of one body with one linear elastic material.
pub fn problem(
    mesh: Mesh,
    analysis: AnalysisKind,
    kinematics: Kinematics,
    e: f64,
    nu: f64,
) -> Problem {
    let ne = mesh.elements.len();
    let nn = mesh.nodes.len();
    Problem {
        name: "test".into(),
        analysis,
        kinematics,
        mesh,
        element_material: vec![0; ne],
        materials: vec![Material {
            name: "m".into(),
            spec: MaterialSpec::LinearElastic { e, nu },
        }],
        bodies: vec![Body {
            name: "b".into(),
            material: 0,
            elements: 0..ne,
            nodes: 0..nn,
            strip: None,
            running: false,
        }],
        functions: vec![TimeFunction {
            name: "ramp".into(),
            points: vec![(0.0, 0.0), (1.0, 1.0)],
        }],
        drivers: vec![],
        rigids: vec![],
        contacts: vec![],
        ties: vec![],
        pressures: vec![],
        forces: vec![],
        body_forces: vec![],
        initial_stresses: vec![],
        times: vec![1.0],
        solver: SolverSettings::default(),
        units: Default::default(),
        parameters: Vec::new(),
        warnings: Vec::new(),
    }
}

/// Structured grid of Q4 or Q8 elements on [x0, x0+w] x [y0, y0+h], its nodes
/// moved by `distort(x, y)` (which must keep the boundary straight for patch tests).
pub fn grid(
    kind: ElementKind,
    origin: [f64; 2],
    size: [f64; 2],
    nx: usize,
    ny: usize,
    distort: impl Fn(f64, f64) -> [f64; 2],
) -> Mesh {
    // Node lattice at half spacing; Q4 uses only the even points.
    let (mx, my) = (2 * nx + 1, 2 * ny + 1);
    let mut index = vec![usize::MAX; mx * my];
    let mut nodes = Vec::new();
    let mut elements = Vec::new();
    let id = |i: usize, j: usize| j * mx + i;
    let mut node = |i: usize, j: usize, nodes: &mut Vec<[f64; 2]>| -> usize {
        let k = id(i, j);
        if index[k] == usize::MAX {
            let x = origin[0] + size[0] * i as f64 / (mx - 1) as f64;
            let y = origin[1] + size[1] * j as f64 / (my - 1) as f64;
            index[k] = nodes.len();
            nodes.push(distort(x, y));
        }
        index[k]
    };
    for ej in 0..ny {
        for ei in 0..nx {
            let (i, j) = (2 * ei, 2 * ej);
            let mut n = vec![
                node(i, j, &mut nodes),
                node(i + 2, j, &mut nodes),
                node(i + 2, j + 2, &mut nodes),
                node(i, j + 2, &mut nodes),
            ];
            if kind == ElementKind::Q8 {
                n.extend([
                    node(i + 1, j, &mut nodes),
                    node(i + 2, j + 1, &mut nodes),
                    node(i + 1, j + 2, &mut nodes),
                    node(i, j + 1, &mut nodes),
                ]);
            }
            elements.push(Element { kind, nodes: n });
        }
    }
    // Edge sets: bottom (face 0), right (face 1), top (face 2), left (face 3).
    let mut edge_sets = BTreeMap::new();
    let mut node_sets = BTreeMap::new();
    let sides: [(&str, usize); 4] = [("bottom", 0), ("right", 1), ("top", 2), ("left", 3)];
    for (name, face) in sides {
        let mut edges = Vec::new();
        for (e, _) in elements.iter().enumerate() {
            let (ei, ej) = (e % nx, e / nx);
            let on = match face {
                0 => ej == 0,
                1 => ei == nx - 1,
                2 => ej == ny - 1,
                _ => ei == 0,
            };
            if on {
                let el: &Element = &elements[e];
                let local = contact2d::mesh::face_local_nodes(kind, face);
                edges.push(Edge {
                    element: e,
                    face,
                    nodes: local.iter().map(|&a| el.nodes[a]).collect(),
                });
            }
        }
        let mut ns: Vec<usize> = edges.iter().flat_map(|e| e.nodes.clone()).collect();
        ns.sort_unstable();
        ns.dedup();
        node_sets.insert(name.to_string(), ns);
        edge_sets.insert(name.to_string(), edges);
    }
    Mesh {
        nodes,
        elements,
        node_sets,
        edge_sets,
        element_sets: BTreeMap::new(),
    }
}

/// Nodes whose coordinates satisfy `pred`.
pub fn nodes_where(mesh: &Mesh, pred: impl Fn(f64, f64) -> bool) -> Vec<usize> {
    mesh.nodes
        .iter()
        .enumerate()
        .filter(|(_, p)| pred(p[0], p[1]))
        .map(|(i, _)| i)
        .collect()
}

/// Convergence rates printed in the Newton log lines.
pub fn rates(lines: &[String]) -> Vec<f64> {
    lines
        .iter()
        .filter_map(|l| l.split("rate ").nth(1)?.trim().parse::<f64>().ok())
        .collect()
}

pub fn silent() -> impl FnMut(contact2d::results::LogCategory, &str) {
    |_, _| {}
}

/// A frictionless Hertz press (the shipped `hertz_*` scenes) at its last
/// increment, against Hertz's pressure with P taken from the computed
/// resultant of the first contact pair.
pub struct Hertz {
    /// Load: per unit thickness over the full cylinder (twice the quarter's
    /// Fy), or the total over the circle for the sphere (Fy itself).
    pub p: f64,
    pub a: f64,
    pub p0: f64,
    /// Nodes of the contact zone: closed in the solution or inside Hertz's a
    /// (reference coordinate X < a).
    pub zone: usize,
    /// Reference X of the last closed and of the first open contactor node.
    pub last_closed: f64,
    pub first_open: f64,
    /// RMS over the contact zone of (tn - p(X)) / p0: tn as reported, p
    /// Hertz's pressure at the node's reference coordinate (zero beyond a).
    pub rms: f64,
    /// The same over the nodes X < 0.8 a (away from the edge).
    pub rms_interior: f64,
    /// (tn - p0) / p0 at the contact point (the first contactor node).
    pub centre: f64,
    /// RMS over the contact zone and at the centre with tn converted to
    /// force per unit CURRENT area (the lengths, and radii, of the deformed
    /// surface), for comparison.
    pub rms_current: f64,
    pub centre_current: f64,
    /// RMS over the contact zone of (tn - p(x)) / p0 with tn as reported and
    /// x the node's CURRENT coordinate: the measure for total Lagrangian
    /// runs, whose tractions are Cauchy tractions on the deformed surface.
    pub rms_deformed: f64,
}

/// Hertz's pressure at x (zero beyond a).
pub fn hertz_pressure(p0: f64, a: f64, x: f64) -> f64 {
    if x < a {
        p0 * (1.0 - x * x / (a * a)).sqrt()
    } else {
        0.0
    }
}

/// Hertz for the solved press `s`: a cylinder (plane) or a sphere
/// (axisymmetric) of `radius` on a rigid flat, E* = E / (1 - nu^2). Plane:
/// a = sqrt(4 P R / (pi E*)), p0 = 2 P / (pi a); axisymmetric:
/// a = (3 P R / (4 E*))^(1/3), p0 = 3 P / (2 pi a^2).
pub fn hertz(s: &contact2d::newton::Solver, radius: f64, e_star: f64) -> Hertz {
    use contact2d::results::NodeState;
    use std::f64::consts::PI;
    let problem = s.problem();
    let axisymmetric = problem.analysis == AnalysisKind::Axisymmetric;
    let pairs = s.last_pairs().unwrap();
    let pair = &pairs[0].1;
    let (p, a, p0) = if axisymmetric {
        let p = pair.fy;
        let a = (3.0 * p * radius / (4.0 * e_star)).cbrt();
        (p, a, 3.0 * p / (2.0 * PI * a * a))
    } else {
        let p = 2.0 * pair.fy;
        let a = (4.0 * p * radius / (PI * e_star)).sqrt();
        (p, a, 2.0 * p / (PI * a))
    };
    let n = &pair.nodes;
    let m = n.x.len();
    let reference: Vec<[f64; 2]> = problem.contacts[0]
        .contactor
        .iter()
        .map(|&c| problem.mesh.nodes[c])
        .collect();
    let current: Vec<[f64; 2]> = (0..m).map(|k| [n.x[k], n.y[k]]).collect();
    let closed: Vec<usize> = (0..m).filter(|&k| n.state[k] != NodeState::Open).collect();
    let last = *closed.last().expect("no node in contact");
    // The contact zone is one run of nodes from the contact point on.
    assert_eq!(
        closed,
        (0..closed.len()).collect::<Vec<_>>(),
        "contact zone"
    );
    let zone: Vec<usize> = (0..m)
        .filter(|&k| n.state[k] != NodeState::Open || reference[k][0] < a)
        .collect();
    let interior: Vec<usize> = zone
        .iter()
        .copied()
        .filter(|&k| reference[k][0] < 0.8 * a)
        .collect();
    let error = |k: usize, tn: f64| (tn - hertz_pressure(p0, a, reference[k][0])) / p0;
    let rms = |ks: &[usize], tn: &dyn Fn(usize) -> f64| {
        (ks.iter().map(|&k| error(k, tn(k)).powi(2)).sum::<f64>() / ks.len() as f64).sqrt()
    };
    // Area elements of the deformed surface over the reference ones: the
    // chord through the neighbouring nodes (times x / X axisymmetric).
    let chord = |q: &[[f64; 2]], i: usize, j: usize| (q[j][0] - q[i][0]).hypot(q[j][1] - q[i][1]);
    let stretch = |k: usize| {
        let (i, j) = (k.saturating_sub(1), k + 1);
        let mut r = chord(&current, i, j) / chord(&reference, i, j);
        if axisymmetric {
            let q = k.max(1);
            r *= current[q][0] / reference[q][0];
        }
        r
    };
    let per_current = |k: usize| n.tn[k] / stretch(k);
    let rms_deformed = (zone
        .iter()
        .map(|&k| ((n.tn[k] - hertz_pressure(p0, a, current[k][0])) / p0).powi(2))
        .sum::<f64>()
        / zone.len() as f64)
        .sqrt();
    Hertz {
        p,
        a,
        p0,
        zone: zone.len(),
        last_closed: reference[last][0],
        first_open: reference[last + 1][0],
        rms: rms(&zone, &|k| n.tn[k]),
        rms_interior: rms(&interior, &|k| n.tn[k]),
        centre: error(0, n.tn[0]),
        rms_current: rms(&zone, &per_current),
        centre_current: error(0, per_current(0)),
        rms_deformed,
    }
}

impl std::fmt::Display for Hertz {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(
            f,
            "P {:.1}  a {:.4}  p0 {:.1}  zone {} nodes (last closed X {:.4}, first open {:.4})  \
             rms {:.2e}  X<0.8a {:.2e}  centre {:+.2e}  | per current area: rms {:.2e} centre {:+.2e}  | at current x: rms {:.2e}",
            self.p,
            self.a,
            self.p0,
            self.zone,
            self.last_closed,
            self.first_open,
            self.rms,
            self.rms_interior,
            self.centre,
            self.rms_current,
            self.centre_current,
            self.rms_deformed
        )
    }
}

/// A frictionless pair "base": the problem's node set "bottom" (sorted by
/// x, so the body is on its left) against a rigid flat at y = `level`
/// (the first rigid target). Returns the contactor nodes.
pub fn bottom_on_flat(p: &mut Problem, level: f64) -> Vec<usize> {
    let mut bottom = p.mesh.node_sets["bottom"].clone();
    bottom.sort_by(|&a, &b| p.mesh.nodes[a][0].total_cmp(&p.mesh.nodes[b][0]));
    p.rigids.push(Rigid {
        name: "flat".into(),
        points: vec![[5.0, level], [-5.0, level]],
        reference: [0.0, 0.0],
        ux: Scaled::constant(0.0),
        uy: Scaled::constant(0.0),
        theta: Scaled::constant(0.0),
    });
    p.contacts.push(ContactPair {
        name: "base".into(),
        body: 0,
        contactor: bottom.clone(),
        closed: false,
        target: Target::Rigid(0),
        mu_s: 0.0,
        mu_d: 0.0,
        rule: FrictionRule::MuDAfterSlip,
        recovery: Recovery::Consistent,
        decisions: Default::default(),
        formulation: Default::default(),
    });
    bottom
}

/// A bar 10 x 1 in plane stress (thickness 2, E = 1000, nu = 0), held in x
/// at its left end (driver `wall`) and in y at its bottom-left corner
/// (`corner`), with `load` (scene text: a driver or a pressure on
/// `bar.right`) and increments of 1 up to `t_end`. Pulled by F on its end,
/// it stretches by F L / (E A) = F / 200, exactly for a uniform stress.
pub fn bar_scene(element: &str, divisions: [usize; 2], load: &str, t_end: f64) -> String {
    format!(
        r#"[analysis]
kind = "plane_stress"
thickness = 2.0
kinematics = "small_strain"

[[material]]
name = "steel"
model = "linear_elastic"
E = 1000.0
nu = 0.0

[[body]]
name = "bar"
material = "steel"
element = "{element}"
mesh = {{ generator = "rectangle", origin = [0.0, 0.0], size = [10.0, 1.0], divisions = [{}, {}] }}

[[driver]]
name = "wall"
set = "bar.left"
ux = 0.0

[[driver]]
name = "corner"
set = "bar.bottom_left"
uy = 0.0

{load}

[steps]
dt = 1.0
t_end = {t_end:?}
"#,
        divisions[0], divisions[1]
    )
}
