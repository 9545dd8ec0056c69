//! The mortar integrals of a pair at an iterate: per contactor node j its
//! weighted gap `g_j = int Phi_j g_n ds` over the contactor, with `Phi_j`
//! the dual basis of the contactor's side interpolation and `g_n` the gap
//! along the interpolated nodal normal, with the gradient (the constraint
//! row) and Hessian (the contact tangent) of each.
//!
//! Segmentation (Popp, Gee & Wall 2009 in 2D): each contactor side is cut
//! where the target side's end nodes project onto it along the contactor's
//! normal field; Gauss points on each cut piece project onto the target
//! side along the same field. Every step is written in `Dual` numbers over
//! the unknowns it depends on (the side's nodes and its neighbours', whose
//! positions set the nodal normals, and the target side's nodes), so the
//! cut points, projections and normals are linearised exactly.

use super::dual::{Dual, V2};
use super::surface::{Surface, node_xi, shape};
use crate::contact::report::Geometry;

/// Points and weights of 3-point Gauss integration on [-1, 1]: exact to
/// degree 5. On a straight side (an 8-node one with its mid-side node in
/// the middle) the position is linear in the parameter, so the integrands
/// are of degree 4 at most (a shape function times a dual basis function,
/// both quadratic, times the radius), and the gap on a piece is linear.
const GAUSS: [(f64, f64); 3] = [
    (-0.774_596_669_241_483_4, 5.0 / 9.0),
    (0.0, 8.0 / 9.0),
    (0.774_596_669_241_483_4, 5.0 / 9.0),
];

/// The pair's surfaces and positions at the iterate.
pub(super) struct Setting<'a> {
    pub contactor: &'a Surface,
    pub target: &'a Surface,
    /// Current positions of the contactor's and the target's surface nodes.
    pub x: &'a [[f64; 2]],
    pub y: &'a [[f64; 2]],
    /// Reference positions of the contactor's nodes.
    pub x_ref: &'a [[f64; 2]],
    /// The integrals' measure: the reference length (small strain: the
    /// multipliers are tractions per reference area, as the element
    /// stresses are) or the current one (total Lagrangian: Cauchy
    /// tractions).
    pub reference_measure: bool,
    pub geometry: Geometry,
    /// How far into the target a contactor point may be and still meet it
    /// (not the far side of a thin target).
    pub reach: f64,
    /// The pair has friction: the parts carry the tangential integrals
    /// (`Part::slips`).
    pub friction: bool,
}

/// One contactor side against one target side: its unknowns' mesh dofs
/// and, per contactor node of the side, that side pair's part of its
/// weighted gap with gradient and Hessian over those unknowns.
pub(super) struct Part {
    pub dofs: Vec<usize>,
    /// (contactor surface node, value, gradient, Hessian row by row; empty
    /// to the first `Order`).
    pub gaps: Vec<(usize, f64, Vec<f64>, Vec<f64>)>,
    /// Per node of `gaps`, the gap weighted by its hat function instead
    /// (`hat`: positive, so this is negative only where the target is
    /// entered near the node): value and gradient.
    pub hat_weighted: Vec<(f64, Vec<f64>)>,
    /// Per node of `gaps`, the integral of its hat function over the
    /// overlap (its covered weight): value and gradient. The hat-weighted
    /// gap over it is the node's mean gap where the target covers it.
    pub covered: Vec<(f64, Vec<f64>)>,
    /// With friction, per node of `gaps`: the side pair's part of `tau_j .
    /// int Phi_j (x - y) ds`, the contactor's points less the target's
    /// points they meet along the normal field, along the node's unit
    /// tangent `tau_j` (`nodal_tangent`): value, gradient, Hessian row by
    /// row (empty to the first `Order`). The weighted slip (`slip_from`)
    /// subtracts it.
    pub slips: Vec<(f64, Vec<f64>, Vec<f64>)>,
}

/// One contactor node's mortar coupling at a configuration: `int Phi_j
/// N_k ds` for the contactor's surface nodes k and `int Phi_j N_l ds` for
/// the target's l, over the overlaps of its sides with the target. Taken
/// at the start of an increment, `sum_k D_jk x_k - sum_l M_jl y_l` in the
/// current positions is the contactor's points less the target's points
/// they met then, weighted (`slip_from`).
#[derive(Clone, Debug, Default)]
pub(super) struct Coupling {
    pub contactor: Vec<(usize, f64)>,
    pub target: Vec<(usize, f64)>,
}

/// How far the integrals are differentiated: the values and gradients
/// (the rows and forces, at every iterate), or the Hessians as well (the
/// contact tangent, for the iterates a solve starts from).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Order {
    First,
    Second,
}

