//! Sparse LDU without pivoting, for the unsymmetric bordered systems of
//! small and mid-size scenes (`Augmented`, issue 14).
//!
//! The system is permuted symmetrically, `M = P A P^T`, in the fill-reducing
//! order of its displacement block with every multiplier placed right after
//! the last displacement unknown its row or column touches: its pivot is
//! then the Schur complement `-c^T S^-1 c` of the unknowns it constrains,
//! not its zero diagonal. `M = L D U` is factored up-looking on the pattern
//! of `M + M^T` (row `k` of `L` and column `k` of `U` from the rows and
//! columns before it), whose structure the elimination tree gives once per
//! pattern: the numeric factorization does no search, no pivoting and no
//! allocation. faer's LU with partial pivoting took 176 us on the capstan
//! FMU's 772-unknown systems, this 40-55 us with the same fill (nnz(L)
//! 4,983) and backward errors of 1e-19 (docs/contact.md section 8).
//!
//! Without pivoting a factorization may meet a tiny pivot (a body held by
//! contact alone, a tangent past a limit point): the caller checks every
//! solve as it checks the unpivoted LDLT (`LDLT_BACKWARD_ERROR`,
//! `LDLT_REFINEMENT`) and factors by LU with pivoting when it fails.
//!
//! An inner solve on an LDU's pattern is factored again, not bordered on
//! the kept factor (`Augmented::try_ldu` gives the measurements).

use faer::sparse::SymbolicSparseColMatRef;

/// The structure of one pattern's factor.
pub(super) struct Symbolic {
    /// `perm[k]`: the unknown of `A` at position `k` of `M`.
    perm: Vec<usize>,
    /// Per column `k` of `M`: the entries of `A` at `M(i, k)`, `i <= k`
    /// (row, index into `A`'s values), then per row `k` those at
    /// `M(k, j)`, `j < k`.
    upper_ptr: Vec<usize>,
    upper: Vec<(usize, usize)>,
    lower_ptr: Vec<usize>,
    lower: Vec<(usize, usize)>,
    /// Per `k`: the columns `j < k` where row `k` of `L` (and column `k`
    /// of `U`) has entries, ascending (a topological order: the elimination
    /// tree's parents follow their children).
    reach_ptr: Vec<usize>,
    reach: Vec<usize>,
    /// Where each of those entries sits in the factor's column storage.
    slot: Vec<usize>,
    /// Column `j` of `L` (rows `> j`) and row `j` of `U` (columns `> j`)
    /// share their indices: `col_ptr`, `row`.
    col_ptr: Vec<usize>,
    row: Vec<usize>,
}

/// The numeric factor: `L` (unit lower) and `U` (unit upper) in the
/// shared column storage, `D` the pivots.
#[derive(Default)]
pub(super) struct Numeric {
    l: Vec<f64>,
    u: Vec<f64>,
    d: Vec<f64>,
    /// The factorization's work: a column of `U` and a row of `L` (`factor`).
    xy: Vec<[f64; 2]>,
    /// The solves' work array, kept.
    work: std::cell::RefCell<Vec<f64>>,
}

/// Multiply-adds of the numeric factorization per entry of `L` (column
/// counts `counts`, diagonal excluded): the measure by which faer chooses a
/// supernodal factorization (above 40), where dense kernels beat this
/// one's scalar loops.
fn flops_per_entry(counts: &[usize]) -> f64 {
    let (mut flops, mut nnz) = (0.0f64, 0.0f64);
    for &c in counts {
        let c = c as f64 + 1.0;
        flops += c * c;
        nnz += c;
    }
    flops / nnz.max(1.0)
}

