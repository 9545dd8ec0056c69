//! Structured meshes for the paper's problems: a graded rectangle, a disk
//! graded toward its contact point, a ring sector and a plate with a hole.
//! Each is a few mapped blocks on a half-spaced node lattice (Q8 mid-side
//! nodes sit on the lattice's odd points); boundary sets are found by geometry.

use super::{Edge, Element, ElementKind, Mesh, MeshError, chain, edge_nodes, face_local_nodes};
use std::collections::HashMap;
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

type Point = [f64; 2];

/// Rectangle [x0, x0+w] x [y0, y0+h], divisions [nx, ny], ratio [rx, ry] =
/// size of the last element / size of the first element along x (left to
/// right) and y (bottom to top), geometric grading; 1.0 = uniform (a single
/// division ignores its ratio). Edge and node sets "bottom", "right", "top",
/// "left"; node sets "bottom_left", "bottom_right", "top_right", "top_left";
/// element set "all".
pub fn rectangle(
    kind: ElementKind,
    origin: [f64; 2],
    size: [f64; 2],
    divisions: [usize; 2],
    ratio: [f64; 2],
) -> Result<Mesh, MeshError> {
    let g = Check("rectangle");
    g.finite("origin", &origin)?;
    for a in 0..2 {
        g.positive(["size[0]", "size[1]"][a], size[a])?;
        g.count(["divisions[0]", "divisions[1]"][a], divisions[a], 1)?;
        g.positive(["ratio[0]", "ratio[1]"][a], ratio[a])?;
    }
    let x = fine(&graded(divisions[0], ratio[0]));
    let y = fine(&graded(divisions[1], ratio[1]));
    let lattice = Lattice::new(divisions[0], divisions[1], |i, j| {
        [origin[0] + size[0] * x[i], origin[1] + size[1] * y[j]]
    });
    let mut b = Builder::new(kind, size[0].max(size[1]));
    b.add(&lattice);
    let [x0, y0] = origin;
    let [x1, y1] = [x0 + size[0], y0 + size[1]];
    let mut mesh = b.finish();
    let tol = 1e-9 * size[0].max(size[1]);
    let near = |a: f64, b: f64| (a - b).abs() <= tol;
    add_edge_set(&mut mesh, "bottom", &[&|p| near(p[1], y0)]);
    add_edge_set(&mut mesh, "right", &[&|p| near(p[0], x1)]);
    add_edge_set(&mut mesh, "top", &[&|p| near(p[1], y1)]);
    add_edge_set(&mut mesh, "left", &[&|p| near(p[0], x0)]);
    for (name, corner) in [
        ("bottom_left", [x0, y0]),
        ("bottom_right", [x1, y0]),
        ("top_right", [x1, y1]),
        ("top_left", [x0, y1]),
    ] {
        add_point_set(&mut mesh, name, corner, tol);
    }
    Ok(mesh)
}

/// The straight reference of a strip laid along a path
/// (`crate::strip::StripPath`): [0, length] x [-t/2, t/2], divisions
/// [along, across], uniform. Edge and node sets "inner" (the face at
/// y = t/2 when `inner_on_top`, else at -t/2), "outer" (the other),
/// "supply" (x = 0) and "takeup" (x = length); element set "all".
pub fn strip(
    kind: ElementKind,
    length: f64,
    thickness: f64,
    inner_on_top: bool,
    divisions: [usize; 2],
) -> Result<Mesh, MeshError> {
    let mut mesh = rectangle(
        kind,
        [0.0, -0.5 * thickness],
        [length, thickness],
        divisions,
        [1.0, 1.0],
    )?;
    let (inner, outer) = if inner_on_top {
        ("top", "bottom")
    } else {
        ("bottom", "top")
    };
    for (from, to) in [
        (inner, "inner"),
        (outer, "outer"),
        ("left", "supply"),
        ("right", "takeup"),
    ] {
        if let Some(edges) = mesh.edge_sets.remove(from) {
            mesh.edge_sets.insert(to.into(), edges);
        }
        if let Some(nodes) = mesh.node_sets.remove(from) {
            mesh.node_sets.insert(to.into(), nodes);
        }
    }
    for corner in ["bottom_left", "bottom_right", "top_right", "top_left"] {
        mesh.node_sets.remove(corner);
    }
    Ok(mesh)
}

