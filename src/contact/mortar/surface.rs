//! The two surfaces of a mortar pair as chains of sides: the contactor
//! (the mortar, or slave, side: the multipliers live on its nodes) and the
//! target body's surface. A side is a 4-node element's edge (2 nodes,
//! linear) or an 8-node element's (corner, mid-side, corner: quadratic).

use crate::mesh::ElementKind;
use crate::problem::{ContactPair, Problem, Target};

/// A surface: its mesh nodes and its sides over them.
#[derive(Clone, Debug)]
pub(super) struct Surface {
    /// Mesh node of each surface node.
    pub nodes: Vec<usize>,
    /// Per side, its surface nodes in order (the body on the left).
    pub sides: Vec<Vec<usize>>,
    /// Per surface node, the sides it lies on and its place in each.
    pub on: Vec<Vec<(usize, usize)>>,
    /// Per surface node, the unit normal of the symmetry plane it lies on
    /// (`hold_symmetry_planes`): its tangent is along it.
    pub mirror: Vec<Option<[f64; 2]>>,
}

impl Surface {
    pub fn from_sides(nodes: Vec<usize>, sides: Vec<Vec<usize>>) -> Self {
        let mut on = vec![Vec::new(); nodes.len()];
        for (s, side) in sides.iter().enumerate() {
            for (l, &k) in side.iter().enumerate() {
                on[k].push((s, l));
            }
        }
        let mirror = vec![None; nodes.len()];
        Surface {
            nodes,
            sides,
            on,
            mirror,
        }
    }

    /// The end nodes of an open chain a driver holds in one direction
    /// (`held(dof)`) whose side, at the mesh's reference positions
    /// `points`, runs within 45 degrees of that direction (a surface meets
    /// its symmetry plane at a right angle): per node, its surface index,
    /// the unit direction held and its side's length.
    pub fn held_ends(
        &self,
        points: &[[f64; 2]],
        held: &dyn Fn(usize) -> bool,
    ) -> Vec<(usize, [f64; 2], f64)> {
        let mut out = Vec::new();
        for k in 0..self.nodes.len() {
            let [(side, _)] = self.on[k][..] else {
                continue;
            };
            let n = self.nodes[k];
            let e = match (held(2 * n), held(2 * n + 1)) {
                (true, false) => [1.0, 0.0],
                (false, true) => [0.0, 1.0],
                _ => continue,
            };
            let nodes = &self.sides[side];
            let (a, b) = (
                points[self.nodes[nodes[0]]],
                points[self.nodes[nodes[nodes.len() - 1]]],
            );
            let d = [b[0] - a[0], b[1] - a[1]];
            let length = d[0].hypot(d[1]);
            if (d[0] * e[0] + d[1] * e[1]).abs() >= std::f64::consts::FRAC_1_SQRT_2 * length {
                out.push((k, e, length));
            }
        }
        out
    }

    /// Marks the contactor's end nodes on a symmetry plane: held in one
    /// direction (`held_ends`), with an end node of the target `target`
    /// held in the same direction on the same plane (within a thousandth
    /// of the contactor's side, at the mesh's reference positions
    /// `points`). The mirror image of the end side continues the surface
    /// there, so the node's tangent is the plane's normal: the mean of the
    /// side's tangent and its image's.
    pub fn hold_symmetry_planes(
        &mut self,
        target: &Surface,
        points: &[[f64; 2]],
        held: &dyn Fn(usize) -> bool,
    ) {
        let partners = target.held_ends(points, held);
        for (k, e, length) in self.held_ends(points, held) {
            let along = |n: usize| points[n][0] * e[0] + points[n][1] * e[1];
            let plane = along(self.nodes[k]);
            let shared = (partners.iter()).any(|&(l, f, _)| {
                f == e && (along(target.nodes[l]) - plane).abs() <= 1e-3 * length
            });
            if shared {
                self.mirror[k] = Some(e);
            }
        }
    }

    /// The contactor of `pair`: its chain, in sides of 2 nodes, or of 3 on
    /// a body of 8-node elements.
    pub fn contactor(problem: &Problem, pair: &ContactPair) -> Result<Self, String> {
        let m = pair.contactor.len();
        let quadratic = body_kind(problem, pair.body) == Some(ElementKind::Q8);
        let step = if quadratic { 2 } else { 1 };
        let count = if pair.closed { m } else { m.saturating_sub(1) };
        if count == 0 || count % step != 0 {
            return Err(format!(
                "pair '{}': a mortar contactor needs whole sides: {m} nodes{} do not make \
                 sides of {} nodes",
                pair.name,
                if pair.closed { " in a loop" } else { "" },
                step + 1
            ));
        }
        let sides = (0..count / step)
            .map(|s| (0..=step).map(|l| (s * step + l) % m).collect())
            .collect();
        Ok(Surface::from_sides(pair.contactor.clone(), sides))
    }

