//! Isoparametric shape functions of the 4- and 8-node quadrilaterals and of
//! their 2- and 3-node faces, with the Gauss rules that integrate them.

use crate::mesh::ElementKind;

/// Most nodes an element has (Q8).
pub const MAX_NODES: usize = 8;

/// Shape function values and their derivatives with respect to (xi, eta).
#[derive(Clone, Copy, Debug)]
pub struct Shape {
    pub n: [f64; MAX_NODES],
    pub dn: [[f64; 2]; MAX_NODES],
}

const CORNERS: [[f64; 2]; 4] = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];

/// Shape functions at (xi, eta) in [-1, 1]^2.
pub fn shape(kind: ElementKind, xi: f64, eta: f64) -> Shape {
    let mut s = Shape {
        n: [0.0; MAX_NODES],
        dn: [[0.0; 2]; MAX_NODES],
    };
    match kind {
        ElementKind::Q4 => {
            for (a, c) in CORNERS.iter().enumerate() {
                let (px, py) = (1.0 + c[0] * xi, 1.0 + c[1] * eta);
                s.n[a] = 0.25 * px * py;
                s.dn[a] = [0.25 * c[0] * py, 0.25 * c[1] * px];
            }
        }
        ElementKind::Q8 => {
            // Serendipity: corners N = (1+xi xi_a)(1+eta eta_a)(xi xi_a + eta eta_a - 1)/4.
            for (a, c) in CORNERS.iter().enumerate() {
                let (px, py) = (1.0 + c[0] * xi, 1.0 + c[1] * eta);
                let q = c[0] * xi + c[1] * eta - 1.0;
                s.n[a] = 0.25 * px * py * q;
                s.dn[a] = [0.25 * c[0] * py * (q + px), 0.25 * c[1] * px * (q + py)];
            }
            // Mid-side nodes of faces 0..3: (0,-1), (1,0), (0,1), (-1,0).
            s.n[4] = 0.5 * (1.0 - xi * xi) * (1.0 - eta);
            s.dn[4] = [-xi * (1.0 - eta), -0.5 * (1.0 - xi * xi)];
            s.n[5] = 0.5 * (1.0 + xi) * (1.0 - eta * eta);
            s.dn[5] = [0.5 * (1.0 - eta * eta), -eta * (1.0 + xi)];
            s.n[6] = 0.5 * (1.0 - xi * xi) * (1.0 + eta);
            s.dn[6] = [-xi * (1.0 + eta), 0.5 * (1.0 - xi * xi)];
            s.n[7] = 0.5 * (1.0 - xi) * (1.0 - eta * eta);
            s.dn[7] = [-0.5 * (1.0 - eta * eta), -eta * (1.0 - xi)];
        }
    }
    s
}

/// Gauss-Legendre points and weights on [-1, 1].
pub fn gauss_1d(n: usize) -> &'static [(f64, f64)] {
    const G1: [(f64, f64); 1] = [(0.0, 2.0)];
    const G2: [(f64, f64); 2] = [
        (-0.577_350_269_189_625_8, 1.0),
        (0.577_350_269_189_625_8, 1.0),
    ];
    const G3: [(f64, f64); 3] = [
        (-0.774_596_669_241_483_4, 5.0 / 9.0),
        (0.0, 8.0 / 9.0),
        (0.774_596_669_241_483_4, 5.0 / 9.0),
    ];
    match n {
        1 => &G1,
        2 => &G2,
        _ => &G3,
    }
}

/// Points per direction: 2x2 for Q4, 3x3 for Q8 (full integration).
pub fn gauss_order(kind: ElementKind) -> usize {
    match kind {
        ElementKind::Q4 => 2,
        ElementKind::Q8 => 3,
    }
}

/// A Gauss rule held inline (no allocation in element loops).
#[derive(Clone, Copy, Debug)]
pub struct GaussRule {
    points: [([f64; 2], f64); 9],
    len: usize,
}

impl GaussRule {
    pub fn iter(&self) -> impl Iterator<Item = ([f64; 2], f64)> + '_ {
        self.points[..self.len].iter().copied()
    }
    pub fn len(&self) -> usize {
        self.len
    }
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
}