/// Every side pair's part of the weighted gaps (`Part`; to the `order`
/// asked), and per contactor node the integral of its shape function (its
/// share of the contactor's area, in the same measure).
pub(super) fn integrate(s: &Setting, order: Order) -> (Vec<Part>, Vec<f64>) {
    let mut parts = Vec::new();
    for e in 0..s.contactor.sides.len() {
        let cover = cover(s, e);
        let support = s.contactor.normal_support(e).len();
        for &m in &cover.met {
            let count = 2
                * (support + s.target.sides[m].len() + cover.extra_nodes(&s.target.sides[m]).len());
            // Each size is one more copy of the dual-number code in the
            // FMU's library, which issue 15 keeps under 2 MB. To the first
            // order one size serves every side pair (a value's operations
            // run over its span, and its copies are small); to the second,
            // three: a linear side pair, a quadratic one or a linear one
            // with cutting nodes, and a quadratic one with cutting nodes.
            // (Forming the linear side pairs' Hessians in 20 unknowns
            // rounds them differently, which took Cattaneo-Mindlin's first
            // increment over two solves per iteration.)
            let part = match (count, order) {
                (_, Order::First) => side_pair::<32, 0>(s, e, m, &cover),
                (..=12, Order::Second) => side_pair::<12, 78>(s, e, m, &cover),
                (13..=20, Order::Second) => side_pair::<20, 210>(s, e, m, &cover),
                (_, Order::Second) => side_pair::<32, 528>(s, e, m, &cover),
            };
            parts.extend(part);
        }
    }
    (parts, areas(s))
}

/// Where a contactor side meets the target: the target sides it overlaps
/// (`met`) and the pieces of its parameter range they cover, merged.
/// Each piece's end is a side end or the projection of the target node
/// that cuts it there (an end of the target surface, or where its
/// projection turns back).
struct Cover {
    met: Vec<usize>,
    pieces: Vec<[Cut; 2]>,
}

/// A covered piece's end in the contactor side's parameter: at a side end
/// (`node` None), or where target surface node `node` projects.
#[derive(Clone, Copy, Debug)]
struct Cut {
    xi: f64,
    node: Option<usize>,
}

impl Cover {
    /// Whether the target covers the whole side.
    fn whole(&self) -> bool {
        matches!(
            self.pieces[..],
            [[Cut { node: None, .. }, Cut { node: None, .. }]]
        )
    }

    /// The target nodes that cut the side and are not among `target`'s.
    fn extra_nodes(&self, target: &[usize]) -> Vec<usize> {
        let mut list = Vec::new();
        for cut in self.pieces.iter().flatten() {
            if let Some(k) = cut.node
                && !target.contains(&k)
                && !list.contains(&k)
            {
                list.push(k);
            }
        }
        list
    }
}

/// Pieces closer than this in the parameter (of order 1) are one: the
/// same target node projected from its two sides agrees to round-off of
/// the projection (`root`, 1e-12).
const SAME_CUT: f64 = 1e-9;

/// The cover of contactor side e (`Cover`), in plain numbers.
fn cover(s: &Setting, e: usize) -> Cover {
    let side = &s.contactor.sides[e];
    let at = |k: usize| V2::<0, 0>::c(s.x[k]);
    let xs: Vec<V2<0, 0>> = side.iter().map(|&k| at(k)).collect();
    let ns = nodal_normals(s.contactor, e, &at);
    let mut met = Vec::new();
    let mut pieces: Vec<[Cut; 2]> = Vec::new();
    let bound = ProjectionBound::of(&xs, &ns);
    for m in (0..s.target.sides.len()).filter(|&m| near(s, e, m)) {
        let target = &s.target.sides[m];
        if bound.is_some_and(|b| {
            b.beyond_one_end([target[0], target[target.len() - 1]].map(|k| s.y[k]))
        }) {
            continue;
        }
        let ys: Vec<V2<0, 0>> = target.iter().map(|&k| V2::c(s.y[k])).collect();
        let Some(ends) = overlap(&xs, &ns, &ys, s.reach) else {
            continue;
        };
        met.push(m);
        pieces.push(ends.map(|(xi, end)| Cut {
            xi: xi.v,
            node: end.map(|i| target[i]),
        }));
    }
    pieces.sort_by(|a, b| a[0].xi.total_cmp(&b[0].xi));
    let mut merged: Vec<[Cut; 2]> = Vec::new();
    for piece in pieces {
        match merged.last_mut() {
            Some(last) if piece[0].xi <= last[1].xi + SAME_CUT => {
                if piece[1].xi > last[1].xi {
                    last[1] = piece[1];
                }
            }
            _ => merged.push(piece),
        }
    }
    Cover {
        met,
        pieces: merged,
    }
}

/// Where a point's projection onto a contactor side along its normal
/// field can lie, from the point's projection onto the side's chord,
/// without the projection's iteration (`cover` skips the side pairs it
/// rules out: in a scene of 160 contactor and 90 target sides, 8,000 pairs
/// lie within reach and 220 meet). The bound: the normal field's tilt
/// against the chord's normal (its nodal normals' largest, `tan`, widened
/// for a 3-node side's interpolation, whose shape functions reach -1/8)
/// moves a point at distance d from the chord by at most `tan (d + sag)`
/// along it, `sag` the side's mid node's distance from the chord; and a
/// 3-node side's parameter lies within `off` (its mid node's offset along
/// the chord from the middle) of the chord's.
#[derive(Clone, Copy)]
struct ProjectionBound {
    a: [f64; 2],
    /// Unit chord and its length.
    u: [f64; 2],
    length: f64,
    tan: f64,
    sag: f64,
    off: f64,
}

