//! The bordered contact system: LDLT against LU and a dense solve, the choice
//! of method, the reuse of the symbolic analyses; an ignored timing of LDLT
//! against LU on Q4-like matrices.

use super::*;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use nalgebra::{DMatrix, DVector};
use std::sync::Arc;
use std::time::Instant;

/// A pseudo-random number in [-1, 1) (xorshift, deterministic).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// CSC pattern and values (both triangles) from triplets, duplicates summed.
fn csc(n: usize, mut t: Vec<(usize, usize, f64)>) -> (Pattern, Vec<f64>) {
    t.sort_unstable_by_key(|&(r, c, _)| (c, r));
    let mut col_ptr = vec![0; n + 1];
    let mut row_idx: Vec<usize> = Vec::with_capacity(t.len());
    let mut values: Vec<f64> = Vec::with_capacity(t.len());
    let mut last = (usize::MAX, usize::MAX);
    for (r, c, v) in t {
        if (r, c) == last {
            *values.last_mut().unwrap() += v;
        } else {
            row_idx.push(r);
            values.push(v);
            col_ptr[c + 1] = row_idx.len();
            last = (r, c);
        }
    }
    for c in 0..n {
        col_ptr[c + 1] = col_ptr[c + 1].max(col_ptr[c]);
    }
    (
        Pattern {
            n,
            col_ptr,
            row_idx,
        },
        values,
    )
}

/// 1D chain of springs, `n` dofs, held at both ends: SPD tridiagonal.
fn chain(n: usize) -> (Pattern, Vec<f64>) {
    let mut t = Vec::new();
    for i in 0..n {
        t.push((i, i, 2.0));
        if i + 1 < n {
            t.push((i, i + 1, -1.0));
            t.push((i + 1, i, -1.0));
        }
    }
    csc(n, t)
}

/// Q4 Laplacian on `nx` x `ny` free nodes, two dofs per node coupled by
/// `[1, 0.3; 0.3, 1]` (the pattern of Q4 plane elasticity). With `fixed`
/// the node row below the grid is held (SPD), else the grid floats (two
/// zero-energy modes, the constants of each dof).
fn q4(nx: usize, ny: usize, fixed: bool) -> (Pattern, Vec<f64>) {
    let ke = [
        [4.0, -1.0, -2.0, -1.0],
        [-1.0, 4.0, -1.0, -2.0],
        [-2.0, -1.0, 4.0, -1.0],
        [-1.0, -2.0, -1.0, 4.0],
    ];
    let d = [[1.0, 0.3], [0.3, 1.0]];
    let rows = if fixed { ny + 1 } else { ny };
    let mut t = Vec::with_capacity((nx - 1) * rows * 64);
    // Node (i, j) of the element rows; with `fixed`, row 0 is held.
    let dof = |i: usize, j: usize| -> Option<usize> {
        let j = if fixed { j.checked_sub(1)? } else { j };
        Some(2 * (j * nx + i))
    };
    for j in 0..rows - 1 {
        for i in 0..nx - 1 {
            let nodes = [dof(i, j), dof(i + 1, j), dof(i + 1, j + 1), dof(i, j + 1)];
            for a in 0..4 {
                for b in 0..4 {
                    if let (Some(da), Some(db)) = (nodes[a], nodes[b]) {
                        for p in 0..2 {
                            for q in 0..2 {
                                t.push((da + p, db + q, ke[a][b] * d[p][q] / 6.0));
                            }
                        }
                    }
                }
            }
        }
    }
    csc(2 * nx * ny, t)
}

/// `m` node-to-segment-like rows on the top and the bottom node rows of a
/// `nx` x `ny` grid: by turns 1 dof (a rigid target, normal y), 2 dofs (a
/// slave node and its normal) and 6 dofs (slave and two master nodes).
fn contact_rows(nx: usize, ny: usize, m: usize, rng: &mut Rng) -> Rows {
    let per_line = m.div_ceil(2);
    assert!(nx >= 3 * per_line.min(nx / 3).max(1));
    (0..m)
        .map(|r| {
            let j = if r % 2 == 0 { ny - 1 } else { 0 };
            let i = (r / 2) * (nx - 3) / per_line.max(1);
            let node = |i: usize| 2 * (j * nx + i);
            let theta = 0.3 * rng.next();
            let (nx_, ny_) = (theta.sin(), theta.cos());
            match r % 3 {
                0 => vec![(node(i) + 1, 1.0)],
                1 => vec![(node(i), nx_), (node(i) + 1, ny_)],
                _ => {
                    let xi = 0.5 + 0.4 * rng.next();
                    vec![
                        (node(i), nx_),
                        (node(i) + 1, ny_),
                        (node(i + 1), -(1.0 - xi) * nx_),
                        (node(i + 1) + 1, -(1.0 - xi) * ny_),
                        (node(i + 2), -xi * nx_),
                        (node(i + 2) + 1, -xi * ny_),
                    ]
                }
            }
        })
        .collect()
}

/// Contact rows: the (dof, coefficient) pairs of each row of C.
type Rows = Vec<Vec<(usize, f64)>>;

/// The entries `(n + i, d, c)` and `(d, n + i, c)` of the rows, as Newton
/// passes them.
fn border(n: usize, rows: &[Vec<(usize, f64)>]) -> Vec<(usize, usize, f64)> {
    let mut extra = Vec::new();
    for (i, row) in rows.iter().enumerate() {
        for &(d, c) in row {
            extra.push((n + i, d, c));
            extra.push((d, n + i, c));
        }
    }
    extra
}

fn dense(p: &Pattern, k: &[f64], extra: &[(usize, usize, f64)], n: usize) -> DMatrix<f64> {
    let mut a = DMatrix::zeros(n, n);
    for c in 0..p.n {
        for q in p.col_ptr[c]..p.col_ptr[c + 1] {
            a[(p.row_idx[q], c)] += k[q];
        }
    }
    for &(r, c, v) in extra {
        a[(r, c)] += v;
    }
    a
}

/// The solution of `a x = b` by a dense LU.
fn dense_solve(a: &DMatrix<f64>, b: &[f64]) -> DVector<f64> {
    a.clone()
        .lu()
        .solve(&DVector::from_column_slice(b))
        .unwrap()
}

/// Asserts `x` is `want` to `tol` of `want`'s largest entry.
fn assert_close(x: &[f64], want: &DVector<f64>, tol: f64, what: &str) {
    let scale = want.amax();
    for i in 0..want.len() {
        assert!((x[i] - want[i]).abs() <= tol * scale, "{what}: unknown {i}");
    }
}

fn residual(a: &DMatrix<f64>, x: &[f64], b: &[f64]) -> f64 {
    let x = DVector::from_column_slice(x);
    let b = DVector::from_column_slice(b);
    (a * x - &b).norm() / b.norm()
}

fn rhs(n: usize, rng: &mut Rng) -> Vec<f64> {
    (0..n).map(|_| rng.next()).collect()
}

