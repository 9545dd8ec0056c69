//! A bordered system solved with the factorization of another one that
//! differs from it in a few rows: the inner solves of a Newton iteration
//! (docs/contact.md section 8) change the contact rows of Eq. (18) while the
//! tangent stays, so each is the factored system `A0` of the iteration with
//! some multipliers released, some rows added and a few displacement entries
//! changed (a sliding gradient matrix, Eq. 24). With `E`, `F`, `D` describing
//! those changes, the system solved is
//!
//! ```text
//! [A0   E] [x0]   [b0]
//! [F^T  D] [y ] = [h ]
//! ```
//!
//! - a multiplier of `A0` that the new system lacks keeps its row with a
//!   slack `s` (`E = e_m`) and is held at zero (`F = e_m`, `D = 0`);
//! - a row the new system adds is a new multiplier `mu` with its column
//!   (`E`), its row (`F`), its diagonal (`D`: 1 for a row on prescribed dofs
//!   alone) and its right-hand side (`h`);
//! - a changed displacement row `i` of the tangent, `Delta_i`, is `z_i =
//!   Delta_i x` (`E = e_i`, `F = Delta_i^T`, `D = -1`).
//!
//! By the Schur complement `S = D - F^T A0^-1 E` (dense, one column of
//! `A0^-1 E` per change: the solves with the factor are the cost, and
//! they are kept for the next inner solve of the same iteration).

use nalgebra::{DMatrix, DVector};
use rustc_hash::FxHashMap as HashMap;

/// A square sparse matrix in CSC form (both triangles, rows sorted).
#[derive(Clone, Copy)]
pub(super) struct Csc<'a> {
    pub col_ptr: &'a [usize],
    pub row_idx: &'a [usize],
    pub values: &'a [f64],
}

impl Csc<'_> {
    fn n(&self) -> usize {
        self.col_ptr.len() - 1
    }

    fn column(&self, j: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let range = self.col_ptr[j]..self.col_ptr[j + 1];
        self.row_idx[range.clone()]
            .iter()
            .copied()
            .zip(self.values[range].iter().copied())
    }

    /// Column `j`'s rows below `nd` and their values.
    fn displacement_part(&self, j: usize, nd: usize) -> (&[usize], &[f64]) {
        let (p, q) = (self.col_ptr[j], self.col_ptr[j + 1]);
        let end = p + self.row_idx[p..q].partition_point(|&i| i < nd);
        (&self.row_idx[p..end], &self.values[p..end])
    }

    /// Entry `(i, j)` (0 outside the pattern).
    fn entry(&self, i: usize, j: usize) -> f64 {
        let (p, q) = (self.col_ptr[j], self.col_ptr[j + 1]);
        self.row_idx[p..q]
            .binary_search(&i)
            .map_or(0.0, |at| self.values[p + at])
    }

    /// `b - A x`.
    fn residual(&self, x: &[f64], b: &[f64]) -> Vec<f64> {
        let mut r = b.to_vec();
        for (j, &xj) in x.iter().enumerate() {
            for (i, v) in self.column(j) {
                r[i] -= v * xj;
            }
        }
        r
    }

    /// `|A|_inf`, the largest row sum of magnitudes.
    fn norm_inf(&self) -> f64 {
        inf(&row_magnitudes(*self))
    }
}

/// A matrix given as the tangent `k` (order `n_disp`, both triangles, rows
/// sorted) and the entries beside it `extra` (row, column, value; sorted
/// by column, then row; duplicates are summed), of order `n`: what the
/// inner solves hand over, read without building its CSC form (a copy of
/// the whole tangent per inner solve).
#[derive(Clone, Copy)]
pub(super) struct Split<'a> {
    pub k: Csc<'a>,
    pub extra: &'a [(usize, usize, f64)],
    pub n: usize,
}