/// Lower part of a disk of radius `radius` centred at `center`, touching
/// y = cy - radius at the contact point (cx, cy - radius): the quarter x >= cx
/// (`half` = false) or the whole lower half (`half` = true).
///
/// `divisions` elements run along the axis from the center to the contact
/// point, graded geometrically so that the element at the center is `ratio`
/// times the one at the contact point; the arc starts with that same small
/// size, so the elements at the contact point are squares.
///
/// An O-grid centred on the contact point: a square core block at it, and a
/// shell around the core out to the diameter, interpolated in log-polar
/// coordinates about the contact point so that its rings of elements grow
/// with the distance from it (corner angles stay within about 40..150 deg).
///
/// Edge and node sets "arc" (with increasing x), "top" (the diameter, from
/// +x to -x), "axis" (x = cx from the center down, quarter only); node set
/// "contact_point"; element set "all". Arc mid-side nodes lie on the circle.
pub fn disk(
    kind: ElementKind,
    center: [f64; 2],
    radius: f64,
    divisions: usize,
    ratio: f64,
    half: bool,
) -> Result<Mesh, MeshError> {
    let g = Check("disk");
    g.finite("center", &center)?;
    g.positive("radius", radius)?;
    g.count("divisions", divisions, 2)?;
    g.at_least_one("ratio", ratio)?;
    // On the unit circle about the origin, C = (0, -1): the core [C, D, P, A]
    // (D on the arc, A on the axis), the shell [A-P-D, arc to E = (1, 0),
    // diameter E to O = (0, 0), axis O to A].
    let n = divisions;
    let d = graded(n, ratio);
    // Elements along the diameter = elements on each ring about C. In
    // log-polar terms a ring element is square when it spans ln q radians,
    // q the growth per element along the axis; at most n (uniform meshes).
    let log_q = ratio.ln() / (n - 1) as f64;
    let along_top = if log_q > 1e-12 {
        (2 * (FRAC_PI_4 / log_q).round() as usize).clamp(2, n)
    } else {
        n
    };
    // A square core [C, D, P, A]: m_axis elements up the axis, m_arc along the arc.
    let m_axis = along_top / 2;
    let m_arc = along_top - m_axis;
    let shell = n - m_axis;

    // Core: u along the arc from C, v up the axis from C.
    // The point at arc length s from C (E = (1, 0) exactly).
    let arc = |s: f64| {
        if s == FRAC_PI_2 {
            [1.0, 0.0]
        } else {
            [s.sin(), -s.cos()]
        }
    };
    debug_assert_eq!(d.len() - 1 - m_axis, shell);
    let arc_d = &d[..=m_arc];
    let s_d = d[m_arc];
    let corner_d = arc(s_d);
    let rho = d[m_axis];
    // P: D moved rho inward, halfway between the arc's normal and the axis
    // direction (square for a small core, no narrow wedge for a large one).
    let inward = [-corner_d[0], 1.0 - corner_d[1]];
    let corner_p = add(corner_d, scale(inward, rho / norm(inward)));
    let corner_a = [0.0, -1.0 + rho];
    let core_bottom: Vec<Point> = fine(arc_d).iter().map(|&s| arc(s)).collect();
    let core_left: Vec<Point> = fine(&d[..=m_axis])
        .iter()
        .map(|&t| [0.0, -1.0 + t])
        .collect();
    let core_right = straight(corner_d, corner_p, &fine(&uniform(m_axis)));
    let core_top = straight(corner_a, corner_p, &fine(&uniform(m_arc)));
    let core = Lattice::transfinite(&core_bottom, &core_top, &core_left, &core_right);

    // Shell: u from the axis (A) over P to the arc (D), v outward.
    let mut shell_bottom = core_top.clone();
    shell_bottom.extend(core_right.iter().rev().skip(1));
    let shell_top = straight([0.0, 0.0], [1.0, 0.0], &fine(&uniform(along_top)));
    let shell_left: Vec<Point> = fine(&d[m_axis..])
        .iter()
        .map(|&t| [0.0, -1.0 + t])
        .collect();
    let arc_s = shell_arc(&d[m_axis..], s_d);
    let shell_right: Vec<Point> = fine(&arc_s).iter().map(|&s| arc(s)).collect();
    let outer = log_polar_lattice(&shell_bottom, &shell_top, &shell_left, &shell_right);

    let mut blocks = vec![core, outer];
    for block in &mut blocks {
        block.straighten_interior();
    }
    if half {
        let mirrored: Vec<Lattice> = blocks.iter().map(Lattice::mirrored).collect();
        blocks.extend(mirrored);
    }
    let mut b = Builder::new(kind, 1.0);
    for block in &blocks {
        b.add(block);
    }
    let mut mesh = b.finish();
    let tol = 1e-9;
    add_edge_set(&mut mesh, "arc", &[&|p| (norm(p) - 1.0).abs() <= tol]);
    add_edge_set(&mut mesh, "top", &[&|p| p[1].abs() <= tol]);
    if !half {
        add_edge_set(&mut mesh, "axis", &[&|p| p[0].abs() <= tol]);
    }
    add_point_set(&mut mesh, "contact_point", [0.0, -1.0], tol);
    for p in &mut mesh.nodes {
        *p = [center[0] + radius * p[0], center[1] + radius * p[1]];
    }
    Ok(mesh)
}

