//! Solves on the trailing block of an LDLT factor (issue 14): the factor
//! seen with its trailing set (`Factor`), the dense solves of its Schur
//! complement (`Dense`), partial solves and their completion
//! (`watched`, `complete_trailing`).
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

use super::{LDLT_BACKWARD_ERROR, LDLT_REFINEMENT};
use crate::assembly::Pattern;
use faer::linalg::matmul::matmul;
use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::linalg::triangular_solve::{
    solve_unit_lower_triangular_in_place, solve_unit_upper_triangular_in_place,
};
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use faer::sparse::linalg::cholesky::{SymbolicCholesky, SymbolicCholeskyRaw};
use faer::{Accum, Mat, MatMut, MatRef, Par};
use std::sync::Arc;

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

/// The forward substitution of `b` (the factor's order) over the factor
/// `f`, the trailing positions left reduced. The inner solves of an
/// iteration change the right-hand side on the contact dofs only: the
/// forward substitution of the last one (`last`: its permuted right-hand
/// side and result) serves, its trailing part shifted by the change there.
pub(super) fn forward_substituted(
    f: &Factor,
    b: &[f64],
    last: &mut Option<(Vec<f64>, Vec<f64>)>,
) -> Vec<f64> {
    let order = b.len();
    let mut y: Vec<f64> = f.fwd.iter().map(|&i| b[i]).collect();
    match last {
        Some((b_last, y_last)) if b_last[..f.b] == y[..f.b] => {
            for p in f.b..order {
                let shifted = y_last[p] + (y[p] - b_last[p]);
                b_last[p] = y[p];
                y[p] = shifted;
            }
            y[..f.b].copy_from_slice(&y_last[..f.b]);
            y_last[f.b..].copy_from_slice(&y[f.b..]);
        }
        _ => {
            let b_perm = y.clone();
            f.forward(&mut y);
            *last = Some((b_perm, y.clone()));
        }
    }
    y
}

/// A partial trailing solve (`Augmented::solve_watching`): the trailing
/// unknowns and the `watch`ed ones (with the supernodes above them) of the
/// solve `p` back-substituted into `rhs` (the caller's order), the rest of
/// the interior NaN until `Augmented::finish`. False when any of them is
/// not finite.
pub(super) fn watched(
    f: &Factor,
    d_inv: &[f64],
    p: &Pending,
    watch: &[usize],
    n_disp: usize,
    rhs: &mut [f64],
) -> bool {
    let need = f.needed(watch.iter().filter(|&&i| i < n_disp).map(|&i| f.inv[i]));
    let mut x = p.y.clone();
    f.backward(d_inv, &mut x, Some(&need));
    let known = |i: usize| x[f.inv[i]];
    if !(x[f.b..].iter().all(|v| v.is_finite())
        && watch.iter().all(|&i| i >= n_disp || known(i).is_finite()))
    {
        return false;
    }
    for (i, out) in rhs[..n_disp].iter_mut().enumerate() {
        *out = known(i);
    }
    for (m, &s) in p.slot_of.iter().enumerate() {
        rhs[n_disp + m] = known(n_disp + s);
    }
    true
}

/// A trailing solve whose interior back substitution, refinement and
/// check wait for `Augmented::finish`: its dense solver of `S0 + Delta`,
/// the factor-order vector with the interior forward-substituted and the
/// trailing unknowns solved, the right-hand side (slots' order), the
/// entries beside the tangent (`summed`, slots' order), the slot of each
/// multiplier and `|A1|_inf`.
pub(super) struct Pending {
    pub(super) dense: Dense,
    pub(super) y: Vec<f64>,
    pub(super) b: Vec<f64>,
    pub(super) extra1: Vec<(usize, usize, f64)>,
    pub(super) slot_of: Vec<usize>,
    pub(super) norm_a: f64,
}

