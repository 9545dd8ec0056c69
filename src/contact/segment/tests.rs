//! Checks of the contact kernel against the paper's potentials and the exact geometry.
//! Eqs. (11) and (17) are written out here independently of the kernel. Their gradient, the
//! contact residual as a function of (x_k, x_A, x_B, multipliers), is taken exactly with dual
//! numbers, and its Jacobian is taken by central differences.
//!
//! Tolerance: both potentials are quadratic, so central differences of their exact gradient
//! have no truncation error. What remains is rounding, about eps |r| / h ~ 1e-9 for h = 1e-6.
//! For the exact projection (not quadratic) the truncation is O(h^2) ~ 1e-12. A relative
//! tolerance of 1e-7 covers both with margin, and still catches any wrong entry.

use std::ops::{Add, Mul, Neg, Sub};

use nalgebra::{DMatrix, DVector, SMatrix, SVector, Vector2};

use super::*;

const H: f64 = 1e-6;
const TOL: f64 = 1e-7;

/// Forward-mode dual number: a value and one directional derivative.
#[derive(Clone, Copy, Debug)]
struct Dual {
    v: f64,
    d: f64,
}

fn k(v: f64) -> Dual {
    Dual { v, d: 0.0 }
}

impl Add for Dual {
    type Output = Dual;
    fn add(self, o: Dual) -> Dual {
        Dual {
            v: self.v + o.v,
            d: self.d + o.d,
        }
    }
}

impl Sub for Dual {
    type Output = Dual;
    fn sub(self, o: Dual) -> Dual {
        self + (-o)
    }
}

impl Neg for Dual {
    type Output = Dual;
    fn neg(self) -> Dual {
        Dual {
            v: -self.v,
            d: -self.d,
        }
    }
}

impl Mul for Dual {
    type Output = Dual;
    fn mul(self, o: Dual) -> Dual {
        Dual {
            v: self.v * o.v,
            d: self.d * o.v + self.v * o.d,
        }
    }
}

/// State after iteration (i-1): positions, location parameter of C, contact force on k.
#[derive(Clone, Copy, Debug)]
struct State {
    xk: [f64; 2],
    xa: [f64; 2],
    xb: [f64; 2],
    beta: f64,
    lambda: [f64; 2],
}

impl State {
    /// Node k at normal overlap `delta` (positive inside the target) off the point `beta`.
    fn new(xa: [f64; 2], xb: [f64; 2], beta: f64, delta: f64, lambda: [f64; 2]) -> Self {
        let mut s = State {
            xk: [0.0; 2],
            xa,
            xb,
            beta,
            lambda,
        };
        let (_, ns, _) = s.frame();
        for p in 0..2 {
            s.xk[p] = xa[p] + beta * (xb[p] - xa[p]) + delta * ns[p];
        }
        s
    }

    /// `n_r / d`, `n_s`, and the overlap vector `x_k - x_C`, written out independently.
    fn frame(&self) -> ([f64; 2], [f64; 2], [f64; 2]) {
        let ab = [self.xb[0] - self.xa[0], self.xb[1] - self.xa[1]];
        let d2 = ab[0] * ab[0] + ab[1] * ab[1];
        let d = d2.sqrt();
        let nbar = [ab[0] / d2, ab[1] / d2];
        let ns = [-ab[1] / d, ab[0] / d];
        let ov = [0, 1].map(|p| self.xk[p] - (self.xa[p] + self.beta * ab[p]));
        (nbar, ns, ov)
    }

    fn positions(&self) -> [f64; 6] {
        [
            self.xk[0], self.xk[1], self.xa[0], self.xa[1], self.xb[0], self.xb[1],
        ]
    }

    fn segment(&self) -> Segment {
        Segment::new(v2(self.xa), v2(self.xb)).unwrap()
    }

    fn with_beta(self, beta: f64) -> Self {
        State { beta, ..self }
    }
}

fn v2(p: [f64; 2]) -> Vector2<f64> {
    Vector2::new(p[0], p[1])
}

/// The overlap after iteration (i), `g = du_k + Delta_k - (1-beta) du_A - beta du_B`, with
/// `z[0..6]` the current positions of k, A, B.
fn overlap_after(s: &State, z: &[Dual]) -> [Dual; 2] {
    let x0 = s.positions();
    let (_, _, ov) = s.frame();
    let du = |i: usize| z[i] - k(x0[i]);
    [0, 1].map(|p| du(p) + k(ov[p]) - k(1.0 - s.beta) * du(2 + p) - k(s.beta) * du(4 + p))
}

