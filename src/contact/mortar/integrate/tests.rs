use super::*;
use std::collections::BTreeMap;

/// A straight chain of `n` sides of `order` + 1 nodes from x = a to x = b
/// at height `y`, its parameter running left to right when `forward`.
fn chain(
    n: usize,
    order: usize,
    [a, b]: [f64; 2],
    y: f64,
    forward: bool,
) -> (Surface, Vec<[f64; 2]>) {
    let count = n * order + 1;
    let mut x: Vec<[f64; 2]> = (0..count)
        .map(|i| [a + (b - a) * i as f64 / (count - 1) as f64, y])
        .collect();
    if !forward {
        x.reverse();
    }
    let sides = (0..n)
        .map(|s| (0..=order).map(|l| s * order + l).collect())
        .collect();
    (Surface::from_sides((0..count).collect(), sides), x)
}

fn setting<'a>(
    c: &'a Surface,
    t: &'a Surface,
    x: &'a [[f64; 2]],
    y: &'a [[f64; 2]],
    geometry: Geometry,
) -> Setting<'a> {
    Setting {
        contactor: c,
        target: t,
        x,
        y,
        x_ref: x,
        reference_measure: false,
        geometry,
        reach: 1.0,
        friction: true,
    }
}

/// Per contactor node, its weighted gap summed over the parts.
fn summed(parts: &[Part], m: usize) -> Vec<f64> {
    let mut g = vec![0.0; m];
    for p in parts {
        for (k, v, _, _) in &p.gaps {
            g[*k] += v;
        }
    }
    g
}

/// A uniform gap d between a contactor and a target that covers it, their
/// meshes not matching: each node's weighted gap is d times its area (the
/// dual basis integrates constants as the shape functions do), for linear
/// and quadratic sides, planar and axisymmetric.
#[test]
fn a_uniform_gap_weighs_as_the_area() {
    let d = 0.03;
    for (order_c, order_t) in [(1, 1), (2, 2), (1, 2), (2, 1)] {
        for geometry in [Geometry::Planar { thickness: 2.0 }, Geometry::Axisymmetric] {
            // Contactor above (its body on the left walking left to right:
            // the body lies above), target below (walking right to left).
            let (c, x) = chain(7, order_c, [1.0, 3.0], d, true);
            let (t, y) = chain(5, order_t, [0.5, 3.5], 0.0, false);
            let s = setting(&c, &t, &x, &y, geometry);
            let (parts, area) = integrate(&s, Order::Second);
            let g = summed(&parts, x.len());
            for k in 0..x.len() {
                assert!(
                    (g[k] - d * area[k]).abs() < 1e-13 * area[k],
                    "{order_c}/{order_t} {geometry:?} node {k}: {} against {}",
                    g[k],
                    d * area[k]
                );
            }
        }
    }
}

/// Curved, non-matching sides of `order`: a contactor of 3 sides that
/// bulges down into a target of 2 whose surface sags, numbered as mesh
/// dofs (contactor nodes as they are, target nodes from 1000).
fn curved(order: usize) -> (Surface, Surface, Vec<[f64; 2]>, Vec<[f64; 2]>) {
    let (mut c, mut x) = chain(3, order, [0.0, 1.0], 0.0, true);
    let (mut t, mut y) = chain(2, order, [-0.2, 1.3], 0.0, false);
    for p in x.iter_mut() {
        p[1] = 0.05 - 0.2 * (p[0] - 0.5) * (p[0] - 0.5) + 0.01 * p[0];
    }
    for p in y.iter_mut() {
        p[1] = 0.04 * (p[0] - 0.6) * (p[0] - 0.6);
    }
    c.nodes = (0..x.len()).collect();
    t.nodes = (1000..1000 + y.len()).collect();
    (c, t, x, y)
}

/// Mesh dof `dof` of `curved`'s numbering moved by h.
fn shift(x: &mut [[f64; 2]], y: &mut [[f64; 2]], dof: usize, h: f64) {
    let n = dof / 2;
    if n < 1000 {
        x[n][dof % 2] += h;
    } else {
        y[n - 1000][dof % 2] += h;
    }
}

