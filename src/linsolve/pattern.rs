//! The bordered matrix of Eq. (18) as faer stores it: the tangent's
//! pattern merged with the contact entries beside it, their values summed
//! in column order, and the symmetry checks that choose LDLT or LU.

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

/// The values of the matrix `bordered` builds from the tangent `k` over
/// `pattern` and the entries `extra`, written over the pattern `a` of an
/// analysis without building one: true when that matrix has the pattern
/// `a` and its values are then `bordered`'s bit for bit. That takes every
/// stored entry to be the sum of at most two terms (a tangent entry and an
/// entry beside it, or two entries beside it), whose sum is the same in
/// either order; at three terms `bordered` sums in its sort's order, which
/// the round-off of a sensitive scene follows (the buried pipe: 2.5e-3 of
/// its largest output), and this leaves them to it. False, `values` and
/// `terms` then spoilt, otherwise. The capstan's systems have 9,000
/// tangent entries and 500-860 beside them: merging every column, as
/// `bordered` does after its sorts, took 7.9 ms of the CLI's 101 ms run of
/// 40 drawn steps; copying the columns that begin with the tangent's rows,
/// 3.1 ms.
pub(super) fn values_in_pattern(
    a: SymbolicSparseColMatRef<'_, usize>,
    pattern: &Pattern,
    k: &[f64],
    extra: &[(usize, usize, f64)],
    values: &mut Vec<f64>,
    terms: &mut Vec<u8>,
) -> bool {
    let (col_ptr, row_idx) = (a.col_ptr(), a.row_idx());
    let n = a.ncols();
    let nnz = row_idx.len();
    if pattern.n > n {
        return false;
    }
    // Every entry is written before it is read (`covered`).
    values.resize(nnz, 0.0);
    terms.clear();
    terms.resize(nnz, 0);
    let mut covered = 0;
    // The tangent's columns into the pattern's (both sorted): a column
    // whose rows begin with the tangent's (the contact rows below them, or
    // none) is copied, any other merged.
    for c in 0..pattern.n {
        let (mut q, end) = (col_ptr[c], col_ptr[c + 1]);
        let (p0, p1) = (pattern.col_ptr[c], pattern.col_ptr[c + 1]);
        let len = p1 - p0;
        if q + len <= end && row_idx[q..q + len] == pattern.row_idx[p0..p1] {
            values[q..q + len].copy_from_slice(&k[p0..p1]);
            terms[q..q + len].fill(1);
            covered += len;
            continue;
        }
        for p in p0..p1 {
            let r = pattern.row_idx[p];
            while q < end && row_idx[q] < r {
                q += 1;
            }
            if q == end || row_idx[q] != r {
                return false;
            }
            values[q] = k[p];
            terms[q] = 1;
            covered += 1;
        }
    }
    for &(r, c, v) in extra {
        if c >= n {
            return false;
        }
        let column = &row_idx[col_ptr[c]..col_ptr[c + 1]];
        let Ok(at) = column.binary_search(&r) else {
            return false;
        };
        let q = col_ptr[c] + at;
        match terms[q] {
            0 => {
                values[q] = v;
                covered += 1;
            }
            1 => values[q] += v,
            _ => return false,
        }
        terms[q] += 1;
    }
    covered == nnz
}

/// The values of a system (pattern `col_ptr`, `row_idx`; values in
/// `values`) rewritten over the pattern `a`, zero at `a`'s other entries:
/// false, `values` unchanged, when `a` does not hold every entry of it.
pub(super) fn scatter_into(
    a: SymbolicSparseColMatRef<'_, usize>,
    col_ptr: &[usize],
    row_idx: &[usize],
    values: &mut Vec<f64>,
) -> bool {
    let (a_ptr, a_rows) = (a.col_ptr(), a.row_idx());
    let mut out = vec![0.0; a_rows.len()];
    for c in 0..a.ncols() {
        let mut q = a_ptr[c];
        for p in col_ptr[c]..col_ptr[c + 1] {
            while q < a_ptr[c + 1] && a_rows[q] < row_idx[p] {
                q += 1;
            }
            if q == a_ptr[c + 1] || a_rows[q] != row_idx[p] {
                return false;
            }
            out[q] = values[p];
        }
    }
    *values = out;
    true
}

