//! One contactor node k against one target segment A->B: the segment geometry (Eqs. 3-6)
//! and the node's contributions to Eq. (18) for sticking (Eqs. 19-21) and sliding
//! (Eqs. 22-24), derived in docs/contact.md from the potentials of Eqs. (11) and (17).
//!
//! Dof order of every vector and matrix here: the displacements
//! `[u_kx, u_ky, u_Ax, u_Ay, u_Bx, u_By]`, then the multiplier increments
//! (`[dlambda_kx, dlambda_ky]` sticking, `[dlambda_s]` sliding). Against a rigid target the
//! caller drops the A and B rows and columns.
//!
//! Conventions: the target body lies to the left of A->B (counter-clockwise numbering, as
//! for the contactor), so the normal `n_s` (the tangent turned +90 degrees) points into the
//! target; the overlap `Delta_k = x_k - x_C` has `n_s . Delta_k > 0` when k has penetrated;
//! `lambda` is the contact force on the contactor node, and the target carries `-lambda`.

use nalgebra::{SMatrix, SVector, Vector2};

use super::ContactError;

/// A vector over the six displacement dofs `[u_kx, u_ky, u_Ax, u_Ay, u_Bx, u_By]`.
pub type NodeVec = SVector<f64, 6>;
/// A matrix over the six displacement dofs.
pub type NodeMat = SMatrix<f64, 6, 6>;

/// Target segment j from node A to node B, at the current positions (after iteration i-1).
/// A smoothed target's segment (`smoothed`) is the Catmull-Rom curve from A to B through
/// its outer neighbours P (before A) and Q (after B), `x(beta) = sum N_i(beta) x_i` over
/// `[P, A, B, Q]`: the surface is C1 at its nodes (docs/contact.md, "Smoothed target").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    xa: Vector2<f64>,
    xb: Vector2<f64>,
    length: f64,
    tangent: Vector2<f64>,
    normal: Vector2<f64>,
    /// `[x_P, x_Q]` of a smoothed segment; None: straight.
    around: Option<[Vector2<f64>; 2]>,
}

/// A smoothed segment's curve at `beta`: the shape functions over `[P, A, B, Q]`, their
/// first derivatives, and the curve's point, first and second derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Curve {
    pub weights: [f64; 4],
    pub slopes: [f64; 4],
    pub point: Vector2<f64>,
    pub d1: Vector2<f64>,
    pub d2: Vector2<f64>,
}

/// The uniform Catmull-Rom shape functions over `[P, A, B, Q]` at `t`, with their first
/// and second derivatives.
fn catmull_rom(t: f64) -> [[f64; 4]; 3] {
    let (t2, t3) = (t * t, t * t * t);
    [
        [
            0.5 * (-t + 2.0 * t2 - t3),
            0.5 * (2.0 - 5.0 * t2 + 3.0 * t3),
            0.5 * (t + 4.0 * t2 - 3.0 * t3),
            0.5 * (-t2 + t3),
        ],
        [
            0.5 * (-1.0 + 4.0 * t - 3.0 * t2),
            0.5 * (-10.0 * t + 9.0 * t2),
            0.5 * (1.0 + 8.0 * t - 9.0 * t2),
            0.5 * (-2.0 * t + 3.0 * t2),
        ],
        [
            0.5 * (4.0 - 6.0 * t),
            0.5 * (-10.0 + 18.0 * t),
            0.5 * (8.0 - 18.0 * t),
            0.5 * (-2.0 + 6.0 * t),
        ],
    ]
}

/// Newton steps of the projection on a smoothed segment (it converges in 2 to 4).
const PROJECTION_STEPS: usize = 30;