/// The disk's shell: arc lengths from C (on the unit circle, C = (0, -1))
/// of its arc nodes, at the distances from C of its axis nodes (`left`,
/// from the core's corner A to O), shifted in log scale from the core's
/// tilt (|CD| / |CA|, D at arc length `s_d`) to the shell's (|CE| / |CO|);
/// the last is E's, pi / 2, exactly.
fn shell_arc(left: &[f64], s_d: f64) -> Vec<f64> {
    let shell = left.len() - 1;
    let left_log: Vec<f64> = left.iter().map(|t| t.ln()).collect();
    let (first, last) = (left_log[0], left_log[shell]);
    let chord = |s: f64| 2.0 * (0.5 * s).sin();
    let (tilt0, tilt1) = (chord(s_d).ln() - first, 2f64.sqrt().ln());
    (left_log.iter().enumerate())
        .map(|(k, &l)| {
            if k == shell {
                return FRAC_PI_2;
            }
            let t = (l - first) / (last - first);
            let rho = (l + tilt0 + t * (tilt1 - tilt0)).exp();
            2.0 * (0.5 * rho).asin()
        })
        .collect()
}

/// The lattice between four sides interpolated in log-polar coordinates
/// about C = (0, -1) (a conformal map), so its rings are near circles about
/// C and its elements near squares; its boundary points exactly the sides'.
fn log_polar_lattice(bottom: &[Point], top: &[Point], left: &[Point], right: &[Point]) -> Lattice {
    let log_polar = |p: Point| {
        let z = [p[0], p[1] + 1.0];
        [norm(z).ln(), z[1].atan2(z[0])]
    };
    let back = |w: Point| [w[0].exp() * w[1].cos(), w[0].exp() * w[1].sin() - 1.0];
    let map = |side: &[Point]| -> Vec<Point> { side.iter().map(|&p| log_polar(p)).collect() };
    let mut lattice = Lattice::transfinite(&map(bottom), &map(top), &map(left), &map(right));
    lattice.points = lattice.points.iter().map(|&w| back(w)).collect();
    lattice.set_sides(bottom, top, left, right);
    lattice
}