impl Split<'_> {
    /// `b - A x`.
    fn residual(&self, x: &[f64], b: &[f64]) -> Vec<f64> {
        let mut r = b.to_vec();
        for (j, &xj) in x.iter().enumerate().take(self.k.n()) {
            for (i, v) in self.k.column(j) {
                r[i] -= v * xj;
            }
        }
        for &(i, j, v) in self.extra {
            r[i] -= v * x[j];
        }
        r
    }

    /// `|A|_inf` from the tangent's row sums of magnitudes `k_rows`
    /// (`row_magnitudes`): a row with an entry beside the tangent has it
    /// summed into the tangent's own entry there.
    fn norm_inf(&self, k_rows: &[f64]) -> f64 {
        let nd = self.k.n();
        let mut rows = k_rows.to_vec();
        rows.resize(self.n, 0.0);
        for (i, j, v) in summed(self.extra) {
            if i < nd && j < nd {
                let kij = self.k.entry(i, j);
                rows[i] += (kij + v).abs() - kij.abs();
            } else {
                rows[i] += v.abs();
            }
        }
        inf(&rows)
    }
}

/// The entries of a list sorted by (column, row), duplicates summed in
/// their order (as `linsolve::bordered` sums them).
fn summed(list: &[(usize, usize, f64)]) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
    let mut at = 0;
    std::iter::from_fn(move || {
        let &(r, c, mut v) = list.get(at)?;
        at += 1;
        while let Some(&(r2, c2, v2)) = list.get(at)
            && (r2, c2) == (r, c)
        {
            v += v2;
            at += 1;
        }
        Some((r, c, v))
    })
}

/// The row sums of the magnitudes of `k`.
fn row_magnitudes(k: Csc) -> Vec<f64> {
    let mut rows = vec![0.0f64; k.n()];
    for j in 0..k.n() {
        for (i, v) in k.column(j) {
            rows[i] += v.abs();
        }
    }
    rows
}

/// The changed displacement rows `Delta = A1 - A0` of two systems on the
/// same tangent, from their entries beside it (sorted as `Split` has
/// them): per row its (column, change), columns ascending.
fn split_delta(
    extra0: &[(usize, usize, f64)],
    extra1: &[(usize, usize, f64)],
    nd: usize,
) -> HashMap<usize, Vec<(usize, f64)>> {
    let disp = |e: &(usize, usize, f64)| e.0 < nd && e.1 < nd;
    let mut c0 = summed(extra0).filter(disp).peekable();
    let mut c1 = summed(extra1).filter(disp).peekable();
    let mut delta_rows: HashMap<usize, Vec<(usize, f64)>> = HashMap::default();
    loop {
        let key = |e: &(usize, usize, f64)| (e.1, e.0);
        let (i, j, d) = match (c0.peek().copied(), c1.peek().copied()) {
            (None, None) => break,
            (Some(e0), None) => {
                c0.next();
                (e0.0, e0.1, -e0.2)
            }
            (None, Some(e1)) => {
                c1.next();
                e1
            }
            (Some(e0), Some(e1)) => match key(&e0).cmp(&key(&e1)) {
                std::cmp::Ordering::Less => {
                    c0.next();
                    (e0.0, e0.1, -e0.2)
                }
                std::cmp::Ordering::Greater => {
                    c1.next();
                    e1
                }
                std::cmp::Ordering::Equal => {
                    c0.next();
                    c1.next();
                    (e0.0, e0.1, e1.2 - e0.2)
                }
            },
        };
        if d != 0.0 {
            delta_rows.entry(i).or_default().push((j, d));
        }
    }
    delta_rows
}