impl ProjectionBound {
    /// None where the bound does not serve: a degenerate chord, or a
    /// normal tilted by more than 60 degrees from the chord's (a surface
    /// corner's node).
    fn of(xs: &[V2<0, 0>], ns: &[V2<0, 0>]) -> Option<Self> {
        let (a, b) = (xs[0].value(), xs[xs.len() - 1].value());
        let d = [b[0] - a[0], b[1] - a[1]];
        let length = d[0].hypot(d[1]);
        if length.is_nan() || length <= 0.0 {
            return None;
        }
        let u = [d[0] / length, d[1] / length];
        let (mut along, mut across) = (0.0f64, 1.0f64);
        for n in ns {
            let n = n.value();
            let size = n[0].hypot(n[1]);
            let t = (n[0] * u[0] + n[1] * u[1]) / size;
            along = along.max(t.abs());
            across = across.min((1.0 - t * t).max(0.0).sqrt());
        }
        if across < 0.5 {
            return None;
        }
        let (sag, off) = if xs.len() == 3 {
            let m = xs[1].value();
            let r = [m[0] - 0.5 * (a[0] + b[0]), m[1] - 0.5 * (a[1] + b[1])];
            (
                (r[0] * u[1] - r[1] * u[0]).abs(),
                (r[0] * u[0] + r[1] * u[1]).abs(),
            )
        } else {
            (0.0, 0.0)
        };
        Some(ProjectionBound {
            a,
            u,
            length,
            tan: 1.25 * along / (across - 0.125),
            sag,
            off,
        })
    }

    /// The range of the side's parameter in which point `y`'s projections
    /// within the side lie (beyond its ends the normal field is
    /// extrapolated, and the bound does not hold).
    fn range(&self, y: [f64; 2]) -> (f64, f64) {
        let r = [y[0] - self.a[0], y[1] - self.a[1]];
        let s = r[0] * self.u[0] + r[1] * self.u[1];
        let d = (r[0] * self.u[1] - r[1] * self.u[0]).abs();
        let spread = self.tan * (d + self.sag) + self.off;
        let xi = |s: f64| 2.0 * s / self.length - 1.0;
        (xi(s - spread), xi(s + spread))
    }

    /// Whether points `ys` have no projection within the side and their
    /// chord projections lie beyond the same end, by more than a quarter
    /// of its length: no overlap.
    fn beyond_one_end(&self, ys: [[f64; 2]; 2]) -> bool {
        let [(lo0, hi0), (lo1, hi1)] = ys.map(|y| self.range(y));
        (lo0 > 1.5 && lo1 > 1.5) || (hi0 < -1.5 && hi1 < -1.5)
    }
}

/// Whether sides e and m lie within `reach` of each other (their bounding
/// boxes grown by it overlap).
fn near(s: &Setting, e: usize, m: usize) -> bool {
    let bbox = |pts: &mut dyn Iterator<Item = [f64; 2]>| {
        pts.fold([f64::MAX, f64::MAX, f64::MIN, f64::MIN], |b, p| {
            [
                b[0].min(p[0]),
                b[1].min(p[1]),
                b[2].max(p[0]),
                b[3].max(p[1]),
            ]
        })
    };
    let a = bbox(&mut s.contactor.sides[e].iter().map(|&k| s.x[k]));
    let b = bbox(&mut s.target.sides[m].iter().map(|&k| s.y[k]));
    let r = s.reach;
    a[0] - r <= b[2] && b[0] - r <= a[2] && a[1] - r <= b[3] && b[1] - r <= a[3]
}

/// Per contactor node, the integral of its shape functions over its
/// sides, in the pair's measure.
fn areas(s: &Setting) -> Vec<f64> {
    let mut area = vec![0.0; s.contactor.nodes.len()];
    for side in &s.contactor.sides {
        let xs: Vec<V2<0, 0>> = (side.iter())
            .map(|&k| {
                V2::c(if s.reference_measure {
                    s.x_ref[k]
                } else {
                    s.x[k]
                })
            })
            .collect();
        for &(z, w) in &GAUSS {
            let (n, dn) = shape(side.len(), Dual::<0, 0>::c(z));
            let ds = measure(s.geometry, &xs, &n, &dn).v * w;
            for (l, &k) in side.iter().enumerate() {
                area[k] += n[l].v * ds;
            }
        }
    }
    area
}

/// `sum w_i v_i`.
fn sum<const N: usize, const H: usize>(w: &[Dual<N, H>], v: &[V2<N, H>]) -> V2<N, H> {
    // Accumulated in place: a Dual is kilobytes, and each `acc + ...`
    // copied it whole.
    let mut acc = V2::zero();
    for (w, v) in w.iter().zip(v) {
        acc.0.add_product(1.0, w, &v.0);
        acc.1.add_product(1.0, w, &v.1);
    }
    acc
}

/// The integrand's measure at a side point: length per parameter times
/// the thickness, or times 2 pi r about the axis.
fn measure<const N: usize, const H: usize>(
    geometry: Geometry,
    xs: &[V2<N, H>],
    n: &[Dual<N, H>],
    dn: &[Dual<N, H>],
) -> Dual<N, H> {
    let length = sum(dn, xs).norm();
    match geometry {
        Geometry::Planar { thickness } => length * thickness,
        Geometry::Axisymmetric => length * sum(n, xs).0 * (2.0 * std::f64::consts::PI),
    }
}

/// The values of `v` with their derivatives dropped, for the plain
/// iterations of a projection (over one unknown, the parameter itself:
/// `root` reads the residual's second derivative in it).
fn plain<const N: usize, const H: usize>(v: &[V2<N, H>]) -> Vec<V2<1, 1>> {
    v.iter().map(|p| V2::c(p.value())).collect()
}