/// Eq. (11) (with Eq. 10): `W = lambda(i)^T g`. `z = [x_k, x_A, x_B, lambda_kx, lambda_ky]`.
fn w_sticking(s: &State, z: &[Dual]) -> Dual {
    let g = overlap_after(s, z);
    z[6] * g[0] + z[7] * g[1]
}

/// Eq. (17): `W = lambda^T g + dbeta lambda^T (du_A - du_B) - dlambda_s n_s^T g`, with
/// `dbeta` from Eq. (14). `z = [x_k, x_A, x_B, dlambda_s]`.
fn w_sliding(s: &State, z: &[Dual]) -> Dual {
    let x0 = s.positions();
    let (nbar, ns, _) = s.frame();
    let g = overlap_after(s, z);
    let lam = s.lambda.map(k);
    let dbeta = k(nbar[0]) * g[0] + k(nbar[1]) * g[1];
    let dab = [0, 1].map(|p| (z[2 + p] - k(x0[2 + p])) - (z[4 + p] - k(x0[4 + p])));
    lam[0] * g[0] + lam[1] * g[1] + dbeta * (lam[0] * dab[0] + lam[1] * dab[1])
        - z[6] * (k(ns[0]) * g[0] + k(ns[1]) * g[1])
}

type Potential = fn(&State, &[Dual]) -> Dual;

/// The contact residual: the exact gradient of the potential at `z`.
fn residual(w: Potential, s: &State, z: &[f64]) -> DVector<f64> {
    DVector::from_fn(z.len(), |j, _| {
        let zd: Vec<Dual> = z
            .iter()
            .enumerate()
            .map(|(i, &v)| Dual {
                v,
                d: if i == j { 1.0 } else { 0.0 },
            })
            .collect();
        w(s, &zd).d
    })
}

/// Central-difference Jacobian of `f` at `z`.
fn fd_jacobian(f: impl Fn(&[f64]) -> DVector<f64>, z: &[f64]) -> DMatrix<f64> {
    let n = f(z).len();
    let mut jac = DMatrix::zeros(n, z.len());
    for j in 0..z.len() {
        let (mut zp, mut zm) = (z.to_vec(), z.to_vec());
        zp[j] += H;
        zm[j] -= H;
        jac.set_column(j, &((f(&zp) - f(&zm)) / (2.0 * H)));
    }
    jac
}

fn rel_err(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    (a - b).norm() / b.norm().max(1e-300)
}

fn dyn_mat<const R: usize, const C: usize>(m: &SMatrix<f64, R, C>) -> DMatrix<f64> {
    DMatrix::from_column_slice(R, C, m.as_slice())
}

/// Inclined segments, beta near 0 and near 1, node penetrating, clear, and on the segment,
/// contact forces with normal and tangential parts.
fn cases() -> Vec<State> {
    vec![
        State::new([0.3, -0.2], [2.1, 1.4], 0.37, 0.05, [-3.0, 1.7]),
        State::new([-1.0, 0.5], [1.5, -0.25], 0.02, -0.03, [0.8, 2.5]),
        State::new([4.0, 1.0], [3.2, 2.9], 0.985, 0.011, [12.0, -4.0]),
        State::new([0.0, 0.0], [2.0, 0.0], 0.5, 0.0, [0.4, -6.0]),
        State::new([1.0, 3.0], [0.9, -2.0], 0.6, -0.2, [5.0, 0.3]),
        State::new([-2.0, -1.0], [-0.5, -1.1], 0.001, 0.0, [-1.5, 7.0]),
    ]
}