/// Solves by `aug` the tangent `k` bordered by `rows` and the entries
/// `beside` it, against a right-hand side seeded by the order plus `seed`,
/// and checks the solution against the dense system.
fn solve_bordered(
    aug: &mut Augmented,
    (p, k): (&Pattern, &[f64]),
    rows: &[Vec<(usize, f64)>],
    beside: &[(usize, usize, f64)],
    seed: u64,
) {
    let n = p.n + rows.len();
    let mut extra = border(p.n, rows);
    extra.extend_from_slice(beside);
    let b = rhs(n, &mut Rng(n as u64 + seed));
    let a = dense(p, k, &extra, n);
    let mut x = b.clone();
    aug.solve(p, k, &mut extra, &mut x).unwrap();
    let r = residual(&a, &x, &b);
    assert!(r < 1e-10, "residual {r:e}");
}

/// Solve with a fresh `Augmented` (LDLT allowed or not); the solution and
/// the solver.
fn solve(
    p: &Pattern,
    k: &[f64],
    extra: &[(usize, usize, f64)],
    b: &[f64],
    force_lu: bool,
) -> (Vec<f64>, Augmented) {
    let mut aug = Augmented {
        force_lu,
        ..Default::default()
    };
    let mut x = b.to_vec();
    aug.solve(p, k, &mut extra.to_vec(), &mut x).unwrap();
    (x, aug)
}

#[test]
fn ldlt_matches_lu_and_dense() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let cases: Vec<(&str, Pattern, Vec<f64>, Rows)> = vec![
        {
            let (p, k) = chain(50);
            let rows = vec![
                vec![(49, 1.0)],
                vec![(10, 0.6), (11, -0.8)],
                vec![(20, 1.0), (21, -0.5), (22, -0.5)],
                vec![
                    (30, 0.3),
                    (31, 0.2),
                    (32, -0.1),
                    (33, 0.4),
                    (34, -0.7),
                    (35, 0.2),
                ],
            ];
            ("chain 50", p, k, rows)
        },
        {
            let (p, k) = q4(12, 12, true);
            let rows = contact_rows(12, 12, 6, &mut rng);
            ("q4 12x12", p, k, rows)
        },
        {
            let (p, k) = q4(16, 15, true);
            let rows = contact_rows(16, 15, 10, &mut rng);
            ("q4 16x15", p, k, rows)
        },
    ];
    for (name, p, k, rows) in cases {
        let n = p.n + rows.len();
        let mut extra = border(p.n, &rows);
        // A symmetric contact stiffness block on a few dofs (summed into K).
        extra.push((3, 3, 0.5));
        extra.push((3, 5, 0.25));
        extra.push((5, 3, 0.25));
        let b = rhs(n, &mut rng);
        let a = dense(&p, &k, &extra, n);
        let (x_ldlt, aug) = solve(&p, &k, &extra, &b, false);
        assert_eq!(aug.method(), Some(Method::Ldlt), "{name}");
        assert_eq!((aug.ldlt, aug.lu, aug.factorizations), (1, 0, 1), "{name}");
        let (x_lu, aug) = solve(&p, &k, &extra, &b, true);
        assert_eq!(aug.method(), Some(Method::Lu), "{name}");
        assert_eq!((aug.ldlt, aug.lu, aug.factorizations), (0, 1, 1), "{name}");
        let x_dense = dense_solve(&a, &b);
        let r_ldlt = residual(&a, &x_ldlt, &b);
        let r_lu = residual(&a, &x_lu, &b);
        assert!(r_ldlt < 1e-10, "{name}: LDLT residual {r_ldlt:e}");
        assert!(r_lu < 1e-10, "{name}: LU residual {r_lu:e}");
        assert_close(&x_ldlt, &x_dense, 1e-8, &format!("{name}, LDLT"));
        assert_close(&x_lu, &x_dense, 1e-8, &format!("{name}, LU"));
    }
}

/// An unsymmetric system is factored by the unpivoted LDU (`ldu`), and
/// solves as LU with pivoting and a dense LU do; where the LDU's pivots
/// fail it (a body that its contact rows alone hold: the displacements,
/// eliminated first, meet the rigid-body modes' zero pivots), by LU.
#[test]
fn unsymmetric_system_takes_the_unpivoted_ldu() {
    let mut rng = Rng(7);
    let (p, k) = q4(10, 10, true);
    let rows = contact_rows(10, 10, 4, &mut rng);
    let n = p.n + rows.len();
    let mut extra = border(p.n, &rows);
    // A sliding-like unsymmetric contact stiffness: (0, 1) without (1, 0).
    extra.push((0, 1, 0.25));
    let b = rhs(n, &mut rng);
    let (x, mut aug) = solve(&p, &k, &extra, &b, false);
    assert_eq!(aug.method(), Some(Method::Ldu));
    assert_eq!(
        (aug.ldlt, aug.lu, aug.ldu, aug.factorizations, aug.analyses),
        (0, 0, 1, 1, 1)
    );
    let a = dense(&p, &k, &extra, n);
    assert!(residual(&a, &x, &b) < 1e-10);
    // An inner solve with a row changed, on the same counted tangent, is
    // factored again (the LDU keeps no factor: `try_ldu`), on the same
    // analysis.
    aug.new_tangent();
    let mut changed = extra.clone();
    for e in changed
        .iter_mut()
        .filter(|e| e.0 == p.n + 1 || e.1 == p.n + 1)
    {
        e.2 *= 1.5;
    }
    changed.push((2, 3, -0.2));
    let mut x2 = b.clone();
    aug.solve(&p, &k, &mut changed.clone(), &mut x2).unwrap();
    aug.solve(&p, &k, &mut changed.clone(), &mut x2).unwrap();
    x2.clone_from(&b);
    aug.solve(&p, &k, &mut changed.clone(), &mut x2).unwrap();
    assert_eq!(
        (
            aug.trailing_solves,
            aug.ldu,
            aug.factorizations,
            aug.analyses
        ),
        (0, 4, 4, 1)
    );
    assert!(residual(&dense(&p, &k, &changed, n), &x2, &b) < 1e-10);
    let (x_lu, aug) = solve(&p, &k, &extra, &b, true);
    assert_eq!((aug.method(), aug.ldu), (Some(Method::Lu), 0));
    let x_dense = dense_solve(&a, &b);
    assert_close(&x, &x_dense, 1e-10, "LDU");
    assert_close(&x_lu, &x_dense, 1e-10, "LU");
    // Every displacement's diagonal zero: the first unknown the LDU
    // eliminates (a displacement) has a zero pivot; LU with pivoting
    // solves it (two factorizations, the failed one counted).
    let mut zero = extra.clone();
    for c in 0..p.n {
        let q = (p.col_ptr[c]..p.col_ptr[c + 1])
            .find(|&q| p.row_idx[q] == c)
            .unwrap();
        zero.push((c, c, -k[q]));
    }
    let a = dense(&p, &k, &zero, n);
    let (x, aug) = solve(&p, &k, &zero, &b, false);
    assert_eq!(aug.method(), Some(Method::Lu));
    assert_eq!((aug.lu, aug.ldu, aug.factorizations), (1, 0, 2));
    assert!(residual(&a, &x, &b) < 1e-10);
    // Below the tolerance (1e-12 of the largest entry) it counts as symmetric.
    let mut extra = border(p.n, &rows);
    extra.push((0, 1, 1e-14));
    let (x, aug) = solve(&p, &k, &extra, &b, false);
    assert_eq!(aug.method(), Some(Method::Ldlt));
    assert!(residual(&dense(&p, &k, &extra, n), &x, &b) < 1e-10);
}

