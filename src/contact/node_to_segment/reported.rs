//! The nodal tractions a node-to-segment pair reports: recovered from the
//! forces of its nodes in contact (`traction`, Eqs. 26/27), or fitted by
//! the quadratic side interpolation on 8-node sides.

use super::traction;
use crate::contact::report::{Geometry, geometry};
use crate::problem::{ContactPair, Kinematics, Problem};
use nalgebra::Vector2;

/// Reported nodal tractions `t_n`, `t_t` of a pair from the forces of its
/// nodes in contact (`frames[k]`: the target's tangent toward the next
/// contactor node and inward normal where node k touches; None: open), per
/// unit area of the configuration the element stresses are written on (the
/// reference one under small strain, the current one under total
/// Lagrangian kinematics). 8-node sides use their quadratic shape
/// functions, 4-node sides `recovery` (Eqs. 26/27 or lumped).
///
/// `sliding[k]`: node k slides with friction `mu_d` (its force at
/// `|q| = mu_d p_n`; None for a node whose force is partly a driver's
/// reaction). On 8-node sides its tangential traction is its law's,
/// `mu_d t_n` with the sign of its own friction force: the quadratic fit
/// spreads each node's force over its sides, so the fitted `t_t` of a
/// sliding node next to sticking ones (or where the frames turn along a
/// curved surface) is not `mu_d` times the fitted `t_n` (up to 1.74 times
/// it, measured).
pub(super) fn reported_tractions(
    problem: &Problem,
    pair: &ContactPair,
    x: &[Vector2<f64>],
    active: &[bool],
    force: &[Vector2<f64>],
    frames: &[Option<(Vector2<f64>, Vector2<f64>)>],
    recovery: crate::problem::Recovery,
    sliding: &[Option<f64>],
) -> Result<(Vec<f64>, Vec<f64>), String> {
    let geometry = geometry(problem);
    let m = x.len();
    let reference_area = matches!(
        problem.kinematics,
        Kinematics::SmallStrain | Kinematics::MaterialNonlinearOnly
    );
    let x_area: Vec<Vector2<f64>> = if reference_area {
        (pair.contactor.iter())
            .map(|&n| Vector2::new(problem.mesh.nodes[n][0], problem.mesh.nodes[n][1]))
            .collect()
    } else {
        x.to_vec()
    };
    let on: Vec<bool> = (0..m).map(|k| frames[k].is_some() && active[k]).collect();
    let f: Vec<Vector2<f64>> = (0..m)
        .map(|k| if on[k] { force[k] } else { Vector2::zeros() })
        .collect();
    let q8 = problem.bodies[pair.body]
        .elements
        .clone()
        .next()
        .is_some_and(|e| problem.mesh.elements[e].kind == crate::mesh::ElementKind::Q8);
    let quadratic = if q8 && m % 2 == (if pair.closed { 0 } else { 1 }) {
        quadratic_tractions(geometry, pair.closed, &x_area, &on, &f)
    } else {
        None
    };
    let fitted = quadratic.is_some();
    let t = match quadratic {
        Some(t) => t,
        None => {
            let xs: Vec<[f64; 2]> = x_area.iter().map(|v| [v.x, v.y]).collect();
            let fs: Vec<[f64; 2]> = f.iter().map(|v| [v.x, v.y]).collect();
            let chain = traction::Chain::new(geometry, pair.closed, &xs)
                .map_err(|e| format!("pair '{}': {e}", pair.name))?;
            traction::recover_tractions(&chain, recovery, &on, &fs)
                .map_err(|e| format!("pair '{}': {e}", pair.name))?
                .into_iter()
                .map(|t| Vector2::new(t[0], t[1]))
                .collect()
        }
    };
    Ok((0..m)
        .map(|k| match frames[k] {
            Some((tau, nu)) if on[k] => {
                let tn = t[k].dot(&nu);
                match sliding.get(k).copied().flatten() {
                    Some(mu_d) if fitted => (tn, mu_d * tn * f[k].dot(&tau).signum()),
                    _ => (tn, t[k].dot(&tau)),
                }
            }
            _ => (0.0, 0.0),
        })
        .unzip())
}