#[test]
fn segment_geometry_and_sign_conventions() {
    let seg = Segment::new(Vector2::new(0.0, 0.0), Vector2::new(2.0, 0.0)).unwrap();
    assert_eq!(seg.length(), 2.0);
    assert_eq!(seg.tangent(), Vector2::new(1.0, 0.0));
    // Target body to the left of A->B: the normal points up, into it.
    assert_eq!(seg.normal(), Vector2::new(0.0, 1.0));

    let inside = seg.project(Vector2::new(0.5, 0.1));
    assert_eq!(inside.beta(), 0.25);
    assert_eq!(inside.point(), Vector2::new(0.5, 0.0));
    assert_eq!(inside.overlap(), Vector2::new(0.0, 0.1));
    assert!((inside.normal_overlap() - 0.1).abs() < 1e-15);
    assert!((inside.gap() + 0.1).abs() < 1e-15);

    let clear = seg.project(Vector2::new(2.2, -0.3));
    assert!((clear.beta() - 1.1).abs() < 1e-15);
    assert!((clear.gap() - 0.3).abs() < 1e-15);
    assert!(!clear.is_within(0.0));
    assert!(clear.is_within(0.2));
    assert!(seg.project(Vector2::new(0.0, 1.0)).is_within(0.0));
    assert!(!seg.project(Vector2::new(-0.01, 1.0)).is_within(0.0));

    // A sticking point keeps its beta, and its overlap keeps a tangential part.
    let stuck = seg.contact_at(Vector2::new(0.5, 0.1), 0.2);
    assert_eq!(stuck.point(), Vector2::new(0.4, 0.0));
    assert!((stuck.overlap() - Vector2::new(0.1, 0.1)).norm() < 1e-15);

    for s in cases() {
        let cp = s.segment().project(v2(s.xk));
        let (_, ns, ov) = s.frame();
        assert!((cp.beta() - s.beta).abs() < 1e-13, "{s:?}");
        assert!((cp.overlap() - v2(ov)).norm() < 1e-13, "{s:?}");
        assert!((cp.segment().normal() - v2(ns)).norm() < 1e-15);
    }
}

#[test]
fn degenerate_segment_is_an_error() {
    let a = Vector2::new(1.0, 2.0);
    let err = Segment::new(a, a).unwrap_err();
    assert_eq!(
        err,
        ContactError::DegenerateSegment {
            xa: [1.0, 2.0],
            xb: [1.0, 2.0],
            length: 0.0
        }
    );
    assert!(err.to_string().contains("(1, 2)"));
    assert!(Segment::new(a, Vector2::new(f64::NAN, 0.0)).is_err());
    assert!(Segment::new(a, Vector2::new(f64::INFINITY, 0.0)).is_err());
}

#[test]
fn sticking_blocks_are_the_gradient_and_hessian_of_eq_11() {
    for base in cases() {
        // The stored beta of a sticking point differs from the projection.
        let s = base.with_beta(base.beta + 0.013);
        let st = s
            .segment()
            .contact_at(v2(s.xk), s.beta)
            .sticking(v2(s.lambda));
        let x0 = s.positions();
        let z0 = [x0.as_slice(), s.lambda.as_slice()].concat();

        let r0 = residual(w_sticking, &s, &z0);
        let expected = DVector::from_iterator(8, st.r_c.iter().chain(st.delta_c.iter()).copied());
        assert!((&r0 - &expected).norm() < 1e-12 * expected.norm(), "{s:?}");

        let jac = fd_jacobian(|z| residual(w_sticking, &s, z), &z0);
        let k_c = dyn_mat(&st.k_c());
        assert!(rel_err(&(-jac), &k_c) < TOL, "{s:?}");
        assert_eq!(k_c, k_c.transpose());
        assert!(k_c.view((0, 0), (6, 6)).iter().all(|&v| v == 0.0));
    }
}

#[test]
fn sliding_blocks_are_the_gradient_and_hessian_of_eq_17() {
    for base in cases() {
        // The foot of the normal (the sliding case), and a point off it, where R_c keeps the
        // c b term and is still the exact gradient.
        for s in [base, base.with_beta(base.beta - 0.02)] {
            let sl = s
                .segment()
                .contact_at(v2(s.xk), s.beta)
                .sliding(v2(s.lambda));
            let x0 = s.positions();
            let z0 = [x0.as_slice(), &[0.0]].concat();

            let r0 = residual(w_sliding, &s, &z0);
            let expected = DVector::from_iterator(7, sl.r_c.iter().copied().chain([sl.delta_c]));
            assert!((&r0 - &expected).norm() < 1e-12 * expected.norm(), "{s:?}");

            let jac = fd_jacobian(|z| residual(w_sliding, &s, z), &z0);
            let k_c = dyn_mat(&sl.k_c());
            assert!(rel_err(&(-jac), &k_c) < TOL, "{s:?}");
            assert!((&k_c - k_c.transpose()).norm() < 1e-14 * k_c.norm());
        }
        // At the foot of the normal, Eq. (22) is Eq. (19).
        let cp = base.segment().project(v2(base.xk));
        let lam = v2(base.lambda);
        assert!((cp.sliding(lam).r_c - cp.sticking(lam).r_c).norm() < 1e-12);
    }
}

