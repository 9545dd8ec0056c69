//! Mesh generators, the Gmsh reader and the mesh operations: areas, set
//! sizes and orientation, grading and element shape are checked in numbers.

use contact2d::mesh::{
    Edge, Element, ElementKind, Mesh, MeshError, face_local_nodes, generators, gmsh,
};
use std::f64::consts::PI;
use std::path::Path;

const KINDS: [ElementKind; 2] = [ElementKind::Q4, ElementKind::Q8];

/// Shape function derivatives (d/dxi, d/deta) of the Q4 or Q8 element.
fn shape_derivatives(kind: ElementKind, xi: f64, eta: f64) -> Vec<[f64; 2]> {
    const C: [[f64; 2]; 4] = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
    let mut d = Vec::new();
    for c in C {
        let (px, py) = (1.0 + c[0] * xi, 1.0 + c[1] * eta);
        d.push(match kind {
            ElementKind::Q4 => [0.25 * c[0] * py, 0.25 * c[1] * px],
            ElementKind::Q8 => {
                let q = c[0] * xi + c[1] * eta - 1.0;
                [0.25 * c[0] * py * (q + px), 0.25 * c[1] * px * (q + py)]
            }
        });
    }
    if kind == ElementKind::Q8 {
        d.push([-xi * (1.0 - eta), -0.5 * (1.0 - xi * xi)]);
        d.push([0.5 * (1.0 - eta * eta), -eta * (1.0 + xi)]);
        d.push([-xi * (1.0 + eta), 0.5 * (1.0 - xi * xi)]);
        d.push([-0.5 * (1.0 - eta * eta), -eta * (1.0 - xi)]);
    }
    d
}

/// Element area by Gauss integration of det J: 2x2 for Q4, 3x3 for Q8.
/// det J is of degree <= 3 in each of xi and eta for both (x, y are at most
/// quadratic per direction), so these rules give the isoparametric area
/// exactly, to round-off.
fn element_area(mesh: &Mesh, el: &Element) -> f64 {
    let g2 = [(-1.0 / 3f64.sqrt(), 1.0), (1.0 / 3f64.sqrt(), 1.0)];
    let s = 0.6f64.sqrt();
    let g3 = [(-s, 5.0 / 9.0), (0.0, 8.0 / 9.0), (s, 5.0 / 9.0)];
    let rule: &[(f64, f64)] = match el.kind {
        ElementKind::Q4 => &g2,
        ElementKind::Q8 => &g3,
    };
    let mut area = 0.0;
    for &(xi, wx) in rule {
        for &(eta, wy) in rule {
            let d = shape_derivatives(el.kind, xi, eta);
            let mut j = [[0.0; 2]; 2];
            for (a, &n) in el.nodes.iter().enumerate() {
                for r in 0..2 {
                    for c in 0..2 {
                        j[r][c] += mesh.nodes[n][r] * d[a][c];
                    }
                }
            }
            let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
            assert!(det > 0.0, "det J = {det} in {el:?}");
            area += wx * wy * det;
        }
    }
    area
}

fn area(mesh: &Mesh) -> f64 {
    mesh.elements.iter().map(|e| element_area(mesh, e)).sum()
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}
fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}
fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    sub(a, b)[0].hypot(sub(a, b)[1])
}

/// The area a circular arc face adds beyond what its element's mesh
/// representation holds: the circular segment R^2 (t - sin t) / 2 over the
/// chord, minus, for Q8, the parabolic segment 4/3 * triangle(a, m, b).
fn arc_defect(mesh: &Mesh, edges: &[Edge], radius: f64) -> f64 {
    edges
        .iter()
        .map(|e| {
            let (a, b) = (mesh.nodes[e.nodes[0]], mesh.nodes[e.nodes[1]]);
            let t = 2.0 * (0.5 * dist(a, b) / radius).asin();
            let circle = 0.5 * radius * radius * (t - t.sin());
            let parabola = match e.nodes.get(2) {
                Some(&m) => 4.0 / 3.0 * 0.5 * cross(sub(mesh.nodes[m], a), sub(b, a)).abs(),
                None => 0.0,
            };
            circle - parabola
        })
        .sum()
}

/// Relative bound on the area an arc's faces leave out: per face of angle t
/// the chord misses R^2 (t - sin t) / 2 <= R^2 t^3 / 12 (Q4), the parabola
/// less than R^2 t^5 / 960 (Q8: the leading term of the difference, which
/// the difference stays below); summed, R^2 (sum t) t_max^2 / 12 or
/// R^2 (sum t) t_max^4 / 960.
fn arc_error_bound(mesh: &Mesh, edges: &[Edge], radius: f64, exact: f64) -> f64 {
    let t: Vec<f64> = edges
        .iter()
        .map(|e| 2.0 * (0.5 * dist(mesh.nodes[e.nodes[0]], mesh.nodes[e.nodes[1]]) / radius).asin())
        .collect();
    let t_max = t.iter().cloned().fold(0.0, f64::max);
    let per = match mesh.elements[0].kind {
        ElementKind::Q4 => t_max.powi(2) / 12.0,
        ElementKind::Q8 => t_max.powi(4) / 960.0,
    };
    radius * radius * t.iter().sum::<f64>() * per / exact
}