/// Ring sector r_inner..r_outer between the angles [a0, a1] (degrees,
/// counter-clockwise from +x); divisions [n_radial, n_circumferential];
/// `ratio` = radial size of the outermost / innermost row. A span of 360
/// degrees closes the ring (no "start" and "end").
/// Edge and node sets "inner" (clockwise), "outer" (counter-clockwise),
/// "start" (at a0, outward), "end" (at a1, inward); element set "all".
pub fn ring(
    kind: ElementKind,
    center: [f64; 2],
    r_inner: f64,
    r_outer: f64,
    angles_deg: [f64; 2],
    divisions: [usize; 2],
    ratio: f64,
) -> Result<Mesh, MeshError> {
    let g = Check("ring");
    g.finite("center", &center)?;
    g.finite("angles", &angles_deg)?;
    g.positive("r_inner", r_inner)?;
    if r_outer <= r_inner || !r_outer.is_finite() {
        return Err(g.error(format!(
            "r_outer = {r_outer:?} must exceed r_inner = {r_inner:?}"
        )));
    }
    g.count("divisions[0]", divisions[0], 1)?;
    g.count("divisions[1]", divisions[1], 1)?;
    g.positive("ratio", ratio)?;
    let span = angles_deg[1] - angles_deg[0];
    let closed = (span - 360.0).abs() <= 1e-9;
    if span <= 0.0 || (span > 360.0 && !closed) {
        return Err(g.error(format!(
            "angles = {angles_deg:?} must increase by more than 0 and at most 360 degrees"
        )));
    }
    let per = span / divisions[1] as f64;
    if per > 120.0 || (closed && divisions[1] < 3) {
        return Err(g.error(format!(
            "divisions[1] = {} leaves {per} degrees per element; at most 120 are allowed",
            divisions[1]
        )));
    }
    let r = fine(&graded(divisions[0], ratio));
    let t = fine(&uniform(divisions[1]));
    let (a0, a1) = (angles_deg[0].to_radians(), angles_deg[1].to_radians());
    // u outward, v counter-clockwise: a right-handed lattice.
    let lattice = Lattice::new(divisions[0], divisions[1], |i, j| {
        let radius = r_inner + (r_outer - r_inner) * r[i];
        let angle = a0 + (a1 - a0) * t[j];
        [
            center[0] + radius * angle.cos(),
            center[1] + radius * angle.sin(),
        ]
    });
    let mut b = Builder::new(kind, r_outer);
    b.add(&lattice);
    let mut mesh = b.finish();
    let tol = 1e-9 * r_outer;
    let radius = |p: Point| norm(sub(p, center));
    add_edge_set(
        &mut mesh,
        "inner",
        &[&|p| (radius(p) - r_inner).abs() <= tol],
    );
    add_edge_set(
        &mut mesh,
        "outer",
        &[&|p| (radius(p) - r_outer).abs() <= tol],
    );
    if !closed {
        let on_ray = |p: Point, a: f64| {
            let v = sub(p, center);
            (v[1] * a.cos() - v[0] * a.sin()).abs() <= tol && dot(v, [a.cos(), a.sin()]) > 0.0
        };
        add_edge_set(&mut mesh, "start", &[&|p| on_ray(p, a0)]);
        add_edge_set(&mut mesh, "end", &[&|p| on_ray(p, a1)]);
    }
    Ok(mesh)
}