/// The dense solver of a trailing solve's `S1 = S0 + Delta` (trailing
/// positions): an LU of its own, or the LU of a block it differs from in
/// few columns (a base: `S0`, or the last block that took an LU of its
/// own, `DenseBases`) updated by the low-rank formula: with `B` the base,
/// `C` the columns `S1 - B` touches, `S1 = B + U V^T` (`U` those columns of
/// `S1 - B`, `V` the unit columns at `C`), so `S1^-1 b = y - W (I +
/// W_C)^-1 y_C` with `y = B^-1 b`, `W = B^-1 U` and `W_C` its rows at `C`.
/// The inner solves of an iteration change a few nodes' rows at a time:
/// the first may take an LU of its own, the next update it.
pub(super) enum Dense {
    /// `S1` is a base (its own LU, or an unchanged one).
    Lu(Arc<PartialPivLu<f64>>),
    Updated(Box<Update>),
}

/// The low-rank update of a base's LU (`Dense`).
pub(super) struct Update {
    pub(super) base: Arc<PartialPivLu<f64>>,
    pub(super) w: Mat<f64>,
    pub(super) columns: Vec<usize>,
    pub(super) capacitance: PartialPivLu<f64>,
}

/// A change of `S0` (sorted by column, then row; summed; no zeros).
type Change = Vec<(usize, usize, f64)>;

/// The bases of the dense solves on a kept factor (`Dense`): the LU of
/// `S0`, made when first needed, and the last block that took an LU of its
/// own, with its `Delta` (sorted by column, then row; summed; no zeros).
#[derive(Default)]
pub(super) struct DenseBases {
    pub(super) s0: Option<Arc<PartialPivLu<f64>>>,
    pub(super) last: Option<(Change, Arc<PartialPivLu<f64>>)>,
}

/// The columns of a change, at most this fraction of the trailing set's,
/// take the low-rank update: it costs about `2 c t^2 + c^3` flops (c
/// columns of `W` and the capacitance), an LU `2 t^3 / 3`; measured on
/// Hertz at 1e5 unknowns (t = 545), the inner solves change 10 to 60
/// columns of `S0`.
const UPDATED_COLUMNS: usize = 4;

/// `a - b` of two changes (sorted by column, then row; no zeros).
pub(super) fn difference(
    a: &[(usize, usize, f64)],
    b: &[(usize, usize, f64)],
) -> Vec<(usize, usize, f64)> {
    let key = |e: &(usize, usize, f64)| (e.1, e.0);
    let (mut p, mut q) = (0, 0);
    let mut out = Vec::with_capacity(a.len() + b.len());
    while p < a.len() || q < b.len() {
        let (i, j, d) = match (a.get(p), b.get(q)) {
            (Some(x), Some(y)) if key(x) == key(y) => {
                p += 1;
                q += 1;
                (x.0, x.1, x.2 - y.2)
            }
            (Some(x), Some(y)) if key(x) < key(y) => {
                p += 1;
                *x
            }
            (Some(x), None) => {
                p += 1;
                *x
            }
            (_, Some(y)) => {
                q += 1;
                (y.0, y.1, -y.2)
            }
            (None, None) => break,
        };
        if d != 0.0 {
            out.push((i, j, d));
        }
    }
    out
}

/// The columns a change touches, ascending.
fn columns_of(delta: &[(usize, usize, f64)]) -> Vec<usize> {
    let mut columns: Vec<usize> = delta.iter().map(|e| e.1).collect();
    columns.dedup();
    columns
}

