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

/// The saddle-point system of Eq. (18): the free-dof tangent bordered by the
/// contact rows, `[K + K_c, C^T; C, 0]`. Its pattern changes with the contact
/// set; the symbolic LU analysis is kept while the pattern holds.
#[derive(Default)]
pub struct Augmented {
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    values: Vec<f64>,
    symbolic: Option<(SymbolicSparseColMat<usize>, SymbolicLu<usize>)>,
    pub factorizations: usize,
    /// Symbolic analyses done (one per distinct pattern in a row).
    pub analyses: usize,
}

impl Augmented {
    /// Solve `A x = rhs` in place, A of order `rhs.len()` given as the CSC
    /// tangent `k` over `pattern` (the first `pattern.n` unknowns) plus the
    /// entries `extra` (row, col, value; duplicates are summed).
    pub fn solve(
        &mut self,
        pattern: &Pattern,
        k: &[f64],
        extra: &mut [(usize, usize, f64)],
        rhs: &mut [f64],
    ) -> Result<(), LinearError> {
        let n = rhs.len();
        extra.sort_unstable_by_key(|&(r, c, _)| (c, r));
        let (col_ptr, row_idx, values) = (&mut self.col_ptr, &mut self.row_idx, &mut self.values);
        let old_ptr = std::mem::take(col_ptr);
        let old_idx = std::mem::take(row_idx);
        values.clear();
        col_ptr.push(0);
        let mut e = 0;
        let mut column: Vec<(usize, f64)> = Vec::new();
        for c in 0..n {
            column.clear();
            if c < pattern.n {
                for p in pattern.col_ptr[c]..pattern.col_ptr[c + 1] {
                    column.push((pattern.row_idx[p], k[p]));
                }
            }
            let start = e;
            while e < extra.len() && extra[e].1 == c {
                column.push((extra[e].0, extra[e].2));
                e += 1;
            }
            if e > start {
                column.sort_unstable_by_key(|&(r, _)| r);
            }
            let mut last = usize::MAX;
            for &(r, v) in &column {
                if r == last {
                    *values.last_mut().expect("a previous entry") += v;
                } else {
                    row_idx.push(r);
                    values.push(v);
                    last = r;
                }
            }
            col_ptr.push(row_idx.len());
        }
        let same = self.symbolic.is_some() && old_ptr == *col_ptr && old_idx == *row_idx;
        if !same {
            let s = SymbolicSparseColMat::new_checked(n, n, col_ptr.clone(), None, row_idx.clone());
            let lu = SymbolicLu::try_new(s.as_ref())
                .map_err(|e| LinearError::Factorization(format!("{e:?}")))?;
            self.symbolic = Some((s, lu));
            self.analyses += 1;
        }
        let (s, lu) = self.symbolic.as_ref().expect("set above");
        let mat = SparseColMatRef::new(s.as_ref(), &self.values);
        self.factorizations += 1;
        let f = Lu::try_new_with_symbolic(lu.clone(), mat)
            .map_err(|e| LinearError::Factorization(format!("{e:?}")))?;
        f.solve_in_place(MatMut::from_column_major_slice_mut(rhs, n, 1));
        if rhs.iter().any(|v| !v.is_finite()) {
            return Err(LinearError::NonFinite);
        }
        Ok(())
    }
}
