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

/// Why a mesh could not be built, read or accepted. Gmsh errors carry the
/// file and 1-based line; element errors the element index.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    #[error("{}: {source}", path.display())]
    Io {
        path: std::path::PathBuf,
        source: std::io::Error,
    },
    #[error("{}:{line}: {message}", path.display())]
    Gmsh {
        path: std::path::PathBuf,
        line: usize,
        message: String,
    },
    /// A generator parameter out of range.
    #[error("{generator}: {message}")]
    Generator {
        generator: &'static str,
        message: String,
    },
    #[error("element {element}: {message}")]
    Element { element: usize, message: String },
    #[error(
        "element {element}: corner {corner} (node {node}) has a non-positive Jacobian \
         (cross product of its edges {cross:e}); the element is inverted, degenerate \
         or not counter-clockwise"
    )]
    Inverted {
        element: usize,
        corner: usize,
        node: usize,
        cross: f64,
    },
    #[error("element {element}: mid-side node {node} of face {face} {message}")]
    MidSideNode {
        element: usize,
        face: usize,
        node: usize,
        message: String,
    },
}

impl Mesh {
    /// Elements `elements` only (in that order, repeats ignored), nodes
    /// renumbered compactly keeping their order, sets restricted to what
    /// remains (empty sets dropped). Panics on an element index out of range.
    pub fn subset(&self, elements: &[usize]) -> Mesh {
        let mut element_map = vec![usize::MAX; self.elements.len()];
        let mut kept = Vec::with_capacity(elements.len());
        for &e in elements {
            if element_map[e] == usize::MAX {
                element_map[e] = kept.len();
                kept.push(e);
            }
        }
        let mut node_map = vec![usize::MAX; self.nodes.len()];
        for &e in &kept {
            for &n in &self.elements[e].nodes {
                node_map[n] = 0;
            }
        }
        let mut nodes = Vec::new();
        for (n, slot) in node_map.iter_mut().enumerate() {
            if *slot == 0 {
                *slot = nodes.len();
                nodes.push(self.nodes[n]);
            }
        }
        let renumber = |list: &[usize], map: &[usize]| -> Vec<usize> {
            list.iter()
                .filter(|&&i| map[i] != usize::MAX)
                .map(|&i| map[i])
                .collect()
        };
        let elements_out = kept
            .iter()
            .map(|&e| Element {
                kind: self.elements[e].kind,
                nodes: renumber(&self.elements[e].nodes, &node_map),
            })
            .collect();
        let node_sets = self
            .node_sets
            .iter()
            .map(|(k, v)| (k.clone(), renumber(v, &node_map)))
            .filter(|(_, v)| !v.is_empty())
            .collect();
        let element_sets = self
            .element_sets
            .iter()
            .map(|(k, v)| {
                let mut v = renumber(v, &element_map);
                v.sort_unstable();
                (k.clone(), v)
            })
            .filter(|(_, v)| !v.is_empty())
            .collect();
        let edge_sets = self
            .edge_sets
            .iter()
            .map(|(k, edges)| {
                let kept: Vec<Edge> = edges
                    .iter()
                    .filter(|e| element_map[e.element] != usize::MAX)
                    .map(|e| Edge {
                        element: element_map[e.element],
                        face: e.face,
                        nodes: e.nodes.iter().map(|&n| node_map[n]).collect(),
                    })
                    .collect();
                (k.clone(), kept)
            })
            .filter(|(_, v)| !v.is_empty())
            .collect();
        Mesh {
            nodes,
            elements: elements_out,
            node_sets,
            edge_sets,
            element_sets,
        }
    }