/// A caller's symmetric tangent (`symmetric_tangent`): the system's
/// symmetry is judged on the entries beside it, as the whole matrix judges
/// it, and a wrong claim (an unsymmetric tangent) still solves, by LU.
#[test]
fn a_symmetric_tangent_is_judged_by_the_entries_beside_it() {
    let mut rng = Rng(9);
    let (p, k) = q4(10, 10, true);
    let rows = contact_rows(10, 10, 4, &mut rng);
    let n = p.n + rows.len();
    let b = rhs(n, &mut rng);
    let claimed = |k: &[f64], extra: &[(usize, usize, f64)]| {
        let mut aug = Augmented::with_slots(false);
        aug.symmetric_tangent = true;
        let mut x = b.clone();
        aug.solve(&p, k, &mut extra.to_vec(), &mut x).unwrap();
        assert!(residual(&dense(&p, k, extra, n), &x, &b) < 1e-10);
        (aug.method(), aug.factorizations)
    };
    let mut extra = border(p.n, &rows);
    let (ldlt, lu) = (Some(Method::Ldlt), Some(Method::Lu));
    assert_eq!(claimed(&k, &extra), (ldlt, 1));
    // A sliding-like entry without its transpose, above the tolerance (1e-12
    // of the largest entry: judged unsymmetric, straight to the unpivoted
    // LDU, one factorization) and below it, and one split in two
    // duplicates that sum to its transpose's value.
    extra.push((0, 1, 0.25));
    assert_eq!(claimed(&k, &extra), (Some(Method::Ldu), 1));
    extra.pop();
    extra.push((0, 1, 1e-14));
    assert_eq!(claimed(&k, &extra), (ldlt, 1));
    extra.pop();
    extra.extend([(0, 1, 0.125), (1, 0, 0.25), (0, 1, 0.125)]);
    assert_eq!(claimed(&k, &extra), (ldlt, 1));
    // The claim wrong: a tangent entry without its transpose's value. The
    // LDLT fails its backward error, and LU solves (two factorizations).
    let mut k1 = k.clone();
    let q = p.col_ptr[1]
        + p.row_idx[p.col_ptr[1]..p.col_ptr[2]]
            .iter()
            .position(|&i| i == 0)
            .unwrap();
    k1[q] += 0.25;
    assert_eq!(claimed(&k1, &border(p.n, &rows)), (lu, 2));
}

/// The kept LU factor of an unsymmetric bordered system solves any number
/// of right-hand sides as a dense LU does, and refuses one of the wrong
/// length.
#[test]
fn factored_lu_solves_many_right_hand_sides() {
    let mut rng = Rng(23);
    let (p, k) = q4(9, 9, true);
    let rows = contact_rows(9, 9, 4, &mut rng);
    let n = p.n + rows.len();
    let mut extra = border(p.n, &rows);
    extra.push((2, 7, 0.3));
    let a = dense(&p, &k, &extra, n);
    let factor = FactoredLu::new(&p, &k, &mut extra, n).unwrap();
    for _ in 0..3 {
        let b = rhs(n, &mut rng);
        let mut x = b.clone();
        factor.solve(&mut x).unwrap();
        assert_close(&x, &dense_solve(&a, &b), 1e-9, "FactoredLu");
    }
    assert!(factor.solve(&mut vec![0.0; n + 1]).is_err());
}

#[test]
fn symbolic_analysis_reused_while_the_pattern_holds() {
    let mut rng = Rng(11);
    let (p, k) = q4(9, 8, true);
    let rows = contact_rows(9, 8, 5, &mut rng);
    let n = p.n + rows.len();
    let mut aug = Augmented::default();
    let check = |aug: &mut Augmented, k: &[f64], rows: &[Vec<(usize, f64)>], extra_k: &[_]| {
        solve_bordered(aug, (&p, k), rows, extra_k, 3);
    };
    check(&mut aug, &k, &rows, &[]);
    assert_eq!(
        (aug.analyses, aug.factorizations, aug.ldlt, aug.lu),
        (1, 1, 1, 0)
    );
    // Same pattern, other values: the analysis is reused.
    let k2: Vec<f64> = k.iter().map(|v| 2.5 * v).collect();
    let rows2: Rows = rows
        .iter()
        .map(|r| r.iter().map(|&(d, c)| (d, 1.5 * c + 0.1)).collect())
        .collect();
    check(&mut aug, &k2, &rows2, &[]);
    assert_eq!(
        (aug.analyses, aug.factorizations, aug.ldlt, aug.lu),
        (1, 2, 2, 0)
    );
    // Unsymmetric on the same pattern ((1, 0) and (0, 1) are stored in K):
    // one LDU analysis more, then reused; LDLT again on a symmetric system.
    check(&mut aug, &k2, &rows2, &[(1, 0, 0.3)]);
    assert_eq!(
        (aug.analyses, aug.factorizations, aug.ldlt, aug.ldu),
        (2, 3, 2, 1)
    );
    check(&mut aug, &k, &rows2, &[(1, 0, -0.3)]);
    assert_eq!(
        (aug.analyses, aug.factorizations, aug.ldlt, aug.ldu),
        (2, 4, 2, 2)
    );
    check(&mut aug, &k, &rows, &[]);
    assert_eq!(
        (aug.analyses, aug.factorizations, aug.ldlt, aug.ldu),
        (2, 5, 3, 2)
    );
    assert_eq!(aug.method(), Some(Method::Ldlt));
    // The pattern changes (a row less, then a row with other dofs): redone.
    check(&mut aug, &k, &rows[..4], &[]);
    assert_eq!(
        (aug.analyses, aug.factorizations, aug.ldlt, aug.ldu),
        (3, 6, 4, 2)
    );
    let mut rows3 = rows.clone();
    rows3[4] = vec![(p.n - 1, 1.0), (p.n - 3, -1.0)];
    check(&mut aug, &k, &rows3, &[]);
    assert_eq!(
        (aug.analyses, aug.factorizations, aug.ldlt, aug.ldu),
        (4, 7, 5, 2)
    );
    check(&mut aug, &k2, &rows3, &[]);
    assert_eq!(
        (aug.analyses, aug.factorizations, aug.ldlt, aug.ldu),
        (4, 8, 6, 2)
    );
    assert_eq!(aug.lu, 0);
    // Back to the first pattern: only the last pattern is kept.
    check(&mut aug, &k, &rows, &[]);
    assert_eq!((aug.analyses, aug.ldlt), (5, 7));
    assert_eq!(n, p.n + 5);
}