    /// The target body's surface of `pair` (None against a rigid target):
    /// its segments joined in sides, two by two on a body of 8-node
    /// elements (corner to mid-side, mid-side to corner).
    pub fn target(problem: &Problem, pair: &ContactPair) -> Result<Option<Self>, String> {
        let Target::Body { body, segments, .. } = &pair.target else {
            return Ok(None);
        };
        let quadratic = body_kind(problem, *body) == Some(ElementKind::Q8);
        let chains: Vec<Vec<usize>> = if quadratic {
            if segments.len() % 2 != 0 {
                return Err(format!(
                    "pair '{}': the target's {} segments do not make 8-node sides",
                    pair.name,
                    segments.len()
                ));
            }
            (segments.chunks(2))
                .map(|s| {
                    if s[0][1] != s[1][0] {
                        Err(format!(
                            "pair '{}': target segments {:?} and {:?} do not make an 8-node side",
                            pair.name, s[0], s[1]
                        ))
                    } else {
                        Ok(vec![s[0][0], s[0][1], s[1][1]])
                    }
                })
                .collect::<Result<_, _>>()?
        } else {
            segments.iter().map(|s| s.to_vec()).collect()
        };
        let mut nodes: Vec<usize> = chains.iter().flatten().copied().collect();
        nodes.sort_unstable();
        nodes.dedup();
        let sides = (chains.iter())
            .map(|c| c.iter().map(|n| nodes.binary_search(n).unwrap()).collect())
            .collect();
        Ok(Some(Surface::from_sides(nodes, sides)))
    }

    /// The surface nodes whose positions the outward normals at side `s`'s
    /// nodes depend on: its own, then those of its neighbouring sides.
    pub fn normal_support(&self, s: usize) -> Vec<usize> {
        let mut list = self.sides[s].clone();
        for &k in &self.sides[s] {
            for &(t, _) in &self.on[k] {
                for &q in &self.sides[t] {
                    if !list.contains(&q) {
                        list.push(q);
                    }
                }
            }
        }
        list
    }
}

/// The element kind of a body (None: no elements).
fn body_kind(problem: &Problem, body: usize) -> Option<ElementKind> {
    let e = problem.bodies[body].elements.clone().next()?;
    Some(problem.mesh.elements[e].kind)
}

/// Shape functions of a side of `n` nodes (2 or 3) at `xi` in [-1, 1] and
/// their derivatives, generic over the number type: the first `n` entries
/// of each array (a 2-node side's third is zero), on the stack (the
/// projections call this at every step of their iterations).
pub(super) fn shape<T>(n: usize, xi: T) -> ([T; 3], [T; 3])
where
    T: Copy
        + std::ops::Add<Output = T>
        + std::ops::Sub<Output = T>
        + std::ops::Mul<Output = T>
        + std::ops::Add<f64, Output = T>
        + std::ops::Mul<f64, Output = T>,
{
    if n == 2 {
        let zero = xi * 0.0;
        (
            [xi * -0.5 + 0.5, xi * 0.5 + 0.5, zero],
            [zero + -0.5, zero + 0.5, zero],
        )
    } else {
        (
            [
                (xi * xi - xi) * 0.5,
                xi * xi * -1.0 + 1.0,
                (xi * xi + xi) * 0.5,
            ],
            [xi + -0.5, xi * -2.0, xi + 0.5],
        )
    }
}

/// Where a side's node `l` of `n` lies in its parameter.
pub(super) fn node_xi(n: usize, l: usize) -> f64 {
    if n == 2 {
        [-1.0, 1.0][l]
    } else {
        [-1.0, 0.0, 1.0][l]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A chain of 2-node sides over the mesh nodes `nodes`.
    fn chain(nodes: Vec<usize>) -> Surface {
        let sides = (0..nodes.len() - 1).map(|s| vec![s, s + 1]).collect();
        Surface::from_sides(nodes, sides)
    }

    /// A quarter arc's contactor (mesh nodes 0..=4, radius 1) and target
    /// (5..=9, radius 1.01) from the x axis to the y axis: both end on the
    /// planes y = 0 and x = 0.
    fn quarter() -> (Surface, Surface, Vec<[f64; 2]>) {
        let arc = |r: f64| {
            (0..5).map(move |i| {
                let a = std::f64::consts::FRAC_PI_2 * f64::from(i) / 4.0;
                [r * a.cos(), r * a.sin()]
            })
        };
        let points: Vec<[f64; 2]> = arc(1.0).chain(arc(1.01)).collect();
        (
            chain(vec![0, 1, 2, 3, 4]),
            chain(vec![9, 8, 7, 6, 5]),
            points,
        )
    }

    /// Held on the symmetry planes (uy = 0 on the x axis, ux = 0 on the y
    /// axis) on both surfaces: both contactor ends lie on a plane, their
    /// tangent along its normal; with the target free at one end, or the
    /// surfaces ending on different planes, that end does not.
    #[test]
    fn end_nodes_on_a_symmetry_plane_both_surfaces_share() {
        let (mut c, t, points) = quarter();
        let symmetry = |d: usize| matches!(d, 1 | 8 | 11 | 18);
        c.hold_symmetry_planes(&t, &points, &symmetry);
        assert_eq!(c.mirror[0], Some([0.0, 1.0]));
        assert_eq!(c.mirror[4], Some([1.0, 0.0]));
        assert!(c.mirror[1..4].iter().all(Option::is_none));

        // The target's end on the x axis free: the contactor's is not on a
        // plane the two share.
        let (mut c, t, points) = quarter();
        c.hold_symmetry_planes(&t, &points, &|d| matches!(d, 1 | 8 | 18));
        assert_eq!((c.mirror[0], c.mirror[4]), (None, Some([1.0, 0.0])));

        // Held along the surface (a side across the held direction): no plane.
        let (mut c, t, points) = quarter();
        c.hold_symmetry_planes(&t, &points, &|d| matches!(d, 0 | 9 | 10 | 19));
        assert!(c.mirror.iter().all(Option::is_none));

        // The target's end held in the same direction on another plane.
        let (mut c, t, mut points) = quarter();
        points[5][1] = 0.05;
        c.hold_symmetry_planes(&t, &points, &symmetry);
        assert_eq!((c.mirror[0], c.mirror[4]), (None, Some([1.0, 0.0])));
    }
}