/// Every property a generated or read mesh promises: `check` passes, nodes
/// are used and distinct, edge sets are faces of their elements with the
/// body on the left, chained head to tail in `chains[name]` pieces, their
/// node sets match, and (when `covered`) the edge sets tile the boundary.
fn assert_sound(mesh: &Mesh, chains: &[(&str, usize)], covered: bool) {
    mesh.check().unwrap();
    let mut used = vec![false; mesh.nodes.len()];
    for el in &mesh.elements {
        for &n in &el.nodes {
            used[n] = true;
        }
    }
    assert!(used.iter().all(|&u| u), "unused nodes");
    let mut sorted: Vec<[f64; 2]> = mesh.nodes.clone();
    sorted.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let scale = sorted
        .iter()
        .map(|p| p[0].abs().max(p[1].abs()))
        .fold(1.0, f64::max);
    for w in sorted.windows(2) {
        assert!(
            dist(w[0], w[1]) > 1e-9 * scale,
            "duplicate node at {:?}",
            w[0]
        );
    }
    for (name, set) in &mesh.node_sets {
        assert!(
            set.windows(2).all(|w| w[0] < w[1]),
            "node set {name} not sorted/unique"
        );
    }
    let mut in_sets = 0;
    for (name, edges) in &mesh.edge_sets {
        for e in edges {
            let el = &mesh.elements[e.element];
            let face: Vec<usize> = face_local_nodes(el.kind, e.face)
                .iter()
                .map(|&l| el.nodes[l])
                .collect();
            assert_eq!(e.nodes, face, "{name}: edge is not its element's face");
            let centroid = (0..4).fold([0.0; 2], |c, l| {
                let p = mesh.nodes[el.nodes[l]];
                [c[0] + 0.25 * p[0], c[1] + 0.25 * p[1]]
            });
            let (a, b) = (mesh.nodes[e.nodes[0]], mesh.nodes[e.nodes[1]]);
            assert!(
                cross(sub(b, a), sub(centroid, a)) > 0.0,
                "{name}: body not on the left"
            );
        }
        let breaks = edges
            .windows(2)
            .filter(|w| w[0].nodes[1] != w[1].nodes[0])
            .count();
        let expected = chains.iter().find(|(n, _)| n == name).map_or(1, |c| c.1);
        assert_eq!(
            breaks + 1,
            expected,
            "{name}: chained in {} pieces",
            breaks + 1
        );
        let mut nodes: Vec<usize> = edges.iter().flat_map(|e| e.nodes.clone()).collect();
        nodes.sort_unstable();
        nodes.dedup();
        assert_eq!(mesh.node_sets[name], nodes, "node set {name}");
        assert_eq!(mesh.edge_set_nodes(name).unwrap(), nodes);
        in_sets += edges.len();
    }
    if covered {
        assert_eq!(
            in_sets,
            mesh.boundary_edges().len(),
            "edge sets do not tile the boundary"
        );
    }
}

/// Element sizes along a straight set of nodes, ordered by `key`.
fn steps(mesh: &Mesh, nodes: &[usize], key: impl Fn([f64; 2]) -> f64) -> Vec<f64> {
    let mut t: Vec<f64> = nodes.iter().map(|&n| key(mesh.nodes[n])).collect();
    t.sort_by(|a, b| a.partial_cmp(b).unwrap());
    t.windows(2).map(|w| w[1] - w[0]).collect()
}

/// Corner nodes of a set (Q8 mid-side nodes left out).
fn corner_nodes(mesh: &Mesh, set: &str) -> Vec<usize> {
    let mut n: Vec<usize> = mesh.edge_sets[set]
        .iter()
        .flat_map(|e| [e.nodes[0], e.nodes[1]])
        .collect();
    n.sort_unstable();
    n.dedup();
    n
}

/// Smallest and largest corner angle (degrees) of all elements.
fn angles(mesh: &Mesh) -> (f64, f64) {
    let (mut lo, mut hi) = (180.0f64, 0.0f64);
    for el in &mesh.elements {
        for c in 0..4 {
            let p = mesh.nodes[el.nodes[c]];
            let e1 = sub(mesh.nodes[el.nodes[(c + 1) % 4]], p);
            let e2 = sub(mesh.nodes[el.nodes[(c + 3) % 4]], p);
            let a = cross(e1, e2)
                .atan2(e1[0] * e2[0] + e1[1] * e2[1])
                .to_degrees();
            lo = lo.min(a);
            hi = hi.max(a);
        }
    }
    (lo, hi)
}

fn assert_close(a: f64, b: f64, rel: f64, what: &str) {
    assert!(
        (a - b).abs() <= rel * b.abs().max(1e-300),
        "{what}: {a} vs {b} (rel {rel:e})"
    );
}

// ---------------------------------------------------------------- rectangle

