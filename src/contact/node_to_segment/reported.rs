//! The nodal tractions a node-to-segment pair reports: recovered from the
//! forces of its nodes in contact (`traction`, Eqs. 26/27), or fitted by
//! the quadratic side interpolation on 8-node sides.

use super::traction;
use crate::contact::report::{geometry, quadratic_tractions};
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