/// Without slots, systems of one order whose entries move back and forth
/// (a mortar side pair met and missed as a contactor node passes over a
/// target node) keep one analysis after the first change: the new pattern
/// takes in the kept one's entries, and either system is held by it, every
/// solve exact against its dense system. Entries of the kept pattern that
/// outnumber the system's own beside the tangent are not taken in.
#[test]
fn an_unslotted_pattern_takes_in_the_last_one_s_entries() {
    let mut rng = Rng(13);
    let (p, k) = q4(9, 8, true);
    let rows = contact_rows(9, 8, 5, &mut rng);
    let mut moved = rows.clone();
    moved[4] = vec![(p.n - 1, 1.0), (p.n - 3, -1.0)];
    // A coupling beside the tangent that moves with the row (a side pair's
    // Hessian), between dofs the tangent does not couple.
    let (near, far) = (
        [(0, p.n - 1, 0.2), (p.n - 1, 0, 0.2)],
        [(1, p.n - 3, 0.2), (p.n - 3, 1, 0.2)],
    );
    assert!(!(p.col_ptr[p.n - 1]..p.col_ptr[p.n]).any(|q| p.row_idx[q] == 0));
    let mut aug = Augmented::default();
    let mut check = |rows: &[Vec<(usize, f64)>], beside: &[(usize, usize, f64)]| {
        solve_bordered(&mut aug, (&p, &k), rows, beside, 5);
        aug.analyses
    };
    assert_eq!(check(&rows, &near), 1);
    assert_eq!(check(&moved, &far), 2);
    assert_eq!(check(&rows, &near), 2);
    assert_eq!(check(&moved, &far), 2);
    assert_eq!(check(&rows, &[]), 2);
    // Five rows elsewhere, of one dof each: the kept pattern's entries
    // outnumber the system's own beside the tangent, and its pattern is
    // its own (a third analysis); back to the first rows, whose entries
    // outnumber those, the new pattern takes them in (a fourth).
    let single: Rows = (0..5).map(|i| vec![(2 * i + 1, 1.0)]).collect();
    assert_eq!(check(&single, &[]), 3);
    assert_eq!(check(&rows, &[]), 4);
}

/// With slots, a contact set that loses rows, or comes back to rows it
/// had, keeps the pattern: one analysis while the keys fit, every solve
/// exact against the dense system.
#[test]
fn multipliers_in_slots_keep_the_analysis() {
    let mut rng = Rng(11);
    let (p, k) = q4(9, 8, true);
    let rows = contact_rows(9, 8, 5, &mut rng);
    let mut aug = Augmented::with_slots(true);
    let check = |aug: &mut Augmented, rows: &[Vec<(usize, f64)>], extra_k: &[_]| {
        solve_bordered(aug, (&p, &k), rows, extra_k, 3);
        (aug.analyses, aug.ldlt, aug.lu + aug.ldu)
    };
    assert_eq!(check(&mut aug, &rows, &[]), (1, 1, 0));
    // Rows left out, in any order: their slots stay empty.
    assert_eq!(check(&mut aug, &rows[..4], &[]), (1, 2, 0));
    let some: Rows = vec![rows[3].clone(), rows[0].clone()];
    assert_eq!(check(&mut aug, &some, &[]), (1, 3, 0));
    // A row with other dofs: a slot more, analysed again; then the first
    // set fits again.
    let mut rows3 = rows.clone();
    rows3[4] = vec![(p.n - 1, 1.0), (p.n - 3, -1.0)];
    assert_eq!(check(&mut aug, &rows3, &[]), (2, 4, 0));
    assert_eq!(check(&mut aug, &rows, &[]), (2, 5, 0));
    // Unsymmetric (an entry on a contact node's dofs, as a sliding
    // gradient): no LU; the tangent with every slot empty factored by LDLT
    // on the same analysis, the system solved on its trailing block.
    assert!(rows.iter().flatten().any(|&(d, _)| d == 0));
    let trailing = aug.trailing_solves;
    assert_eq!(check(&mut aug, &rows[1..], &[(1, 0, 0.3)]), (2, 6, 0));
    assert_eq!(check(&mut aug, &rows[2..], &[(1, 0, 0.3)]), (2, 7, 0));
    assert_eq!(aug.trailing_solves, trailing + 2);
    // Unsymmetric away from the contact rows: factored whole (by the
    // unpivoted LDU) on the same pattern.
    let inner = 2 * (4 * 9 + 4);
    assert!(
        rows.iter()
            .flatten()
            .all(|&(d, _)| d != inner && d != inner + 1)
    );
    assert_eq!(
        check(&mut aug, &rows[2..], &[(inner + 1, inner, 0.3)]),
        (3, 7, 1)
    );
    assert_eq!((aug.method(), aug.lu), (Some(Method::Ldu), 0));
    // No rows at all.
    assert_eq!(check(&mut aug, &[], &[]).1, 8);
}

/// Inner solves on the trailing block of the factor (the slots' dofs and
/// multipliers eliminated last): releases, an unsymmetric row, a tangent
/// entry changed on a contact dof, each against the dense system; a change
/// outside the trailing set is factored instead, and right.
#[test]
fn trailing_solves_match_the_dense_system() {
    let mut rng = Rng(31);
    let (p, k) = q4(12, 10, true);
    let rows = contact_rows(12, 10, 6, &mut rng);
    let n_disp = p.n;
    let mut aug = Augmented::with_slots(true);
    aug.new_tangent();
    let mut extra = border(n_disp, &rows);
    let b0 = rhs(n_disp + rows.len(), &mut Rng(3));
    let mut x = b0.clone();
    aug.solve(&p, &k, &mut extra, &mut x).unwrap();
    assert_eq!(aug.method(), Some(Method::Ldlt));
    let kmax = k.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    // A contact dof (in the trailing set) and a dof far from the rows.
    let (contact_dof, inner_dof) = (rows[0][0].0, 2 * (5 * 12 + 6));
    assert!(rows.iter().flatten().all(|&(d, _)| d != inner_dof));
    let mut check = |extra: &mut Vec<(usize, usize, f64)>, b: &[f64], trailing: bool| {
        let n = b.len();
        let a = dense(&p, &k, extra, n);
        let mut x = b.to_vec();
        let (before, factored) = (aug.trailing_solves, aug.factorizations);
        aug.solve(&p, &k, extra, &mut x).unwrap();
        let r = residual(&a, &x, b);
        assert!(r < 1e-10, "residual {r:e}");
        assert_eq!(aug.trailing_solves - before, usize::from(trailing));
        assert_eq!(aug.factorizations - factored, usize::from(!trailing));
        // The solve before its refinement was sound: the refinement
        // corrects round-off only (a wrong forward substitution kept from
        // the last solve would be corrected there, unseen in x).
        if trailing {
            let c = aug.trailing_work.correction;
            assert!(c < 1e-12, "refinement step {c:e} of x");
        }
    };
    // Rows 1 and 3 released.
    let kept: Rows = [0, 2, 4, 5].map(|i| rows[i].clone()).to_vec();
    let b1 = rhs(n_disp + kept.len(), &mut Rng(11));
    check(&mut border(n_disp, &kept), &b1, true);
    // The same system, its right-hand side changed on the trailing set only
    // (a contact dof and the multipliers' rows), as between inner solves:
    // the last forward substitution serves, shifted.
    let mut b2 = b1.clone();
    b2[contact_dof] += 3.0;
    for v in &mut b2[n_disp..] {
        *v -= 0.5;
    }
    check(&mut border(n_disp, &kept), &b2, true);
    // Row 5's column unlike its row (a slip row's friction column), and a
    // tangent entry changed on a contact dof.
    let mut extra = border(n_disp, &kept[..3]);
    let m5 = n_disp + 3;
    for &(d, c) in &rows[5] {
        extra.push((m5, d, c));
        extra.push((d, m5, 0.7 * c));
    }
    extra.push((contact_dof, contact_dof, 0.25 * kmax));
    check(&mut extra, &rhs(n_disp + 4, &mut Rng(12)), true);
    // A tangent entry changed away from the contact rows: factored.
    let mut extra = border(n_disp, &kept);
    extra.push((inner_dof, inner_dof, 0.25 * kmax));
    check(&mut extra, &rhs(n_disp + kept.len(), &mut Rng(13)), false);
}