/// The order of `M` (`perm[k]`: the unknown of `a` at position `k`): the
/// displacements in the order `disp`, each multiplier right after the
/// last displacement it touches (one touching none: at the end).
fn multipliers_placed(
    a: SymbolicSparseColMatRef<'_, usize>,
    n_disp: usize,
    disp: &[usize],
) -> Vec<usize> {
    let n = a.nrows();
    let mut pos_of = vec![0usize; n_disp];
    for (p, &d) in disp.iter().enumerate() {
        pos_of[d] = p;
    }
    let mut last = vec![usize::MAX; n - n_disp];
    for j in 0..n {
        for &i in a.row_idx_of_col_raw(j) {
            let (m, d) = match (i >= n_disp, j >= n_disp) {
                (true, false) => (i, j),
                (false, true) => (j, i),
                _ => continue,
            };
            let l = &mut last[m - n_disp];
            if *l == usize::MAX || pos_of[d] > *l {
                *l = pos_of[d];
            }
        }
    }
    // Position of each unknown in M: a displacement at its place in
    // `disp` plus the multipliers placed before it.
    let mut before = vec![0usize; n_disp + 1];
    for &l in last.iter().filter(|&&l| l != usize::MAX) {
        before[l + 1] += 1;
    }
    for p in 0..n_disp {
        before[p + 1] += before[p];
    }
    let mut perm = vec![0usize; n];
    let mut next: Vec<usize> = (0..=n_disp).map(|p| p + before[p]).collect();
    for (p, &d) in disp.iter().enumerate() {
        perm[p + before[p]] = d;
        next[p] += 1;
    }
    for (m, &l) in last.iter().enumerate() {
        let at = &mut next[if l == usize::MAX { n_disp } else { l }];
        perm[*at] = n_disp + m;
        *at += 1;
    }
    perm
}

/// `A`'s entries by `M`'s triangles (`Symbolic`'s fields of the same
/// names): per column `k` of `M` the entries at `M(i, k)`, `i <= k` (row,
/// index into `A`'s values), per row `k` those at `M(k, j)`, `j < k`.
struct Triangles {
    upper_ptr: Vec<usize>,
    upper: Vec<(usize, usize)>,
    lower_ptr: Vec<usize>,
    lower: Vec<(usize, usize)>,
}

impl Triangles {
    /// The triangles of `a` in the order whose inverse is `inv`.
    fn of(a: SymbolicSparseColMatRef<'_, usize>, inv: &[usize]) -> Self {
        let n = a.nrows();
        let (mut up_count, mut low_count) = (vec![0usize; n + 1], vec![0usize; n + 1]);
        for j in 0..n {
            for &i in a.row_idx_of_col_raw(j) {
                let (r, c) = (inv[i], inv[j]);
                if r <= c {
                    up_count[c + 1] += 1;
                } else {
                    low_count[r + 1] += 1;
                }
            }
        }
        for k in 0..n {
            up_count[k + 1] += up_count[k];
            low_count[k + 1] += low_count[k];
        }
        let (upper_ptr, lower_ptr) = (up_count.clone(), low_count.clone());
        let mut upper = vec![(0, 0); upper_ptr[n]];
        let mut lower = vec![(0, 0); lower_ptr[n]];
        let mut p = 0;
        for j in 0..n {
            for &i in a.row_idx_of_col_raw(j) {
                let (r, c) = (inv[i], inv[j]);
                if r <= c {
                    upper[up_count[c]] = (r, p);
                    up_count[c] += 1;
                } else {
                    lower[low_count[r]] = (c, p);
                    low_count[r] += 1;
                }
                p += 1;
            }
        }
        Triangles {
            upper_ptr,
            upper,
            lower_ptr,
            lower,
        }
    }

    /// The pattern of `M + M^T` above the diagonal in column `k`: the upper
    /// entries of column `k` and the lower ones of row `k` (a duplicate
    /// changes neither the tree nor the row patterns).
    fn above(&self, k: usize) -> impl Iterator<Item = usize> + '_ {
        let up = self.upper[self.upper_ptr[k]..self.upper_ptr[k + 1]].iter();
        let low = self.lower[self.lower_ptr[k]..self.lower_ptr[k + 1]].iter();
        (up.map(|e| e.0).filter(move |&i| i < k)).chain(low.map(|e| e.0))
    }
}

/// The elimination tree of `M + M^T` (`parent`, `usize::MAX` at a root;
/// path compression through `ancestor`).
fn elimination_tree(t: &Triangles, n: usize) -> Vec<usize> {
    let none = usize::MAX;
    let mut parent = vec![none; n];
    let mut ancestor = vec![none; n];
    for k in 0..n {
        for i0 in t.above(k) {
            let mut i = i0;
            while i != none && i < k {
                let next = ancestor[i];
                ancestor[i] = k;
                if next == none {
                    parent[i] = k;
                }
                i = next;
            }
        }
    }
    parent
}

/// Visits, row by row, the entries of row `k` of `L`: the tree paths from
/// each entry of row `k` of `M + M^T` up to `k`, each column `i` once
/// (`visit(k, i)`).
fn paths_to_rows(t: &Triangles, parent: &[usize], mut visit: impl FnMut(usize, usize)) {
    let n = parent.len();
    let mut mark = vec![usize::MAX; n];
    for k in 0..n {
        mark[k] = k;
        for i0 in t.above(k) {
            let mut i = i0;
            while mark[i] != k {
                mark[i] = k;
                visit(k, i);
                i = parent[i];
            }
        }
    }
}

