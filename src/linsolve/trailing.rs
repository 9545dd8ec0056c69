//! Inner solves on the trailing block of an LDLT factor (issue 14).
//!
//! The bordered system of a Newton iteration is factored with its
//! trailing set `T` eliminated last: the multipliers and the displacement
//! dofs their rows and columns touch (against rigid targets those are the
//! contact nodes' dofs). An inner solve changes entries inside `T x T`
//! only (a multiplier released or added in its slot, a stick/slip row, a
//! sliding gradient on a contact node's dofs), so the interior's part of
//! the factor holds for it and the new system is
//!
//! ```text
//! [A_II  A_IT     ] [x_I]   [b_I]
//! [A_TI  A_TT + Δ ] [x_T] = [b_T]
//! ```
//!
//! whose Schur complement onto `T` is `S0 + Δ`, `S0 = L_TT D_T L_TT^T`
//! read from the factor. A solve is a forward substitution over the
//! interior (it leaves the reduced right-hand side `b_T - L_TI y_I` in the
//! trailing rows), a dense LU solve of order `t`, and a back substitution
//! over the interior with `x_T` known: one triangular solve in all.

use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{
    solve_unit_lower_triangular_in_place, solve_unit_upper_triangular_in_place,
};
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use faer::sparse::linalg::cholesky::{SymbolicCholesky, SymbolicCholeskyRaw};
use faer::{Accum, Mat, MatMut, MatRef, Par};

/// A supernodal LDLT factor (faer's layout: per supernode a dense
/// column-major block, its diagonal block unit lower with `D` on the
/// diagonal, then the rows of its pattern) seen with its trailing set, the
/// factor's positions `b..`.
pub(super) struct Factor<'a> {
    symbolic: &'a SymbolicSupernodalCholesky<usize>,
    values: &'a [f64],
    /// Position in the factor of each unknown, and the unknown at each
    /// position.
    pub inv: &'a [usize],
    pub fwd: &'a [usize],
    /// The first trailing position.
    pub b: usize,
}

/// One supernode: its first column, its width, its pattern (rows below
/// the diagonal block) and its values.
struct Node<'a> {
    start: usize,
    width: usize,
    pattern: &'a [usize],
    values: &'a [f64],
}

impl Node<'_> {
    /// Rows of the block (the diagonal block's, then the pattern's).
    fn rows(&self) -> usize {
        self.width + self.pattern.len()
    }

    /// Column `j` of the block.
    fn column(&self, j: usize) -> &[f64] {
        let r = self.rows();
        &self.values[j * r..(j + 1) * r]
    }
}

impl<'a> Factor<'a> {
    /// The factor of `symbolic` (supernodal, with its permutation) and
    /// `values`, its last `t` positions trailing; None for a simplicial
    /// factor or one without a permutation.
    pub fn new(symbolic: &'a SymbolicCholesky<usize>, values: &'a [f64], t: usize) -> Option<Self> {
        let SymbolicCholeskyRaw::Supernodal(s) = symbolic.raw() else {
            return None;
        };
        let perm = symbolic.perm()?;
        let (fwd, inv) = perm.arrays();
        let n = s.nrows();
        (t <= n && values.len() == s.len_val()).then_some(Factor {
            symbolic: s,
            values,
            inv,
            fwd,
            b: n - t,
        })
    }

    fn nodes(&self) -> usize {
        self.symbolic.n_supernodes()
    }

