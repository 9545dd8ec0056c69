//! The tangent alone: Cholesky (LLT) for a symmetric positive definite
//! tangent, LU when it is unsymmetric or LLT meets a non-positive pivot (a
//! tangent past a limit point), the symbolic analysis made once.

use super::{LinearError, LinearTimes, Method, amd_of_block};
use crate::assembly::Pattern;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::linalg::solvers::Solve;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, SymbolicCholesky, SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par, Side};
use std::time::Instant;

enum Factor {
    /// In `LinearSolver::llt` and `llt_values`.
    Llt,
    Lu(Box<Lu<usize, f64>>),
}

pub struct LinearSolver {
    symbolic: SymbolicSparseColMat<usize>,
    /// The LLT analysis (in `order`) and its workspace; the factor's values
    /// in `llt_values`.
    llt: Option<(SymbolicCholesky<usize>, MemBuffer)>,
    llt_values: Vec<f64>,
    /// The fill-reducing order (AMD: forward, inverse), made on the first
    /// analysis or given by the bordered solver, which orders the same
    /// displacement block (`share_order`).
    order: Option<(Vec<usize>, Vec<usize>)>,
    lu: Option<SymbolicLu<usize>>,
    factor: Option<Factor>,
    /// Start with LLT (symmetric tangent); switches to LU for good on a failed LLT.
    try_llt: bool,
    pub factorizations: usize,
    pub times: LinearTimes,
}

impl LinearSolver {
    pub fn new(p: &Pattern, symmetric: bool) -> Result<Self, LinearError> {
        let symbolic =
            SymbolicSparseColMat::new_checked(p.n, p.n, p.col_ptr.clone(), None, p.row_idx.clone());
        Ok(LinearSolver {
            symbolic,
            llt: None,
            llt_values: Vec::new(),
            order: None,
            lu: None,
            factor: None,
            try_llt: symmetric,
            factorizations: 0,
            times: LinearTimes::default(),
        })
    }

    pub fn method(&self) -> Option<Method> {
        match self.factor {
            Some(Factor::Llt) => Some(Method::Llt),
            Some(Factor::Lu(_)) => Some(Method::Lu),
            None => None,
        }
    }

    /// The fill-reducing order of the matrix, once made.
    pub fn order(&self) -> Option<&(Vec<usize>, Vec<usize>)> {
        self.order.as_ref()
    }

    /// Takes `order` (of the same order; the bordered solver's displacement
    /// block is this matrix, plus a few couplings against a deformable
    /// target, and any order is valid) unless one is made: one AMD for
    /// both solvers.
    pub fn share_order(&mut self, order: Option<&(Vec<usize>, Vec<usize>)>) {
        if let Some(o) = order
            && self.order.is_none()
            && o.0.len() == self.symbolic.nrows()
        {
            self.order = Some(o.clone());
        }
    }

    /// Factorize the matrix with values `values` over the pattern.
    pub fn factorize(&mut self, values: &[f64]) -> Result<(), LinearError> {
        let mat = SparseColMatRef::new(self.symbolic.as_ref(), values);
        self.factorizations += 1;
        if self.try_llt {
            if self.llt.is_none() {
                let clock = Instant::now();
                let n = self.symbolic.nrows();
                if self.order.as_ref().is_none_or(|(fwd, _)| fwd.len() != n) {
                    self.order = Some(
                        amd_of_block(self.symbolic.as_ref(), n)
                            .map_err(|e| LinearError::Factorization(format!("{e:?}")))?,
                    );
                }
                let (fwd, inv) = self.order.as_ref().expect("set above");
                let s = factorize_symbolic_cholesky(
                    self.symbolic.as_ref(),
                    Side::Lower,
                    SymmetricOrdering::Custom(PermRef::new_checked(fwd, inv, n)),
                    CholeskySymbolicParams::default(),
                )
                .map_err(|e| LinearError::Factorization(format!("{e:?}")))?;
                let req = StackReq::any_of(&[
                    s.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
                    s.solve_in_place_scratch::<f64>(1, Par::Seq),
                ]);
                let mem = MemBuffer::try_new(req)
                    .map_err(|e| LinearError::Factorization(format!("{e:?}")))?;
                self.llt = Some((s, mem));
                self.times.symbolic += clock.elapsed();
            }
            let clock = Instant::now();
            let (sym, mem) = self.llt.as_mut().expect("set above");
            self.llt_values.clear();
            self.llt_values.resize(sym.len_val(), 0.0);
            let llt = sym.factorize_numeric_llt(
                &mut self.llt_values,
                mat,
                Side::Lower,
                LltRegularization::default(),
                Par::Seq,
                MemStack::new(mem),
                Default::default(),
            );
            self.times.numeric += clock.elapsed();
            match llt {
                Ok(_) => {
                    self.factor = Some(Factor::Llt);
                    return Ok(());
                }
                Err(_) => self.try_llt = false,
            }
        }
        if self.lu.is_none() {
            let clock = Instant::now();
            let s = SymbolicLu::try_new(self.symbolic.as_ref())
                .map_err(|e| LinearError::Factorization(format!("{e:?}")))?;
            self.lu = Some(s);
            self.times.symbolic += clock.elapsed();
        }
        let clock = Instant::now();
        let sym = self.lu.clone().expect("set above");
        let f = Lu::try_new_with_symbolic(sym, mat)
            .map_err(|e| LinearError::Factorization(format!("{e:?}")))?;
        self.factor = Some(Factor::Lu(Box::new(f)));
        self.times.numeric += clock.elapsed();
        Ok(())
    }

    /// Solve in place with the last factorization.
    pub fn solve(&mut self, rhs: &mut [f64]) -> Result<(), LinearError> {
        let clock = Instant::now();
        let n = rhs.len();
        let m = MatMut::from_column_major_slice_mut(rhs, n, 1);
        match (&self.factor, self.llt.as_mut()) {
            (Some(Factor::Llt), Some((sym, mem))) => {
                faer::sparse::linalg::cholesky::LltRef::new(sym, &self.llt_values)
                    .solve_in_place_with_conj(Conj::No, m, Par::Seq, MemStack::new(mem))
            }
            (Some(Factor::Lu(f)), _) => f.solve_in_place(m),
            _ => return Err(LinearError::Factorization("no factorization".into())),
        }
        self.times.solve += clock.elapsed();
        if rhs.iter().any(|v| !v.is_finite()) {
            return Err(LinearError::NonFinite);
        }
        Ok(())
    }
}