#[test]
fn rectangle_counts_sets_and_area() {
    for kind in KINDS {
        let m = generators::rectangle(kind, [1.0, -2.0], [4.0, 1.5], [4, 2], [1.0, 1.0]).unwrap();
        assert_sound(&m, &[], true);
        let (nodes, per_side) = match kind {
            ElementKind::Q4 => (15, 5),
            ElementKind::Q8 => (37, 9),
        };
        assert_eq!((m.nodes.len(), m.elements.len()), (nodes, 8));
        assert_eq!(m.node_sets["bottom"].len(), per_side);
        assert_eq!(m.edge_sets["bottom"].len(), 4);
        assert_eq!(m.edge_sets["left"].len(), 2);
        assert_eq!(m.element_sets["all"], (0..8).collect::<Vec<_>>());
        // Exact: straight sides, the isoparametric map is bilinear/affine.
        assert_close(area(&m), 6.0, 1e-13, "rectangle area");
        for (name, p) in [
            ("bottom_left", [1.0, -2.0]),
            ("bottom_right", [5.0, -2.0]),
            ("top_right", [5.0, -0.5]),
            ("top_left", [1.0, -0.5]),
        ] {
            assert_eq!(m.node_sets[name].len(), 1, "{name}");
            assert_eq!(m.nodes[m.node_sets[name][0]], p, "{name}");
        }
        // Each side runs from corner to corner with the body on the left.
        let ends = |s: &str| {
            let e = &m.edge_sets[s];
            (e[0].nodes[0], e[e.len() - 1].nodes[1])
        };
        let at = |s: &str| m.node_sets[s][0];
        assert_eq!(ends("bottom"), (at("bottom_left"), at("bottom_right")));
        assert_eq!(ends("right"), (at("bottom_right"), at("top_right")));
        assert_eq!(ends("top"), (at("top_right"), at("top_left")));
        assert_eq!(ends("left"), (at("top_left"), at("bottom_left")));
    }
}

#[test]
fn rectangle_grading_ratio() {
    for kind in KINDS {
        let m = generators::rectangle(kind, [0.0, 0.0], [3.0, 2.0], [5, 4], [4.0, 0.25]).unwrap();
        assert_sound(&m, &[], true);
        let dx = steps(&m, &corner_nodes(&m, "bottom"), |p| p[0]);
        let dy = steps(&m, &corner_nodes(&m, "left"), |p| p[1]);
        assert_eq!((dx.len(), dy.len()), (5, 4));
        assert_close(dx[4] / dx[0], 4.0, 1e-12, "x ratio");
        assert_close(dy[3] / dy[0], 0.25, 1e-12, "y ratio");
        // Geometric: equal growth between neighbours.
        for w in dx.windows(2) {
            assert_close(w[1] / w[0], 4f64.powf(0.25), 1e-12, "x growth");
        }
        assert_close(area(&m), 6.0, 1e-13, "area");
        if kind == ElementKind::Q8 {
            // Mid-side nodes halfway between graded corners.
            for e in &m.edge_sets["bottom"] {
                let (a, b, c) = (
                    m.nodes[e.nodes[0]],
                    m.nodes[e.nodes[1]],
                    m.nodes[e.nodes[2]],
                );
                assert_close(c[0], 0.5 * (a[0] + b[0]), 1e-15, "mid-side x");
            }
        }
    }
}

#[test]
fn generator_errors_name_the_value() {
    let e = generators::rectangle(ElementKind::Q4, [0.0, 0.0], [1.0, -1.0], [1, 1], [1.0, 1.0]);
    assert_eq!(
        e.unwrap_err().to_string(),
        "rectangle: size[1] = -1.0 must be positive"
    );
    let e = generators::rectangle(ElementKind::Q4, [0.0, 0.0], [1.0, 1.0], [0, 1], [1.0, 1.0]);
    assert_eq!(
        e.unwrap_err().to_string(),
        "rectangle: divisions[0] = 0 must be at least 1"
    );
    let e = generators::disk(ElementKind::Q4, [0.0, 0.0], 1.0, 4, 0.5, false);
    assert_eq!(
        e.unwrap_err().to_string(),
        "disk: ratio = 0.5 must be at least 1"
    );
    let e = generators::disk(ElementKind::Q4, [0.0, 0.0], 1.0, 1, 1.0, false);
    assert_eq!(
        e.unwrap_err().to_string(),
        "disk: divisions = 1 must be at least 2"
    );
    let e = generators::ring(
        ElementKind::Q4,
        [0.0; 2],
        2.0,
        1.0,
        [0.0, 90.0],
        [1, 1],
        1.0,
    );
    assert_eq!(
        e.unwrap_err().to_string(),
        "ring: r_outer = 1.0 must exceed r_inner = 2.0"
    );
    let e = generators::ring(
        ElementKind::Q4,
        [0.0; 2],
        1.0,
        2.0,
        [0.0, 360.0],
        [1, 2],
        1.0,
    );
    assert_eq!(
        e.unwrap_err().to_string(),
        "ring: divisions[1] = 2 leaves 180 degrees per element; at most 120 are allowed"
    );
    let e = generators::plate_with_hole(ElementKind::Q4, 1.0, 3.0, [-0.5, 2.0], [2, 4], 1.0);
    assert_eq!(
        e.unwrap_err().to_string(),
        "plate_with_hole: y_range = [-0.5, 2.0] must reach below -hole_radius and above hole_radius = 1.0"
    );
}