impl Segment {
    /// The segment from `xa` to `xb`, with the target body to the left of A->B.
    pub fn new(xa: Vector2<f64>, xb: Vector2<f64>) -> Result<Self, ContactError> {
        let length = (xb - xa).norm();
        if !length.is_finite() || length <= 0.0 {
            return Err(ContactError::DegenerateSegment {
                xa: [xa.x, xa.y],
                xb: [xb.x, xb.y],
                length,
            });
        }
        let tangent = (xb - xa) / length;
        Ok(Self {
            xa,
            xb,
            length,
            tangent,
            normal: Vector2::new(-tangent.y, tangent.x),
            around: None,
        })
    }

    /// The segment smoothed through its outer neighbours `[x_P, x_Q]` (at an end of the
    /// target, the end node mirrored: `x_P = 2 x_A - x_B`).
    pub fn smoothed(mut self, around: [Vector2<f64>; 2]) -> Self {
        self.around = Some(around);
        self
    }

    /// Whether the segment is a smoothed target's curve.
    pub fn is_smooth(&self) -> bool {
        self.around.is_some()
    }

    /// The curve at `beta` (None for a straight segment).
    pub fn curve(&self, beta: f64) -> Option<Curve> {
        let [xp, xq] = self.around?;
        let [n, dn, ddn] = catmull_rom(beta);
        let sum = |w: [f64; 4]| w[0] * xp + w[1] * self.xa + w[2] * self.xb + w[3] * xq;
        Some(Curve {
            weights: n,
            slopes: dn,
            point: sum(n),
            d1: sum(dn),
            d2: sum(ddn),
        })
    }

    /// Unit normal and tangent where the target is at `beta`: the segment's, or the
    /// smoothed curve's there.
    pub fn frame_at(&self, beta: f64) -> (Vector2<f64>, Vector2<f64>) {
        if self.around.is_none() {
            return (self.normal, self.tangent);
        }
        self.curve_frame(beta)
    }

    /// `frame_at` on the curve (out of line: the straight segments' callers
    /// stay as small as they were).
    #[inline(never)]
    fn curve_frame(&self, beta: f64) -> (Vector2<f64>, Vector2<f64>) {
        let Some(c) = self.curve(beta) else {
            return (self.normal, self.tangent);
        };
        let t = c.d1 / c.d1.norm();
        (Vector2::new(-t.y, t.x), t)
    }

    pub fn xa(&self) -> Vector2<f64> {
        self.xa
    }

    pub fn xb(&self) -> Vector2<f64> {
        self.xb
    }

    /// `d_j`, Eq. (4).
    pub fn length(&self) -> f64 {
        self.length
    }

    /// Unit tangent `n_r`, from A to B.
    pub fn tangent(&self) -> Vector2<f64> {
        self.tangent
    }

    /// Unit normal `n_s`: the tangent turned +90 degrees; points into the target body.
    pub fn normal(&self) -> Vector2<f64> {
        self.normal
    }

    /// The point `(1 - beta) x_A + beta x_B`, or the smoothed curve's at `beta`.
    pub fn point_at(&self, beta: f64) -> Vector2<f64> {
        if self.around.is_none() {
            return self.xa + beta * (self.xb - self.xa);
        }
        self.curve_point(beta)
    }

    #[inline(never)]
    fn curve_point(&self, beta: f64) -> Vector2<f64> {
        self.curve(beta)
            .map_or(self.xa + beta * (self.xb - self.xa), |c| c.point)
    }

    /// Contact point at the foot of the normal from `xk` (Eq. 5 with `Delta_k` along `n_s`):
    /// the point a sliding node, or a node new to contact, is referred to. On a smoothed
    /// segment, Newton's iteration on `(x_k - x(beta)) . x'(beta) = 0` from the chord's foot
    /// (each step kept within half a segment beyond the ends).
    pub fn project(&self, xk: Vector2<f64>) -> ContactPoint {
        let mut beta = self.tangent.dot(&(xk - self.xa)) / self.length;
        if self.is_smooth() {
            beta = self.foot_on_curve(xk, beta);
        }
        self.contact_at(xk, beta)
    }