impl Dense {
    /// The solver of `S0 + delta` (trailing positions, duplicates summed)
    /// from the bases (made or replaced here as needed).
    pub(super) fn new(
        s0: &Mat<f64>,
        bases: &mut DenseBases,
        delta: &[(usize, usize, f64)],
        t: usize,
    ) -> Self {
        let delta = difference(&summed(delta.to_vec()), &[]);
        let from_s0 = columns_of(&delta);
        let from_last = (bases.last.as_ref()).map(|(d, _)| difference(&delta, d));
        let (change, base) = match from_last {
            Some(change) if columns_of(&change).len() < from_s0.len() => {
                let lu = bases.last.as_ref().map(|(_, lu)| lu.clone());
                (change, lu.expect("a last base"))
            }
            _ if from_s0.len() * UPDATED_COLUMNS > t => {
                let mut s1 = s0.clone();
                for &(i, j, d) in &delta {
                    s1[(i, j)] += d;
                }
                let lu = Arc::new(s1.partial_piv_lu());
                bases.last = Some((delta, lu.clone()));
                return Dense::Lu(lu);
            }
            _ => {
                let lu = bases
                    .s0
                    .get_or_insert_with(|| Arc::new(s0.partial_piv_lu()));
                (delta.clone(), lu.clone())
            }
        };
        let columns = columns_of(&change);
        let c = columns.len();
        if c == 0 {
            return Dense::Lu(base);
        }
        if c * UPDATED_COLUMNS > t {
            // Too far from the last base as well: an LU of its own.
            bases.last = None;
            return Dense::new(s0, bases, &delta, t);
        }
        let mut w = Mat::<f64>::zeros(t, c);
        for &(i, j, d) in &change {
            let q = columns.binary_search(&j).expect("a column of the change");
            w[(i, q)] += d;
        }
        base.solve_in_place(w.as_mut());
        let capacitance = Mat::from_fn(c, c, |i, j| {
            w[(columns[i], j)] + if i == j { 1.0 } else { 0.0 }
        });
        Dense::Updated(Box::new(Update {
            base,
            capacitance: capacitance.partial_piv_lu(),
            w,
            columns,
        }))
    }

    /// `y` (the trailing positions' right-hand side) becomes `S1^-1 y`.
    pub(super) fn solve(&self, y: &mut [f64]) {
        let t = y.len();
        match self {
            Dense::Lu(lu) => lu.solve_in_place(MatMut::from_column_major_slice_mut(y, t, 1)),
            Dense::Updated(u) => {
                let Update {
                    base,
                    w,
                    columns,
                    capacitance,
                } = &**u;
                base.solve_in_place(MatMut::from_column_major_slice_mut(y, t, 1));
                let mut z: Vec<f64> = columns.iter().map(|&j| y[j]).collect();
                let c = z.len();
                capacitance.solve_in_place(MatMut::from_column_major_slice_mut(&mut z, c, 1));
                faer::linalg::matmul::matmul(
                    MatMut::from_column_major_slice_mut(y, t, 1),
                    faer::Accum::Add,
                    w.as_ref(),
                    faer::MatRef::from_column_major_slice(&z, c, 1),
                    -1.0,
                    Par::Seq,
                );
            }
        }
    }
}

