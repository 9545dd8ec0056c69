//! Multi-point constraints that tie the nodes of one body to the surface of
//! another (the constraint-equation solutions beside the contact ones in the
//! paper's Section 4.4): along the surface normal only (tangentially free,
//! the mu = 0 counterpart) or in both directions (mu = infinity). The rows
//! are constant, built on the reference geometry, as the paper's constraint
//! equations neglect the deformations; their Lagrange multipliers are the
//! tie forces.

/// Which relative displacement a tie suppresses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TieKind {
    /// Along the surface normal; the tangential one stays free.
    Normal,
    /// Both components (x and y).
    Full,
}

/// One constraint `sum c_q u_q = 0` acting on a tied node and the ends of
/// the surface segment it lies on.
#[derive(Clone, Debug, PartialEq)]
pub struct TieRow {
    /// Position of the tied node in `Tie::nodes`.
    pub node: usize,
    /// The direction the row constrains (unit vector).
    pub direction: [f64; 2],
    pub dofs: Vec<(usize, f64)>,
}

/// A set of nodes tied to another body's surface segments.
#[derive(Clone, Debug, PartialEq)]
pub struct Tie {
    pub name: String,
    pub kind: TieKind,
    /// The tied nodes (mesh numbering).
    pub nodes: Vec<usize>,
    /// Per tied node: the surface normal into the other body.
    pub normals: Vec<[f64; 2]>,
    pub rows: Vec<TieRow>,
}

/// Forces of a tie on its tied nodes' body, from the multipliers.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TieResult {
    /// Resultant [Fx, Fy] on the tied nodes.
    pub force: [f64; 2],
    /// Per tied node, in `Tie::nodes` order: the force along the surface
    /// normal, positive in compression of the interface.
    pub normal: Vec<f64>,
    /// Per tied node: the force vector [Fx, Fy].
    pub nodal: Vec<[f64; 2]>,
    /// Per tied node: the force along the surface tangent, the normal into
    /// the other body turned by +90 degrees (`[-n_y, n_x]`).
    pub tangential: Vec<f64>,
    /// Per tied node: its current position (filled by the solver; empty
    /// from [`Tie::result`]).
    pub position: Vec<[f64; 2]>,
}

/// A node closer to a segment than this fraction of the segment's length
/// lies on it; a node at a segment's end within it coincides with that end.
const ON_SURFACE: f64 = 1e-6;

/// The rows that tie each of `nodes` (reference positions `points`) to the
/// nearest of `segments` (pairs of node numbers with the surface's body on
/// the left from the first to the second). A node that is not on the
/// surface (to `ON_SURFACE` of a segment's length) is an error naming it.
/// At a node that coincides with segment ends the normal is the mean of the
/// normals of the segments meeting there (the node-to-node tie of coincident
/// meshes); elsewhere the segment's own. Returns the rows and each node's
/// normal.
pub fn tie_rows(
    points: &[[f64; 2]],
    nodes: &[usize],
    segments: &[[usize; 2]],
    kind: TieKind,
) -> Result<(Vec<TieRow>, Vec<[f64; 2]>), String> {
    let sub = |a: [f64; 2], b: [f64; 2]| [a[0] - b[0], a[1] - b[1]];
    let len = |v: [f64; 2]| v[0].hypot(v[1]);
    // Unit normal into the surface's body (left of A -> B).
    let normal = |s: &[usize; 2]| {
        let d = sub(points[s[1]], points[s[0]]);
        let l = len(d);
        [-d[1] / l, d[0] / l]
    };
    let mut rows = Vec::new();
    let mut normals = Vec::with_capacity(nodes.len());
    for (k, &n) in nodes.iter().enumerate() {
        let p = points[n];
        // Nearest point of the surface: (distance / length, segment, beta).
        let mut best: Option<(f64, usize, f64)> = None;
        for (j, s) in segments.iter().enumerate() {
            let (a, b) = (points[s[0]], points[s[1]]);
            let d = sub(b, a);
            let l2 = d[0] * d[0] + d[1] * d[1];
            if l2 == 0.0 {
                continue;
            }
            let ap = sub(p, a);
            let beta = ((ap[0] * d[0] + ap[1] * d[1]) / l2).clamp(0.0, 1.0);
            let q = [a[0] + beta * d[0], a[1] + beta * d[1]];
            let gap = len(sub(p, q)) / l2.sqrt();
            if best.is_none_or(|(g, _, _)| gap < g) {
                best = Some((gap, j, beta));
            }
        }
        let Some((_, j, beta)) = best.filter(|b| b.0 <= ON_SURFACE) else {
            return Err(format!(
                "node at ({}, {}) is not on the surface it is tied to",
                p[0], p[1]
            ));
        };
        let s = segments[j];
        let (weights, direction_n): (Vec<(usize, f64)>, [f64; 2]) =
            if beta <= ON_SURFACE || beta >= 1.0 - ON_SURFACE {
                let end = if beta <= ON_SURFACE { s[0] } else { s[1] };
                let mut m = [0.0, 0.0];
                for t in segments.iter().filter(|t| t.contains(&end)) {
                    let nt = normal(t);
                    m = [m[0] + nt[0], m[1] + nt[1]];
                }
                let l = len(m);
                (vec![(end, 1.0)], [m[0] / l, m[1] / l])
            } else {
                (vec![(s[0], 1.0 - beta), (s[1], beta)], normal(&s))
            };
        normals.push(direction_n);
        let directions = match kind {
            TieKind::Normal => vec![direction_n],
            TieKind::Full => vec![[1.0, 0.0], [0.0, 1.0]],
        };
        for d in directions {
            let mut dofs = Vec::with_capacity(6);
            for c in 0..2 {
                if d[c] == 0.0 {
                    continue;
                }
                dofs.push((2 * n + c, d[c]));
                for &(m, w) in &weights {
                    dofs.push((2 * m + c, -w * d[c]));
                }
            }
            rows.push(TieRow {
                node: k,
                direction: d,
                dofs,
            });
        }
    }
    Ok((rows, normals))
}