// --------------------------------------------------------------------- disk

#[test]
fn disk_quarter_area_sets_and_contact_point() {
    let (c, r) = ([1.0, 3.0], 2.0);
    for kind in KINDS {
        for (n, ratio) in [(4, 1.0), (8, 10.0)] {
            let m = generators::disk(kind, c, r, n, ratio, false).unwrap();
            assert_sound(&m, &[], true);
            // n elements up the axis; Q8 adds a mid-side node to each.
            assert_eq!(m.edge_sets["axis"].len(), n);
            let per = if kind == ElementKind::Q8 { 2 } else { 1 };
            assert_eq!(m.node_sets["axis"].len(), per * n + 1);
            let along_top = m.edge_sets["top"].len();
            assert_eq!(m.node_sets["top"].len(), per * along_top + 1);
            // The contact point, and the arc starting there.
            assert_eq!(m.node_sets["contact_point"].len(), 1);
            let cp = m.node_sets["contact_point"][0];
            assert!(dist(m.nodes[cp], [1.0, 1.0]) < 1e-12 * r);
            let arc = &m.edge_sets["arc"];
            assert_eq!(arc[0].nodes[0], cp, "arc starts at the contact point");
            assert!(dist(m.nodes[arc[arc.len() - 1].nodes[1]], [3.0, 3.0]) < 1e-12 * r);
            // Every arc node, mid-side ones included, on the circle.
            for &k in &m.node_sets["arc"] {
                assert!(
                    (dist(m.nodes[k], c) - r).abs() < 1e-12 * r,
                    "node {k} off the circle"
                );
            }
            // Increasing x along the arc.
            assert!(
                arc.windows(2)
                    .all(|w| m.nodes[w[1].nodes[0]][0] > m.nodes[w[0].nodes[0]][0])
            );

            // Area: the mesh holds the quarter disk minus, on each arc face,
            // the circular segment beyond its chord (Q4) or beyond its
            // parabola (Q8) -- exactly, so every element is where it belongs.
            let exact = PI * r * r / 4.0;
            let a = area(&m);
            assert_close(
                a + arc_defect(&m, arc, r),
                exact,
                1e-12,
                "disk area with segments",
            );
            // And it approaches the disk's within the bound on what arcs miss.
            let bound = arc_error_bound(&m, arc, r, exact);
            assert!(
                bound < if kind == ElementKind::Q4 { 0.1 } else { 1e-3 },
                "bound {bound}"
            );
            assert_close(a, exact, bound, "disk area");
        }
    }
}

#[test]
fn curved_areas_converge_at_the_element_order() {
    // Doubling the divisions halves the arc faces' angles: the area error
    // falls 4 times for Q4 (chords, t^2) and 16 times for Q8 (parabolas, t^4).
    for kind in KINDS {
        let disk = |n| {
            let m = generators::disk(kind, [0.0; 2], 1.0, n, 1.0, false).unwrap();
            (area(&m) - PI / 4.0).abs()
        };
        let ring = |n| {
            let m = generators::ring(kind, [0.0; 2], 1.0, 2.0, [0.0, 90.0], [2, n], 1.0).unwrap();
            (area(&m) - 0.75 * PI).abs()
        };
        let fall = if kind == ElementKind::Q4 { 3.5 } else { 14.0 };
        for error in [&disk as &dyn Fn(usize) -> f64, &ring] {
            let (e4, e8, e16) = (error(4), error(8), error(16));
            assert!(
                e4 / e8 > fall && e8 / e16 > fall,
                "{kind:?}: {e4:e} {e8:e} {e16:e}"
            );
        }
    }
}

#[test]
fn disk_grading_and_square_elements_at_the_contact_point() {
    let (c, r) = ([0.0, 0.0], 1.0);
    for kind in KINDS {
        for (n, ratio) in [(6, 1.0), (10, 5.0), (20, 30.0)] {
            let m = generators::disk(kind, c, r, n, ratio, false).unwrap();
            let dy = steps(&m, &corner_nodes(&m, "axis"), |p| p[1]);
            assert_eq!(dy.len(), n);
            // Largest at the center, smallest at the contact point.
            assert_close(dy[n - 1] / dy[0], ratio, 1e-9, "axis grading");
            // The first arc element is as long (along the arc) as the first
            // axis element: the contact element is square.
            let arc = &m.edge_sets["arc"];
            let (a, b) = (m.nodes[arc[0].nodes[0]], m.nodes[arc[0].nodes[1]]);
            let along_arc = r * 2.0 * (0.5 * dist(a, b) / r).asin();
            assert_close(along_arc, dy[0], 1e-12, "first arc element");
            let cp = m.node_sets["contact_point"][0];
            let el = m
                .elements
                .iter()
                .find(|e| e.nodes[..4].contains(&cp))
                .unwrap();
            let sides: Vec<f64> = (0..4)
                .map(|k| dist(m.nodes[el.nodes[k]], m.nodes[el.nodes[(k + 1) % 4]]))
                .collect();
            let aspect = sides.iter().cloned().fold(0.0, f64::max)
                / sides.iter().cloned().fold(f64::MAX, f64::min);
            assert!(aspect < 1.2, "contact element aspect {aspect}");
        }
    }
}