/// Right half of the plate [0, width] x [y_min, y_max] with a hole of radius
/// `hole_radius` at the origin. divisions [n_radial, n_circumferential]:
/// elements from the hole out to a box around it, and along the half circle;
/// `ratio` = radial size of the box's outer row / of the row at the hole.
/// Edge and node sets "hole" (top to bottom), "axis" (x = 0: the part above
/// the hole, top down, then the part below), "right", "top", "bottom";
/// element set "all".
pub fn plate_with_hole(
    kind: ElementKind,
    hole_radius: f64,
    width: f64,
    y_range: [f64; 2],
    divisions: [usize; 2],
    ratio: f64,
) -> Result<Mesh, MeshError> {
    let g = Check("plate_with_hole");
    g.positive("hole_radius", hole_radius)?;
    g.finite("y_range", &y_range)?;
    let a = hole_radius;
    if width <= a || !width.is_finite() {
        return Err(g.error(format!("width = {width:?} must exceed hole_radius = {a:?}")));
    }
    let [y_min, y_max] = y_range;
    if y_min >= -a || y_max <= a {
        return Err(g.error(format!(
            "y_range = {y_range:?} must reach below -hole_radius and above hole_radius = {a:?}"
        )));
    }
    g.count("divisions[0]", divisions[0], 1)?;
    g.count("divisions[1]", divisions[1], 3)?;
    g.at_least_one("ratio", ratio)?;
    let [n_r, n_c] = divisions;

    // An O-grid of straight rays from the hole to a box [0, bx] x [-bb, bt]
    // at most twice as long as its shortest half side; uniform Cartesian
    // strips (and corner blocks) fill the rest of the plate.
    let shortest = width.min(y_max).min(-y_min);
    let (bx, bt, bb) = (
        width.min(2.0 * shortest),
        y_max.min(2.0 * shortest),
        (-y_min).min(2.0 * shortest),
    );
    let (hole_angles, n_top, n_right) = hole_angles(n_c, [bx, bt, bb]);
    let mut hole: Vec<Point> = fine(&hole_angles)
        .iter()
        .map(|&t| [a * t.cos(), a * t.sin()])
        .collect();
    // The ends on the axis exactly.
    let fu = hole.len() - 1;
    (hole[0], hole[fu]) = ([0.0, a], [0.0, -a]);
    let corners = [0, n_top, n_top + n_right, n_c];
    let outer = midpoints(&box_points(&hole_angles, corners, [bx, bt, bb]));
    let w = fine(&graded(n_r, ratio));
    // u along the hole from the top, v outward: right-handed.
    let o_grid = Lattice::new(n_c, n_r, |i, j| {
        let (p, q) = (hole[i], outer[i]);
        [p[0] + w[j] * (q[0] - p[0]), p[1] + w[j] * (q[1] - p[1])]
    });

    // Strips: sizes of the O-grid's outer row where it meets each box side.
    let last = 1.0 - w[w.len() - 3];
    let strip = |from: f64, to: f64, row: f64| -> Result<Vec<f64>, MeshError> {
        // Elements as long as the O-grid's outer row: a plate far larger
        // than its hole would need more than any mesh may have.
        let n = ((to - from) / row).round().max(1.0);
        if n > MAX_STRIP as f64 {
            return Err(g.error(format!(
                "the plate from {from:.6e} to {to:.6e} would need {n:.3e} elements of the size of the O-grid's outer row (at most {MAX_STRIP}): make the plate smaller against the hole or the O-grid's divisions fewer"
            )));
        }
        Ok(fine(&uniform(n as usize))
            .iter()
            .map(|t| from + (to - from) * t)
            .collect())
    };
    let xs_right = strip(bx, width, (bx - a) * last)?;
    let ys_top = strip(bt, y_max, (bt - a) * last)?;
    let ys_bottom: Vec<f64> = strip(y_min, -bb, (bb - a) * last)?;
    let side = |range: std::ops::RangeInclusive<usize>, c: usize| -> Vec<f64> {
        outer[range].iter().map(|p| p[c]).collect()
    };
    let f = |k: usize| 2 * k; // coarse to fine index
    // The box sides as the O-grid runs them: top left to right, right and
    // bottom backwards.
    let xs_top = side(0..=f(n_top), 0);
    let mut ys_right = side(f(n_top)..=f(n_top + n_right), 1);
    let mut xs_bottom = side(f(n_top + n_right)..=f(n_c), 0);
    ys_right.reverse();
    xs_bottom.reverse();
    let grid = |xs: &[f64], ys: &[f64]| {
        Lattice::new((xs.len() - 1) / 2, (ys.len() - 1) / 2, |i, j| {
            [xs[i], ys[j]]
        })
    };
    let mut blocks = vec![o_grid];
    if width > bx {
        blocks.push(grid(&xs_right, &ys_right));
    }
    if y_max > bt {
        blocks.push(grid(&xs_top, &ys_top));
        if width > bx {
            blocks.push(grid(&xs_right, &ys_top));
        }
    }
    if -y_min > bb {
        blocks.push(grid(&xs_bottom, &ys_bottom));
        if width > bx {
            blocks.push(grid(&xs_right, &ys_bottom));
        }
    }
    let size = width.max(y_max - y_min);
    let mut b = Builder::new(kind, size);
    for block in &blocks {
        b.add(block);
    }
    let mut mesh = b.finish();
    add_plate_edge_sets(&mut mesh, a, width, y_range, 1e-9 * size);
    Ok(mesh)
}

/// The O-grid's angles along the hole (coarse, from the top at pi/2 to the
/// bottom at -pi/2), the half circle split among the box `[0, bx] x [-bb,
/// bt]`'s top, right and bottom by the angles of its corners (each side
/// at least one element); with the elements along the top and along the
/// right.
fn hole_angles(n_c: usize, [bx, bt, bb]: [f64; 3]) -> (Vec<f64>, usize, usize) {
    let top_right = bt.atan2(bx);
    let bottom_right = (-bb).atan2(bx);
    let share = |angle: f64| angle / PI * n_c as f64;
    let n_top = (share(FRAC_PI_2 - top_right).round() as usize).clamp(1, n_c - 2);
    let n_bottom = (share(bottom_right + FRAC_PI_2).round() as usize).clamp(1, n_c - 1 - n_top);
    let n_right = n_c - n_top - n_bottom;
    let mut angles = Vec::with_capacity(n_c + 1);
    for (from, to, count) in [
        (FRAC_PI_2, top_right, n_top),
        (top_right, bottom_right, n_right),
        (bottom_right, -FRAC_PI_2, n_bottom),
    ] {
        let start = usize::from(!angles.is_empty());
        for k in start..=count {
            angles.push(from + (to - from) * k as f64 / count as f64);
        }
    }
    (angles, n_top, n_right)
}