/// Per node k a quantity's gradient and Hessian (sums per dof and dof
/// pair) against central differences of `value(x, y, k)`: every gradient
/// entry to 1e-7, and the Hessians of a node inside and of the last (every
/// third entry: each takes four evaluations) to 1e-5 relative.
#[allow(clippy::type_complexity)]
fn check_differences(
    label: &str,
    (x, y): (&[[f64; 2]], &[[f64; 2]]),
    value: &dyn Fn(&[[f64; 2]], &[[f64; 2]], usize) -> f64,
    grad: &[BTreeMap<usize, f64>],
    hess: &[BTreeMap<(usize, usize), f64>],
) {
    let h = 1e-6;
    let m = x.len();
    for k in 0..m {
        for (&dof, &g) in &grad[k] {
            let (mut xp, mut yp, mut xm, mut ym) = (x.to_vec(), y.to_vec(), x.to_vec(), y.to_vec());
            shift(&mut xp, &mut yp, dof, h);
            shift(&mut xm, &mut ym, dof, -h);
            let fd = (value(&xp, &yp, k) - value(&xm, &ym, k)) / (2.0 * h);
            assert!(
                (g - fd).abs() < 1e-7,
                "{label} node {k} dof {dof}: {g} against {fd}"
            );
        }
    }
    for k in [m / 2, m - 1] {
        for (&(a, b), &v) in hess[k].iter().filter(|(ab, _)| ab.0 <= ab.1).step_by(3) {
            let eval = |ha: f64, hb: f64| {
                let (mut xx, mut yy) = (x.to_vec(), y.to_vec());
                shift(&mut xx, &mut yy, a, ha);
                shift(&mut xx, &mut yy, b, hb);
                value(&xx, &yy, k)
            };
            let e = 1e-4;
            let fd = (eval(e, e) - eval(e, -e) - eval(-e, e) + eval(-e, -e)) / (4.0 * e * e);
            assert!(
                (v - fd).abs() < 1e-5 * (1.0 + v.abs()),
                "{label} node {k} dofs {a},{b}: {v} against {fd}"
            );
        }
    }
}

/// The gradients and Hessians of the weighted gaps against central
/// differences of the values, on curved, non-matching sides.
#[test]
fn derivatives_match_differences() {
    for order in [1, 2] {
        let (cs, ts, x, y) = curved(order);
        let geometry = Geometry::Axisymmetric;
        let total = |x: &[[f64; 2]], y: &[[f64; 2]], k: usize| {
            let (parts, _) = integrate(&setting(&cs, &ts, x, y, geometry), Order::Second);
            summed(&parts, x.len())[k]
        };
        let (parts, _) = integrate(&setting(&cs, &ts, &x, &y, geometry), Order::Second);
        assert!(!parts.is_empty());
        // The node totals' gradients and Hessians: summed over parts.
        let m = x.len();
        let mut grad = vec![BTreeMap::<usize, f64>::new(); m];
        let mut hess = vec![BTreeMap::<(usize, usize), f64>::new(); m];
        for part in &parts {
            let count = part.dofs.len();
            for (k, _, g, hh) in &part.gaps {
                for a in 0..count {
                    *grad[*k].entry(part.dofs[a]).or_default() += g[a];
                    for b in 0..count {
                        *hess[*k].entry((part.dofs[a], part.dofs[b])).or_default() +=
                            hh[a * count + b];
                    }
                }
            }
        }
        check_differences(&format!("order {order}"), (&x, &y), &total, &grad, &hess);
    }
}

/// Each contactor node's weighted slip at positions `x`, `y` from the
/// coupling `start` of the increment's start: `slip_from` less the parts'
/// `slips`, with its gradient and Hessian as (dof, value) and ((dof, dof),
/// value) sums.
type Slip = (f64, BTreeMap<usize, f64>, BTreeMap<(usize, usize), f64>);

fn weighted_slips(s: &Setting, start: &[Coupling]) -> Vec<Slip> {
    let (parts, _) = integrate(s, Order::Second);
    let mut out: Vec<Slip> = vec![Default::default(); s.x.len()];
    for part in &parts {
        let count = part.dofs.len();
        for ((k, ..), (v, g, h)) in part.gaps.iter().zip(&part.slips) {
            let o = &mut out[*k];
            o.0 -= v;
            for a in 0..count {
                *o.1.entry(part.dofs[a]).or_default() -= g[a];
                for b in 0..count {
                    *o.2.entry((part.dofs[a], part.dofs[b])).or_default() -= h[a * count + b];
                }
            }
        }
    }
    for (k, o) in out.iter_mut().enumerate() {
        let from = slip_from(s, k, &start[k]);
        o.0 += from.value;
        for (d, v) in from.gradient {
            *o.1.entry(d).or_default() += v;
        }
        for (a, b, v) in from.hessian {
            *o.2.entry((a, b)).or_default() += v;
        }
    }
    out
}

