//! One LU factorization kept for many right-hand sides (the sensitivities
//! of a converged state), each solve refined.

//! Sparse linear solves with faer, the symbolic analysis done once per
//! pattern and reused:
//! - [`Linear`] (`linear.rs`), the one solver Newton hands its systems to:
//!   the tangent's, and Eq. (18)'s bordered ones; it owns the order they
//!   share, the multipliers' slots (`slots.rs`) and the counters;
//! - [`LinearSolver`] (`tangent.rs`), the tangent alone: Cholesky (LLT) for
//!   a symmetric positive definite tangent, LU when it is unsymmetric or
//!   LLT meets a non-positive pivot (a tangent past a limit point);
//! - [`Augmented`], the contact system of Eq. (18): it solves each on the
//!   kept LDLT factor's trailing block when it can (`trailing.rs`), else
//!   factors it (LDLT with the multipliers last, the unpivoted LDU of
//!   `ldu.rs`, or LU), each solve checked;
//! - [`FactoredLu`], one factorization kept for many right-hand sides (the
//!   sensitivities of a converged state).

use super::*;

/// One sparse LU factorization of a bordered matrix (as [`Augmented`]
/// builds it), kept for any number of solves: the sensitivities of a
/// converged state solve with its tangent once per seed. Each solve is
/// refined against the matrix (a stiff body beside a soft one leaves the
/// factor a few digits short).
pub struct FactoredLu {
    lu: Lu<usize, f64>,
    mat: SymbolicSparseColMat<usize>,
    values: Vec<f64>,
}

/// Refinement steps of a [`FactoredLu`] solve at most; it stops when a
/// correction is below 1e-15 of the solution.
pub(super) const REFINEMENT_STEPS: usize = 3;

impl FactoredLu {
    /// Factorizes the order-`n` matrix `k` over `pattern` plus `extra`.
    pub fn new(
        pattern: &Pattern,
        k: &[f64],
        extra: &mut [(usize, usize, f64)],
        n: usize,
    ) -> Result<Self, LinearError> {
        let (col_ptr, row_idx, values) = bordered_new(pattern, k, extra, n);
        let mat = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        let symbolic = SymbolicLu::try_new(mat.as_ref())
            .map_err(|e| LinearError::Factorization(format!("{e:?}")))?;
        let lu = Lu::try_new_with_symbolic(symbolic, SparseColMatRef::new(mat.as_ref(), &values))
            .map_err(|e| LinearError::Factorization(format!("{e:?}")))?;
        Ok(FactoredLu { lu, mat, values })
    }

    /// Solves `A x = rhs` in place.
    pub fn solve(&self, rhs: &mut [f64]) -> Result<(), LinearError> {
        let n = self.mat.nrows();
        if rhs.len() != n {
            return Err(LinearError::Factorization(format!(
                "right-hand side of length {} for a matrix of order {n}",
                rhs.len()
            )));
        }
        let b = rhs.to_vec();
        self.lu
            .solve_in_place(MatMut::from_column_major_slice_mut(rhs, n, 1));
        let inf = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for _ in 0..REFINEMENT_STEPS {
            // r = b - A x, then x += A^-1 r.
            let mut r = b.clone();
            for j in 0..n {
                let rows = self.mat.row_idx_of_col_raw(j);
                let values = &self.values[self.mat.col_ptr()[j]..self.mat.col_ptr()[j + 1]];
                for (&i, &v) in rows.iter().zip(values) {
                    r[i] -= v * rhs[j];
                }
            }
            self.lu
                .solve_in_place(MatMut::from_column_major_slice_mut(&mut r, n, 1));
            for (x, d) in rhs.iter_mut().zip(&r) {
                *x += d;
            }
            let step = inf(&r);
            if step.is_nan() || step <= 1e-15 * inf(rhs) {
                break;
            }
        }
        if rhs.iter().any(|v| !v.is_finite()) {
            return Err(LinearError::NonFinite);
        }
        Ok(())
    }
}