#[test]
fn disk_elements_are_well_shaped_for_any_grading() {
    // Corner angles stay within 30..160 degrees (in fact about 40..153) for
    // coarse to fine and uniform to strongly graded meshes, quarter and half.
    for n in [2, 3, 4, 5, 8, 13, 20, 40] {
        for ratio in [1.0, 2.0, 5.0, 10.0, 30.0, 100.0] {
            for half in [false, true] {
                let m =
                    generators::disk(ElementKind::Q8, [0.5, -1.0], 3.0, n, ratio, half).unwrap();
                m.check().unwrap();
                let (lo, hi) = angles(&m);
                assert!(
                    lo > 30.0 && hi < 160.0,
                    "n {n} ratio {ratio}: angles {lo}..{hi}"
                );
            }
        }
    }
}

#[test]
fn disk_half_mirrors_the_quarter() {
    let (c, r) = ([0.0, 3.0], 3.0);
    for kind in KINDS {
        let q = generators::disk(kind, c, r, 6, 4.0, false).unwrap();
        let h = generators::disk(kind, c, r, 6, 4.0, true).unwrap();
        assert_sound(&h, &[], true);
        assert!(!h.edge_sets.contains_key("axis"));
        assert_eq!(h.elements.len(), 2 * q.elements.len());
        // The axis nodes are shared.
        assert_eq!(h.nodes.len(), 2 * q.nodes.len() - q.node_sets["axis"].len());
        assert_eq!(h.edge_sets["arc"].len(), 2 * q.edge_sets["arc"].len());
        assert_eq!(h.edge_sets["top"].len(), 2 * q.edge_sets["top"].len());
        // The arc runs from (-R, 0) through the contact point to (R, 0).
        let arc = &h.edge_sets["arc"];
        assert!(dist(h.nodes[arc[0].nodes[0]], [-3.0, 3.0]) < 1e-12);
        assert!(dist(h.nodes[arc[arc.len() - 1].nodes[1]], [3.0, 3.0]) < 1e-12);
        let cp = h.node_sets["contact_point"][0];
        assert_eq!(h.nodes[cp], [0.0, 0.0]);
        let middle = arc.len() / 2;
        assert_eq!(arc[middle].nodes[0], cp);
        assert_close(area(&h), 2.0 * area(&q), 1e-12, "half = two quarters");
    }
}

// --------------------------------------------------------------------- ring

#[test]
fn ring_sector_area_sets_and_grading() {
    let (c, ri, ro) = ([1.0, -1.0], 1.0, 3.0);
    for kind in KINDS {
        let m = generators::ring(kind, c, ri, ro, [30.0, 120.0], [4, 6], 3.0).unwrap();
        assert_sound(&m, &[], true);
        let per = if kind == ElementKind::Q8 { 2 } else { 1 };
        for (name, edges) in [("inner", 6), ("outer", 6), ("start", 4), ("end", 4)] {
            assert_eq!(m.edge_sets[name].len(), edges, "{name}");
            assert_eq!(m.node_sets[name].len(), per * edges + 1, "{name}");
        }
        for (name, radius) in [("inner", ri), ("outer", ro)] {
            for &k in &m.node_sets[name] {
                assert!((dist(m.nodes[k], c) - radius).abs() < 1e-12 * radius);
            }
        }
        // "start" runs outward along 30 degrees, "end" inward along 120.
        let s = &m.edge_sets["start"];
        let p = m.nodes[s[0].nodes[0]];
        let angle = (p[1] - c[1]).atan2(p[0] - c[0]).to_degrees();
        assert_close(angle, 30.0, 1e-12, "start angle");
        assert_close(dist(p, c), ri, 1e-12, "start begins inside");
        let radial = steps(&m, &corner_nodes(&m, "start"), |p| dist(p, c));
        assert_close(radial[3] / radial[0], 3.0, 1e-12, "radial grading");
        // Exact sector area, less the circular segments over the outer
        // faces' chords (parabolas), plus those over the inner ones, which
        // the body does not hold.
        let exact = 0.25 * PI * (ro * ro - ri * ri);
        let defect =
            arc_defect(&m, &m.edge_sets["outer"], ro) - arc_defect(&m, &m.edge_sets["inner"], ri);
        assert_close(area(&m) + defect, exact, 1e-12, "ring area with segments");
        let bound = arc_error_bound(&m, &m.edge_sets["outer"], ro, exact)
            + arc_error_bound(&m, &m.edge_sets["inner"], ri, exact);
        assert_close(area(&m), exact, bound, "ring area");
    }
}