impl Tie {
    /// The forces the multipliers `lambda` (one per row) put on the tied
    /// nodes.
    pub fn result(&self, lambda: &[f64]) -> TieResult {
        let m = self.nodes.len();
        let mut out = TieResult {
            force: [0.0; 2],
            normal: vec![0.0; m],
            nodal: vec![[0.0; 2]; m],
            tangential: vec![0.0; m],
            position: Vec::new(),
        };
        for (row, &l) in self.rows.iter().zip(lambda) {
            let f = [l * row.direction[0], l * row.direction[1]];
            out.nodal[row.node][0] += f[0];
            out.nodal[row.node][1] += f[1];
            out.force[0] += f[0];
            out.force[1] += f[1];
        }
        // A force on the tied node along the normal into the other body
        // pulls the interface apart: compression pushes the node away.
        for ((t, f), n) in out.normal.iter_mut().zip(&out.nodal).zip(&self.normals) {
            *t = -(f[0] * n[0] + f[1] * n[1]);
        }
        for ((t, f), n) in out.tangential.iter_mut().zip(&out.nodal).zip(&self.normals) {
            *t = -f[0] * n[1] + f[1] * n[0];
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coincident_node_takes_the_mean_normal() {
        // Surface: (0,0) -> (1,0) -> (2,1), body on the left (above).
        let points = [[0.0, 0.0], [1.0, 0.0], [2.0, 1.0], [1.0, 0.0]];
        let (rows, _) = tie_rows(&points, &[3], &[[0, 1], [1, 2]], TieKind::Normal).unwrap();
        assert_eq!(rows.len(), 1);
        let d = rows[0].direction;
        let expected = [
            -(std::f64::consts::PI / 8.0).sin(),
            (std::f64::consts::PI / 8.0).cos(),
        ];
        assert!((d[0] - expected[0]).abs() < 1e-12 && (d[1] - expected[1]).abs() < 1e-12);
        // u_3 . n - u_1 . n = 0
        assert_eq!(rows[0].dofs.len(), 4);
    }

    #[test]
    fn node_inside_a_segment_is_interpolated_and_a_far_node_refused() {
        let points = [[0.0, 0.0], [2.0, 0.0], [0.5, 0.0], [0.5, 0.1]];
        let (rows, normals) = tie_rows(&points, &[2], &[[0, 1]], TieKind::Full).unwrap();
        assert_eq!(normals, vec![[0.0, 1.0]]);
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0].dofs, vec![(4, 1.0), (0, -0.75), (2, -0.25)]);
        assert!(tie_rows(&points, &[3], &[[0, 1]], TieKind::Full).is_err());
    }
}