/// The trailing block serves while the caller's counted tangent is the
/// factored one's (`new_tangent`): a change it reports, or a caller that
/// counts none, has the system factored, and right.
#[test]
fn a_counted_tangent_change_leaves_the_trailing_block() {
    let mut rng = Rng(41);
    let (p, k) = q4(12, 10, true);
    let rows = contact_rows(12, 10, 6, &mut rng);
    let n_disp = p.n;
    let kept: Rows = [0, 2, 4, 5].map(|i| rows[i].clone()).to_vec();
    let b = rhs(n_disp + kept.len(), &mut Rng(11));
    // The trailing solves and factorizations of the released system on
    // tangent `k`, and its residual.
    let solve = |aug: &mut Augmented, k: &[f64]| {
        let mut x = b.clone();
        let counts = (aug.trailing_solves, aug.factorizations);
        aug.solve(&p, k, &mut border(n_disp, &kept), &mut x)
            .unwrap();
        let a = dense(&p, k, &border(n_disp, &kept), b.len());
        let r = residual(&a, &x, &b);
        assert!(r < 1e-10, "residual {r:e}");
        (
            aug.trailing_solves - counts.0,
            aug.factorizations - counts.1,
        )
    };
    for counted in [true, false] {
        let mut aug = Augmented::with_slots(true);
        if counted {
            aug.new_tangent();
        }
        let mut x = rhs(n_disp + rows.len(), &mut Rng(3));
        aug.solve(&p, &k, &mut border(n_disp, &rows), &mut x)
            .unwrap();
        // The same tangent: on the trailing block when counted.
        let want = if counted { (1, 0) } else { (0, 1) };
        assert_eq!(solve(&mut aug, &k), want, "counted {counted}");
        if !counted {
            continue;
        }
        // A tangent entry changed far from the contact rows (an entry off
        // the diagonal: the tangent unsymmetric), the change reported:
        // factored (the tangent's LDLT with the slots empty, then the LDU).
        let mut k1 = k.clone();
        let inner = p.col_ptr[2 * (5 * 12 + 6)];
        k1[inner] *= 1.25;
        aug.new_tangent();
        let (trailing, factored) = solve(&mut aug, &k1);
        assert_eq!(trailing, 0);
        assert!(factored >= 1);
    }
}

/// A partial inner solve on the trailing block (`solve_watching`) gives
/// the multipliers and the watched unknowns as the whole solve does,
/// leaves interior unknowns it did not need unsolved (NaN), and `finish`
/// completes it into the system's solution; a later solve drops what was
/// left partial.
#[test]
fn deferred_trailing_solves_give_the_watched_unknowns_then_the_solution() {
    let mut rng = Rng(41);
    let (p, k) = q4(16, 12, true);
    let rows = contact_rows(16, 12, 6, &mut rng);
    let n_disp = p.n;
    let mut aug = Augmented::with_slots(true);
    aug.new_tangent();
    let mut extra = border(n_disp, &rows);
    let mut x = rhs(n_disp + rows.len(), &mut Rng(3));
    aug.solve(&p, &k, &mut extra, &mut x).unwrap();
    // Nothing partial: `finish` leaves the solution as it is.
    let solved = x.clone();
    aug.finish(&p, &k, &mut extra, &mut x).unwrap();
    assert_eq!(x, solved);
    // Watched: a contact dof and a few dofs away from the rows (their
    // values need the supernodes above theirs).
    let contact_dof = rows[0][0].0;
    let mut watch = vec![contact_dof];
    let on_rows = |w: usize| rows.iter().flatten().any(|&(d, _)| d == w);
    watch.extend((1..n_disp).step_by(41).filter(|&w| !on_rows(w)));
    // Rows 1 and 3 released.
    let kept: Rows = [0, 2, 4, 5].map(|i| rows[i].clone()).to_vec();
    let mut extra = border(n_disp, &kept);
    let b = rhs(n_disp + kept.len(), &mut Rng(11));
    let a = dense(&p, &k, &extra, b.len());
    let mut partial = b.clone();
    let whole = aug.solve_watching(&p, &k, &mut extra, &mut partial, Some(&watch));
    assert!(!whole.unwrap());
    assert_eq!(aug.deferred_rhs().as_deref(), Some(&b[..]));
    assert_eq!((aug.trailing_solves, aug.deferred_solves), (1, 1));
    let unsolved = partial[..n_disp].iter().filter(|v| v.is_nan()).count();
    assert!(unsolved > 0, "every interior unknown solved");
    let mut x = partial.clone();
    let factored = aug.factorizations;
    aug.finish(&p, &k, &mut extra, &mut x).unwrap();
    assert_eq!(aug.factorizations, factored, "finished by a factorization");
    assert!(aug.deferred_rhs().is_none());
    let r = residual(&a, &x, &b);
    assert!(r < 1e-10, "residual {r:e}");
    // The deferred solve is the same solve, before its refinement.
    let scale = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let known = (watch.iter().copied()).chain(n_disp..b.len());
    for i in known {
        let d = (partial[i] - x[i]).abs();
        assert!(
            d <= 1e-10 * scale,
            "unknown {i}: {} against {}",
            partial[i],
            x[i]
        );
    }
    // Partial again, then another solve: nothing left to finish.
    let mut y = b.clone();
    let whole = aug.solve_watching(&p, &k, &mut extra, &mut y, Some(&watch));
    assert!(!whole.unwrap());
    let mut z = b.clone();
    aug.solve(&p, &k, &mut extra, &mut z).unwrap();
    assert!(aug.deferred_rhs().is_none());
    let unfinished = y.clone();
    aug.finish(&p, &k, &mut extra, &mut y).unwrap();
    assert!(
        y.iter()
            .zip(&unfinished)
            .all(|(a, b)| a.to_bits() == b.to_bits())
    );
    assert!(residual(&a, &z, &b) < 1e-10);
}