#[test]
fn closed_ring_merges_its_seam() {
    for kind in KINDS {
        let m = generators::ring(kind, [0.0, 0.0], 1.0, 2.0, [-90.0, 270.0], [2, 8], 1.0).unwrap();
        assert_sound(&m, &[], true);
        assert!(!m.edge_sets.contains_key("start") && !m.edge_sets.contains_key("end"));
        let nodes = match kind {
            ElementKind::Q4 => 3 * 8,
            ElementKind::Q8 => 3 * 8 + 2 * 8 + 3 * 8,
        };
        assert_eq!(m.nodes.len(), nodes);
        for name in ["inner", "outer"] {
            let e = &m.edge_sets[name];
            assert_eq!(e.len(), 8);
            assert_eq!(e[e.len() - 1].nodes[1], e[0].nodes[0], "{name} loop closes");
        }
        let a = area(&m);
        let exact = PI * 3.0;
        let defect =
            arc_defect(&m, &m.edge_sets["outer"], 2.0) - arc_defect(&m, &m.edge_sets["inner"], 1.0);
        assert_close(a + defect, exact, 1e-12, "closed ring area");
    }
}

// ------------------------------------------------------------ plate with hole

#[test]
fn plate_with_hole_area_sets_and_grading() {
    let a = 1.0;
    // A square plate (one O-grid block) and a wide, shallow one (O-grid plus
    // strips): the buried pipe near the surface.
    for (width, y_range, divisions, ratio) in [
        (4.0, [-4.0, 4.0], [5, 12], 3.0),
        (6.0, [-7.0, 1.5], [4, 10], 2.0),
    ] {
        for kind in KINDS {
            let m = generators::plate_with_hole(kind, a, width, y_range, divisions, ratio).unwrap();
            assert_sound(&m, &[("axis", 2)], true);
            let hole = &m.edge_sets["hole"];
            assert_eq!(hole.len(), divisions[1]);
            for &k in &m.node_sets["hole"] {
                assert!(
                    (dist(m.nodes[k], [0.0, 0.0]) - a).abs() < 1e-12,
                    "hole node {k}"
                );
            }
            // The hole runs from its top to its bottom; the axis from the top
            // of the plate down to the hole, then from the hole down.
            assert_eq!(m.nodes[hole[0].nodes[0]], [0.0, a]);
            assert_eq!(m.nodes[hole[hole.len() - 1].nodes[1]], [0.0, -a]);
            let axis = &m.edge_sets["axis"];
            assert_eq!(m.nodes[axis[0].nodes[0]], [0.0, y_range[1]]);
            assert_eq!(m.nodes[axis[axis.len() - 1].nodes[1]], [0.0, y_range[0]]);
            let exact = width * (y_range[1] - y_range[0]) - 0.5 * PI * a * a;
            let defect = arc_defect(&m, hole, a);
            assert_close(area(&m) - defect, exact, 1e-12, "plate area with segments");
            let bound = arc_error_bound(&m, hole, a, exact);
            assert_close(area(&m), exact, bound, "plate area");
            for side in ["right", "top", "bottom"] {
                assert!(!m.edge_sets[side].is_empty());
            }
        }
    }
    // Radial grading along the axis above the hole (square plate: the O-grid
    // reaches the top).
    let m =
        generators::plate_with_hole(ElementKind::Q4, a, 4.0, [-4.0, 4.0], [5, 12], 3.0).unwrap();
    let above: Vec<usize> = corner_nodes(&m, "axis")
        .into_iter()
        .filter(|&n| m.nodes[n][1] > 0.0)
        .collect();
    let dy = steps(&m, &above, |p| p[1]);
    assert_eq!(dy.len(), 5);
    assert_close(dy[4] / dy[0], 3.0, 1e-12, "radial grading");
    let (lo, hi) = angles(&m);
    assert!(lo > 30.0 && hi < 160.0, "angles {lo}..{hi}");
}

// -------------------------------------------------------------- operations

#[test]
fn subset_renumbers_and_restricts_sets() {
    // 3 x 1 Q4 strip: elements 0, 1, 2 left to right; keep 1 and 2.
    let m =
        generators::rectangle(ElementKind::Q4, [0.0, 0.0], [3.0, 1.0], [3, 1], [1.0, 1.0]).unwrap();
    let s = m.subset(&[1, 2]);
    assert_eq!(s.elements.len(), 2);
    assert_eq!(
        s.nodes,
        vec![
            [1.0, 0.0],
            [2.0, 0.0],
            [3.0, 0.0],
            [1.0, 1.0],
            [2.0, 1.0],
            [3.0, 1.0]
        ]
    );
    assert_eq!(s.elements[0].nodes, vec![0, 1, 4, 3]);
    assert_eq!(s.elements[1].nodes, vec![1, 2, 5, 4]);
    assert_eq!(s.element_sets["all"], vec![0, 1]);
    assert_eq!(s.edge_sets["bottom"].len(), 2);
    assert_eq!(s.edge_sets["bottom"][0].element, 0);
    assert_eq!(s.node_sets["bottom"], vec![0, 1, 2]);
    assert_eq!(s.node_sets["right"], vec![2, 5]);
    // The left side and its corners went with element 0.
    assert!(!s.edge_sets.contains_key("left"));
    assert!(!s.node_sets.contains_key("left") && !s.node_sets.contains_key("bottom_left"));
    s.check().unwrap();
}