#[test]
fn sliding_gradient_matrix_entries_match_the_surviving_fragments_of_eq_24() {
    let s = cases()[0];
    let cp = s.segment().project(v2(s.xk));
    let k = cp.sliding(v2(s.lambda)).k_uu;
    let (nbar, _, _) = s.frame();
    let (b, [lx, ly]) = (s.beta, s.lambda);
    let close = |a: f64, e: f64| (a - e).abs() < 1e-13;
    assert!(close(k[(0, 0)], 0.0) && close(k[(1, 1)], 0.0));
    assert!(close(k[(0, 2)], -nbar[0] * lx));
    assert!(close(k[(0, 3)], -nbar[0] * ly));
    assert!(close(k[(2, 2)], 2.0 * (1.0 - b) * nbar[0] * lx));
    assert!(close(k[(2, 3)], (1.0 - b) * (nbar[0] * ly + nbar[1] * lx)));
    assert!(close(
        k[(2, 4)],
        -(1.0 - b) * nbar[0] * lx + b * nbar[0] * lx
    ));
    assert!(close(k[(4, 4)], -2.0 * b * nbar[0] * lx));
    assert!(close(k[(4, 5)], -b * (nbar[0] * ly + nbar[1] * lx)));
}

/// Exact projection parameter of x_k on A->B, positions `[x_k, x_A, x_B]`.
fn projected_beta(x: &[f64]) -> f64 {
    let ab = [x[4] - x[2], x[5] - x[3]];
    let ak = [x[0] - x[2], x[1] - x[3]];
    (ak[0] * ab[0] + ak[1] * ab[1]) / (ab[0] * ab[0] + ab[1] * ab[1])
}

#[test]
fn eq_14_is_the_linearised_projection() {
    for s in cases() {
        let cp = s.segment().project(v2(s.xk));
        let x0 = s.positions();
        let fd = fd_jacobian(|x| DVector::from_element(1, projected_beta(x)), &x0);
        // Exact on the segment; off it, the projection moves by (delta/d^2) n_s . (du_B - du_A)
        // more, while Eq. (14) follows the point x_k - Delta_k.
        let seg = cp.segment();
        let ns = seg.normal() * cp.normal_overlap() / seg.length().powi(2);
        let correction = SVector::<f64, 6>::from([0.0, 0.0, -ns.x, -ns.y, ns.x, ns.y]);
        let exact = cp.dbeta_du() + correction;
        assert!(rel_err(&fd, &dyn_mat(&exact.transpose())) < TOL, "{s:?}");
        if cp.normal_overlap().abs() < 1e-15 {
            assert!(
                rel_err(&fd, &dyn_mat(&cp.dbeta_du().transpose())) < TOL,
                "{s:?}"
            );
        }
    }
}

#[test]
fn sliding_gradient_matrix_is_twice_the_symmetric_part_of_the_force_jacobian() {
    // With lambda fixed and beta following the projection, the nodal forces are
    // G(beta(x))^T lambda. On the segment their Jacobian J is b a^T; the paper's matrix,
    // the Hessian of Eq. (17), is -(J + J^T).
    for c in cases() {
        let s = State::new(c.xa, c.xb, c.beta, 0.0, c.lambda);
        let cp = s.segment().project(v2(s.xk));
        assert!(cp.normal_overlap().abs() < 1e-15, "{s:?}");
        let lam = s.lambda;
        let forces = |x: &[f64]| {
            let b = projected_beta(x);
            DVector::from_vec(vec![
                lam[0],
                lam[1],
                -(1.0 - b) * lam[0],
                -(1.0 - b) * lam[1],
                -b * lam[0],
                -b * lam[1],
            ])
        };
        let jac = fd_jacobian(forces, &s.positions());
        let k_uu = dyn_mat(&cp.sliding(v2(lam)).k_uu);
        assert!(rel_err(&(-(&jac + jac.transpose())), &k_uu) < TOL, "{s:?}");
    }
}