/// The contactor slid by `d` along a flat target that covers it, meshes
/// not matching: each node's weighted slip is d times its area at the
/// start (the measure the start's coupling integrates in; about the axis
/// a radial slide changes it), and a rigid motion of both (a turn and a
/// shift) slips nothing.
#[test]
fn a_uniform_slide_weighs_as_the_area_and_a_rigid_motion_slips_nothing() {
    let d = 0.07;
    for (order_c, order_t) in [(1, 1), (2, 2), (1, 2), (2, 1)] {
        for geometry in [Geometry::Planar { thickness: 2.0 }, Geometry::Axisymmetric] {
            let (c, x0) = chain(7, order_c, [1.0, 3.0], 0.01, true);
            let (t, y0) = chain(5, order_t, [0.5, 3.5], 0.0, false);
            let start = couplings(&setting(&c, &t, &x0, &y0, geometry));
            let (_, area) = integrate(&setting(&c, &t, &x0, &y0, geometry), Order::Second);
            let x: Vec<[f64; 2]> = x0.iter().map(|p| [p[0] + d, p[1]]).collect();
            let s = setting(&c, &t, &x, &y0, geometry);
            for (k, slip) in weighted_slips(&s, &start).iter().enumerate() {
                assert!(
                    (slip.0 - d * area[k]).abs() < 1e-13 * area[k],
                    "{order_c}/{order_t} {geometry:?} node {k}: {} against {}",
                    slip.0,
                    d * area[k]
                );
            }
            if geometry != Geometry::Axisymmetric {
                let (sin, cos) = 0.3f64.sin_cos();
                let turn =
                    |p: &[f64; 2]| [cos * p[0] - sin * p[1] + 0.4, sin * p[0] + cos * p[1] - 0.2];
                let (x, y): (Vec<_>, Vec<_>) =
                    (x0.iter().map(turn).collect(), y0.iter().map(turn).collect());
                let s = setting(&c, &t, &x, &y, geometry);
                for (k, slip) in weighted_slips(&s, &start).iter().enumerate() {
                    assert!(
                        slip.0.abs() < 1e-13,
                        "{order_c}/{order_t} node {k}: {}",
                        slip.0
                    );
                }
            }
        }
    }
}

/// The gradients and Hessians of the weighted slips (the parts' and
/// `slip_from`'s together) against central differences, on curved,
/// non-matching sides that have slid since the start.
#[test]
fn slip_derivatives_match_differences() {
    for order in [1, 2] {
        let (cs, ts, x, y) = curved(order);
        let geometry = Geometry::Planar { thickness: 1.5 };
        // The start: the contactor 0.05 to the left and a little higher.
        let x0: Vec<[f64; 2]> = x.iter().map(|p| [p[0] - 0.05, p[1] + 0.01]).collect();
        let start = couplings(&setting(&cs, &ts, &x0, &y, geometry));
        let total = |x: &[[f64; 2]], y: &[[f64; 2]], k: usize| {
            weighted_slips(&setting(&cs, &ts, x, y, geometry), &start)[k].0
        };
        let slips = weighted_slips(&setting(&cs, &ts, &x, &y, geometry), &start);
        assert!(slips.iter().all(|s| !s.1.is_empty()));
        let (grad, hess): (Vec<_>, Vec<_>) = slips.into_iter().map(|s| (s.1, s.2)).unzip();
        check_differences(&format!("order {order}"), (&x, &y), &total, &grad, &hess);
    }
}

/// `ProjectionBound`: every projection of a point onto a contactor side
/// along its normal field within the side (every root of `onto_contactor`
/// in [-1, 1], found by sampling) lies in the range the bound gives from
/// the chord, for 2- and 3-node sides, straight and curved,
/// their mid node off the middle, nodal normals tilted up to 55 degrees,
/// and points up to five side lengths away on either side.
#[test]
fn projections_lie_within_the_chord_s_bound() {
    let mut seed = 7u64;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed % 1_000_000) as f64 / 1e6
    };
    let mut checked = 0;
    for case in 0..100 {
        let nodes = 2 + case % 2;
        let (a, b) = ([0.3, -0.2], [1.1 + next(), 0.4 * next()]);
        let mut xs = vec![V2::<0, 0>::c(a)];
        if nodes == 3 {
            let m = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
            xs.push(V2::c([
                m[0] + 0.3 * (next() - 0.5),
                m[1] + 0.6 * (next() - 0.5),
            ]));
        }
        xs.push(V2::c(b));
        let chord = (b[1] - a[1]).atan2(b[0] - a[0]) + std::f64::consts::FRAC_PI_2;
        let ns: Vec<V2<0, 0>> = (0..nodes)
            .map(|_| {
                let tilt = (next() - 0.5) * 2.0 * 55f64.to_radians();
                V2::c([(chord + tilt).cos(), (chord + tilt).sin()])
            })
            .collect();
        let bound = ProjectionBound::of(&xs, &ns).expect("tilts under 60 degrees");
        for _ in 0..10 {
            let y = [-4.0 + 10.0 * next(), -5.0 + 10.0 * next()];
            let (lo, hi) = bound.range(y);
            let f = |xi: f64| onto_contactor(&xs, &ns, V2::c(y), Dual::c(xi)).0.v;
            let step = 2e-4;
            let mut last = f(-1.0);
            for i in 1..=10_000 {
                let xi = -1.0 + step * i as f64;
                let now = f(xi);
                // A root in [xi - step, xi]: that interval meets the range.
                if last.signum() != now.signum() {
                    assert!(
                        xi >= lo && xi - step <= hi,
                        "case {case}: root near {xi} outside [{lo}, {hi}] for {y:?}"
                    );
                    checked += 1;
                }
                last = now;
            }
        }
    }
    assert!(checked > 100, "{checked} roots");
}