/// The root of `f` (value and derivative) near `start`, with its first
/// and second derivatives in the `N` unknowns: `plain_root`, then
/// `dual_root`. None if the plain iteration does not converge.
fn root<const N: usize, const H: usize>(
    f: impl Fn(Dual<N, H>) -> (Dual<N, H>, Dual<N, H>),
    f0: impl Fn(Dual<1, 1>) -> (Dual<1, 1>, Dual<1, 1>),
    start: f64,
) -> Option<Dual<N, H>> {
    plain_root(&f0, start).map(|xi| dual_root(f, f0, xi))
}

/// The root of `f0` near `start`, iterated in plain numbers to round-off;
/// None if the iteration does not converge.
fn plain_root(f0: impl Fn(Dual<1, 1>) -> (Dual<1, 1>, Dual<1, 1>), start: f64) -> Option<f64> {
    let mut xi = start;
    for _ in 0..30 {
        let (v, d) = f0(Dual::c(xi));
        let step = v.v / d.v;
        if !step.is_finite() {
            return None;
        }
        xi -= step;
        if xi.abs() > 1e3 {
            return None;
        }
        // Parameters are of order 1: 1e-12 is round-off's reach after
        // the cancellation in the residual.
        if step.abs() <= 1e-12 * (1.0 + xi.abs()) {
            return Some(xi);
        }
    }
    None
}

/// The root `r` of `f` at its plain value `xi` (`plain_root`) with its
/// first and second derivatives in the `N` unknowns. By the implicit
/// function theorem at `f(r, p) = 0`, `r_p = -f_p / f_r` and `r_pp =
/// -(f_pp + f_rp r_p^T + r_p f_rp^T + f_rr r_p r_p^T) / f_r`: one Newton
/// step in dual numbers from `xi` (`xi - f / f_r`, whose derivatives are
/// `r_p` and the first three terms of `r_pp`) and the last term added
/// (`f_rr` from `f0` with the parameter as its unknown). Its value is `xi`.
fn dual_root<const N: usize, const H: usize>(
    f: impl Fn(Dual<N, H>) -> (Dual<N, H>, Dual<N, H>),
    f0: impl Fn(Dual<1, 1>) -> (Dual<1, 1>, Dual<1, 1>),
    xi: f64,
) -> Dual<N, H> {
    let (v, d) = f(Dual::c(xi));
    let mut x = Dual::c(xi) - v / d;
    let (_, d0) = f0(Dual::var(xi, 0));
    let curvature = d0.g[0] / d.v;
    let first = x - Dual::c(x.v);
    x.add_product(-0.5 * curvature, &first, &first);
    // Its value is the plain root's, which decided where the root lies
    // (`overlap`: a target node that projects onto a contactor node cuts
    // one of its two sides, whose pairs read the same number).
    x.v = xi;
    x
}

/// The contactor side at `xi`: its point, tangent, and the normal field
/// interpolated from its nodal normals `ns` with its derivative.
fn contactor_at<const N: usize, const H: usize>(
    xs: &[V2<N, H>],
    ns: &[V2<N, H>],
    xi: Dual<N, H>,
) -> (V2<N, H>, V2<N, H>, V2<N, H>, V2<N, H>) {
    let (n, dn) = shape(xs.len(), xi);
    (sum(&n, xs), sum(&dn, xs), sum(&n, ns), sum(&dn, ns))
}

/// The contactor side's point at `xi` and its normal field there (not
/// unit): `contactor_at`'s first and third.
fn point_and_normal<const N: usize, const H: usize>(
    xs: &[V2<N, H>],
    ns: &[V2<N, H>],
    xi: Dual<N, H>,
) -> (V2<N, H>, V2<N, H>) {
    let (n, _) = shape(xs.len(), xi);
    (sum(&n, xs), sum(&n, ns))
}

/// Where point `y` lies on the contactor side along its normal field:
/// `(y - x(xi)) x n(xi)` and its derivative in xi.
fn onto_contactor<const N: usize, const H: usize>(
    xs: &[V2<N, H>],
    ns: &[V2<N, H>],
    y: V2<N, H>,
    xi: Dual<N, H>,
) -> (Dual<N, H>, Dual<N, H>) {
    let (x, t, n, dn) = contactor_at(xs, ns, xi);
    let d = y - x;
    (d.cross(&n), d.cross(&dn) - t.cross(&n))
}

/// Where the line through `p` along `n` meets the target side at eta:
/// `(y(eta) - p) x n` and its derivative in eta.
fn onto_target<const N: usize, const H: usize>(
    ys: &[V2<N, H>],
    p: &V2<N, H>,
    n: &V2<N, H>,
    eta: Dual<N, H>,
) -> (Dual<N, H>, Dual<N, H>) {
    let (w, dw) = shape(ys.len(), eta);
    ((sum(&w, ys) - *p).cross(n), sum(&dw, ys).cross(n))
}

/// The outward unit normals at side e's nodes: the average of the unit
/// tangents of the sides at each node, turned outward. `at(k)` is surface
/// node k's position.
fn nodal_normals<const N: usize, const H: usize>(
    surface: &Surface,
    e: usize,
    at: &dyn Fn(usize) -> V2<N, H>,
) -> Vec<V2<N, H>> {
    (surface.sides[e].iter())
        .map(|&k| nodal_tangent(surface, k, at).right())
        .collect()
}