    /// Append `other`, prefixing each of its set names with `prefix` (e.g.
    /// "cylinder."). A set whose prefixed name exists already is extended.
    /// Returns (node_offset, element_offset) of `other` in `self`.
    pub fn append(&mut self, other: &Mesh, prefix: &str) -> (usize, usize) {
        let (dn, de) = (self.nodes.len(), self.elements.len());
        self.nodes.extend_from_slice(&other.nodes);
        self.elements.extend(other.elements.iter().map(|e| Element {
            kind: e.kind,
            nodes: e.nodes.iter().map(|n| n + dn).collect(),
        }));
        for (name, set) in &other.node_sets {
            let target = self.node_sets.entry(format!("{prefix}{name}")).or_default();
            target.extend(set.iter().map(|n| n + dn));
            target.sort_unstable();
            target.dedup();
        }
        for (name, set) in &other.element_sets {
            let target = self
                .element_sets
                .entry(format!("{prefix}{name}"))
                .or_default();
            target.extend(set.iter().map(|e| e + de));
            target.sort_unstable();
            target.dedup();
        }
        for (name, set) in &other.edge_sets {
            let target = self.edge_sets.entry(format!("{prefix}{name}")).or_default();
            target.extend(set.iter().map(|e| Edge {
                element: e.element + de,
                face: e.face,
                nodes: e.nodes.iter().map(|n| n + dn).collect(),
            }));
        }
        (dn, de)
    }

    /// Nodes of an edge set (sorted, unique).
    pub fn edge_set_nodes(&self, name: &str) -> Option<Vec<usize>> {
        self.edge_sets.get(name).map(|edges| edge_nodes(edges))
    }