/// The symmetry test against the dense definition on random sparse
/// patterns: symmetric ones, one entry changed beyond and within the
/// tolerance, and one entry whose transpose is not stored (above the
/// diagonal and below it), which the one-pass cursors must still see.
#[test]
fn symmetry_test_matches_its_dense_definition() {
    let mut rng = Rng(57);
    let n = 40;
    let csc = |a: &DMatrix<f64>, stored: &dyn Fn(usize, usize) -> bool| {
        let (mut ptr, mut idx, mut val) = (vec![0], Vec::new(), Vec::new());
        for j in 0..n {
            for i in 0..n {
                if stored(i, j) {
                    idx.push(i);
                    val.push(a[(i, j)]);
                }
            }
            ptr.push(idx.len());
        }
        (ptr, idx, val)
    };
    for trial in 0..20 {
        let mut a = DMatrix::<f64>::zeros(n, n);
        for j in 0..n {
            for i in j..n {
                if i == j || rng.next() > 0.6 {
                    let v = rng.next() + if i == j { 4.0 } else { 0.0 };
                    a[(i, j)] = v;
                    a[(j, i)] = v;
                }
            }
        }
        let nonzero = |i: usize, j: usize| a[(i, j)] != 0.0;
        let (ptr, idx, val) = csc(&a, &nonzero);
        assert!(is_symmetric(&ptr, &idx, &val), "trial {trial}");
        // Off-diagonal entries, their values changed by 1e-9 and by 1e-14.
        let (i, j) = (0..n * n)
            .map(|q| (q % n, q / n))
            .find(|&(i, j)| i != j && nonzero(i, j) && (i * 7 + j * 3 + trial) % 5 == 0)
            .expect("an off-diagonal entry");
        for (dv, symmetric) in [(1e-9, false), (1e-14, true)] {
            let mut b = a.clone();
            b[(i, j)] += dv;
            let (ptr, idx, val) = csc(&b, &nonzero);
            assert_eq!(
                is_symmetric(&ptr, &idx, &val),
                symmetric,
                "trial {trial}, {dv:e}"
            );
        }
        // A stored entry without its transpose: above, then below the diagonal.
        let free = (0..n * n)
            .map(|q| (q % n, q / n))
            .filter(|&(i, j)| i < j && !nonzero(i, j))
            .nth(trial)
            .expect("a zero pair");
        for (r, c) in [free, (free.1, free.0)] {
            let mut b = a.clone();
            b[(r, c)] = 0.5;
            let stored = |i: usize, j: usize| b[(i, j)] != 0.0;
            let (ptr, idx, val) = csc(&b, &stored);
            assert!(!is_symmetric(&ptr, &idx, &val), "trial {trial}, ({r}, {c})");
        }
    }
}

/// The values of a bordered matrix written over a kept pattern
/// (`values_in_pattern`) are `bordered`'s bit for bit, entries summed in
/// pairs included, on a tangent with contact rows, a friction-like column
/// and a changed tangent entry; refused where a stored entry would sum
/// three terms, where an entry lies outside the pattern, and where the
/// pattern would lose an entry. The slots' index (`SlotGroups::place`)
/// places each key on the first free slot of its own.
#[test]
fn values_written_over_a_kept_pattern_are_bordered_values() {
    let mut rng = Rng(61);
    let (p, k) = q4(6, 5, true);
    let rows = contact_rows(6, 5, 4, &mut rng);
    let n = p.n + rows.len();
    let mut extra = border(p.n, &rows);
    let (d0, m0) = (rows[0][0].0, p.n);
    // Beside a multiplier's column, at a tangent entry (two terms), and
    // twice at one place off the tangent's diagonal (two terms again).
    extra.push((d0, m0, 0.3));
    extra.push((d0, d0, 0.7 * rng.next()));
    let off = (p.row_idx[p.col_ptr[3]], 3);
    extra.push((off.0, off.1, 0.1));
    let far = (0..p.n)
        .find(|r| !p.row_idx[p.col_ptr[d0]..p.col_ptr[d0 + 1]].contains(r))
        .expect("a row off the tangent's column");
    extra.push((far, d0, 1e-3));
    extra.push((far, d0, -2e-3));
    let mut sorted = extra.clone();
    let (col_ptr, row_idx, want) = bordered_new(&p, &k, &mut sorted, n);
    let pattern = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
    let (mut values, mut terms) = (Vec::new(), Vec::new());
    // In the given order and in reverse: the same values.
    for list in [extra.clone(), extra.iter().rev().copied().collect()] {
        assert!(values_in_pattern(
            pattern.as_ref(),
            &p,
            &k,
            &list,
            &mut values,
            &mut terms
        ));
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&values), bits(&want));
    }
    // A third term at (far, d0): left to `bordered`.
    let mut three = extra.clone();
    three.push((far, d0, 5e-4));
    assert!(!values_in_pattern(
        pattern.as_ref(),
        &p,
        &k,
        &three,
        &mut values,
        &mut terms
    ));
    // An entry outside the pattern (two multipliers coupled).
    let mut outside = extra.clone();
    outside.push((m0, m0 + 1, 1.0));
    assert!(!values_in_pattern(
        pattern.as_ref(),
        &p,
        &k,
        &outside,
        &mut values,
        &mut terms
    ));
    // Without the two entries at (far, d0) that place is no longer stored.
    let fewer: Vec<_> = extra
        .iter()
        .copied()
        .filter(|e| (e.0, e.1) != (far, d0))
        .collect();
    let mut sorted = fewer.clone();
    let (col_ptr, row_idx, _) = bordered_new(&p, &k, &mut sorted, n);
    assert_eq!(row_idx.len() + 1, pattern.row_idx().len());
    assert_ne!(col_ptr.as_slice(), pattern.col_ptr());
    assert!(!values_in_pattern(
        pattern.as_ref(),
        &p,
        &k,
        &fewer,
        &mut values,
        &mut terms
    ));
    // Slots: keys repeated, placed on the first free slot of each.
    let key = |r: &[usize]| SlotKey {
        row: r.to_vec(),
        column: r.to_vec(),
    };
    let slots = vec![key(&[1, 2]), key(&[3]), key(&[1, 2]), key(&[4]), key(&[3])];
    let groups = SlotGroups::of(&slots);
    for (keys, want) in [
        (
            vec![key(&[3]), key(&[1, 2]), key(&[1, 2]), key(&[3])],
            Some(vec![1, 0, 2, 4]),
        ),
        (vec![key(&[4])], Some(vec![3])),
        (vec![key(&[1, 2]), key(&[1, 2]), key(&[1, 2])], None),
        (vec![key(&[5])], None),
    ] {
        assert_eq!(groups.place(&keys), want, "{keys:?}");
    }
}