/// The dual basis of a contactor side at `xs` (`Phi_j = sum_k A_jk N_k`)
/// over the `pieces` of its parameter range the target covers:
/// biorthogonal to its shape functions there in the pair's measure (`int
/// Phi_j N_k = delta_jk int N_k`, both over the pieces): `A = D M^-1`.
/// Taken over the covered part only (Cichosz & Bischoff 2011; Popp et al.
/// 2013), a node's weighted gap keeps the sign of the gap there: over the
/// whole side, the negative lobe of `Phi_j` over a piece next to the other
/// node could cancel a positive gap, and a node far from the target was
/// held on it.
fn dual_basis<const N: usize, const H: usize>(
    geometry: Geometry,
    xs: &[V2<N, H>],
    pieces: &[[Dual<N, H>; 2]],
) -> Vec<Vec<Dual<N, H>>> {
    let n = xs.len();
    let mut m = vec![vec![Dual::<N, H>::c(0.0); n]; n];
    let mut d = vec![Dual::<N, H>::c(0.0); n];
    for [lo, hi] in pieces {
        let (mid, half) = ((*lo + *hi) * 0.5, (*hi - *lo) * 0.5);
        for &(z, w) in &GAUSS {
            let (sh, dsh) = shape(n, mid + half * z);
            let ds = measure(geometry, xs, &sh, &dsh) * half * w;
            for j in 0..n {
                d[j].add_product(1.0, &sh[j], &ds);
                let shds = sh[j] * ds;
                for k in 0..n {
                    m[j][k].add_product(1.0, &shds, &sh[k]);
                }
            }
        }
    }
    let inv = inverse(&m);
    (0..n)
        .map(|j| (0..n).map(|k| d[j] * inv[j][k]).collect())
        .collect()
}

/// The covered pieces of a contactor side at `xs` (nodal normals `ns`) in
/// `N` unknowns: a cut by target node k is where `target_at(k)` projects
/// onto the side along its normal field.
fn pieces<const N: usize, const H: usize>(
    cover: &Cover,
    xs: &[V2<N, H>],
    ns: &[V2<N, H>],
    target_at: &dyn Fn(usize) -> V2<N, H>,
) -> Vec<[Dual<N, H>; 2]> {
    if cover.whole() || cover.pieces.is_empty() {
        // A side the target does not meet keeps the basis of its whole
        // range.
        return vec![[Dual::c(-1.0), Dual::c(1.0)]];
    }
    let (xs0, ns0) = (plain(xs), plain(ns));
    let cut = |c: &Cut| match c.node {
        None => Dual::c(c.xi),
        Some(k) => {
            let y = target_at(k);
            let y0 = V2::c(y.value());
            // Where the plain projection had converged from the chord,
            // started on its root it stays there; a zero slope there (a
            // projection at its turning point) keeps the plain cut.
            root(
                |xi| onto_contactor(xs, ns, y, xi),
                |xi| onto_contactor(&xs0, &ns0, y0, xi),
                c.xi,
            )
            .unwrap_or(Dual::c(c.xi))
        }
    };
    (cover.pieces.iter())
        .map(|[lo, hi]| [cut(lo), cut(hi)])
        .collect()
}

/// The inverse of a 2x2 or 3x3 matrix (cofactors over the determinant).
fn inverse<const N: usize, const H: usize>(m: &[Vec<Dual<N, H>>]) -> Vec<Vec<Dual<N, H>>> {
    if m.len() == 2 {
        let det = (m[0][0] * m[1][1] - m[0][1] * m[1][0]).recip();
        return vec![
            vec![m[1][1] * det, -m[0][1] * det],
            vec![-m[1][0] * det, m[0][0] * det],
        ];
    }
    let c = |i: usize, j: usize| {
        let (r, s) = ((i + 1) % 3, (i + 2) % 3);
        let (p, q) = ((j + 1) % 3, (j + 2) % 3);
        m[r][p] * m[s][q] - m[r][q] * m[s][p]
    };
    let det = (m[0][0] * c(0, 0) + m[0][1] * c(0, 1) + m[0][2] * c(0, 2)).recip();
    (0..3)
        .map(|i| (0..3).map(|j| c(j, i) * det).collect())
        .collect()
}