/// Tensor-product Gauss rule of the element: ((xi, eta), weight).
pub fn gauss_points(kind: ElementKind) -> GaussRule {
    let g = gauss_1d(gauss_order(kind));
    let mut rule = GaussRule {
        points: [([0.0; 2], 0.0); 9],
        len: 0,
    };
    for &(eta, we) in g {
        for &(xi, wx) in g {
            rule.points[rule.len] = ([xi, eta], wx * we);
            rule.len += 1;
        }
    }
    rule
}

/// Shape functions of a face (2 nodes: start, end; 3 nodes: start, end,
/// middle) at s in [-1, 1], and d/ds.
pub fn face_shape(nodes: usize, s: f64) -> ([f64; 3], [f64; 3]) {
    if nodes == 2 {
        ([0.5 * (1.0 - s), 0.5 * (1.0 + s), 0.0], [-0.5, 0.5, 0.0])
    } else {
        (
            [0.5 * s * (s - 1.0), 0.5 * s * (s + 1.0), 1.0 - s * s],
            [s - 0.5, s + 0.5, -2.0 * s],
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn nodes_of(kind: ElementKind) -> Vec<[f64; 2]> {
        let mut v: Vec<[f64; 2]> = CORNERS.to_vec();
        if kind == ElementKind::Q8 {
            v.extend([[0.0, -1.0], [1.0, 0.0], [0.0, 1.0], [-1.0, 0.0]]);
        }
        v
    }

    #[test]
    fn kronecker_partition_of_unity_and_derivatives() {
        for kind in [ElementKind::Q4, ElementKind::Q8] {
            let nn = kind.node_count();
            let pts = nodes_of(kind);
            for (a, p) in pts.iter().enumerate() {
                let s = shape(kind, p[0], p[1]);
                for b in 0..nn {
                    let expect = if a == b { 1.0 } else { 0.0 };
                    assert!((s.n[b] - expect).abs() < 1e-14);
                }
            }
            let (xi, eta) = (0.31, -0.47);
            let s = shape(kind, xi, eta);
            let sum: f64 = s.n[..nn].iter().sum();
            assert!((sum - 1.0).abs() < 1e-14);
            let h = 1e-6;
            let sx = shape(kind, xi + h, eta);
            let sxm = shape(kind, xi - h, eta);
            let sy = shape(kind, xi, eta + h);
            let sym = shape(kind, xi, eta - h);
            for a in 0..nn {
                let fx = (sx.n[a] - sxm.n[a]) / (2.0 * h);
                let fy = (sy.n[a] - sym.n[a]) / (2.0 * h);
                // central differences of a quadratic: error ~ h^2 * third derivative (0)
                assert!((fx - s.dn[a][0]).abs() < 1e-9, "{kind:?} node {a}");
                assert!((fy - s.dn[a][1]).abs() < 1e-9, "{kind:?} node {a}");
            }
        }
    }

    #[test]
    fn gauss_rules_integrate_polynomials() {
        // 3 points are exact to degree 5: integral of x^4 over [-1,1] is 2/5.
        let i: f64 = gauss_1d(3).iter().map(|(x, w)| w * x.powi(4)).sum();
        assert!((i - 0.4).abs() < 1e-15);
        let i: f64 = gauss_1d(2).iter().map(|(x, w)| w * x.powi(2)).sum();
        assert!((i - 2.0 / 3.0).abs() < 1e-15);
        let a: f64 = gauss_points(ElementKind::Q8).iter().map(|p| p.1).sum();
        assert_eq!(gauss_points(ElementKind::Q8).len(), 9);
        assert!((a - 4.0).abs() < 1e-14);
    }

    #[test]
    fn face_shapes_interpolate() {
        for nodes in [2, 3] {
            let (n, _) = face_shape(nodes, -1.0);
            assert!((n[0] - 1.0).abs() < 1e-15);
            let (n, _) = face_shape(nodes, 1.0);
            assert!((n[1] - 1.0).abs() < 1e-15);
            let (n, dn) = face_shape(nodes, 0.3);
            assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-15);
            assert!(dn.iter().sum::<f64>().abs() < 1e-15);
        }
    }
}