#[test]
fn normal_multiplier_gives_no_tangential_force() {
    for s in cases() {
        let cp = s.segment().project(v2(s.xk));
        let (t, n) = (cp.segment().tangent(), cp.segment().normal());
        let sl = cp.sliding(v2(s.lambda));
        let mut net = Vector2::zeros();
        let mut moment = 0.0;
        let x = s.positions();
        for node in 0..3 {
            let f = Vector2::new(sl.k_ul[2 * node], sl.k_ul[2 * node + 1]);
            assert!(t.dot(&f).abs() < 1e-15, "{s:?}");
            assert!((n.dot(&f).abs() - f.norm()).abs() < 1e-15);
            net += f;
            moment += x[2 * node] * f.y - x[2 * node + 1] * f.x;
        }
        // The column is minus the force per unit dlambda_s: k is pushed by -n_s, out of the
        // target.
        assert!((sl.k_ul[0] - n.x).abs() < 1e-15 && (sl.k_ul[1] - n.y).abs() < 1e-15);
        assert!(net.norm() < 1e-15);
        assert!(moment.abs() < 1e-13, "{s:?}");

        // Frictionless: every force of R_c is normal to the segment, too.
        let frictionless = cp.sliding(-2.5 * n);
        for node in 0..3 {
            let f = Vector2::new(frictionless.r_c[2 * node], frictionless.r_c[2 * node + 1]);
            assert!(t.dot(&f).abs() < 1e-14, "{s:?}");
        }
    }
}

#[test]
fn new_contact_without_force_has_no_sliding_stiffness() {
    for s in cases() {
        let sl = s.segment().project(v2(s.xk)).sliding(Vector2::zeros());
        assert_eq!(sl.k_uu, NodeMat::zeros());
        assert_eq!(sl.r_c, NodeVec::zeros());
    }
}

/// Springs on every displacement dof, at equilibrium before contact.
fn springs() -> NodeMat {
    NodeMat::from_diagonal(&NodeVec::from([200.0, 300.0, 500.0, 700.0, 1100.0, 1300.0]))
}

#[test]
fn sticking_constraint_removes_the_overlap() {
    for base in cases() {
        let s = base.with_beta(base.beta + 0.013);
        let cp = s.segment().contact_at(v2(s.xk), s.beta);
        let st = cp.sticking(v2(s.lambda));

        // Rigid target: only k's rows; the solve moves k onto C exactly.
        let k_c = st.k_c();
        let mut a = SMatrix::<f64, 4, 4>::zeros();
        a.fixed_view_mut::<2, 2>(0, 0)
            .copy_from(&springs().fixed_view::<2, 2>(0, 0));
        a.fixed_view_mut::<2, 2>(0, 2)
            .copy_from(&k_c.fixed_view::<2, 2>(0, 6));
        a.fixed_view_mut::<2, 2>(2, 0)
            .copy_from(&k_c.fixed_view::<2, 2>(6, 0));
        let rhs = SVector::<f64, 4>::from([st.r_c[0], st.r_c[1], st.delta_c.x, st.delta_c.y]);
        let z = a.lu().solve(&rhs).unwrap();
        assert!((v2(s.xk) + Vector2::new(z[0], z[1]) - cp.point()).norm() < 1e-14);

        // Flexible target: the new positions satisfy x_k = (1-beta) x_A + beta x_B exactly.
        let mut a = k_c;
        a.fixed_view_mut::<6, 6>(0, 0).copy_from(&springs());
        let rhs = SVector::<f64, 8>::from_iterator(st.r_c.iter().chain(st.delta_c.iter()).copied());
        let z = a.lu().solve(&rhs).unwrap();
        let x = s.positions();
        let new = |i: usize| Vector2::new(x[2 * i] + z[2 * i], x[2 * i + 1] + z[2 * i + 1]);
        let gap = new(0) - ((1.0 - s.beta) * new(1) + s.beta * new(2));
        assert!(gap.norm() < 1e-14, "{s:?}: {gap}");
        // The springs carry the total contact force, lambda + dlambda, spread by G^T.
        let total = v2(s.lambda) + Vector2::new(z[6], z[7]);
        let du = z.fixed_rows::<6>(0).into_owned();
        assert!((springs() * du - cp.sticking(total).r_c).norm() < 1e-11);
    }
}