/// Nodal tractions on a chain of 8-node sides (corner, mid-side, corner,
/// ...) from nodal forces: the consistent system of the quadratic side
/// interpolation, over the nodes in contact (the others carry zero). Weights
/// by 3-point Gauss integration, exact for the quadratic-times-quadratic
/// (times linear radius) integrands of straight sides. None if singular or
/// too large for the dense solve (then the linear recovery stays).
pub(super) fn quadratic_tractions(
    geometry: Geometry,
    closed: bool,
    x: &[Vector2<f64>],
    on: &[bool],
    f: &[Vector2<f64>],
) -> Option<Vec<Vector2<f64>>> {
    let m = x.len();
    let index: Vec<Option<usize>> = {
        let mut next = 0;
        on.iter()
            .map(|&a| {
                a.then(|| {
                    next += 1;
                    next - 1
                })
            })
            .collect()
    };
    let n = on.iter().filter(|&&a| a).count();
    if n == 0 || n > 600 {
        return None;
    }
    let mut a = nalgebra::DMatrix::<f64>::zeros(n, n);
    let sides = if closed { m / 2 } else { (m - 1) / 2 };
    // Per node: the integral of its shape function over its sides (the
    // lumped tributary), and whether one of its sides is partly open.
    let mut tributary = vec![0.0; m];
    let mut edge = vec![false; m];
    let gauss = [
        (-(0.6f64).sqrt(), 5.0 / 9.0),
        (0.0, 8.0 / 9.0),
        ((0.6f64).sqrt(), 5.0 / 9.0),
    ];
    for s in 0..sides {
        let nodes = [2 * s, 2 * s + 1, (2 * s + 2) % m];
        if nodes.iter().any(|&k| !on[k]) {
            for &k in &nodes {
                edge[k] = true;
            }
        }
        for &(xi, w) in &gauss {
            let nshape = [0.5 * xi * (xi - 1.0), 1.0 - xi * xi, 0.5 * xi * (xi + 1.0)];
            let dshape = [xi - 0.5, -2.0 * xi, xi + 0.5];
            let mut dx = Vector2::zeros();
            let mut pos = Vector2::zeros();
            for i in 0..3 {
                dx += dshape[i] * x[nodes[i]];
                pos += nshape[i] * x[nodes[i]];
            }
            let weight = w
                * dx.norm()
                * match geometry {
                    Geometry::Planar { thickness } => thickness,
                    Geometry::Axisymmetric => 2.0 * std::f64::consts::PI * pos.x,
                };
            for i in 0..3 {
                tributary[nodes[i]] += weight * nshape[i];
                let Some(r) = index[nodes[i]] else { continue };
                for j in 0..3 {
                    if let Some(c) = index[nodes[j]] {
                        a[(r, c)] += weight * nshape[i] * nshape[j];
                    }
                }
            }
        }
    }
    let lu = a.lu();
    let mut t = vec![Vector2::zeros(); m];
    for comp in 0..2 {
        let b = nalgebra::DVector::from_iterator(n, (0..m).filter(|&k| on[k]).map(|k| f[k][comp]));
        let sol = lu.solve(&b)?;
        for k in 0..m {
            if let Some(r) = index[k] {
                t[k][comp] = sol[r];
            }
        }
    }
    // On a side partly open the traction is not quadratic (it falls to
    // zero like a square root at the contact edge): its closed nodes report
    // their force over their tributary instead of the quadratic fit, which
    // overshoots there.
    for k in 0..m {
        if on[k] && edge[k] && tributary[k] > 0.0 {
            t[k] = f[k] / tributary[k];
        }
    }
    t.iter()
        .all(|v| v.x.is_finite() && v.y.is_finite())
        .then_some(t)
}