/// The column storage of `L` (and of `U`'s rows) from its column counts
/// and row patterns: column pointers, row indices, and where each row
/// pattern's entry sits (`Symbolic::slot`).
fn columns_of_l(
    counts: &[usize],
    reach_ptr: &[usize],
    reach: &[usize],
) -> (Vec<usize>, Vec<usize>, Vec<usize>) {
    let n = counts.len();
    let mut col_ptr = vec![0usize; n + 1];
    for j in 0..n {
        col_ptr[j + 1] = col_ptr[j] + counts[j];
    }
    let mut fill = col_ptr.clone();
    let mut row = vec![0usize; col_ptr[n]];
    let mut slot = vec![0usize; reach.len()];
    for k in 0..n {
        for q in reach_ptr[k]..reach_ptr[k + 1] {
            let j = reach[q];
            row[fill[j]] = k;
            slot[q] = fill[j];
            fill[j] += 1;
        }
    }
    (col_ptr, row, slot)
}

impl Symbolic {
    /// The analysis of `a` (square, `n_disp` displacement unknowns first)
    /// in the displacement order `disp` (forward permutation of the
    /// `n_disp` block); None when its factor would take more than
    /// `max_flops_per_entry` multiply-adds per entry (`flops_per_entry`).
    pub(super) fn new(
        a: SymbolicSparseColMatRef<'_, usize>,
        n_disp: usize,
        disp: &[usize],
        max_flops_per_entry: f64,
    ) -> Option<Self> {
        let n = a.nrows();
        let perm = multipliers_placed(a, n_disp, disp);
        let mut inv = vec![0usize; n];
        for (k, &j) in perm.iter().enumerate() {
            inv[j] = k;
        }
        let t = Triangles::of(a, &inv);
        let parent = elimination_tree(&t, n);
        // Row k of L: the tree paths from each entry of row k up to k.
        // Counted first, nothing stored: a pattern too dense for these
        // scalar loops is left before its structure is built.
        let mut counts = vec![0usize; n];
        paths_to_rows(&t, &parent, |_, i| counts[i] += 1);
        if flops_per_entry(&counts) > max_flops_per_entry {
            return None;
        }
        // Then stored, row by row (in `k`'s order), each row ascending.
        let mut reach_ptr = vec![0; n + 1];
        let mut reach = Vec::with_capacity(counts.iter().sum());
        paths_to_rows(&t, &parent, |k, i| {
            reach.push(i);
            reach_ptr[k + 1] += 1;
        });
        for k in 0..n {
            reach_ptr[k + 1] += reach_ptr[k];
            reach[reach_ptr[k]..reach_ptr[k + 1]].sort_unstable();
        }
        let (col_ptr, row, slot) = columns_of_l(&counts, &reach_ptr, &reach);
        let Triangles {
            upper_ptr,
            upper,
            lower_ptr,
            lower,
        } = t;
        Some(Symbolic {
            perm,
            upper_ptr,
            upper,
            lower_ptr,
            lower,
            reach_ptr,
            reach,
            slot,
            col_ptr,
            row,
        })
    }

    /// Factors `A` (its values in the analysed pattern's order) into `f`;
    /// false at a zero or non-finite pivot.
    pub(super) fn factor(&self, values: &[f64], f: &mut Numeric) -> bool {
        let n = self.perm.len();
        let nnz = self.row.len();
        f.l.resize(nnz, 0.0);
        f.u.resize(nnz, 0.0);
        f.d.resize(n, 0.0);
        // Column k of M above and on the diagonal (first) and row k before
        // the diagonal (second), side by side: each update reads and
        // writes one place.
        f.xy.clear();
        f.xy.resize(n, [0.0; 2]);
        let xy = &mut f.xy;
        for k in 0..n {
            for &(i, p) in &self.upper[self.upper_ptr[k]..self.upper_ptr[k + 1]] {
                xy[i][0] += values[p];
            }
            for &(j, p) in &self.lower[self.lower_ptr[k]..self.lower_ptr[k + 1]] {
                xy[j][1] += values[p];
            }
            let mut dk = xy[k][0];
            xy[k][0] = 0.0;
            for q in self.reach_ptr[k]..self.reach_ptr[k + 1] {
                let j = self.reach[q];
                // (D U)(j, k) and (L D)(k, j).
                let [uj, vj] = xy[j];
                xy[j] = [0.0; 2];
                let at = self.slot[q];
                for p in self.col_ptr[j]..at {
                    let e = &mut xy[self.row[p]];
                    e[0] -= f.l[p] * uj;
                    e[1] -= f.u[p] * vj;
                }
                let dj = f.d[j];
                let lj = vj / dj;
                dk -= lj * uj;
                f.l[at] = lj;
                f.u[at] = uj / dj;
            }
            if dk == 0.0 || !dk.is_finite() {
                return false;
            }
            f.d[k] = dk;
        }
        true
    }

