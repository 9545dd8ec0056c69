//! Sparse linear solves with faer: the symbolic analysis is done once per
//! pattern and reused; Cholesky (LLT) for symmetric positive definite
//! tangents, LU when the tangent is unsymmetric or LLT meets a non-positive
//! pivot (a tangent past a limit point).

use crate::assembly::Pattern;
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, Lu, SymbolicLlt, SymbolicLu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{MatMut, Side};

#[derive(Debug, thiserror::Error)]
pub enum LinearError {
    #[error("sparse factorization failed: {0}")]
    Factorization(String),
    #[error("linear solve produced a non-finite value")]
    NonFinite,
}

/// Which factorization the last solve used.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    Llt,
    Lu,
}

enum Factor {
    Llt(Llt<usize, f64>),
    Lu(Box<Lu<usize, f64>>),
}

pub struct LinearSolver {
    symbolic: SymbolicSparseColMat<usize>,
    llt: Option<SymbolicLlt<usize>>,
    lu: Option<SymbolicLu<usize>>,
    factor: Option<Factor>,
    /// Start with LLT (symmetric tangent); switches to LU for good on a failed LLT.
    try_llt: bool,
    pub factorizations: usize,
}

impl LinearSolver {
    pub fn new(p: &Pattern, symmetric: bool) -> Result<Self, LinearError> {
        let symbolic =
            SymbolicSparseColMat::new_checked(p.n, p.n, p.col_ptr.clone(), None, p.row_idx.clone());
        Ok(LinearSolver {
            symbolic,
            llt: None,
            lu: None,
            factor: None,
            try_llt: symmetric,
            factorizations: 0,
        })
    }

    pub fn method(&self) -> Option<Method> {
        match self.factor {
            Some(Factor::Llt(_)) => Some(Method::Llt),
            Some(Factor::Lu(_)) => Some(Method::Lu),
            None => None,
        }
    }

    /// Factorize the matrix with values `values` over the pattern.
    pub fn factorize(&mut self, values: &[f64]) -> Result<(), LinearError> {
        let mat = SparseColMatRef::new(self.symbolic.as_ref(), values);
        self.factorizations += 1;
        if self.try_llt {
            if self.llt.is_none() {
                let s = SymbolicLlt::try_new(self.symbolic.as_ref(), Side::Lower)
                    .map_err(|e| LinearError::Factorization(format!("{e:?}")))?;
                self.llt = Some(s);
            }
            let sym = self.llt.clone().expect("set above");
            match Llt::try_new_with_symbolic(sym, mat, Side::Lower) {
                Ok(f) => {
                    self.factor = Some(Factor::Llt(f));
                    return Ok(());
                }
                Err(_) => self.try_llt = false,
            }
        }
        if self.lu.is_none() {
            let s = SymbolicLu::try_new(self.symbolic.as_ref())
                .map_err(|e| LinearError::Factorization(format!("{e:?}")))?;
            self.lu = Some(s);
        }
        let sym = self.lu.clone().expect("set above");
        let f = Lu::try_new_with_symbolic(sym, mat)
            .map_err(|e| LinearError::Factorization(format!("{e:?}")))?;
        self.factor = Some(Factor::Lu(Box::new(f)));
        Ok(())
    }

    /// Solve in place with the last factorization.
    pub fn solve(&self, rhs: &mut [f64]) -> Result<(), LinearError> {
        let n = rhs.len();
        let m = MatMut::from_column_major_slice_mut(rhs, n, 1);
        match &self.factor {
            Some(Factor::Llt(f)) => f.solve_in_place(m),
            Some(Factor::Lu(f)) => f.solve_in_place(m),
            None => return Err(LinearError::Factorization("no factorization".into())),
        }
        if rhs.iter().any(|v| !v.is_finite()) {
            return Err(LinearError::NonFinite);
        }
        Ok(())
    }
}