/// The pattern `col_ptr`, `row_idx` (values `values`) with `a`'s entries
/// added as zeros, when `a` has at most `limit` entries it lacks (so that
/// a kept pattern does not grow without end: past the limit, the system's
/// own). Both are of the same order.
pub(super) fn merge_pattern(
    a: SymbolicSparseColMatRef<'_, usize>,
    [col_ptr, row_idx]: [&mut Vec<usize>; 2],
    values: &mut Vec<f64>,
    limit: usize,
) {
    let (a_ptr, a_rows) = (a.col_ptr(), a.row_idx());
    let n = a.ncols();
    let mut missing = 0;
    for c in 0..n {
        let rows = &row_idx[col_ptr[c]..col_ptr[c + 1]];
        missing += (a_ptr[c]..a_ptr[c + 1])
            .filter(|&q| rows.binary_search(&a_rows[q]).is_err())
            .count();
        if missing > limit {
            return;
        }
    }
    if missing == 0 {
        return;
    }
    let (mut ptr, mut rows, mut vals) = (
        Vec::with_capacity(n + 1),
        Vec::with_capacity(row_idx.len() + missing),
        Vec::with_capacity(row_idx.len() + missing),
    );
    ptr.push(0);
    for c in 0..n {
        let (mut p, p_end) = (col_ptr[c], col_ptr[c + 1]);
        let (mut q, q_end) = (a_ptr[c], a_ptr[c + 1]);
        while p < p_end || q < q_end {
            let (rp, rq) = (
                row_idx.get(p).filter(|_| p < p_end),
                a_rows.get(q).filter(|_| q < q_end),
            );
            match (rp, rq) {
                (Some(&r), Some(&s)) if r == s => {
                    rows.push(r);
                    vals.push(values[p]);
                    (p, q) = (p + 1, q + 1);
                }
                (Some(&r), Some(&s)) if s < r => {
                    rows.push(s);
                    vals.push(0.0);
                    q += 1;
                }
                (Some(&r), _) => {
                    rows.push(r);
                    vals.push(values[p]);
                    p += 1;
                }
                (None, Some(&s)) => {
                    rows.push(s);
                    vals.push(0.0);
                    q += 1;
                }
                (None, None) => unreachable!("the loop's condition"),
            }
        }
        ptr.push(rows.len());
    }
    (*col_ptr, *row_idx, *values) = (ptr, rows, vals);
}

/// Sorts entries (row, column, value) by column, then row, as
/// `sort_unstable_by_key` does: by counting the columns where the entries
/// are many beside the largest column and no place holds two (then the
/// order is the one order; an inner solve of the capstan FMU sorts its
/// 500-860 entries over some 700 columns, 12 us by comparisons), else by
/// comparisons (two entries at one place are summed in the order that
/// sort leaves them, which the factored systems' round-off has: another
/// order moved the buried pipe's soil reaction by 2.5e-3 of the scene's
/// largest output).
pub(super) fn sort_by_column(extra: &mut [(usize, usize, f64)]) {
    let columns = extra.iter().map(|e| e.1 + 1).max().unwrap_or(0);
    if columns > 8 * extra.len() {
        extra.sort_unstable_by_key(|&(r, c, _)| (c, r));
        return;
    }
    let mut start = vec![0usize; columns + 1];
    for e in extra.iter() {
        start[e.1 + 1] += 1;
    }
    for c in 0..columns {
        start[c + 1] += start[c];
    }
    let mut next = start.clone();
    let mut sorted = vec![(0usize, 0usize, 0.0f64); extra.len()];
    for &e in extra.iter() {
        sorted[next[e.1]] = e;
        next[e.1] += 1;
    }
    for c in 0..columns {
        sorted[start[c]..start[c + 1]].sort_unstable_by_key(|e| e.0);
    }
    if sorted
        .windows(2)
        .any(|w| (w[0].0, w[0].1) == (w[1].0, w[1].1))
    {
        extra.sort_unstable_by_key(|&(r, c, _)| (c, r));
    } else {
        extra.copy_from_slice(&sorted);
    }
}