/// Where side pair (e, m) overlaps in the contactor side's parameter, in
/// `N` unknowns over `xs`, `ns` (the contactor side's positions and
/// nodal normals) and `ys` (the target side's positions): the target's end
/// nodes projected onto the contactor side along its normal field, clipped
/// to the side. None: no overlap, or the sides do not face each other
/// within `reach` (checked at the overlap's middle).
fn overlap<const N: usize, const H: usize>(
    xs: &[V2<N, H>],
    ns: &[V2<N, H>],
    ys: &[V2<N, H>],
    reach: f64,
) -> Option<[(Dual<N, H>, Option<usize>); 2]> {
    let (xs0, ns0, ys0) = (plain(xs), plain(ns), plain(ys));
    let last = ys.len() - 1;
    // The ends' projections in plain numbers; in dual numbers only where
    // they cut the side (an end beyond it clips at the side's end).
    let [Some(a), Some(b)] = [0, last].map(|i| {
        plain_root(
            |xi| onto_contactor(&xs0, &ns0, ys0[i], xi),
            chord_xi(&xs0, ys0[i].value()),
        )
    }) else {
        return None;
    };
    let (lo, hi) = if a <= b {
        ((a, 0), (b, last))
    } else {
        ((b, last), (a, 0))
    };
    let cut = |(xi, i): (f64, usize), inside: bool, side_end: f64| {
        if inside {
            let root = dual_root(
                |xi| onto_contactor(xs, ns, ys[i], xi),
                |xi| onto_contactor(&xs0, &ns0, ys0[i], xi),
                xi,
            );
            (root, Some(i))
        } else {
            (Dual::c(side_end), None)
        }
    };
    let lo = cut(lo, lo.0 > -1.0, -1.0);
    let hi = cut(hi, hi.0 < 1.0, 1.0);
    // However short, an overlap counts: its value vanishes with its length
    // but not its derivative, the motion of its cut, which cancels the
    // neighbouring piece's (a target node projecting just past a contactor
    // node). Dropped below a threshold, the neighbour's stayed alone: the
    // cylinder of 80 divisions on a block of 120 matched at its centre
    // node, and Newton cycled there at |r|/F = 2e-6.
    if hi.0.v <= lo.0.v {
        return None;
    }
    let (p, n) = point_and_normal(&xs0, &ns0, Dual::c(0.5 * (lo.0.v + hi.0.v)));
    let n = n.unit();
    let eta = plain_root(|eta| onto_target(&ys0, &p, &n, eta), 0.0)?;
    let (w, dw) = shape(ys0.len(), Dual::c(eta));
    let gap = (sum(&w, &ys0) - p).dot(&n).v;
    let facing = sum(&dw, &ys0).right().dot(&n).v < 0.0;
    (facing && gap >= -reach && eta.abs() <= 1.0 + 1e-6).then_some([lo, hi])
}

/// The part of side pair (e, m) in the contactor nodes' weighted gaps, in
/// `N` unknowns: the side's nodes and its neighbours' (the nodal normals),
/// the target side's, and the target nodes that cut the side's `cover`
/// elsewhere (the dual basis of a partly covered side depends on them).
/// None: the sides do not meet after all.
fn side_pair<const N: usize, const H: usize>(
    s: &Setting,
    e: usize,
    m: usize,
    cover: &Cover,
) -> Option<Part> {
    let support = s.contactor.normal_support(e);
    let target = &s.target.sides[m];
    let extra = cover.extra_nodes(target);
    let count = 2 * (support.len() + target.len() + extra.len());
    assert!(
        count <= N,
        "mortar side pair of {} + {} + {} nodes over {N} unknowns",
        support.len(),
        target.len(),
        extra.len()
    );
    let side = &s.contactor.sides[e];
    let var =
        |p: [f64; 2], i: usize| V2(Dual::<N, H>::var(p[0], 2 * i), Dual::var(p[1], 2 * i + 1));
    let at = |k: usize| {
        let i = support
            .iter()
            .position(|&q| q == k)
            .expect("in the support");
        var(s.x[k], i)
    };
    let xs: Vec<V2<N, H>> = side.iter().map(|&k| at(k)).collect();
    let ns = nodal_normals(s.contactor, e, &at);
    let target_at = |k: usize| match target.iter().position(|&q| q == k) {
        Some(i) => var(s.y[k], support.len() + i),
        None => {
            let i = extra.iter().position(|&q| q == k).expect("a cutting node");
            var(s.y[k], support.len() + target.len() + i)
        }
    };
    let ys: Vec<V2<N, H>> = target.iter().map(|&k| target_at(k)).collect();
    let reference: Vec<V2<N, H>> = side.iter().map(|&k| V2::c(s.x_ref[k])).collect();
    let measured = if s.reference_measure { &reference } else { &xs };
    let a_dual = dual_basis(s.geometry, measured, &pieces(cover, &xs, &ns, &target_at));
    let zero = Dual::<N, H>::c(0.0);
    let mut gaps = vec![zero; side.len()];
    let mut hat_weighted = vec![zero; side.len()];
    let mut covered = vec![zero; side.len()];
    let mut apart = vec![V2::<N, H>::zero(); if s.friction { side.len() } else { 0 }];
    for point in points(s, &xs, &ns, &ys, measured)? {
        let g = (point.y - point.x).dot(&point.n);
        let gds = g * point.ds;
        for (j, gap) in gaps.iter_mut().enumerate() {
            let mut phi = zero;
            for k in 0..side.len() {
                phi.add_product(1.0, &a_dual[j][k], &point.sh[k]);
            }
            gap.add_product(1.0, &phi, &gds);
            let hat_j = hat(side.len(), j, point.xi);
            // Their values and gradients alone are read (`Part`).
            hat_weighted[j].add_product_first_order(1.0, &hat_j, &gds);
            covered[j].add_product_first_order(1.0, &hat_j, &point.ds);
            if let Some(v) = apart.get_mut(j) {
                *v = *v + (point.x - point.y).scale(phi * point.ds);
            }
        }
    }

    let mut dofs = Vec::with_capacity(count);
    for &k in &support {
        dofs.extend([2 * s.contactor.nodes[k], 2 * s.contactor.nodes[k] + 1]);
    }
    for &k in target.iter().chain(&extra) {
        dofs.extend([2 * s.target.nodes[k], 2 * s.target.nodes[k] + 1]);
    }
    let hessian = |g: &Dual<N, H>| -> Vec<f64> {
        if H == 0 {
            return Vec::new();
        }
        (0..count)
            .flat_map(|i| (0..count).map(move |j| g.hessian(i, j)))
            .collect()
    };
    let plain_gradient = |g: &Dual<N, H>| (g.v, g.g[..count].to_vec());
    let hat_weighted = hat_weighted.iter().map(plain_gradient).collect();
    let covered = covered.iter().map(plain_gradient).collect();
    let gaps = (side.iter().zip(&gaps))
        .map(|(&k, g)| (k, g.v, g.g[..count].to_vec(), hessian(g)))
        .collect();
    // tau_j: the unit tangent the outward normal n_j turns from.
    let slips = (apart.iter().zip(&ns))
        .map(|(v, n)| {
            let t = v.dot(&V2(-n.1, n.0));
            (t.v, t.g[..count].to_vec(), hessian(&t))
        })
        .collect();
    Some(Part {
        dofs,
        gaps,
        hat_weighted,
        covered,
        slips,
    })
}

