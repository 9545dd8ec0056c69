//! Nodes, quadrilateral elements, and the named node and edge sets that
//! scenes refer to. Generators build the shapes the paper's problems need;
//! `gmsh` reads Gmsh 4.1 ASCII files.

pub mod generators;
pub mod gmsh;

use std::collections::BTreeMap;

/// The two element families of the paper.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ElementKind {
    Q4,
    Q8,
}

impl ElementKind {
    pub fn node_count(self) -> usize {
        match self {
            ElementKind::Q4 => 4,
            ElementKind::Q8 => 8,
        }
    }
}

/// A quadrilateral. Node order: the four corners counter-clockwise, then
/// (Q8 only) the mid-side nodes of faces 0..3, face f joining corner f to
/// corner (f+1) % 4.
#[derive(Clone, Debug, PartialEq)]
pub struct Element {
    pub kind: ElementKind,
    pub nodes: Vec<usize>,
}

/// One element face on a boundary. `nodes` run start, end, then the mid-side
/// node for Q8; walking from start to end the body lies on the left (the
/// paper's contactor convention; it holds for every face of a
/// counter-clockwise element).
#[derive(Clone, Debug, PartialEq)]
pub struct Edge {
    pub element: usize,
    pub face: usize,
    pub nodes: Vec<usize>,
}

/// A body's mesh: coordinates, elements and named sets. Node sets are sorted
/// and free of duplicates; edge sets are chained head to tail where the
/// boundary is connected.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub nodes: Vec<[f64; 2]>,
    pub elements: Vec<Element>,
    pub node_sets: BTreeMap<String, Vec<usize>>,
    pub edge_sets: BTreeMap<String, Vec<Edge>>,
    /// Named groups of elements (Gmsh physical surfaces; generators add "all").
    pub element_sets: BTreeMap<String, Vec<usize>>,
}

/// Local corner indices of face `f`, and its mid-side node index (Q8).
pub fn face_local_nodes(kind: ElementKind, face: usize) -> Vec<usize> {
    let a = face;
    let b = (face + 1) % 4;
    match kind {
        ElementKind::Q4 => vec![a, b],
        ElementKind::Q8 => vec![a, b, 4 + face],
    }
}