#[test]
fn append_offsets_and_prefixes() {
    let mut a = generators::rectangle(ElementKind::Q4, [0.0, -1.0], [2.0, 1.0], [2, 1], [1.0, 1.0])
        .unwrap();
    let b = generators::disk(ElementKind::Q4, [1.0, 1.0], 1.0, 2, 1.0, false).unwrap();
    let (na, ea) = (a.nodes.len(), a.elements.len());
    let offsets = a.append(&b, "wheel.");
    assert_eq!(offsets, (na, ea));
    assert_eq!(a.nodes.len(), na + b.nodes.len());
    assert_eq!(
        a.elements[ea].nodes,
        b.elements[0]
            .nodes
            .iter()
            .map(|n| n + na)
            .collect::<Vec<_>>()
    );
    assert_eq!(
        a.node_sets["wheel.contact_point"],
        vec![b.node_sets["contact_point"][0] + na]
    );
    assert_eq!(
        a.element_sets["wheel.all"],
        (ea..ea + b.elements.len()).collect::<Vec<_>>()
    );
    assert_eq!(
        a.edge_sets["wheel.arc"][0].element,
        b.edge_sets["arc"][0].element + ea
    );
    assert_eq!(
        a.edge_set_nodes("wheel.arc").unwrap(),
        b.node_sets["arc"]
            .iter()
            .map(|n| n + na)
            .collect::<Vec<_>>()
    );
    assert!(a.edge_sets.contains_key("bottom") && a.edge_set_nodes("nothing").is_none());
    a.check().unwrap();
}

#[test]
fn check_names_the_element_and_corner() {
    let mut m =
        generators::rectangle(ElementKind::Q4, [0.0, 0.0], [2.0, 1.0], [2, 1], [1.0, 1.0]).unwrap();
    m.elements[1].nodes.reverse(); // clockwise
    match m.check().unwrap_err() {
        MeshError::Inverted {
            element, corner, ..
        } => assert_eq!((element, corner), (1, 0)),
        e => panic!("{e}"),
    }
    // A bow-tie: corner 2 crosses over.
    let mut m =
        generators::rectangle(ElementKind::Q4, [0.0, 0.0], [1.0, 1.0], [1, 1], [1.0, 1.0]).unwrap();
    m.nodes[3] = [-0.5, 0.5];
    let e = m.check().unwrap_err();
    assert!(
        matches!(
            e,
            MeshError::Inverted {
                element: 0,
                corner: 2,
                ..
            }
        ),
        "{e}"
    );
    assert!(
        e.to_string()
            .starts_with("element 0: corner 2 (node 3) has a non-positive Jacobian"),
        "{e}"
    );
    // A Q8 mid-side node at 0.3 of its face (at 0.25 the Jacobian would
    // vanish at corner 0: a quarter-point element).
    let mut m =
        generators::rectangle(ElementKind::Q8, [0.0, 0.0], [1.0, 1.0], [1, 1], [1.0, 1.0]).unwrap();
    let mid = m.elements[0].nodes[4];
    m.nodes[mid] = [0.3, 0.0];
    let e = m.check().unwrap_err();
    assert!(
        matches!(
            e,
            MeshError::MidSideNode {
                element: 0,
                face: 0,
                ..
            }
        ),
        "{e}"
    );
    assert_eq!(
        e.to_string(),
        format!(
            "element 0: mid-side node {mid} of face 0 lies at 0.300 of the face's length, outside its middle third"
        )
    );
}

// --------------------------------------------------------------------- gmsh

const BLOCK: &str = "tests/data/block_q4.msh";
const QUAD8: &str = "tests/data/quad_q8.msh";

fn edge(element: usize, face: usize, nodes: &[usize]) -> Edge {
    Edge {
        element,
        face,
        nodes: nodes.to_vec(),
    }
}

#[test]
fn gmsh_q4_block() {
    let m = gmsh::read(Path::new(BLOCK)).unwrap();
    // Node tags 1, 12, 3, 5, 10, 11 in file order; tag 7 is used by no quad.
    assert_eq!(
        m.nodes,
        vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [2.0, 0.0],
            [0.0, 1.0],
            [1.0, 1.0],
            [2.0, 1.0]
        ]
    );
    let q4 = |nodes: [usize; 4]| Element {
        kind: ElementKind::Q4,
        nodes: nodes.to_vec(),
    };
    // The second quad is clockwise in the file (12 10 11 3).
    assert_eq!(m.elements, vec![q4([0, 1, 4, 3]), q4([1, 2, 5, 4])]);
    assert_eq!(m.element_sets.len(), 1);
    assert_eq!(m.element_sets["block"], vec![0, 1]);
    // The lines come in the file right to left; chained left to right.
    assert_eq!(
        m.edge_sets["bottom"],
        vec![edge(0, 0, &[0, 1]), edge(1, 0, &[1, 2])]
    );
    assert_eq!(m.node_sets["bottom"], vec![0, 1, 2]);
    assert_eq!(m.node_sets["corner"], vec![0]);
    assert_eq!(m.node_sets.len(), 2);
    assert_sound(&m, &[], false);
}