/// A Gauss point of a side pair's overlap: the contactor side's parameter
/// and shape functions there, its point, the unit normal of its normal
/// field, the target's point met along it and the target side's shape
/// functions there, and the point's weight in the pair's measure.
struct Point<const N: usize, const H: usize> {
    xi: Dual<N, H>,
    sh: [Dual<N, H>; 3],
    x: V2<N, H>,
    n: V2<N, H>,
    y: V2<N, H>,
    wt: [Dual<N, H>; 3],
    ds: Dual<N, H>,
}

/// The Gauss points of the overlap of the contactor side at `xs` (nodal
/// normals `ns`, its measure taken on `measured`) with the target side at
/// `ys` (None: they do not meet).
fn points<const N: usize, const H: usize>(
    s: &Setting,
    xs: &[V2<N, H>],
    ns: &[V2<N, H>],
    ys: &[V2<N, H>],
    measured: &[V2<N, H>],
) -> Option<Vec<Point<N, H>>> {
    let ys0 = plain(ys);
    let [(lo, _), (hi, _)] = overlap(xs, ns, ys, s.reach)?;
    let (mid, half) = ((lo + hi) * 0.5, (hi - lo) * 0.5);
    let mut out = Vec::with_capacity(GAUSS.len());
    for &(z, w) in &GAUSS {
        let xi = mid + half * z;
        let (x, n) = point_and_normal(xs, ns, xi);
        let n = n.unit();
        let (x0, n0) = (V2::c(x.value()), V2::c(n.value()));
        let eta = root(
            |eta| onto_target(ys, &x, &n, eta),
            |eta| onto_target(&ys0, &x0, &n0, eta),
            0.0,
        )?;
        let (wt, _) = shape(ys.len(), eta);
        let (sh, dsh) = shape(xs.len(), xi);
        let ds = measure(s.geometry, measured, &sh, &dsh) * half * w;
        out.push(Point {
            xi,
            y: sum(&wt, ys),
            sh,
            x,
            n,
            wt,
            ds,
        });
    }
    Some(out)
}

/// Per contactor node, its coupling (`Coupling`) at the setting's
/// positions, in plain numbers.
pub(super) fn couplings(s: &Setting) -> Vec<Coupling> {
    let mut out = vec![Coupling::default(); s.contactor.nodes.len()];
    for e in 0..s.contactor.sides.len() {
        let cover = cover(s, e);
        if cover.met.is_empty() {
            continue;
        }
        let side = &s.contactor.sides[e];
        let at = |k: usize| V2::<0, 0>::c(s.x[k]);
        let xs: Vec<V2<0, 0>> = side.iter().map(|&k| at(k)).collect();
        let ns = nodal_normals(s.contactor, e, &at);
        let reference: Vec<V2<0, 0>> = side.iter().map(|&k| V2::c(s.x_ref[k])).collect();
        let measured = if s.reference_measure { &reference } else { &xs };
        let target_at = |k: usize| V2::<0, 0>::c(s.y[k]);
        let a_dual = dual_basis(s.geometry, measured, &pieces(&cover, &xs, &ns, &target_at));
        for &m in &cover.met {
            let target = &s.target.sides[m];
            let ys: Vec<V2<0, 0>> = target.iter().map(|&k| V2::c(s.y[k])).collect();
            let Some(points) = points(s, &xs, &ns, &ys, measured) else {
                continue;
            };
            for point in points {
                for (j, &node) in side.iter().enumerate() {
                    let phi: f64 = (0..side.len())
                        .map(|k| a_dual[j][k].v * point.sh[k].v)
                        .sum();
                    let c = &mut out[node];
                    for (&k, sh) in side.iter().zip(&point.sh) {
                        add_to(&mut c.contactor, k, phi * sh.v * point.ds.v);
                    }
                    for (&l, wt) in target.iter().zip(&point.wt) {
                        add_to(&mut c.target, l, phi * wt.v * point.ds.v);
                    }
                }
            }
        }
    }
    out
}

/// `list[key] += v` in a short list of (key, value).
fn add_to(list: &mut Vec<(usize, f64)>, key: usize, v: f64) {
    match list.iter_mut().find(|(k, _)| *k == key) {
        Some(entry) => entry.1 += v,
        None => list.push((key, v)),
    }
}