    /// Faces that belong to one element only, in element then face order,
    /// oriented with the body on the left.
    pub fn boundary_edges(&self) -> Vec<Edge> {
        let mut count: std::collections::HashMap<(usize, usize), usize> =
            std::collections::HashMap::new();
        for el in &self.elements {
            for f in 0..4 {
                let (a, b) = (el.nodes[f], el.nodes[(f + 1) % 4]);
                *count.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        let mut edges = Vec::new();
        for (e, el) in self.elements.iter().enumerate() {
            for f in 0..4 {
                let (a, b) = (el.nodes[f], el.nodes[(f + 1) % 4]);
                if count[&(a.min(b), a.max(b))] == 1 {
                    edges.push(Edge {
                        element: e,
                        face: f,
                        nodes: face_local_nodes(el.kind, f)
                            .iter()
                            .map(|&l| el.nodes[l])
                            .collect(),
                    });
                }
            }
        }
        edges
    }

    /// Every element is well formed and has a positive Jacobian at its
    /// corners: the cross product of the two edges meeting at each corner is
    /// positive (for Q8 also with the tangents the mid-side nodes give), and
    /// Q8 mid-side nodes lie near the middle third of their face.
    pub fn check(&self) -> Result<(), MeshError> {
        for (e, el) in self.elements.iter().enumerate() {
            let bad = |message: String| MeshError::Element {
                element: e,
                message,
            };
            if el.nodes.len() != el.kind.node_count() {
                return Err(bad(format!(
                    "{:?} element with {} nodes (expected {})",
                    el.kind,
                    el.nodes.len(),
                    el.kind.node_count()
                )));
            }
            if let Some(&n) = el.nodes.iter().find(|&&n| n >= self.nodes.len()) {
                return Err(bad(format!(
                    "node {n} does not exist (the mesh has {} nodes)",
                    self.nodes.len()
                )));
            }
            let x = |l: usize| self.nodes[el.nodes[l]];
            if let Some(l) = (0..el.nodes.len()).find(|&l| !x(l).iter().all(|c| c.is_finite())) {
                return Err(bad(format!(
                    "node {} has coordinates {:?}",
                    el.nodes[l],
                    x(l)
                )));
            }
            for c in 0..4 {
                let (p, next, prev) = (x(c), x((c + 1) % 4), x((c + 3) % 4));
                let mut cross = cross(sub(next, p), sub(prev, p));
                if el.kind == ElementKind::Q8 && cross > 0.0 {
                    // Tangents of the quadratic faces at the corner.
                    let t_next = sub(
                        add(x(4 + c), x(4 + c)),
                        add(scale(p, 1.5), scale(next, 0.5)),
                    );
                    let m_prev = x(4 + (c + 3) % 4);
                    let t_prev = sub(add(m_prev, m_prev), add(scale(p, 1.5), scale(prev, 0.5)));
                    cross = cross.min(4.0 * self::cross(t_next, t_prev));
                }
                if cross.is_nan() || cross <= 0.0 {
                    return Err(MeshError::Inverted {
                        element: e,
                        corner: c,
                        node: el.nodes[c],
                        cross,
                    });
                }
            }
            if el.kind == ElementKind::Q8 {
                for f in 0..4 {
                    let (a, b, m) = (x(f), x((f + 1) % 4), x(4 + f));
                    let chord = sub(b, a);
                    let length2 = dot(chord, chord);
                    let along = dot(sub(m, a), chord) / length2;
                    let off = self::cross(chord, sub(m, a)).abs() / length2;
                    let message = if !(1.0 / 3.0 - 1e-9..=2.0 / 3.0 + 1e-9).contains(&along) {
                        format!("lies at {along:.3} of the face's length, outside its middle third")
                    } else if off > 0.5 {
                        format!("lies {off:.3} face lengths off the face's chord (at most 0.5)")
                    } else {
                        continue;
                    };
                    return Err(MeshError::MidSideNode {
                        element: e,
                        face: f,
                        node: el.nodes[4 + f],
                        message,
                    });
                }
            }
        }
        Ok(())
    }
}

/// Nodes of some edges, sorted and unique.
pub(crate) fn edge_nodes(edges: &[Edge]) -> Vec<usize> {
    let mut nodes: Vec<usize> = edges.iter().flat_map(|e| e.nodes.iter().copied()).collect();
    nodes.sort_unstable();
    nodes.dedup();
    nodes
}

/// Edges ordered head to tail. Open chains come first, in the order their
/// first edge had in `edges`; closed loops then start at their smallest
/// start node.
pub(crate) fn chain(edges: Vec<Edge>) -> Vec<Edge> {
    use std::collections::{HashMap, HashSet};
    let mut by_start: HashMap<usize, Vec<usize>> = HashMap::new();
    for (i, e) in edges.iter().enumerate() {
        by_start.entry(e.nodes[0]).or_default().push(i);
    }
    let ends: HashSet<usize> = edges.iter().map(|e| e.nodes[1]).collect();
    let mut used = vec![false; edges.len()];
    let mut order = Vec::with_capacity(edges.len());
    let follow = |mut i: usize, used: &mut Vec<bool>, order: &mut Vec<usize>| loop {
        used[i] = true;
        order.push(i);
        let end = edges[i].nodes[1];
        match by_start
            .get(&end)
            .and_then(|c| c.iter().copied().find(|&j| !used[j]))
        {
            Some(j) => i = j,
            None => break,
        }
    };
    for i in 0..edges.len() {
        if !used[i] && !ends.contains(&edges[i].nodes[0]) {
            follow(i, &mut used, &mut order);
        }
    }
    while let Some(i) = (0..edges.len())
        .filter(|&i| !used[i])
        .min_by_key(|&i| edges[i].nodes[0])
    {
        follow(i, &mut used, &mut order);
    }
    let mut slots: Vec<Option<Edge>> = edges.into_iter().map(Some).collect();
    order.iter().map(|&i| slots[i].take().unwrap()).collect()
}

/// Twice the signed area of the polygon through `corners` (positive when
/// counter-clockwise).
pub(crate) fn twice_signed_area(corners: &[[f64; 2]]) -> f64 {
    (0..corners.len())
        .map(|i| cross(corners[i], corners[(i + 1) % corners.len()]))
        .sum()
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}
fn add(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] + b[0], a[1] + b[1]]
}
fn scale(a: [f64; 2], s: f64) -> [f64; 2] {
    [a[0] * s, a[1] * s]
}
fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}
