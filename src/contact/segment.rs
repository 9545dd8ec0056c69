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
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    xa: Vector2<f64>,
    xb: Vector2<f64>,
    length: f64,
    tangent: Vector2<f64>,
    normal: Vector2<f64>,
}

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
        })
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

    /// The point `(1 - beta) x_A + beta x_B`.
    pub fn point_at(&self, beta: f64) -> Vector2<f64> {
        self.xa + beta * (self.xb - self.xa)
    }

    /// Contact point at the foot of the normal from `xk` (Eq. 5 with `Delta_k` along `n_s`):
    /// the point a sliding node, or a node new to contact, is referred to.
    pub fn project(&self, xk: Vector2<f64>) -> ContactPoint {
        let beta = self.tangent.dot(&(xk - self.xa)) / self.length;
        self.contact_at(xk, beta)
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

    /// Normal overlap `n_s . Delta_k`: positive when k has penetrated the target.
    pub fn normal_overlap(&self) -> f64 {
        self.segment.normal.dot(&self.overlap)
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