    /// The foot of the normal from `xk` on the curve, by Newton from `beta`.
    #[inline(never)]
    fn foot_on_curve(&self, xk: Vector2<f64>, beta: f64) -> f64 {
        let mut beta = beta.clamp(-0.5, 1.5);
        for _ in 0..PROJECTION_STEPS {
            let Some(c) = self.curve(beta) else { break };
            let d = xk - c.point;
            let slope = -c.d1.norm_squared() + d.dot(&c.d2);
            if slope >= 0.0 || slope.is_nan() {
                break;
            }
            let next = (beta - d.dot(&c.d1) / slope).clamp(-0.5, 1.5);
            let done = (next - beta).abs() <= 1e-14;
            beta = next;
            if done {
                break;
            }
        }
        beta
    }

    /// Contact point at the fixed location `beta`: the material point a sticking node
    /// stays attached to (Section 2.1, `beta(i) = beta(i-1)`).
    pub fn contact_at(&self, xk: Vector2<f64>, beta: f64) -> ContactPoint {
        let x_c = self.point_at(beta);
        ContactPoint {
            segment: *self,
            beta,
            x_c,
            overlap: xk - x_c,
        }
    }
}

/// Contactor node k referred to the point C at `beta` on a target segment (Fig. 3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactPoint {
    segment: Segment,
    beta: f64,
    x_c: Vector2<f64>,
    overlap: Vector2<f64>,
}

impl ContactPoint {
    pub fn segment(&self) -> &Segment {
        &self.segment
    }

    /// Location parameter `beta` of C on A->B (0 at A, 1 at B).
    pub fn beta(&self) -> f64 {
        self.beta
    }

    /// Current position of the contact point C.
    pub fn point(&self) -> Vector2<f64> {
        self.x_c
    }

    /// Overlap vector `Delta_k = x_k - x_C`, Eq. (3).
    pub fn overlap(&self) -> Vector2<f64> {
        self.overlap
    }

    /// Unit normal `n_s` of the target at C, into the target (the segment's, or the
    /// smoothed curve's at C).
    pub fn normal(&self) -> Vector2<f64> {
        self.segment.frame_at(self.beta).0
    }

    /// Unit tangent `n_r` of the target at C, from A toward B.
    pub fn tangent(&self) -> Vector2<f64> {
        self.segment.frame_at(self.beta).1
    }

    /// Normal overlap `n_s . Delta_k`: positive when k has penetrated the target.
    pub fn normal_overlap(&self) -> f64 {
        self.normal().dot(&self.overlap)
    }

    /// Normal gap, `-normal_overlap()`: positive when k is clear of the target.
    pub fn gap(&self) -> f64 {
        -self.normal_overlap()
    }

    /// Whether C lies on the segment, `-tol <= beta <= 1 + tol` (`tol` in units of beta).
    pub fn is_within(&self, tol: f64) -> bool {
        self.beta >= -tol && self.beta <= 1.0 + tol
    }

    /// `G = [I, -(1-beta) I, -beta I]`: `G dU` is the motion of k relative to the material
    /// point C; `G^T lambda` spreads the force on k and its reaction over k, A, B (Eqs. 7, 8).
    pub fn relative_motion(&self) -> SMatrix<f64, 2, 6> {
        let (wa, wb) = (1.0 - self.beta, self.beta);
        SMatrix::<f64, 2, 6>::new(
            1.0, 0.0, -wa, 0.0, -wb, 0.0, //
            0.0, 1.0, 0.0, -wa, 0.0, -wb,
        )
    }

    /// `a = G^T n_r / d`: the linearised change of beta, `Delta beta = a . dU + n_r . Delta_k / d`
    /// (Eq. 14).
    pub fn dbeta_du(&self) -> NodeVec {
        let nbar = self.segment.tangent / self.segment.length;
        self.relative_motion().transpose() * nbar
    }