/// Where each of the O-grid's rays (`angles`) meets the box `[0, bx] x
/// [-bb, bt]`; the rays at `corners` (the top of the axis, the top right
/// and bottom right corners, the bottom of the axis) end on them exactly.
fn box_points(angles: &[f64], corners: [usize; 4], [bx, bt, bb]: [f64; 3]) -> Vec<Point> {
    let corner_points = [[0.0, bt], [bx, bt], [bx, -bb], [0.0, -bb]];
    (angles.iter().enumerate())
        .map(|(k, &t)| {
            // (The four are distinct: each side has an element.)
            if let Some(c) = corners.iter().position(|&c| c == k) {
                return corner_points[c];
            }
            let (c, s) = (t.cos(), t.sin());
            let reach = |limit: f64, v: f64| {
                if v.abs() > 1e-12 {
                    limit / v
                } else {
                    f64::INFINITY
                }
            };
            let l = reach(bx, c).min(reach(if s > 0.0 { bt } else { -bb }, s));
            [l * c, l * s]
        })
        .collect()
}

/// The plate's edge sets: `hole`, `axis` (both sides of the hole),
/// `right`, `top` and `bottom`, a node on one within `tol`.
fn add_plate_edge_sets(mesh: &mut Mesh, a: f64, width: f64, [y_min, y_max]: [f64; 2], tol: f64) {
    let near = |u: f64, v: f64| (u - v).abs() <= tol;
    add_edge_set(mesh, "hole", &[&|p| near(norm(p), a)]);
    add_edge_set(
        mesh,
        "axis",
        &[&|p| near(p[0], 0.0) && p[1] > 0.0, &|p| {
            near(p[0], 0.0) && p[1] < 0.0
        }],
    );
    add_edge_set(mesh, "right", &[&|p| near(p[0], width)]);
    add_edge_set(mesh, "top", &[&|p| near(p[1], y_max)]);
    add_edge_set(mesh, "bottom", &[&|p| near(p[1], y_min)]);
}

/// Parameter checks naming the generator and the offending value.
struct Check(&'static str);

impl Check {
    fn error(&self, message: String) -> MeshError {
        MeshError::Generator {
            generator: self.0,
            message,
        }
    }
    fn positive(&self, what: &str, v: f64) -> Result<(), MeshError> {
        if v > 0.0 && v.is_finite() {
            Ok(())
        } else {
            Err(self.error(format!("{what} = {v:?} must be positive")))
        }
    }
    fn at_least_one(&self, what: &str, v: f64) -> Result<(), MeshError> {
        if v >= 1.0 && v.is_finite() {
            Ok(())
        } else {
            Err(self.error(format!("{what} = {v:?} must be at least 1")))
        }
    }
    fn finite(&self, what: &str, v: &[f64; 2]) -> Result<(), MeshError> {
        if v.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(self.error(format!("{what} = {v:?} must be finite")))
        }
    }
    fn count(&self, what: &str, n: usize, min: usize) -> Result<(), MeshError> {
        if n >= min {
            Ok(())
        } else {
            Err(self.error(format!("{what} = {n} must be at least {min}")))
        }
    }
}

/// n + 1 positions from 0 to 1 whose steps grow geometrically, the last
/// `ratio` times the first.
fn graded(n: usize, ratio: f64) -> Vec<f64> {
    if n == 1 || (ratio - 1.0).abs() < 1e-14 {
        return uniform(n);
    }
    let log_q = ratio.ln() / (n - 1) as f64;
    let total = (n as f64 * log_q).exp_m1();
    let mut t: Vec<f64> = (0..=n)
        .map(|k| (k as f64 * log_q).exp_m1() / total)
        .collect();
    t[n] = 1.0;
    t
}

/// Elements one strip of `plate_with_hole` may have.
const MAX_STRIP: usize = 1_000_000;

fn uniform(n: usize) -> Vec<f64> {
    (0..=n).map(|k| k as f64 / n as f64).collect()
}

/// The positions with their midpoints inserted (the half-spaced lattice).
fn fine(t: &[f64]) -> Vec<f64> {
    let mut f = Vec::with_capacity(2 * t.len() - 1);
    for w in t.windows(2) {
        f.extend([w[0], 0.5 * (w[0] + w[1])]);
    }
    f.push(t[t.len() - 1]);
    f
}

/// Points with the midpoints of consecutive points inserted.
fn midpoints(p: &[Point]) -> Vec<Point> {
    let mut f = Vec::with_capacity(2 * p.len() - 1);
    for w in p.windows(2) {
        f.extend([w[0], scale(add(w[0], w[1]), 0.5)]);
    }
    f.push(p[p.len() - 1]);
    f
}