/// The CSC form (both triangles, rows sorted) of the order-`n` matrix made
/// of the tangent `k` over `pattern` (its first `pattern.n` unknowns) plus
/// the entries `extra` (row, col, value; sorted here, duplicates summed).
pub(super) fn bordered(
    pattern: &Pattern,
    k: &[f64],
    extra: &mut [(usize, usize, f64)],
    n: usize,
    [col_ptr, row_idx]: [&mut Vec<usize>; 2],
    values: &mut Vec<f64>,
) {
    sort_by_column(extra);
    col_ptr.clear();
    row_idx.clear();
    values.clear();
    let nnz = pattern.col_ptr.get(pattern.n).copied().unwrap_or(0) + extra.len();
    col_ptr.reserve(n + 1);
    row_idx.reserve(nnz);
    values.reserve(nnz);
    col_ptr.push(0);
    let mut e = 0;
    let mut column: Vec<(usize, f64)> = Vec::new();
    for c in 0..n {
        let tangent = if c < pattern.n {
            pattern.col_ptr[c]..pattern.col_ptr[c + 1]
        } else {
            0..0
        };
        let start = e;
        while e < extra.len() && extra[e].1 == c {
            e += 1;
        }
        if e == start {
            // The tangent's column as it is (its rows sorted, no duplicates).
            row_idx.extend_from_slice(&pattern.row_idx[tangent.clone()]);
            values.extend_from_slice(&k[tangent]);
            col_ptr.push(row_idx.len());
            continue;
        }
        column.clear();
        column.extend(tangent.map(|p| (pattern.row_idx[p], k[p])));
        column.extend(extra[start..e].iter().map(|&(r, _, v)| (r, v)));
        column.sort_unstable_by_key(|&(r, _)| r);
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
}

/// `bordered` into new arrays: `(col_ptr, row_idx, values)`.
pub(super) fn bordered_new(
    pattern: &Pattern,
    k: &[f64],
    extra: &mut [(usize, usize, f64)],
    n: usize,
) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
    let (mut col_ptr, mut row_idx, mut values) = (Vec::new(), Vec::new(), Vec::new());
    bordered(
        pattern,
        k,
        extra,
        n,
        [&mut col_ptr, &mut row_idx],
        &mut values,
    );
    (col_ptr, row_idx, values)
}

/// A matrix is symmetric when `|a_ij - a_ji| <= SYMMETRY max|a|`.
pub(super) const SYMMETRY: f64 = 1e-12;

/// The largest `|e_ij - e_ji|` of the entries `extra` (duplicates summed;
/// an entry whose transpose is not among them is compared with zero).
pub(super) fn asymmetry(extra: &[(usize, usize, f64)]) -> f64 {
    let e = summed(extra.to_vec());
    e.iter()
        .map(|&(r, c, v)| {
            // `summed` orders by (column, row): the transpose (c, r) is
            // found by the key (r, c).
            let t = e
                .binary_search_by_key(&(r, c), |&(r2, c2, _)| (c2, r2))
                .map_or(0.0, |q| e[q].2);
            (v - t).abs()
        })
        .fold(0.0f64, f64::max)
}

/// `|a_ij - a_ji| <= SYMMETRY max|a|` for every stored entry (an entry
/// whose transpose is not stored is compared with zero); columns sorted by
/// row.
pub(super) fn is_symmetric(col_ptr: &[usize], row_idx: &[usize], values: &[f64]) -> bool {
    let max = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if !max.is_finite() {
        return false;
    }
    let tol = SYMMETRY * max;
    let n = col_ptr.len().saturating_sub(1);
    // Each entry's transpose, found by a cursor per column: the columns
    // are swept in order, and the transpose of an entry of column j is
    // row j of another column, so the rows asked of each column come in
    // order too (one pass, no search).
    let mut next: Vec<usize> = col_ptr[..n].to_vec();
    for j in 0..n {
        for p in col_ptr[j]..col_ptr[j + 1] {
            let i = row_idx[p];
            if i == j {
                continue;
            }
            let at = &mut next[i];
            let end = col_ptr[i + 1];
            while *at < end && row_idx[*at] < j {
                *at += 1;
            }
            let transpose = if *at < end && row_idx[*at] == j {
                values[*at]
            } else {
                0.0
            };
            if (values[p] - transpose).abs() > tol {
                return false;
            }
        }
    }
    true
}