    /// Sticking contributions (Eqs. 19-21), with `lambda` the contact force on k after
    /// iteration i-1.
    pub fn sticking(&self, lambda: Vector2<f64>) -> Sticking {
        let gt = self.relative_motion().transpose();
        Sticking {
            r_c: gt * lambda,
            k_ul: -gt,
            delta_c: self.overlap,
        }
    }

    /// Sliding contributions (Eqs. 22-24), with `lambda` the contact force on k after
    /// iteration i-1 (normal and frictional parts).
    pub fn sliding(&self, lambda: Vector2<f64>) -> Sliding {
        let gt = self.relative_motion().transpose();
        let a = self.dbeta_du();
        // b = H^T lambda: the change of G^T lambda per unit increase of beta.
        let b = NodeVec::from([0.0, 0.0, lambda.x, lambda.y, -lambda.x, -lambda.y]);
        let ab = a * b.transpose();
        // n_r . Delta_k / d: zero when C is the foot of the normal, so that Eq. (22) = Eq. (19).
        let c = self.segment.tangent.dot(&self.overlap) / self.segment.length;
        Sliding {
            r_c: gt * lambda + c * b,
            k_uu: -(ab + ab.transpose()),
            k_ul: gt * self.segment.normal,
            delta_c: -self.normal_overlap(),
        }
    }
}

/// Contributions of a sticking node to Eq. (18); multipliers `[dlambda_kx, dlambda_ky]`.
/// The displacement block of `K_c` is zero (Eq. 21).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sticking {
    /// Contact force vector `R_c = G^T lambda`, Eq. (19).
    pub r_c: NodeVec,
    /// Displacement-multiplier block of `K_c`, `-G^T`; the multiplier-displacement block is
    /// its transpose (Eq. 21).
    pub k_ul: SMatrix<f64, 6, 2>,
    /// Overlap vector `Delta_c = Delta_k`, Eq. (20).
    pub delta_c: Vector2<f64>,
}

impl Sticking {
    /// The full symmetric 8x8 `K_c` of Eq. (21).
    pub fn k_c(&self) -> SMatrix<f64, 8, 8> {
        let mut k = SMatrix::<f64, 8, 8>::zeros();
        k.fixed_view_mut::<6, 2>(0, 6).copy_from(&self.k_ul);
        k.fixed_view_mut::<2, 6>(6, 0)
            .copy_from(&self.k_ul.transpose());
        k
    }
}

/// Contributions of a sliding node to Eq. (18); one multiplier `dlambda_s`, the increase of
/// the compressive normal force (Eq. 16: `dlambda_k = -dlambda_s n_s`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sliding {
    /// Contact force vector `R_c = G^T lambda`, Eq. (22).
    pub r_c: NodeVec,
    /// Sliding gradient matrix, the displacement block of Eq. (24): `-(a b^T + b a^T)` with
    /// `a = G^T n_r / d`, `b = [0; lambda; -lambda]`.
    pub k_uu: NodeMat,
    /// Displacement-multiplier column of `K_c`, `G^T n_s`; the multiplier row is its
    /// transpose (Eq. 24).
    pub k_ul: NodeVec,
    /// Normal overlap `Delta_c = -n_s . Delta_k`, Eq. (23).
    pub delta_c: f64,
}

impl Sliding {
    /// The full symmetric 7x7 `K_c` of Eq. (24).
    pub fn k_c(&self) -> SMatrix<f64, 7, 7> {
        let mut k = SMatrix::<f64, 7, 7>::zeros();
        k.fixed_view_mut::<6, 6>(0, 0).copy_from(&self.k_uu);
        k.fixed_view_mut::<6, 1>(0, 6).copy_from(&self.k_ul);
        k.fixed_view_mut::<1, 6>(6, 0)
            .copy_from(&self.k_ul.transpose());
        k
    }
}

#[cfg(test)]
mod tests;