    /// Solves `A x = b` in place.
    pub(super) fn solve(&self, f: &Numeric, b: &mut [f64]) {
        let n = self.perm.len();
        let mut work = f.work.borrow_mut();
        work.clear();
        work.extend(self.perm.iter().map(|&j| b[j]));
        let w = &mut work[..];
        // L z = w (unit lower, by columns), then D.
        for j in 0..n {
            let wj = w[j];
            if wj != 0.0 {
                for p in self.col_ptr[j]..self.col_ptr[j + 1] {
                    w[self.row[p]] -= f.l[p] * wj;
                }
            }
            w[j] = wj / f.d[j];
        }
        // U x = z (unit upper, by rows).
        for j in (0..n).rev() {
            let mut t = 0.0;
            for p in self.col_ptr[j]..self.col_ptr[j + 1] {
                t += f.u[p] * w[self.row[p]];
            }
            w[j] -= t;
        }
        for (k, &j) in self.perm.iter().enumerate() {
            b[j] = w[k];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::SymbolicSparseColMat;
    use nalgebra::{DMatrix, DVector};

    /// A chain of `m` springs (an unsymmetric coupling beside each) with a
    /// multiplier on dofs 0 and `m - 1`, and an empty slot (an identity
    /// row, placed last): the LDU's solve of each of three right-hand
    /// sides is the dense LU's.
    #[test]
    fn solves_as_a_dense_lu() {
        let m = 12;
        let n = m + 2;
        let mut a = DMatrix::<f64>::zeros(n, n);
        for i in 0..m {
            a[(i, i)] = 4.0 + 0.1 * i as f64;
            if i + 1 < m {
                a[(i, i + 1)] = -1.0;
                a[(i + 1, i)] = -1.3;
            }
        }
        for (d, c) in [(0, 1.0), (m - 1, -0.5)] {
            a[(m, d)] = c;
            a[(d, m)] = c + 0.2;
        }
        a[(m + 1, m + 1)] = 1.0;
        let (mut col_ptr, mut row_idx, mut values) = (vec![0], Vec::new(), Vec::new());
        for j in 0..n {
            for i in 0..n {
                if a[(i, j)] != 0.0 {
                    row_idx.push(i);
                    values.push(a[(i, j)]);
                }
            }
            col_ptr.push(row_idx.len());
        }
        let pattern = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        // A displacement order that is not the identity.
        let disp: Vec<usize> = (0..m).rev().collect();
        let s = Symbolic::new(pattern.as_ref(), m, &disp, 40.0).unwrap();
        // A limit below this chain's factor's density leaves it.
        assert!(Symbolic::new(pattern.as_ref(), m, &disp, 1.0).is_none());
        let mut f = Numeric::default();
        assert!(s.factor(&values, &mut f));
        let cols = 3;
        let b: Vec<f64> = (0..n * cols)
            .map(|i| ((i * 37) % 11) as f64 - 5.0)
            .collect();
        let lu = a.clone().lu();
        for c in 0..cols {
            let want = lu
                .solve(&DVector::from_column_slice(&b[c * n..(c + 1) * n]))
                .unwrap();
            let mut one = b[c * n..(c + 1) * n].to_vec();
            s.solve(&f, &mut one);
            for i in 0..n {
                assert!((one[i] - want[i]).abs() < 1e-12 * want.amax(), "{c} {i}");
            }
        }
        // A zero pivot (the first displacement eliminated has a zero
        // diagonal and nothing before it): refused.
        let mut zero = values.clone();
        let first = disp[0];
        let q = (pattern.col_ptr()[first]..pattern.col_ptr()[first + 1])
            .find(|&q| pattern.row_idx()[q] == first)
            .unwrap();
        zero[q] = 0.0;
        assert!(!s.factor(&zero, &mut f));
    }
}