#[test]
fn gmsh_q8_quad() {
    let m = gmsh::read(Path::new(QUAD8)).unwrap();
    // File order: tag 3, then 1 2 5, then 4 6 7 8.
    assert_eq!(
        m.nodes,
        vec![
            [2.0, 1.0],
            [0.0, 0.0],
            [2.0, 0.0],
            [1.0, 0.0],
            [0.0, 1.0],
            [2.0, 0.5],
            [1.0, 1.0],
            [0.0, 0.5]
        ]
    );
    // Clockwise 1 4 3 2 | 8 7 6 5 in the file: tags 1..8 once reordered.
    assert_eq!(m.elements.len(), 1);
    assert_eq!(m.elements[0].kind, ElementKind::Q8);
    assert_eq!(m.elements[0].nodes, vec![1, 2, 0, 4, 3, 5, 6, 7]);
    // The 3-node line runs 2 -> 1; the edge follows the face 1 -> 2.
    assert_eq!(m.edge_sets["bottom"], vec![edge(0, 0, &[1, 2, 3])]);
    assert_eq!(m.node_sets["bottom"], vec![1, 2, 3]);
    assert_eq!(m.node_sets["corner"], vec![0]);
    assert_eq!(m.element_sets["block"], vec![0]);
    assert_sound(&m, &[], false);
    assert_close(area(&m), 2.0, 1e-14, "area");
}

#[test]
fn gmsh_group_names() {
    let text = std::fs::read_to_string(BLOCK).unwrap();
    let spaced = text.replace("2 3 \"block\"", "2 3  \"soil block\" ");
    let m = gmsh::parse(&spaced, Path::new(BLOCK)).unwrap();
    assert_eq!(m.element_sets["soil block"], vec![0, 1]);
    // Without $PhysicalNames the groups are named by tag.
    let start = text.find("$PhysicalNames").unwrap();
    let end = text.find("$Entities").unwrap();
    let text = format!("{}{}", &text[..start], &text[end..]);
    let m = gmsh::parse(&text, Path::new(BLOCK)).unwrap();
    assert_eq!(m.element_sets["group3"], vec![0, 1]);
    assert_eq!(m.edge_sets["group2"].len(), 2);
    assert_eq!(m.node_sets["group1"], vec![0]);
}

/// The block file with lines replaced ((1-based line, text)); the parse error.
fn gmsh_error(replace: &[(usize, &str)]) -> String {
    let text = std::fs::read_to_string(BLOCK).unwrap();
    let mut lines: Vec<&str> = text.lines().collect();
    for &(line, replacement) in replace {
        lines[line - 1] = replacement;
    }
    let text = lines.join("\n");
    gmsh::parse(&text, Path::new(BLOCK))
        .unwrap_err()
        .to_string()
}

#[test]
fn gmsh_errors_give_file_and_line() {
    assert_eq!(
        gmsh_error(&[(44, "2 1 2 2")]),
        "tests/data/block_q4.msh:44: element type 2 (3-node triangle) is not supported; \
         use quadrilaterals (3 or 16)"
    );
    assert_eq!(
        gmsh_error(&[(2, "2.2 0 8")]),
        "tests/data/block_q4.msh:2: MSH version 2.2 is not supported; save the mesh as version \
         4.1 ASCII (gmsh -format msh41, or Mesh.MshFileVersion = 4.1)"
    );
    assert_eq!(
        gmsh_error(&[(2, "4.1 1 8")]),
        "tests/data/block_q4.msh:2: binary MSH files are not supported; save the mesh as ASCII \
         (Mesh.Binary = 0)"
    );
    // The surface entity refers to physical group 4, which has no name.
    assert_eq!(
        gmsh_error(&[(14, "1 0 0 0 2 1 0 1 4 0")]),
        "tests/data/block_q4.msh:14: physical group 4 (dimension 2) of entity 1 has no name in \
         $PhysicalNames"
    );
    assert_eq!(
        gmsh_error(&[(31, "1 1 0.25")]),
        "tests/data/block_q4.msh:31: node 10 has z = 0.25; only plane meshes in z = 0 are supported"
    );
    // The diagonal 1-10 is no quad's face.
    assert_eq!(
        gmsh_error(&[(43, "3 1 10")]),
        "tests/data/block_q4.msh:43: line element 3 (nodes 1 10) is not on the face of any quadrilateral"
    );
    assert_eq!(
        gmsh_error(&[(46, "5 12 10 11")]),
        "tests/data/block_q4.msh:47: expected a node tag, found \"$EndElements\": the section ends early"
    );
    // Mixed Q4 and Q8.
    assert_eq!(
        gmsh_error(&[
            (38, "4 6 1 6"),
            (46, "5 12 10 11 3\n2 1 16 1\n6 1 12 10 5 1 1 1 1")
        ]),
        "tests/data/block_q4.msh:48: element 6 is a 8-node quadrilateral in a mesh of 4-node ones; \
         mixed Q4 and Q8 meshes are not supported"
    );
    let e = gmsh::read(Path::new("tests/data/no_such.msh")).unwrap_err();
    assert!(e.to_string().starts_with("tests/data/no_such.msh: "), "{e}");
}