/// The unit tangent of the contactor surface at its node `k` (toward the
/// next node; its outward normal turns from it): the average of the unit
/// tangents of the sides at the node, in `N` unknowns over the positions
/// `at` gives; on a symmetry plane (`Surface::mirror`), the plane's
/// normal.
pub(super) fn nodal_tangent<const N: usize, const H: usize>(
    surface: &Surface,
    k: usize,
    at: &dyn Fn(usize) -> V2<N, H>,
) -> V2<N, H> {
    let mut t = V2::zero();
    for &(side, l) in &surface.on[k] {
        let nodes = &surface.sides[side];
        let (_, dn) = shape(nodes.len(), Dual::<N, H>::c(node_xi(nodes.len(), l)));
        let xs: Vec<V2<N, H>> = nodes.iter().map(|&q| at(q)).collect();
        t = t + sum(&dn, &xs).unit();
    }
    match surface.mirror[k] {
        // On a symmetry plane: the side's tangent and its mirror image's
        // meet along the plane's normal `e`, whatever the side's turn.
        Some(e) => {
            let s = (t.value()[0] * e[0] + t.value()[1] * e[1]).signum();
            V2::c([s * e[0], s * e[1]])
        }
        None => t.unit(),
    }
}

/// The hat function of node `j` of a side of `n` nodes at `xi`: the
/// linear shape function on a 2-node side; on a 3-node side the linear
/// hats over its two halves (corner, mid-side, corner), which unlike the
/// quadratic shape functions are nowhere negative.
fn hat<const N: usize, const H: usize>(n: usize, j: usize, xi: Dual<N, H>) -> Dual<N, H> {
    let zero = Dual::c(0.0);
    match (n, j) {
        (2, 0) => xi * -0.5 + 0.5,
        (2, _) => xi * 0.5 + 0.5,
        (_, 0) if xi.v < 0.0 => -xi,
        (_, 2) if xi.v > 0.0 => xi,
        (_, 1) if xi.v < 0.0 => xi + 1.0,
        (_, 1) => -xi + 1.0,
        _ => zero,
    }
}

/// Where `y` projects on the chord of the contactor side, in its parameter:
/// the start of the projection along the normal field.
fn chord_xi<const N: usize, const H: usize>(xs: &[V2<N, H>], y: [f64; 2]) -> f64 {
    let (a, b) = (xs[0].value(), xs[xs.len() - 1].value());
    let d = [b[0] - a[0], b[1] - a[1]];
    let t = ((y[0] - a[0]) * d[0] + (y[1] - a[1]) * d[1]) / (d[0] * d[0] + d[1] * d[1]);
    2.0 * t - 1.0
}

#[cfg(test)]
mod tests;

/// The contactor's points less the target's points they met at the start
/// of the increment, weighted, along node k's unit tangent: `tau_k .
/// (sum_l D_kl x_l - sum_l M_kl y_l)` with the start's coupling and the
/// current positions (the weighted slip adds it to the current iterate's
/// `-Part::slips`). Value, gradient and Hessian entries over mesh dofs.
pub(super) fn slip_from(s: &Setting, k: usize, coupling: &Coupling) -> Sparse {
    let mut support: Vec<usize> = Vec::new();
    for &(side, _) in &s.contactor.on[k] {
        for &q in &s.contactor.sides[side] {
            if !support.contains(&q) {
                support.push(q);
            }
        }
    }
    assert!(
        support.len() <= 5,
        "a node's tangent over {} nodes",
        support.len()
    );
    let at = |q: usize| {
        let i = support
            .iter()
            .position(|&p| p == q)
            .expect("in the support");
        V2(
            Dual::<12, 78>::var(s.x[q][0], 2 * i),
            Dual::var(s.x[q][1], 2 * i + 1),
        )
    };
    let tau = nodal_tangent(s.contactor, k, &at);
    let tau = [tau.0, tau.1];
    // c = sum D x - sum M y: linear in the positions, dc_i/d(dof) per dof.
    let mut c = [0.0; 2];
    let mut linear: Vec<(usize, usize, f64)> = Vec::new();
    for &(q, d) in &coupling.contactor {
        for i in 0..2 {
            c[i] += d * s.x[q][i];
            linear.push((2 * s.contactor.nodes[q] + i, i, d));
        }
    }
    for &(l, m) in &coupling.target {
        for i in 0..2 {
            c[i] -= m * s.y[l][i];
            linear.push((2 * s.target.nodes[l] + i, i, -m));
        }
    }
    let dof = |a: usize| 2 * s.contactor.nodes[support[a / 2]] + a % 2;
    let count = 2 * support.len();
    let mut out = Sparse {
        value: tau[0].v * c[0] + tau[1].v * c[1],
        ..Default::default()
    };
    for a in 0..count {
        out.gradient
            .push((dof(a), tau[0].g[a] * c[0] + tau[1].g[a] * c[1]));
        for b in 0..count {
            let h = tau[0].hessian(a, b) * c[0] + tau[1].hessian(a, b) * c[1];
            out.hessian.push((dof(a), dof(b), h));
        }
        for &(d, i, v) in &linear {
            out.hessian.push((dof(a), d, tau[i].g[a] * v));
            out.hessian.push((d, dof(a), tau[i].g[a] * v));
        }
    }
    for &(d, i, v) in &linear {
        out.gradient.push((d, tau[i].v * v));
    }
    out
}

/// A scalar's value, gradient and Hessian as mesh-dof entries (repeated
/// dofs add up).
#[derive(Clone, Debug, Default)]
pub(super) struct Sparse {
    pub value: f64,
    pub gradient: Vec<(usize, f64)>,
    pub hessian: Vec<(usize, usize, f64)>,
}