#[test]
fn sliding_constraint_removes_the_normal_overlap() {
    for s in cases() {
        let cp = s.segment().project(v2(s.xk));
        let sl = cp.sliding(v2(s.lambda));
        let mut a = sl.k_c();
        let k_total = springs() + sl.k_uu;
        a.fixed_view_mut::<6, 6>(0, 0).copy_from(&k_total);
        let rhs = SVector::<f64, 7>::from_iterator(sl.r_c.iter().copied().chain([sl.delta_c]));
        let z = a.lu().solve(&rhs).unwrap();
        let x = s.positions();
        let new = |i: usize| Vector2::new(x[2 * i] + z[2 * i], x[2 * i + 1] + z[2 * i + 1]);
        let rel = new(0) - ((1.0 - s.beta) * new(1) + s.beta * new(2));
        // The normal overlap (along the n_s of iteration i-1) is gone.
        assert!(cp.segment().normal().dot(&rel).abs() < 1e-14, "{s:?}");
    }
}

/// Four surface points P, A, B, Q and the next one R: two neighbouring
/// smoothed segments A -> B (through P, Q) and B -> Q (through A, R).
fn smoothed_pair() -> (Segment, Segment) {
    let [p, a, b, q, r] = [[2.1, 0.4], [1.0, 0.1], [0.0, 0.0], [-1.2, 0.2], [-2.0, 0.7]].map(v2);
    let first = Segment::new(a, b).unwrap().smoothed([p, q]);
    let second = Segment::new(b, q).unwrap().smoothed([a, r]);
    (first, second)
}

/// The smoothed curve passes through A and B, and two neighbouring
/// segments meet at their shared node with one tangent (C1): a node sliding
/// over it meets no corner.
#[test]
fn smoothed_segments_meet_with_one_tangent() {
    let (first, second) = smoothed_pair();
    assert!((first.point_at(0.0) - first.xa()).norm() < 1e-15);
    assert!((first.point_at(1.0) - first.xb()).norm() < 1e-15);
    let (c1, c0) = (first.curve(1.0).unwrap(), second.curve(0.0).unwrap());
    assert!((c1.d1 - c0.d1).norm() < 1e-15, "{:?} {:?}", c1.d1, c0.d1);
    let (n1, t1) = first.frame_at(1.0);
    let (n0, t0) = second.frame_at(0.0);
    assert!((n1 - n0).norm() < 1e-15 && (t1 - t0).norm() < 1e-15);
    // The normal is the tangent turned +90 degrees, as a straight segment's.
    assert!((n1 - Vector2::new(-t1.y, t1.x)).norm() < 1e-15);
}

/// On nodes evenly spaced along a line the smoothed curve is the line
/// itself, traced at constant speed: the curve reduces to the paper's
/// segment there.
#[test]
fn a_smoothed_segment_on_a_line_is_the_straight_segment() {
    let [p, a, b, q] = [[-2.0, -1.0], [0.0, 0.0], [2.0, 1.0], [4.0, 2.0]].map(v2);
    let curved = Segment::new(a, b).unwrap().smoothed([p, q]);
    let straight = Segment::new(a, b).unwrap();
    let x = v2([1.3, 1.9]);
    let (cs, ss) = (curved.project(x), straight.project(x));
    assert!((cs.beta() - ss.beta()).abs() < 1e-14);
    assert!((cs.point() - ss.point()).norm() < 1e-14);
    assert!((cs.normal() - straight.normal()).norm() < 1e-15);
    assert!((cs.normal_overlap() - ss.normal_overlap()).abs() < 1e-14);
}

/// The projection on a smoothed segment is the foot of the normal: the
/// overlap lies along the curve's normal there, from either side and from
/// a node that has passed an end.
#[test]
fn the_projection_on_a_smoothed_segment_is_the_foot_of_the_normal() {
    let (first, _) = smoothed_pair();
    for x in [[0.4, -0.3], [0.4, 0.3], [0.95, 0.0], [-0.1, 0.05]].map(v2) {
        let cp = first.project(x);
        let along = cp.overlap().dot(&cp.tangent());
        assert!(along.abs() < 1e-14, "{x:?}: {along:e}");
        let (n, t) = first.frame_at(cp.beta());
        assert_eq!((cp.normal(), cp.tangent()), (n, t));
    }
}