/// Points of the segment a-b at the (fine) positions `t`.
fn straight(a: Point, b: Point, t: &[f64]) -> Vec<Point> {
    t.iter().map(|&s| add(a, scale(sub(b, a), s))).collect()
}

/// A block of nu x nv elements as a (2 nu + 1) x (2 nv + 1) lattice of
/// points, u fastest; element corners at even indices.
struct Lattice {
    nu: usize,
    nv: usize,
    points: Vec<Point>,
}

impl Lattice {
    fn new(nu: usize, nv: usize, point: impl Fn(usize, usize) -> Point) -> Self {
        let points = (0..=2 * nv)
            .flat_map(|j| (0..=2 * nu).map(move |i| (i, j)))
            .map(|(i, j)| point(i, j))
            .collect();
        Lattice { nu, nv, points }
    }

    /// Transfinite interpolation of four sides given as fine point lists:
    /// bottom and top run in u, left and right in v; boundary points are
    /// taken as given. The blending weights average the normalised lengths
    /// along opposite sides.
    fn transfinite(bottom: &[Point], top: &[Point], left: &[Point], right: &[Point]) -> Self {
        assert!(bottom.len() == top.len() && left.len() == right.len());
        let (fu, fv) = (bottom.len() - 1, left.len() - 1);
        let average = |a: &[Point], b: &[Point]| -> Vec<f64> {
            let (la, lb) = (lengths(a), lengths(b));
            la.iter().zip(&lb).map(|(x, y)| 0.5 * (x + y)).collect()
        };
        let u = average(bottom, top);
        let v = average(left, right);
        let corner = [bottom[0], bottom[fu], top[fu], top[0]];
        Lattice::new(fu / 2, fv / 2, |i, j| {
            if j == 0 {
                return bottom[i];
            }
            if j == fv {
                return top[i];
            }
            if i == 0 {
                return left[j];
            }
            if i == fu {
                return right[j];
            }
            let (s, t) = (u[i], v[j]);
            let mut p = [0.0; 2];
            for c in 0..2 {
                p[c] = (1.0 - t) * bottom[i][c]
                    + t * top[i][c]
                    + (1.0 - s) * left[j][c]
                    + s * right[j][c]
                    - (1.0 - s) * (1.0 - t) * corner[0][c]
                    - s * (1.0 - t) * corner[1][c]
                    - s * t * corner[2][c]
                    - (1.0 - s) * t * corner[3][c];
            }
            p
        })
    }

    fn set_sides(&mut self, bottom: &[Point], top: &[Point], left: &[Point], right: &[Point]) {
        let (fu, fv) = (2 * self.nu, 2 * self.nv);
        let w = fu + 1;
        for i in 0..=fu {
            self.points[i] = bottom[i];
            self.points[fv * w + i] = top[i];
        }
        for j in 0..=fv {
            self.points[j * w] = left[j];
            self.points[j * w + fu] = right[j];
        }
    }

    /// Interior mid-side points at the middle of their element side (the
    /// interpolation may have bent the sides).
    fn straighten_interior(&mut self) {
        let (fu, fv) = (2 * self.nu, 2 * self.nv);
        let w = fu + 1;
        for j in 1..fv {
            for i in 1..fu {
                let (a, b) = match (i % 2, j % 2) {
                    (1, 0) => (j * w + i - 1, j * w + i + 1),
                    (0, 1) => ((j - 1) * w + i, (j + 1) * w + i),
                    _ => continue,
                };
                self.points[j * w + i] = scale(add(self.points[a], self.points[b]), 0.5);
            }
        }
    }

    /// The mirror image in x = 0, u reversed to stay counter-clockwise.
    fn mirrored(&self) -> Self {
        let w = 2 * self.nu + 1;
        Lattice::new(self.nu, self.nv, |i, j| {
            let p = self.points[j * w + (2 * self.nu - i)];
            [-p[0], p[1]]
        })
    }
}

/// Normalised cumulative lengths along a polyline, 0 to 1.
fn lengths(p: &[Point]) -> Vec<f64> {
    let mut l = vec![0.0];
    for w in p.windows(2) {
        l.push(l[l.len() - 1] + norm(sub(w[1], w[0])));
    }
    let total = l[l.len() - 1];
    l.iter().map(|x| x / total).collect()
}

/// Collects blocks into one mesh, merging nodes that coincide (shared block
/// sides, a closed ring's seam, a mirrored disk's axis).
struct Builder {
    kind: ElementKind,
    tol: f64,
    nodes: Vec<Point>,
    elements: Vec<Element>,
    cells: HashMap<(i64, i64), Vec<usize>>,
}