/// The trailing block's dense solver of `S0 + Delta`: by the low-rank
/// update of `S0`'s LU when `Delta` touches few columns (and by `S0`'s LU
/// alone when it touches none), by its own LU otherwise, and by the update
/// of that LU when the next `Delta` differs from its in fewer columns than
/// from `S0`; each against nalgebra's dense LU, on an unsymmetric,
/// indefinite `S0`.
#[test]
fn trailing_dense_solver_matches_a_dense_solve() {
    let mut rng = Rng(63);
    let t = 40;
    let s0 = Mat::from_fn(t, t, |i, j| {
        rng.next()
            + if i == j {
                6.0 * (-1.0f64).powi(i as i32)
            } else {
                0.0
            }
    });
    let b: Vec<f64> = (0..t).map(|_| rng.next()).collect();
    let mut bases = DenseBases::default();
    let change = |columns: std::ops::Range<usize>, rng: &mut Rng| {
        let mut delta = Vec::new();
        for q in columns {
            let j = (7 * q + 2) % t;
            for i in [j, (j + 5) % t, (3 * j + 1) % t] {
                delta.push((i, j, 2.0 * rng.next()));
            }
        }
        delta
    };
    let eleven = change(0..11, &mut rng);
    let mut twelve = eleven.clone();
    twelve.extend(change(11..12, &mut rng));
    // The first of the eleven columns changed again.
    twelve.push((2, 2, 0.5));
    for (delta, kind) in [
        (Vec::new(), "s0"),
        (change(0..3, &mut rng), "updated s0"),
        (change(0..10, &mut rng), "updated s0"),
        (eleven, "own"),
        (twelve, "updated last"),
        (change(0..3, &mut rng), "updated s0"),
    ] {
        let dense = Dense::new(&s0, &mut bases, &delta, t);
        let is = |base: &Arc<_>, of: Option<&Arc<_>>| of.is_some_and(|b| Arc::ptr_eq(base, b));
        let last = bases.last.as_ref().map(|(_, lu)| lu);
        let got = match &dense {
            Dense::Lu(lu) if is(lu, bases.s0.as_ref()) => "s0",
            Dense::Lu(lu) if is(lu, last) => "own",
            Dense::Lu(_) => "unknown",
            Dense::Updated(u) if is(&u.base, bases.s0.as_ref()) => "updated s0",
            Dense::Updated(u) if is(&u.base, last) => "updated last",
            Dense::Updated(_) => "updated unknown",
        };
        assert_eq!(got, kind, "{} entries", delta.len());
        let mut a = DMatrix::from_fn(t, t, |i, j| s0[(i, j)]);
        for &(i, j, d) in &delta {
            a[(i, j)] += d;
        }
        let expected = a
            .lu()
            .solve(&DVector::from_column_slice(&b))
            .expect("regular");
        let mut x = b.clone();
        dense.solve(&mut x);
        let error = (0..t)
            .map(|i| (x[i] - expected[i]).abs())
            .fold(0.0, f64::max);
        assert!(error < 1e-12 * expected.amax(), "{kind}: error {error:e}");
    }
}

#[test]
fn no_multipliers_is_plain_ldlt() {
    let (p, k) = q4(8, 8, true);
    let b = rhs(p.n, &mut Rng(5));
    let (x, aug) = solve(&p, &k, &[], &b, false);
    assert_eq!(aug.method(), Some(Method::Ldlt));
    assert!(residual(&dense(&p, &k, &[], p.n), &x, &b) < 1e-10);
}

/// A body held only by the contact rows: K is singular (two zero-energy
/// modes), the bordered system is not. The unpivoted LDLT with the
/// multipliers last meets a (round-off) zero pivot; the solve must still be
/// right (LU).
#[test]
fn floating_body_held_by_contact_rows() {
    let (p, k) = q4(10, 10, false);
    let rows = vec![vec![(0, 1.0)], vec![(1, 1.0)], vec![(20, 0.5), (21, 0.5)]];
    let n = p.n + rows.len();
    let extra = border(p.n, &rows);
    let b = rhs(n, &mut Rng(13));
    let (x, aug) = solve(&p, &k, &extra, &b, false);
    let r = residual(&dense(&p, &k, &extra, n), &x, &b);
    assert!(r < 1e-10, "{:?}: residual {r:e}", aug.method());
    assert_eq!(aug.method(), Some(Method::Lu));
    assert_eq!((aug.ldlt, aug.lu, aug.factorizations), (0, 1, 2));
}

/// The same floating body with slots, its rows symmetric, then with a
/// friction-like column on its third row (unsymmetric, inside the trailing
/// set). The tangent with every slot empty is factored with the contact
/// dofs last: its interior is the body with those dofs held, regular, and
/// the dense system on the trailing set (with the multipliers) is regular
/// too, so the solve is right without LU, where the unpivoted LDLT of the
/// whole system is not (tried first for the symmetric one, and failed).
#[test]
fn floating_body_unsymmetric_on_the_trailing_block() {
    let (p, k) = q4(10, 10, false);
    let rows = [vec![(0, 1.0)], vec![(1, 1.0)], vec![(20, 0.5), (21, 0.5)]];
    let n = p.n + rows.len();
    let mut symmetric = border(p.n, &rows);
    let b = rhs(n, &mut Rng(12));
    let mut x = b.clone();
    let mut aug = Augmented::with_slots(true);
    aug.solve(&p, &k, &mut symmetric, &mut x).unwrap();
    let r = residual(&dense(&p, &k, &symmetric, n), &x, &b);
    assert!(r < 1e-10, "{:?}: residual {r:e}", aug.method());
    assert_eq!(aug.method(), Some(Method::Ldlt));
    assert_eq!((aug.ldlt, aug.lu, aug.factorizations), (1, 0, 2));
    let mut extra = border(p.n, &rows[..2]);
    for &(d, c) in &rows[2] {
        extra.push((p.n + 2, d, c));
        extra.push((d, p.n + 2, 0.7 * c));
    }
    let a = dense(&p, &k, &extra, n);
    for seed in [13, 14] {
        let b = rhs(n, &mut Rng(seed));
        let mut x = b.clone();
        aug.solve(&p, &k, &mut extra.clone(), &mut x).unwrap();
        let r = residual(&a, &x, &b);
        assert!(r < 1e-10, "{:?}: residual {r:e}", aug.method());
        assert_eq!(aug.method(), Some(Method::Ldlt));
    }
    assert_eq!((aug.ldlt, aug.lu, aug.trailing_solves), (3, 0, 3));
}