/// The matrix of a bordered solve: built, or split (`Split`) when it is on
/// the factored system's tangent.
#[derive(Clone, Copy)]
pub(super) enum System<'a> {
    Built(Csc<'a>),
    Split(Split<'a>),
}

fn inf(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// The normwise backward error of `x` from its residual `r = b - A x`:
/// `|r|_inf / (|A|_inf |x|_inf + |b|_inf)`.
pub(super) fn backward_error(r: &[f64], norm_a: f64, x: &[f64], b: &[f64]) -> f64 {
    inf(r) / (norm_a * inf(x) + inf(b))
}

/// The multipliers (unknowns `n_disp..`) of a bordered matrix: per
/// multiplier its row and its column over the displacement unknowns, and
/// its diagonal entry, in two flat lists (no allocation per multiplier: an
/// inner solve of the capstan FMU reads some 500 of them).
struct Multipliers {
    /// Multiplier `m`'s row is `rows[row_at[m]..row_at[m + 1]]`.
    row_at: Vec<usize>,
    rows: Vec<(usize, f64)>,
    /// Its column, likewise.
    column_at: Vec<usize>,
    columns: Vec<(usize, f64)>,
    diagonal: Vec<f64>,
}

impl Multipliers {
    /// The multipliers of `a`, whose first `n_disp` unknowns are
    /// displacements: its entries outside the displacement block, in
    /// column order (a CSC form has no duplicates), as `of_list` reads them.
    fn of(a: Csc, n_disp: usize) -> Self {
        let n = a.n();
        let mut entries = Vec::new();
        for j in 0..n {
            let (p, q) = (a.col_ptr[j], a.col_ptr[j + 1]);
            // Rows sorted: a displacement column's multiplier rows last.
            let from = if j < n_disp {
                p + a.row_idx[p..q].partition_point(|&i| i < n_disp)
            } else {
                p
            };
            entries.extend((from..q).map(|t| (a.row_idx[t], j, a.values[t])));
        }
        Self::of_list(&entries, n_disp, n)
    }

    /// The multipliers of the order-`n` matrix whose entries beside its
    /// tangent (of order `nd`) are `extra` (sorted as `Split` has them).
    fn of_list(extra: &[(usize, usize, f64)], nd: usize, n: usize) -> Self {
        let m = n - nd.min(n);
        let mut row_at = vec![0usize; m + 1];
        for (r, c, _) in summed(extra) {
            if r >= nd && c < nd {
                row_at[r - nd + 1] += 1;
            }
        }
        for k in 0..m {
            row_at[k + 1] += row_at[k];
        }
        let mut next = row_at.clone();
        let mut rows = vec![(0usize, 0.0f64); row_at[m]];
        let mut column_at = vec![0usize; m + 1];
        let mut columns = Vec::new();
        let mut diagonal = vec![0.0; m];
        for (r, c, v) in summed(extra) {
            if c < nd {
                if r >= nd {
                    rows[next[r - nd]] = (c, v);
                    next[r - nd] += 1;
                }
                continue;
            }
            let k = c - nd;
            if r < nd {
                columns.push((r, v));
                column_at[k + 1] = columns.len();
            } else if r == c {
                diagonal[k] = v;
            } else {
                diagonal[k] = f64::NAN;
            }
        }
        for k in 0..m {
            column_at[k + 1] = column_at[k + 1].max(column_at[k]);
        }
        Multipliers {
            row_at,
            rows,
            column_at,
            columns,
            diagonal,
        }
    }

    fn len(&self) -> usize {
        self.diagonal.len()
    }

    fn row(&self, m: usize) -> &[(usize, f64)] {
        &self.rows[self.row_at[m]..self.row_at[m + 1]]
    }

    fn column(&self, m: usize) -> &[(usize, f64)] {
        &self.columns[self.column_at[m]..self.column_at[m + 1]]
    }

    /// An identity-like row of its own: no coupling to the displacements
    /// (an empty slot of a kept pattern, or a row on prescribed dofs
    /// alone), a nonzero diagonal. Its unknown is `h / diagonal` in any
    /// system it is part of: no change to border.
    fn decoupled(&self, m: usize) -> bool {
        let d = self.diagonal[m];
        self.row(m)
            .iter()
            .chain(self.column(m))
            .all(|&(_, v)| v == 0.0)
            && d != 0.0
            && d.is_finite()
    }

    /// Bit-exact identity into `key`: a row the inner solves keep is
    /// rebuilt from the same decision at the same iterate, entry for entry.
    fn key_into(&self, m: usize, key: &mut Vec<u64>) {
        key.clear();
        for &(i, v) in self.row(m) {
            key.extend([i as u64, v.to_bits()]);
        }
        key.push(u64::MAX);
        for &(i, v) in self.column(m) {
            key.extend([i as u64, v.to_bits()]);
        }
        key.push(u64::MAX);
        key.push(self.diagonal[m].to_bits());
    }

    fn key(&self, m: usize) -> Vec<u64> {
        let mut key = Vec::new();
        self.key_into(m, &mut key);
        key
    }

    /// A hash of `key_into`'s words, without building them.
    fn key_hash(&self, m: usize) -> u64 {
        use std::hash::Hasher;
        let mut h = rustc_hash::FxHasher::default();
        for &(i, v) in self.row(m) {
            h.write_u64(i as u64);
            h.write_u64(v.to_bits());
        }
        h.write_u64(u64::MAX);
        for &(i, v) in self.column(m) {
            h.write_u64(i as u64);
            h.write_u64(v.to_bits());
        }
        h.write_u64(u64::MAX);
        h.write_u64(self.diagonal[m].to_bits());
        h.finish()
    }

    /// Whether multiplier `m` has `other`'s multiplier `k`'s key.
    fn same_key(&self, m: usize, other: &Multipliers, k: usize) -> bool {
        fn same(a: &[(usize, f64)], b: &[(usize, f64)]) -> bool {
            a.len() == b.len()
                && a.iter()
                    .zip(b)
                    .all(|(x, y)| x.0 == y.0 && x.1.to_bits() == y.1.to_bits())
        }
        same(self.row(m), other.row(k))
            && same(self.column(m), other.column(k))
            && self.diagonal[m].to_bits() == other.diagonal[k].to_bits()
    }
}

/// What distinguishes a column of `E` (for the kept `A0^-1 E`).
#[derive(Clone, PartialEq, Eq, Hash)]
enum Change {
    Released(usize),
    Added(Vec<u64>),
    Displacement(usize),
}

/// The factored system `A0` the inner solves border: its multipliers by
/// key, and the columns of `A0^-1 E` solved so far.
pub(super) struct Base {
    n: usize,
    n_disp: usize,
    /// `A0`'s multipliers by key, and per multiplier whether it is
    /// decoupled (`Multipliers::decoupled`): indexed by the first bordered
    /// solve (most factorizations of a Newton iteration have none).
    index: Option<MultiplierIndex>,
    /// The right-hand side `A0` was factored with and its solution: an
    /// inner solve whose right-hand side differs from it only where a
    /// kept column `A0^-1 e_i` is (a released multiplier, a changed
    /// displacement row) needs no solve with the factor for it.
    b0: Vec<f64>,
    x0: Vec<f64>,
    solved: HashMap<Change, Vec<f64>>,
    /// The entries beside the tangent `A0` was built from (sorted as
    /// `Split` has them) and the caller's count of its tangent then
    /// (`Augmented::new_tangent`): a system on the same tangent is bordered
    /// as a `Split`.
    extra0: Option<Vec<(usize, usize, f64)>>,
    tangent: Option<u64>,
    /// The tangent's row sums of magnitudes (`row_magnitudes`), made by the
    /// first `Split` solve.
    k_rows: Option<Vec<f64>>,
}

struct MultiplierIndex {
    /// `A0`'s multipliers, and by the hash of their keys
    /// (`Multipliers::key_hash`) their indices, ascending.
    all: Multipliers,
    keys: HashMap<u64, Vec<usize>>,
    decoupled: Vec<bool>,
}

impl MultiplierIndex {
    /// From `a0`, or from its entries beside the tangent when they are
    /// kept (`Base::on_tangent`; the same multipliers, without a pass over
    /// the whole matrix).
    fn of(a0: Csc, n_disp: usize, extra0: Option<&[(usize, usize, f64)]>) -> Self {
        // Each key's multipliers in ascending order.
        let mut keys: HashMap<u64, Vec<usize>> = HashMap::default();
        let all = match extra0 {
            Some(extra0) => Multipliers::of_list(extra0, n_disp, a0.n()),
            None => Multipliers::of(a0, n_disp),
        };
        for m in 0..all.len() {
            keys.entry(all.key_hash(m)).or_default().push(m);
        }
        MultiplierIndex {
            decoupled: (0..all.len()).map(|m| all.decoupled(m)).collect(),
            keys,
            all,
        }
    }
}

impl Base {
    /// The base of `a0` (of order `n`), factored with `b0` and solved to
    /// `x0`.
    pub(super) fn new(n: usize, n_disp: usize, b0: Vec<f64>, x0: Vec<f64>) -> Self {
        Base {
            n,
            n_disp,
            index: None,
            b0,
            x0,
            solved: HashMap::default(),
            extra0: None,
            tangent: None,
            k_rows: None,
        }
    }

    /// `A0` is the tangent counted `tangent` (`Augmented::new_tangent`)
    /// and the entries `extra0` beside it (sorted by column, then row).
    pub(super) fn on_tangent(mut self, tangent: u64, extra0: Vec<(usize, usize, f64)>) -> Self {
        self.tangent = Some(tangent);
        self.extra0 = Some(extra0);
        self
    }

    /// Whether a system on the tangent counted `tangent` is bordered as a
    /// `Split`.
    pub(super) fn splits(&self, tangent: Option<u64>) -> bool {
        tangent.is_some() && self.tangent == tangent && self.extra0.is_some()
    }
}

/// Why a bordered solve was not done: the caller factors the system itself.
#[derive(Debug)]
pub(super) enum NotBordered {
    /// More changes than `max_rank`.
    TooMany,
    /// The Schur complement is singular or the refined solution is off.
    Unsound,
}

/// The changed displacement rows `Delta = A1 - A0` of two built systems:
/// per row its (column, change), columns ascending.
fn built_delta(a0: Csc, a1: Csc, nd: usize) -> HashMap<usize, Vec<(usize, f64)>> {
    let mut delta_rows: HashMap<usize, Vec<(usize, f64)>> = HashMap::default();
    for j in 0..nd {
        // Most columns are the tangent's alone in both (rows sorted: the
        // displacement rows come first): equal slices, no change.
        let (r0, v0) = a0.displacement_part(j, nd);
        let (r1, v1) = a1.displacement_part(j, nd);
        if r0 == r1 && v0 == v1 {
            continue;
        }
        let mut c0 = a0.column(j).filter(|e| e.0 < nd).peekable();
        let mut c1 = a1.column(j).filter(|e| e.0 < nd).peekable();
        loop {
            let (i, d) = match (c0.peek().copied(), c1.peek().copied()) {
                (None, None) => break,
                (Some((i, v)), None) => {
                    c0.next();
                    (i, -v)
                }
                (None, Some((i, v))) => {
                    c1.next();
                    (i, v)
                }
                (Some((i0, v0)), Some((i1, v1))) => {
                    if i0 < i1 {
                        c0.next();
                        (i0, -v0)
                    } else if i1 < i0 {
                        c1.next();
                        (i1, v1)
                    } else {
                        c0.next();
                        c1.next();
                        (i0, v1 - v0)
                    }
                }
            };
            if d != 0.0 {
                delta_rows.entry(i).or_default().push((j, d));
            }
        }
    }
    delta_rows
}

/// Solves `A1 x = rhs` (in place) with `A0`'s factorization, `solve0`
/// solving `A0 X = B` in place for `k` columns (column-major, `A0`'s order
/// each). Returns whether the solution was refined: with `defer` (only the
/// linearised problem's state decisions read it; should it become the
/// Newton correction, the caller solves it again without) a first
/// solution whose normwise backward error is below
/// `UNREFINED_BACKWARD_ERROR` is taken as it is.
pub(super) fn solve(
    base: &mut Base,
    a0: Csc,
    a1: System,
    rhs: &mut [f64],
    max_rank: usize,
    defer: bool,
    solve0: &mut dyn FnMut(&mut [f64], usize) -> bool,
) -> Result<bool, NotBordered> {
    let (n0, nd) = (base.n, base.n_disp);
    let n1 = match a1 {
        System::Built(a) => a.n(),
        System::Split(a) => a.n,
    };
    if a0.n() != n0 {
        return Err(NotBordered::Unsound);
    }
    let index = &*base
        .index
        .get_or_insert_with(|| MultiplierIndex::of(a0, nd, base.extra0.as_deref()));
    if nd > n1 {
        return Err(NotBordered::Unsound);
    }
    // The changed displacement rows: Delta = A1 - A0 on the displacements.
    let delta_rows = match a1 {
        System::Built(a1) => built_delta(a0, a1, nd),
        System::Split(a1) => {
            let Some(extra0) = base.extra0.as_deref().filter(|_| a1.k.n() == nd) else {
                return Err(NotBordered::Unsound);
            };
            split_delta(extra0, a1.extra, nd)
        }
    };
    // Multipliers: matched by key, released, added.
    let new = match a1 {
        System::Built(a1) => Multipliers::of(a1, nd),
        System::Split(a1) => Multipliers::of_list(a1.extra, a1.k.n(), a1.n),
    };
    let mut matched: Vec<Option<usize>> = Vec::with_capacity(new.len());
    let mut used = vec![false; n0 - nd];
    for m1 in 0..new.len() {
        // The first of A0's multipliers with the same key not taken yet.
        let m0 = (index.keys.get(&new.key_hash(m1))).and_then(|list| {
            (list.iter().copied()).find(|&m| !used[m] && index.all.same_key(m, &new, m1))
        });
        if let Some(m) = m0 {
            used[m] = true;
        }
        matched.push(m0);
    }
    // A decoupled multiplier of A0 left out is no change (its unknown was
    // alone); a decoupled one of A1 not in A0 is solved alone (`direct`).
    let mut changes: Vec<Change> = Vec::new();
    let left_out = (0..n0 - nd).filter(|&m| !used[m] && !index.decoupled[m]);
    changes.extend(left_out.map(Change::Released));
    let unmatched = |m: &usize| matched[*m].is_none();
    let added: Vec<usize> = (0..new.len())
        .filter(unmatched)
        .filter(|&m| !new.decoupled(m))
        .collect();
    let direct: Vec<usize> = (0..new.len())
        .filter(unmatched)
        .filter(|&m| new.decoupled(m))
        .collect();
    changes.extend(added.iter().map(|&m| Change::Added(new.key(m))));
    let mut delta: Vec<usize> = delta_rows.keys().copied().collect();
    delta.sort_unstable();
    changes.extend(delta.iter().map(|&i| Change::Displacement(i)));
    let released = (0..n0 - nd)
        .filter(|&m| !used[m] && !index.decoupled[m])
        .count();
    let r = changes.len();
    if r > max_rank {
        return Err(NotBordered::TooMany);
    }
    if new.diagonal.iter().any(|d| d.is_nan()) {
        return Err(NotBordered::Unsound);
    }
    // The columns of E, and A0^-1 E for those not solved yet.
    let column_of = |c: &Change| -> Vec<f64> {
        let mut e = vec![0.0; n0];
        match c {
            Change::Released(m) => e[nd + m] = 1.0,
            Change::Added(_) => {}
            Change::Displacement(i) => e[*i] = 1.0,
        }
        e
    };
    let mut added_iter = added.iter();
    let mut pending: Vec<(Change, Vec<f64>)> = Vec::new();
    for c in &changes {
        let m =
            matches!(c, Change::Added(_)).then(|| *added_iter.next().expect("one per added row"));
        if base.solved.contains_key(c) {
            continue;
        }
        let mut e = column_of(c);
        if let Some(m) = m {
            for &(i, v) in new.column(m) {
                e[i] = v;
            }
        }
        pending.push((c.clone(), e));
    }
    if !pending.is_empty() {
        let k = pending.len();
        let mut block = Vec::with_capacity(n0 * k);
        for (_, e) in &pending {
            block.extend_from_slice(e);
        }
        if !solve0(&mut block, k) || block.iter().any(|v| !v.is_finite()) {
            return Err(NotBordered::Unsound);
        }
        for ((c, _), z) in pending.into_iter().zip(block.chunks(n0)) {
            base.solved.insert(c, z.to_vec());
        }
    }
    let z: Vec<&Vec<f64>> = changes.iter().map(|c| &base.solved[c]).collect();
    // F^T v for each change, and D.
    let f_dot = |q: usize, v: &[f64]| -> f64 {
        match &changes[q] {
            Change::Released(m) => v[nd + m],
            Change::Added(_) => new
                .row(added[q - released])
                .iter()
                .map(|&(j, c)| c * v[j])
                .sum(),
            Change::Displacement(i) => delta_rows[i].iter().map(|&(j, d)| d * v[j]).sum(),
        }
    };
    let d_of = |q: usize| -> f64 {
        match &changes[q] {
            Change::Released(_) => 0.0,
            Change::Added(_) => new.diagonal[added[q - released]],
            Change::Displacement(_) => -1.0,
        }
    };
    let mut s = DMatrix::<f64>::zeros(r, r);
    for q in 0..r {
        for (p, zp) in z.iter().enumerate() {
            s[(q, p)] = -f_dot(q, zp);
        }
        s[(q, q)] += d_of(q);
    }
    let lu = s.lu();
    // The kept unit columns `A0^-1 e_i`, by the position i.
    let unit: HashMap<usize, &Vec<f64>> = (changes.iter().zip(&z))
        .filter_map(|(c, zc)| match c {
            Change::Released(m) => Some((nd + m, *zc)),
            Change::Displacement(i) => Some((*i, *zc)),
            Change::Added(_) => None,
        })
        .collect();
    // One application: b1 (A1's layout) -> x1; `first`: b1 is the
    // right-hand side (not a residual), so it may differ from A0's only
    // where a unit column is kept.
    let mut apply = |b1: &[f64], first: bool| -> Option<Vec<f64>> {
        let mut w = vec![0.0; n0];
        w[..nd].copy_from_slice(&b1[..nd]);
        for (m1, m0) in matched.iter().enumerate() {
            if let Some(m0) = m0 {
                w[nd + m0] = b1[nd + m1];
            }
        }
        let changed: Option<Vec<(usize, f64)>> = (first && base.x0.len() == n0)
            .then(|| {
                (w.iter().zip(&base.b0).enumerate())
                    .filter(|(_, (a, b))| a != b)
                    .map(|(i, (a, b))| unit.contains_key(&i).then_some((i, a - b)))
                    .collect()
            })
            .flatten();
        match changed {
            Some(changed) => {
                w.copy_from_slice(&base.x0);
                for (i, d) in changed {
                    for (wi, zi) in w.iter_mut().zip(unit[&i].iter()) {
                        *wi += zi * d;
                    }
                }
            }
            None => {
                if !solve0(&mut w, 1) {
                    return None;
                }
            }
        }
        let mut h = DVector::<f64>::zeros(r);
        for q in 0..r {
            let hq = match &changes[q] {
                Change::Added(_) => b1[nd + added[q - released]],
                _ => 0.0,
            };
            h[q] = hq - f_dot(q, &w);
        }
        // (No change to border: A1 is A0 but for decoupled rows.)
        let y = if r == 0 { h } else { lu.solve(&h)? };
        for (p, zp) in z.iter().enumerate() {
            let yp = y[p];
            for (wi, zi) in w.iter_mut().zip(zp.iter()) {
                *wi -= zi * yp;
            }
        }
        let mut x1 = vec![0.0; n1];
        x1[..nd].copy_from_slice(&w[..nd]);
        for (m1, m0) in matched.iter().enumerate() {
            if let Some(m0) = m0 {
                x1[nd + m1] = w[nd + m0];
            }
        }
        for (q, &m1) in added.iter().enumerate() {
            x1[nd + m1] = y[released + q];
        }
        for &m1 in &direct {
            x1[nd + m1] = b1[nd + m1] / new.diagonal[m1];
        }
        Some(x1)
    };
    // One step of refinement against A1 itself, then its normwise backward
    // error, accepted below the factored solves' `LDLT_BACKWARD_ERROR`.
    // (Taken without the refinement at a normwise backward error of 1e-12,
    // the solutions cost the stress suite's 4-node rubber sheet at 160x16
    // iterations: median 5.5 and max 11 per increment against 5 and 8. The
    // convergence test's round-off floor, 1e-13 of the forces, sees what
    // that norm, dominated by the tangent's entries times the multipliers,
    // does not.)
    let b = rhs.to_vec();
    let norm_a = match a1 {
        System::Built(a1) => a1.norm_inf(),
        System::Split(a1) => a1.norm_inf(base.k_rows.get_or_insert_with(|| row_magnitudes(a1.k))),
    };
    let residual = |x: &[f64]| match a1 {
        System::Built(a1) => a1.residual(x, &b),
        System::Split(a1) => a1.residual(x, &b),
    };
    let mut x = apply(&b, true).ok_or(NotBordered::Unsound)?;
    let r0 = residual(&x);
    if defer && backward_error(&r0, norm_a, &x, &b) <= UNREFINED_BACKWARD_ERROR {
        rhs.copy_from_slice(&x);
        return Ok(false);
    }
    let dx = apply(&r0, false).ok_or(NotBordered::Unsound)?;
    for (xi, di) in x.iter_mut().zip(&dx) {
        *xi += di;
    }
    let backward = backward_error(&residual(&x), norm_a, &x, &b);
    // (NaN fails too.)
    if backward.is_nan() || backward > super::LDLT_BACKWARD_ERROR {
        return Err(NotBordered::Unsound);
    }
    rhs.copy_from_slice(&x);
    Ok(true)
}

/// The normwise backward error below which a bordered solve that only the
/// linearised problem's state decisions read (`solve`'s `defer`) is taken
/// without its step of refinement: four orders below the default force
/// tolerance of the iteration (1e-8 of the forces), which those decisions
/// compare with. The capstan FMU's unrefined solves have 1e-19 to 1e-16.
/// The refinement is needed where a solve becomes the Newton correction:
/// there the convergence test's round-off floor (1e-13 of the forces) sees
/// what this norm does not (see `solve`).
const UNREFINED_BACKWARD_ERROR: f64 = 1e-12;