/// The back substitution of a trailing solve (`Pending`), one step of
/// refinement against the system, and its normwise backward error checked
/// against the factored solves' (`LDLT_BACKWARD_ERROR`); the solution into
/// `rhs` (the caller's order), the refinement step relative to it into
/// `correction`.
#[allow(clippy::too_many_arguments)]
pub(super) fn complete_trailing(
    f: &Factor,
    d_inv: &[f64],
    p: &Pending,
    pattern: &Pattern,
    k: &[f64],
    rhs: &mut [f64],
    correction: &mut f64,
) -> bool {
    let n_disp = pattern.n;
    // `b - A1 x`, from the tangent and the entries.
    let residual = |x: &[f64], b: &[f64]| {
        let mut r = b.to_vec();
        for (j, &xj) in x.iter().enumerate().take(pattern.n) {
            for q in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
                r[pattern.row_idx[q]] -= k[q] * xj;
            }
        }
        for &(i, j, v) in &p.extra1 {
            r[i] -= v * x[j];
        }
        r
    };
    // `x` (the factor's order) from its trailing solve, back-substituted.
    let finish = |x: &mut Vec<f64>| -> Option<Vec<f64>> {
        f.backward(d_inv, x, None);
        let mut out = vec![0.0; x.len()];
        for (q, &i) in f.fwd.iter().enumerate() {
            out[i] = x[q];
        }
        x.iter().all(|v| v.is_finite()).then_some(out)
    };
    let mut y = p.y.clone();
    let Some(mut x) = finish(&mut y) else {
        return false;
    };
    // One step of refinement (more gain nothing: measured on Hertz at
    // 1e5 unknowns, the residual is at its round-off after one).
    let r = residual(&x, &p.b);
    let mut y: Vec<f64> = f.fwd.iter().map(|&i| r[i]).collect();
    f.forward(&mut y);
    p.dense.solve(&mut y[f.b..]);
    let Some(dx) = finish(&mut y) else {
        return false;
    };
    for (xi, di) in x.iter_mut().zip(&dx) {
        *xi += di;
    }
    let inf = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    *correction = inf(&dx) / inf(&x);
    // A factor unsound along a near-null direction of the tangent shows in
    // the refinement step, as for the factored LDLT solves
    // (`LDLT_REFINEMENT`); the tangent's own factor with every slot empty
    // (an unsymmetric system's) is checked here alone.
    if inf(&dx[..n_disp]) > LDLT_REFINEMENT * inf(&x[..n_disp]) {
        return false;
    }
    let backward = backward_error(&residual(&x, &p.b), p.norm_a, &x, &p.b);
    // (NaN fails too.)
    if backward.is_nan() || backward > LDLT_BACKWARD_ERROR {
        return false;
    }
    rhs[..n_disp].copy_from_slice(&x[..n_disp]);
    for (m, &s) in p.slot_of.iter().enumerate() {
        rhs[n_disp + m] = x[n_disp + s];
    }
    true
}

/// The normwise backward error of `x` from its residual `r = b - A x`:
/// `|r|_inf / (|A|_inf |x|_inf + |b|_inf)`.
fn backward_error(r: &[f64], norm_a: f64, x: &[f64], b: &[f64]) -> f64 {
    let inf = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    inf(r) / (norm_a * inf(x) + inf(b))
}

/// What the solves on the trailing block keep of the factored system (set
/// by `factor_and_solve`): the caller's count of its tangent then, the row
/// sums of the tangent's magnitudes (made by the first solve), its entries beside the tangent in
/// the slots (`summed`), and the last forward substitution (the permuted
/// right-hand side and its result), which serves the next inner solve.
#[derive(Default)]
pub(super) struct TrailingWork {
    /// The caller's tangent count then (`Augmented::new_tangent`).
    pub(super) k0_tangent: Option<u64>,
    pub(super) k_rows: Vec<f64>,
    pub(super) extra0: Vec<(usize, usize, f64)>,
    pub(super) forward: Option<(Vec<f64>, Vec<f64>)>,
    /// The last solve's refinement step relative to its solution (round-off
    /// for a sound solve; the tests read it).
    pub(super) correction: f64,
    /// The last solve, left partial (`Augmented::solve_watching`).
    pub(super) pending: Option<Pending>,
    /// The dense LUs the trailing solves on the kept factor update
    /// (`Dense`).
    pub(super) bases: DenseBases,
}

/// The entries sorted by (column, row), duplicates summed.
pub(super) fn summed(mut e: Vec<(usize, usize, f64)>) -> Vec<(usize, usize, f64)> {
    e.sort_unstable_by_key(|&(r, c, _)| (c, r));
    let mut out: Vec<(usize, usize, f64)> = Vec::with_capacity(e.len());
    for (r, c, v) in e {
        match out.last_mut() {
            Some(last) if last.0 == r && last.1 == c => last.2 += v,
            _ => out.push((r, c, v)),
        }
    }
    out
}