    fn node(&self, s: usize) -> Node<'a> {
        let sym = self.symbolic;
        let (start, end) = (sym.supernode_begin()[s], sym.supernode_end()[s]);
        let p0 = sym.col_ptr_for_row_idx()[s];
        let pattern = &sym.row_idx()[p0..p0 + sym.nnz_per_super()[s]];
        let v = sym.col_ptr_for_val();
        Node {
            start,
            width: end - start,
            pattern,
            values: &self.values[v[s]..v[s + 1]],
        }
    }

    /// The Schur complement of the interior onto the trailing set, `L_TT
    /// D_T L_TT^T` (order `t`, trailing positions).
    pub fn schur(&self) -> Mat<f64> {
        let n = self.symbolic.nrows();
        let t = n - self.b;
        let mut l = Mat::<f64>::zeros(t, t);
        let mut d = vec![0.0; t];
        for s in 0..self.nodes() {
            let node = self.node(s);
            if node.start + node.width <= self.b {
                continue;
            }
            for j in 0..node.width {
                let c = node.start + j;
                if c < self.b {
                    continue;
                }
                let col = node.column(j);
                let cj = c - self.b;
                d[cj] = col[j];
                l[(cj, cj)] = 1.0;
                for i in j + 1..node.width {
                    l[(node.start + i - self.b, cj)] = col[i];
                }
                for (k, &r) in node.pattern.iter().enumerate() {
                    l[(r - self.b, cj)] = col[node.width + k];
                }
            }
        }
        let ld = Mat::from_fn(t, t, |i, j| l[(i, j)] * d[j]);
        ld * l.transpose()
    }

    /// `D_I^-1`, the interior's pivots inverted (one strided pass over the
    /// factor, made once per factor for `backward`).
    pub fn d_inv(&self) -> Vec<f64> {
        let mut d = vec![0.0; self.b];
        for s in 0..self.nodes() {
            let node = self.node(s);
            for j in 0..node.width.min(self.b.saturating_sub(node.start)) {
                d[node.start + j] = 1.0 / node.column(j)[j];
            }
        }
        d
    }

    /// Forward substitution over the interior columns, in place on `x` in
    /// the factor's order: `x_I` becomes `y_I = L_II^-1 b_I` and `x_T` the
    /// reduced right-hand side `b_T - L_TI y_I`. (faer's dense kernels on
    /// each supernode's block: the pass is bound by reading the factor.)
    pub fn forward(&self, x: &mut [f64]) {
        let mut tmp = Vec::new();
        for s in 0..self.nodes() {
            let node = self.node(s);
            if node.start >= self.b {
                break;
            }
            let (w, at, q) = (node.width, node.start, node.pattern.len());
            let k = w.min(self.b - at);
            let block = MatRef::from_column_major_slice(node.values, node.rows(), w);
            let (top, bottom) = block.split_at_row(w);
            let (head, rest) = x[at..].split_at_mut(k);
            let mut xa = MatMut::from_column_major_slice_mut(head, k, 1);
            solve_unit_lower_triangular_in_place(top.submatrix(0, 0, k, k), xa.rb_mut(), Par::Seq);
            if k < w {
                // A supernode across the boundary: its trailing columns'
                // rows of the diagonal block.
                matmul(
                    MatMut::from_column_major_slice_mut(&mut rest[..w - k], w - k, 1),
                    Accum::Add,
                    top.submatrix(k, 0, w - k, k),
                    xa.rb(),
                    -1.0,
                    Par::Seq,
                );
            }
            tmp.clear();
            tmp.resize(q, 0.0);
            matmul(
                MatMut::from_column_major_slice_mut(&mut tmp, q, 1),
                Accum::Replace,
                bottom.subcols(0, k),
                xa.rb(),
                1.0,
                Par::Seq,
            );
            for (&r, &v) in node.pattern.iter().zip(&tmp) {
                x[r] -= v;
            }
        }
    }

    /// The supernodes whose columns a back substitution needs to give the
    /// unknowns at the interior positions `at`: theirs and every
    /// ancestor's (a column's solution reads the rows of its pattern, which
    /// lie in its ancestors). The rest of the interior is left unsolved by
    /// `backward` with this mask.
    pub fn needed(&self, at: impl Iterator<Item = usize>) -> Vec<bool> {
        let sym = self.symbolic;
        let nodes = self.nodes();
        let mut node_of = vec![0usize; self.b];
        for s in 0..nodes {
            let (start, end) = (sym.supernode_begin()[s], sym.supernode_end()[s]);
            for c in node_of.iter_mut().take(end).skip(start) {
                *c = s;
            }
        }
        let mut need = vec![false; nodes];
        for p in at.filter(|&p| p < self.b) {
            need[node_of[p]] = true;
        }
        // Parents follow their children in the supernodes' order.
        for s in 0..nodes {
            if !need[s] {
                continue;
            }
            let parent = (self.node(s).pattern.iter().min()).filter(|&&r| r < self.b);
            if let Some(&r) = parent {
                need[node_of[r]] = true;
            }
        }
        need
    }

    /// `D_I^-1` and the back substitution over the interior columns, in
    /// place on `x` in the factor's order: `x_I` holds `y_I` and `x_T` the
    /// trailing unknowns' solution; on return `x_I` is the interior's, or,
    /// with `need` (`needed`), that of the needed supernodes' columns.
    pub fn backward(&self, d_inv: &[f64], x: &mut [f64], need: Option<&[bool]>) {
        for (xi, di) in x.iter_mut().zip(d_inv) {
            *xi *= di;
        }
        let mut tmp = Vec::new();
        for s in (0..self.nodes()).rev() {
            let node = self.node(s);
            if node.start >= self.b {
                continue;
            }
            if need.is_some_and(|need| !need[s]) {
                let end = (node.start + node.width).min(self.b);
                x[node.start..end].fill(f64::NAN);
                continue;
            }
            let (w, at, q) = (node.width, node.start, node.pattern.len());
            let k = w.min(self.b - at);
            tmp.clear();
            tmp.extend(node.pattern.iter().map(|&r| x[r]));
            let block = MatRef::from_column_major_slice(node.values, node.rows(), w);
            let (top, bottom) = block.split_at_row(w);
            let (head, rest) = x[at..].split_at_mut(k);
            let mut xa = MatMut::from_column_major_slice_mut(head, k, 1);
            matmul(
                xa.rb_mut(),
                Accum::Add,
                bottom.subcols(0, k).transpose(),
                MatRef::from_column_major_slice(&tmp, q, 1),
                -1.0,
                Par::Seq,
            );
            if k < w {
                matmul(
                    xa.rb_mut(),
                    Accum::Add,
                    top.submatrix(k, 0, w - k, k).transpose(),
                    MatRef::from_column_major_slice(&rest[..w - k], w - k, 1),
                    -1.0,
                    Par::Seq,
                );
            }
            solve_unit_upper_triangular_in_place(
                top.submatrix(0, 0, k, k).transpose(),
                xa,
                Par::Seq,
            );
        }
    }
}