impl Builder {
    fn new(kind: ElementKind, size: f64) -> Self {
        Builder {
            kind,
            tol: 1e-9 * size,
            nodes: Vec::new(),
            elements: Vec::new(),
            cells: HashMap::new(),
        }
    }

    fn node(&mut self, p: Point) -> usize {
        let cell = |x: f64| (x / self.tol).round() as i64;
        let (cx, cy) = (cell(p[0]), cell(p[1]));
        for dx in -1..=1 {
            for dy in -1..=1 {
                if let Some(found) = self.cells.get(&(cx + dx, cy + dy)) {
                    for &n in found {
                        let q = self.nodes[n];
                        if (q[0] - p[0]).abs() <= self.tol && (q[1] - p[1]).abs() <= self.tol {
                            return n;
                        }
                    }
                }
            }
        }
        self.nodes.push(p);
        let n = self.nodes.len() - 1;
        self.cells.entry((cx, cy)).or_default().push(n);
        n
    }

    /// The lattice's nodes row by row, then its elements row by row.
    fn add(&mut self, l: &Lattice) {
        let w = 2 * l.nu + 1;
        let kind = self.kind;
        let used = |i: usize, j: usize| match kind {
            ElementKind::Q4 => i.is_multiple_of(2) && j.is_multiple_of(2),
            ElementKind::Q8 => i.is_multiple_of(2) || j.is_multiple_of(2),
        };
        let mut id = vec![usize::MAX; l.points.len()];
        for j in 0..=2 * l.nv {
            for i in 0..=2 * l.nu {
                if used(i, j) {
                    id[j * w + i] = self.node(l.points[j * w + i]);
                }
            }
        }
        for ej in 0..l.nv {
            for ei in 0..l.nu {
                let (i, j) = (2 * ei, 2 * ej);
                let at = |di: usize, dj: usize| id[(j + dj) * w + i + di];
                let mut nodes = vec![at(0, 0), at(2, 0), at(2, 2), at(0, 2)];
                if self.kind == ElementKind::Q8 {
                    nodes.extend([at(1, 0), at(2, 1), at(1, 2), at(0, 1)]);
                }
                self.elements.push(Element {
                    kind: self.kind,
                    nodes,
                });
            }
        }
    }

    fn finish(self) -> Mesh {
        let all = (0..self.elements.len()).collect();
        let mut mesh = Mesh {
            nodes: self.nodes,
            elements: self.elements,
            ..Mesh::default()
        };
        mesh.element_sets.insert("all".into(), all);
        mesh
    }
}

/// Edge and node set `name`: the boundary faces whose nodes all satisfy one
/// of `parts`, each part chained head to tail, in the order given.
fn add_edge_set(mesh: &mut Mesh, name: &str, parts: &[&dyn Fn(Point) -> bool]) {
    let boundary = mesh.boundary_edges();
    let mut edges: Vec<Edge> = Vec::new();
    for on in parts {
        let part: Vec<Edge> = boundary
            .iter()
            .filter(|e| e.nodes.iter().all(|&n| on(mesh.nodes[n])))
            .cloned()
            .collect();
        edges.extend(chain(part));
    }
    debug_assert!(edges.iter().all(|e| {
        let el = &mesh.elements[e.element];
        face_local_nodes(el.kind, e.face)
            .iter()
            .zip(&e.nodes)
            .all(|(&l, &n)| el.nodes[l] == n)
    }));
    mesh.node_sets.insert(name.into(), edge_nodes(&edges));
    mesh.edge_sets.insert(name.into(), edges);
}

/// Node set `name` holding the node at `p`.
fn add_point_set(mesh: &mut Mesh, name: &str, p: Point, tol: f64) {
    let n = mesh
        .nodes
        .iter()
        .position(|q| (q[0] - p[0]).abs() <= tol && (q[1] - p[1]).abs() <= tol)
        .expect("the generator places a node there");
    mesh.node_sets.insert(name.into(), vec![n]);
}

fn add(a: Point, b: Point) -> Point {
    [a[0] + b[0], a[1] + b[1]]
}
fn sub(a: Point, b: Point) -> Point {
    [a[0] - b[0], a[1] - b[1]]
}
fn scale(a: Point, s: f64) -> Point {
    [a[0] * s, a[1] * s]
}
fn dot(a: Point, b: Point) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
fn norm(a: Point) -> f64 {
    dot(a, a).sqrt()
}
