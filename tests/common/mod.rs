//! Problems for the solver tests: built in code, or read from the shipped
//! scenes with text edits (a refined mesh, another coefficient).
#![allow(dead_code)]

use contact2d::mesh::{Edge, Element, ElementKind, Mesh};
use contact2d::problem::*;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// The shipped scene `name` (a path under scenes/) with each `(old, new)`
/// replaced once; each `old` must occur.
pub fn shipped_scene(name: &str, edits: &[(&str, &str)]) -> Problem {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name);
    let mut text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
    for (old, new) in edits {
        assert!(text.contains(old), "{name} has no {old:?}");
        text = text.replacen(old, new, 1);
    }
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
        }],
        functions: vec![TimeFunction {
            name: "ramp".into(),
            points: vec![(0.0, 0.0), (1.0, 1.0)],
        }],
        drivers: vec![],
        rigids: vec![],
        contacts: vec![],
        pressures: vec![],
        forces: vec![],
        body_forces: vec![],
        initial_stresses: vec![],
        times: vec![1.0],
        solver: SolverSettings::default(),
        units: Default::default(),
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

pub fn silent() -> impl FnMut(contact2d::results::LogCategory, &str) {
    |_, _| {}
}