/// The shortest of `reps` runs of `f`, in seconds.
fn best(reps: usize, f: &mut dyn FnMut()) -> f64 {
    (0..reps)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

/// A tangent over its pattern, the entries beside it and the order.
type System = (Pattern, Vec<f64>, Vec<(usize, usize, f64)>, usize);

/// The timing tests' system: a fixed `side` x `side` Q4 tangent bordered
/// by 100 contact rows, and its order.
fn timing_system(side: usize, rng: &mut Rng) -> System {
    let (p, k) = q4(side, side, true);
    let rows = contact_rows(side, side, 100, rng);
    let n = p.n + rows.len();
    let extra = border(p.n, &rows);
    (p, k, extra, n)
}

/// Numeric LDLT against numeric LU (symbolic analyses cached) on Q4-like
/// matrices of about 1e4 and 1e5 unknowns with 100 contact rows:
/// `cargo test --release --lib linsolve::tests::timing -- --ignored --nocapture`.
#[test]
#[ignore]
fn timing_ldlt_against_lu() {
    for (side, reps) in [(71, 5), (224, 3)] {
        let mut rng = Rng(17);
        let (p, k, extra, n) = timing_system(side, &mut rng);
        let b = rhs(n, &mut rng);

        let t = Instant::now();
        let (x_ldlt, mut ldlt) = solve(&p, &k, &extra, &b, false);
        let first_ldlt = t.elapsed().as_secs_f64();
        assert_eq!(ldlt.method(), Some(Method::Ldlt));
        let t = Instant::now();
        let (x_lu, mut lu) = solve(&p, &k, &extra, &b, true);
        let first_lu = t.elapsed().as_secs_f64();
        let diff = x_ldlt
            .iter()
            .zip(&x_lu)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        let xmax = x_lu.iter().fold(0.0f64, |m, v| m.max(v.abs()));

        // Full solve() with the analysis cached.
        let solve_ldlt = best(reps, &mut || {
            let mut x = b.clone();
            ldlt.solve(&p, &k, &mut extra.clone(), &mut x).unwrap();
        });
        let solve_lu = best(reps, &mut || {
            let mut x = b.clone();
            lu.solve(&p, &k, &mut extra.clone(), &mut x).unwrap();
        });
        assert_eq!((ldlt.lu, lu.ldlt), (0, 0));

        // Numeric factorizations alone.
        let a = ldlt.analysis.as_mut().unwrap();
        let (symbolic, mem) = a.ldlt.as_mut().unwrap();
        let mat = SparseColMatRef::new(a.mat.as_ref(), &ldlt.values);
        let mut l_values = vec![0.0; symbolic.len_val()];
        let supernodal = matches!(
            symbolic.raw(),
            faer::sparse::linalg::cholesky::SymbolicCholeskyRaw::Supernodal(_)
        );
        let num_ldlt = best(reps, &mut || {
            symbolic
                .factorize_numeric_ldlt(
                    &mut l_values,
                    mat,
                    Side::Lower,
                    LdltRegularization::default(),
                    Par::Seq,
                    MemStack::new(mem),
                    Default::default(),
                )
                .unwrap();
        });
        let a_lu = lu.analysis.as_ref().unwrap();
        let sym_lu = &a_lu.lu.as_ref().unwrap().0;
        let mat_lu = SparseColMatRef::new(a_lu.mat.as_ref(), &lu.values);
        let mut numeric = NumericLu::new();
        let req = sym_lu.factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default());
        let mut mem_lu = MemBuffer::new(req);
        let num_lu = best(reps, &mut || {
            sym_lu
                .factorize_numeric_lu(
                    &mut numeric,
                    mat_lu,
                    Par::Seq,
                    MemStack::new(&mut mem_lu),
                    Default::default(),
                )
                .unwrap();
        });
        // Reference: LLT of K alone (the notes' table).
        let ks =
            SymbolicSparseColMat::new_checked(p.n, p.n, p.col_ptr.clone(), None, p.row_idx.clone());
        let t = Instant::now();
        let sym_llt = SymbolicLlt::try_new(ks.as_ref(), Side::Lower).unwrap();
        let symbolic_llt = t.elapsed().as_secs_f64();
        let kmat = SparseColMatRef::new(ks.as_ref(), &k);
        let num_llt = best(reps, &mut || {
            Llt::try_new_with_symbolic(sym_llt.clone(), kmat, Side::Lower).unwrap();
        });
        println!(
            "n = {n} ({} + {} rows), nnz(A) = {}: LDLT ({}, nnz(L) = {}) numeric {:.4} s, \
             first solve {:.4} s, cached solve {:.4} s | LU numeric {:.4} s, first solve \
             {:.4} s, cached solve {:.4} s | LLT of K: symbolic {:.4} s, numeric {:.4} s | \
             max |x_ldlt - x_lu| = {:.1e} of max |x| {:.1e}",
            p.n,
            n - p.n,
            ldlt.values.len(),
            if supernodal {
                "supernodal"
            } else {
                "simplicial"
            },
            symbolic.len_val(),
            num_ldlt,
            first_ldlt,
            solve_ldlt,
            num_lu,
            first_lu,
            solve_lu,
            symbolic_llt,
            num_llt,
            diff,
            xmax,
        );
    }
}

/// What a kept pattern's refill costs (`values_in_pattern`) against
/// faer's argsort: the argsort of the system's entries (the tangent's and
/// those beside it; made again for each system, as the entries beside the
/// tangent change from system to system) and the refill from it. Run with
/// `cargo test --release --lib timing_pattern_refill -- --ignored
/// --nocapture`; docs/performance-log.md holds the figures.
#[test]
#[ignore]
fn timing_pattern_refill_against_argsort() {
    use faer::sparse::{Pair, SparseColMat};
    for (side, reps) in [(71, 20), (224, 5)] {
        let mut rng = Rng(17);
        let (p, k, extra, n) = timing_system(side, &mut rng);
        let (_, aug) = solve(&p, &k, &extra, &rhs(n, &mut rng), false);
        let mat = aug.analysis.as_ref().unwrap().mat.clone();
        let (mut values, mut terms) = (Vec::new(), Vec::new());
        let in_place = best(reps, &mut || {
            assert!(values_in_pattern(
                mat.as_ref(),
                &p,
                &k,
                &extra,
                &mut values,
                &mut terms
            ));
        });
        // The entries as faer takes them: indices, then values.
        let mut idx = Vec::with_capacity(k.len() + extra.len());
        let mut val = Vec::with_capacity(k.len() + extra.len());
        for c in 0..p.n {
            for q in p.col_ptr[c]..p.col_ptr[c + 1] {
                idx.push(Pair::new(p.row_idx[q], c));
                val.push(k[q]);
            }
        }
        for &(r, c, v) in &extra {
            idx.push(Pair::new(r, c));
            val.push(v);
        }
        let mut argsorted = None;
        let argsort = best(reps, &mut || {
            argsorted = Some(SymbolicSparseColMat::try_new_from_indices(n, n, &idx).unwrap());
        });
        let (symbolic, order) = argsorted.unwrap();
        let mut refilled = None;
        let refill = best(reps, &mut || {
            refilled =
                Some(SparseColMat::new_from_argsort(symbolic.clone(), &order, &val).unwrap());
        });
        let refilled = refilled.unwrap();
        let diff =
            (refilled.val().iter().zip(&values)).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        println!(
            "{n:>7} unknowns, {} entries: in place {:.3} ms; faer argsort {:.3} ms + refill {:.3} ms; largest difference {diff:.1e}",
            idx.len(),
            1e3 * in_place,
            1e3 * argsort,
            1e3 * refill,
        );
    }
}
