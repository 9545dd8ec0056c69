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

use crate::assembly::Pattern;
pub use crate::results::LinearTimes;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::linalg::solvers::Solve;
use faer::perm::PermRef;
use faer::sparse::linalg::amd;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, SymbolicCholesky, SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::sparse::linalg::lu::{LuRef, NumericLu, SymbolicLu as LuSymbolic};
use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::sparse::{FaerError, SparseColMatRef, SymbolicSparseColMat, SymbolicSparseColMatRef};
use faer::{Conj, Mat, MatMut, Par, Side};
use std::borrow::Cow;
use std::time::Instant;

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
    /// Sparse LDLT without pivoting (the symmetric bordered system).
    Ldlt,
    Lu,
    /// Sparse LDU without pivoting (the unsymmetric bordered system of a
    /// small or mid-size scene, `ldu`).
    Ldu,
}

/// Symbolic data of one pattern of the bordered matrix, kept while it holds.
struct Analysis {
    mat: SymbolicSparseColMat<usize>,
    /// Order of the displacement block (the multipliers follow it).
    n_disp: usize,
    /// LDLT analysis (AMD of the displacement block, multipliers last) and
    /// its workspace; made on the first symmetric system of the pattern.
    ldlt: Option<(SymbolicCholesky<usize>, MemBuffer)>,
    /// LDLT failed on this pattern: LU until the pattern changes or the
    /// multipliers take other slots.
    ldlt_failed: bool,
    /// An unsymmetric system of this pattern failed on the tangent's LDLT
    /// with every slot empty (`Augmented::solve_kept`): LU for the rest.
    split_failed: bool,
    /// LU's symbolic analysis and its factorization's workspace.
    lu: Option<(LuSymbolic<usize>, MemBuffer)>,
    /// The unpivoted LDU's analysis (`ldu`), made on the first unsymmetric
    /// system of the pattern; None with `ldu_failed`.
    ldu: Option<ldu::Symbolic>,
    /// The LDU does not serve this pattern (its factor too dense for its
    /// scalar loops, or a solve failed its checks): LU until the pattern
    /// changes.
    ldu_failed: bool,
    /// Unknowns of the trailing set eliminated last by the LDLT analysis
    /// (`trailing`), 0 without one.
    trailing: usize,
    /// The multiplier unknowns `n_disp..` of the pattern: a system's
    /// multipliers take slots of their key (`place`); a slot left empty is
    /// an identity row, its entries on the key's dofs zeros (`in_slots`).
    /// So a contact set that loses rows, or changes rows between keys it
    /// had before, keeps the pattern and its analyses (issue 14).
    slots: Vec<SlotKey>,
    /// `slots` by key, for `SlotGroups::place`.
    slot_groups: SlotGroups,
}

/// The saddle-point system of Eq. (18): the free-dof tangent bordered by the
/// contact rows, `[K + K_c, C^T; C, 0]`. Its pattern changes with the contact
/// set; the symbolic analyses are kept while the pattern holds.
///
/// A numerically symmetric system (`|a_ij - a_ji| <= 1e-12 max|a|` over the
/// stored entries) is factored by sparse LDLT without pivoting, ordered by AMD
/// on the displacement block with the multipliers last (their Schur
/// complement `-C K^-1 C^T` is negative definite when K is positive
/// definite). An unsymmetric system, or one whose LDLT meets a zero pivot,
/// gives non-finite values, a backward error above `1e-8` or a refinement
/// step larger than `1e-6` of the solution (a near-null direction of K: a
/// body held by contact alone), is solved by sparse LU; after such an LDLT
/// failure the pattern stays on LU.
#[derive(Default)]
pub struct Augmented {
    /// Column pointers and row indices for the next system's pattern (the
    /// system's own are its analysis's, `Analysis::mat`).
    spare: [Vec<usize>; 2],
    values: Vec<f64>,
    /// Per stored entry, the terms `values_in_pattern` has summed there.
    terms: Vec<u8>,
    analysis: Option<Analysis>,
    /// Values of the LDLT factor.
    l_values: Vec<f64>,
    /// The system's own values while `values` holds the tangent with every
    /// slot empty that `solve_kept` factored for it (an unsymmetric system
    /// solved on the trailing block).
    split_values: Vec<f64>,
    /// Solution of the LDLT path before it is accepted.
    x: Vec<f64>,
    last: Option<Method>,
    /// Solve every system by LU (comparisons); LDLT is tried only when false.
    pub force_lu: bool,
    /// No trailing set (`trailing`): every solve is factored
    /// (comparisons).
    pub no_trailing: bool,
    /// Numeric factorizations done (LDLT attempts that failed included).
    pub factorizations: usize,
    /// Symbolic analyses done (LDLT or LU; at most one of each per distinct
    /// pattern in a row).
    pub analyses: usize,
    /// Solves done by LDLT.
    pub ldlt: usize,
    /// Solves done by LU.
    pub lu: usize,
    /// Solves done by the unpivoted LDU (`ldu`).
    pub ldu: usize,
    /// The numeric LDU factor of the last system `solve` factored by it.
    ldu_numeric: ldu::Numeric,
    /// The last LDLT factor's Schur complement onto its trailing set and
    /// the inverse of its diagonal (`trailing::Factor`), kept for the
    /// solves on the trailing block; None after any other factorization.
    schur: Option<(Mat<f64>, Vec<f64>)>,
    /// Solves done on the kept factor's trailing block (`trailing`).
    pub trailing_solves: usize,
    /// Of those, the ones left partial (`solve_watching`).
    pub deferred_solves: usize,
    /// The numeric LU factor of the last system factored by LU, its arrays
    /// kept for the next.
    lu_numeric: NumericLu<usize, f64>,
    lu_order: usize,
    trailing_work: TrailingWork,
    pub times: LinearTimes,
    /// The fill-reducing order of the displacement block (AMD), made on the
    /// first pattern and kept for every later one: the block is the
    /// tangent's pattern plus, against a deformable target, a few contact
    /// couplings, and any order is valid (`analyse_ldlt`).
    disp_order: Option<(Vec<usize>, Vec<usize>)>,
    /// The slot of each multiplier of the last system `solve` factored.
    last_slots: Vec<usize>,
    /// Keep the multipliers in slots (`Analysis::slots`); when false, each
    /// contact set is a pattern of its own.
    pub slots: bool,
    /// The system being solved has no entry between its displacements and
    /// its multipliers (the tangent bordered by empty slots: a solve
    /// without contact rows on the contact system's pattern). Its LDLT is
    /// the tangent's own, and along a near-null direction of the tangent
    /// LU would do no better: the step of refinement that exposes one
    /// (`LDLT_REFINEMENT`) is left out, as the tangent's own LLT solve
    /// (`LinearSolver`) has none.
    decoupled: bool,
    /// The caller's count of its tangent's changes (`new_tangent`); None
    /// while it keeps none.
    tangent: Option<u64>,
    /// The caller's tangents are symmetric (to round-off, as
    /// `is_symmetric` judges): a system is then symmetric when its entries
    /// beside the tangent are (`asymmetry`), and where those are few
    /// `solve` does not sweep the whole matrix for it (0.8 ms of a 35 ms
    /// Hertz increment at 1e4 unknowns). A wrong claim costs time alone: the LDLT's backward
    /// error is taken against the whole stored system, and LU follows.
    pub symmetric_tangent: bool,
    /// With `symmetric_tangent`, the system's `asymmetry`.
    extra_asymmetry: Option<f64>,
}

/// Largest normwise backward error `|b - A x|_inf / (|A|_inf |x|_inf +
/// |b|_inf)` accepted from the unpivoted LDLT before falling back to LU.
pub(super) const LDLT_BACKWARD_ERROR: f64 = 1e-8;
/// Largest correction `|dx|_inf / |x|_inf` over the displacements of one
/// refinement step accepted from the unpivoted LDLT before falling back to
/// LU. Measured: 129 to 8540 on a layer held by contact alone
/// (`scenes/wire_winding.toml`, whose tests fail without the check), 1.3e-7
/// on the buried pipe (whose pipe is held by contact alone too, but whose
/// LDLT solve is sound: its overlaps close to 1e-14, where LU leaves 2e-6).
/// The multipliers are not measured: they are large forces, recovered
/// again from the out-of-balance forces (contact) or corrected by the next
/// iteration's residual (ties).
pub(super) const LDLT_REFINEMENT: f64 = 1e-4;

impl Augmented {
    /// Forgets the slots (and the analysis and factor that hold them):
    /// the next system is laid out from its own multipliers. Without slots
    /// nothing changes (an analysis is a function of its pattern).
    pub fn restart(&mut self) {
        if self.slots {
            self.analysis = None;
            self.schur = None;
            self.last_slots.clear();
        }
    }

    /// The displacement block's fill-reducing order, once made.
    pub fn order(&self) -> Option<&(Vec<usize>, Vec<usize>)> {
        self.disp_order.as_ref()
    }

    /// Takes `order` for the displacement block unless one is made
    /// (`LinearSolver::share_order`; `analyse_ldlt` checks its size).
    pub fn share_order(&mut self, order: Option<&(Vec<usize>, Vec<usize>)>) {
        if self.disp_order.is_none() {
            self.disp_order = order.cloned();
        }
    }

    /// An empty solver whose multipliers keep slots (`slots`) or not.
    pub fn with_slots(slots: bool) -> Self {
        Augmented {
            slots,
            ..Augmented::default()
        }
    }

    /// The caller's tangent has changed (or may have). A caller that says
    /// so after every change it makes (the Newton solver, before each
    /// assembly of K) has its systems solved on the kept factor's trailing
    /// block while the tangent is the factored one's (`solve`); a caller
    /// that never says it has every system factored.
    pub fn new_tangent(&mut self) {
        self.tangent = Some(self.tangent.map_or(0, |g| g + 1));
    }

    /// The factorization the last successful solve used.
    pub fn method(&self) -> Option<Method> {
        self.last
    }

    /// Factors `A` (as given to `solve`) and solves `A x = rhs` in place:
    /// the multipliers placed in the kept analysis's slots, or a new
    /// analysis made; then `solve_kept`.
    fn factor_and_solve(
        &mut self,
        pattern: &Pattern,
        k: &[f64],
        extra: &mut [(usize, usize, f64)],
        rhs: &mut [f64],
    ) -> Result<(), LinearError> {
        self.schur = None;
        self.trailing_work.pending = None;
        let clock = Instant::now();
        let n = rhs.len();
        let n_disp = pattern.n.min(n);
        let keys = (n > n_disp && self.slots)
            .then(|| slot_keys(extra, n_disp, n - n_disp))
            .flatten();
        let slot_of = self.lay_out(pattern, k, extra, n, keys.as_deref());
        self.solve_laid_out(pattern, k, extra, rhs, keys.is_some(), &slot_of, clock)
    }

    /// Lays the system out over the kept analysis (its values in `values`)
    /// and returns the slot of each multiplier: the multipliers in the
    /// slots of the kept analysis, when they fit and the pattern is the
    /// same; else a new analysis, its slots the old ones and the new keys
    /// (while they stay few), else the keys. Without `keys` (no slots), the
    /// system as given, the kept analysis while its pattern holds.
    fn lay_out(
        &mut self,
        pattern: &Pattern,
        k: &[f64],
        extra: &mut [(usize, usize, f64)],
        n: usize,
        keys: Option<&[SlotKey]>,
    ) -> Vec<usize> {
        let n_disp = pattern.n.min(n);
        let mut fresh = false;
        loop {
            let kept = self
                .analysis
                .as_ref()
                .filter(|a| a.n_disp == n_disp && !fresh);
            let placed = keys.zip(kept).and_then(|(k, a)| a.slot_groups.place(k));
            let (slots, slot_of, reuse, groups) = match (placed, keys) {
                (Some(slot_of), _) => {
                    let slots =
                        kept.map_or(Cow::Owned(Vec::new()), |a| Cow::Borrowed(&a.slots[..]));
                    (slots, slot_of, true, None)
                }
                (None, Some(keys)) => {
                    let slots = new_slots(kept.map_or(&[], |a| &a.slots[..]), keys);
                    let groups = SlotGroups::of(&slots);
                    let slot_of = groups.place(keys).expect("every key has a slot");
                    (Cow::Owned(slots), slot_of, false, Some(groups))
                }
                // Multipliers coupled to each other: no slots, the system
                // as given.
                (None, None) => (Cow::Owned(Vec::new()), Vec::new(), false, None),
            };
            let order = if keys.is_some() {
                n_disp + slots.len()
            } else {
                n
            };
            let mut placed_extra: Vec<(usize, usize, f64)>;
            let extra_now: &mut [(usize, usize, f64)] = if keys.is_some() {
                placed_extra = in_slots(extra, n_disp, &slots, &slot_of);
                &mut placed_extra
            } else {
                &mut *extra
            };
            // The kept analysis's pattern, its values written in place.
            let in_place = (reuse || keys.is_none()).then_some(kept).flatten();
            if in_place.is_some_and(|a| {
                a.mat.nrows() == order
                    && values_in_pattern(
                        a.mat.as_ref(),
                        pattern,
                        k,
                        extra_now,
                        &mut self.values,
                        &mut self.terms,
                    )
            }) {
                return slot_of;
            }
            let [mut col_ptr, mut row_idx] = std::mem::take(&mut self.spare);
            bordered(
                pattern,
                k,
                extra_now,
                order,
                [&mut col_ptr, &mut row_idx],
                &mut self.values,
            );
            let same =
                kept.is_some_and(|a| a.mat.col_ptr() == col_ptr && a.mat.row_idx() == row_idx);
            // Without slots, the kept analysis holds while its pattern holds
            // the system's (zeros where the system has no entry).
            let unslotted = keys.is_none() && kept.is_some();
            if (reuse || unslotted) && same {
                self.spare = [col_ptr, row_idx];
                return slot_of;
            }
            let held = kept.filter(|a| unslotted && a.mat.nrows() == order);
            if let Some(a) = held
                && scatter_into(a.mat.as_ref(), &col_ptr, &row_idx, &mut self.values)
            {
                self.spare = [col_ptr, row_idx];
                return slot_of;
            }
            // A new pattern without slots takes in the kept one's entries
            // while they are few beside the system's own (`merge_pattern`):
            // a contact set that moves back and forth between side pairs
            // (a contactor node over a target node) keeps one analysis.
            if let Some(a) = held {
                merge_pattern(
                    a.mat.as_ref(),
                    [&mut col_ptr, &mut row_idx],
                    &mut self.values,
                    extra_now.len(),
                );
            }
            if reuse {
                // The slots fit but the displacement block changed.
                self.spare = [col_ptr, row_idx];
                fresh = true;
                continue;
            }
            // The arrays move into the analysis (at 1e6 unknowns a copy of
            // them took 0.4 s).
            let mat = SymbolicSparseColMat::new_checked(order, order, col_ptr, None, row_idx);
            self.analysis = Some(Analysis {
                mat,
                n_disp,
                ldlt: None,
                ldlt_failed: false,
                split_failed: false,
                lu: None,
                ldu: None,
                ldu_failed: false,
                trailing: 0,
                slot_groups: groups.unwrap_or_else(|| SlotGroups::of(&slots)),
                slots: slots.into_owned(),
            });
            return slot_of;
        }
    }

    /// Solves the system laid out by `lay_out` (`slot_of`: each
    /// multiplier's slot, with `slotted`) by `solve_kept`, `rhs` in place,
    /// and keeps what the trailing solves compare their systems with.
    #[allow(clippy::too_many_arguments)]
    fn solve_laid_out(
        &mut self,
        pattern: &Pattern,
        k: &[f64],
        extra: &[(usize, usize, f64)],
        rhs: &mut [f64],
        slotted: bool,
        slot_of: &[usize],
        clock: Instant,
    ) -> Result<(), LinearError> {
        let n = rhs.len();
        let n_disp = pattern.n.min(n);
        // An LDLT that failed is tried again once the multipliers take
        // other slots (a new contact set, as a new pattern did before).
        if self.last_slots != *slot_of
            && let Some(a) = self.analysis.as_mut()
        {
            a.ldlt_failed = false;
        }
        self.last_slots.clone_from(&slot_of.to_vec());
        // The right-hand side in the slots' order (an empty slot's 0).
        let order = self.analysis.as_ref().map_or(n, |a| a.mat.nrows());
        let mut full = vec![0.0; order];
        if slotted {
            full[..n_disp].copy_from_slice(&rhs[..n_disp]);
            for (m, &s) in slot_of.iter().enumerate() {
                full[n_disp + s] = rhs[n_disp + m];
            }
        } else {
            full.copy_from_slice(rhs);
        }
        self.decoupled = n > n_disp
            && (extra.iter()).all(|&(r, c, v)| v == 0.0 || (r >= n_disp) == (c >= n_disp));
        // (The slots permute rows and columns alike: the entries' symmetry
        // is theirs in any order.) Sorting the entries costs some 30 steps
        // each, the sweep of the whole matrix one per entry, or less when
        // it stops at the first unsymmetric one: the sort only where the
        // entries are few beside the tangent's (Hertz at 1e4, 500 against
        // 180,000; not the capstan FMU's 500-860 against 9,000, where the
        // sort took 23 us and the sweep stops at a friction column).
        self.extra_asymmetry =
            (self.symmetric_tangent && 32 * extra.len() < k.len()).then(|| asymmetry(extra));
        self.times.system += clock.elapsed();
        let split = self.solve_kept(pattern, k, n_disp, &mut full)?;
        // What the trailing solves compare their systems with: this one's
        // tangent and its entries beside it, in the slots (with `split`,
        // the factored system's: every slot empty).
        if self.schur.is_some()
            && let Some(a) = self.analysis.as_ref()
        {
            let clock = Instant::now();
            let work = &mut self.trailing_work;
            work.k0_tangent = self.tangent;
            work.k_rows.clear();
            work.extra0 = if split {
                summed(in_slots(&[], n_disp, &a.slots, &[]))
            } else {
                summed(in_slots(extra, n_disp, &a.slots, slot_of))
            };
            self.times.system += clock.elapsed();
        }
        if split {
            // The system itself on the factor's trailing block; should that
            // fail, by LU.
            let mut x = rhs.to_vec();
            if self.solve_on_trailing_block(pattern, k, extra, &mut x, None) {
                rhs.copy_from_slice(&x);
                self.ldlt += 1;
                self.last = Some(Method::Ldlt);
                return Ok(());
            }
            if let Some(a) = self.analysis.as_mut() {
                a.split_failed = true;
            }
            self.schur = None;
            std::mem::swap(&mut self.values, &mut self.split_values);
            self.solve_kept(pattern, k, n_disp, &mut full)?;
        }
        if slotted {
            rhs[..n_disp].copy_from_slice(&full[..n_disp]);
            for (m, &s) in slot_of.iter().enumerate() {
                rhs[n_disp + m] = full[n_disp + s];
            }
        } else {
            rhs.copy_from_slice(&full);
        }
        Ok(())
    }

    /// Factors the system built in `col_ptr`, `row_idx`, `values` over the
    /// kept analysis and solves it in place (`solve`).
    ///
    /// An unsymmetric system with slots whose trailing set holds (every
    /// entry beside the tangent lies in `T x T`, as with rigid targets) is
    /// not factored by LU: the tangent with every slot empty (`K` and an
    /// identity on the slots) is factored by LDLT, `T` last, and left in
    /// `col_ptr`, `row_idx`, `values` as the kept system; returns true then,
    /// and the system is to be solved on its trailing block (`solve`).
    fn solve_kept(
        &mut self,
        pattern: &Pattern,
        k: &[f64],
        n_disp: usize,
        rhs: &mut [f64],
    ) -> Result<bool, LinearError> {
        let clock = Instant::now();
        self.trailing_work.forward = None;
        self.trailing_work.bases = DenseBases::default();
        let n = rhs.len();
        let b = rhs.to_vec();
        let symmetric = self.symmetric_system();
        let analysis = self.analysis.as_mut().expect("set above");
        let split_dofs = (!symmetric
            && !self.force_lu
            && self.slots
            && !self.no_trailing
            && !analysis.split_failed)
            .then(|| trailing_dofs(&analysis.slots, n_disp, n))
            .flatten();
        // The trailing set is the analysis's (its slots'): when it is too
        // large, it stays so (the capstan FMU sorted its 770 keys' dofs at
        // every factorization, 2 % of its time).
        if split_dofs.is_none() && !symmetric {
            analysis.split_failed = true;
        }
        self.times.system += clock.elapsed();
        if let Some(dofs) = split_dofs
            && self.factor_split(pattern, k, n_disp, n, &dofs)
        {
            return Ok(true);
        }
        if symmetric {
            if self.solve_by_ldlt(n_disp, rhs) {
                return Ok(false);
            }
            // The tangent's own LDLT with the contact dofs last may still
            // hold (a body held by contact alone): as for an unsymmetric
            // system, before LU.
            let a = self.analysis.as_ref().expect("set above");
            if a.ldlt.is_some() && self.slots && !self.no_trailing && !a.split_failed {
                return self.solve_kept(pattern, k, n_disp, rhs);
            }
        }
        if !symmetric && self.try_ldu(n_disp, rhs, &b) {
            return Ok(false);
        }
        self.solve_by_lu(rhs)?;
        Ok(false)
    }

    /// Whether the system in `values` is symmetric (to `SYMMETRY`), LDLT
    /// allowed on its pattern.
    fn symmetric_system(&self) -> bool {
        let analysis = self.analysis.as_ref().expect("set above");
        !self.force_lu
            && !analysis.ldlt_failed
            && match self.extra_asymmetry {
                Some(a) => {
                    let max = self.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                    max.is_finite() && a <= SYMMETRY * max
                }
                None => is_symmetric(analysis.mat.col_ptr(), analysis.mat.row_idx(), &self.values),
            }
    }

    /// The unsymmetric system's split (`solve_kept`): the tangent with
    /// every slot empty factored by LDLT with the trailing set `dofs` and
    /// the slots last, kept with its Schur complement; false (and the
    /// split failed for the pattern) when the system differs from it
    /// outside the trailing set or the factor fails.
    fn factor_split(
        &mut self,
        pattern: &Pattern,
        k: &[f64],
        n_disp: usize,
        n: usize,
        dofs: &[usize],
    ) -> bool {
        let analysis = self.analysis.as_mut().expect("set above");
        let clock = Instant::now();
        let mut base_extra = in_slots(&[], n_disp, &analysis.slots, &[]);
        let (mut col_ptr, mut row_idx, mut values) = (Vec::new(), Vec::new(), Vec::new());
        bordered(
            pattern,
            k,
            &mut base_extra,
            n,
            [&mut col_ptr, &mut row_idx],
            &mut values,
        );
        // The system differs from it in `T x T` alone (its entries
        // beside the tangent lie on the slots and their keys' dofs).
        let mut in_t = vec![false; n];
        for &d in dofs {
            in_t[d] = true;
        }
        in_t[n_disp..].fill(true);
        let same = col_ptr == analysis.mat.col_ptr()
            && row_idx == analysis.mat.row_idx()
            && (0..n).all(|j| {
                (col_ptr[j]..col_ptr[j + 1])
                    .all(|q| values[q] == self.values[q] || (in_t[j] && in_t[row_idx[q]]))
            });
        self.times.system += clock.elapsed();
        if analysis.ldlt.is_none() && same {
            let clock = Instant::now();
            self.analyses += 1;
            match analyse_ldlt(
                analysis.mat.as_ref(),
                n_disp,
                &mut self.disp_order,
                Some(dofs),
            ) {
                Ok(s) => {
                    analysis.trailing = dofs.len() + (n - n_disp);
                    analysis.ldlt = Some(s);
                }
                Err(_) => analysis.split_failed = true,
            }
            self.times.symbolic += clock.elapsed();
        }
        if let Some((symbolic, mem)) = analysis
            .ldlt
            .as_mut()
            .filter(|_| same && analysis.trailing > 0)
        {
            self.factorizations += 1;
            let mat = SparseColMatRef::new(analysis.mat.as_ref(), &values);
            let stack = MemStack::new(mem);
            let factored =
                factor_ldlt(symbolic, stack, &mut self.l_values, mat, &mut self.times).is_some();
            let clock = Instant::now();
            let schur = factored
                .then(|| trailing::Factor::new(symbolic, &self.l_values, analysis.trailing))
                .flatten()
                .map(|f| (f.schur(), f.d_inv()))
                .filter(|(s0, d_inv)| {
                    d_inv.iter().all(|v| v.is_finite())
                        && (0..s0.ncols()).all(|j| s0.col(j).iter().all(|v| v.is_finite()))
                });
            self.times.solve += clock.elapsed();
            if let Some(schur) = schur {
                // The kept system is the factored one.
                self.split_values = std::mem::replace(&mut self.values, values);
                self.schur = Some(schur);
                return true;
            }
        }
        analysis.split_failed = true;
        false
    }

    /// The symmetric system in `values` factored by LDLT (its analysis made
    /// on the pattern's first, the trailing set last where it holds) and
    /// solved, checked (`solve_ldlt`), into `rhs`; the factor kept. False
    /// when the analysis or the checked solve fails (`ldlt_failed` then).
    fn solve_by_ldlt(&mut self, n_disp: usize, rhs: &mut [f64]) -> bool {
        let n = rhs.len();
        let analysis = self.analysis.as_mut().expect("set above");
        if analysis.ldlt.is_none() {
            let clock = Instant::now();
            self.analyses += 1;
            let trailing = (self.slots && !self.no_trailing)
                .then(|| trailing_dofs(&analysis.slots, n_disp, n))
                .flatten();
            match analyse_ldlt(
                analysis.mat.as_ref(),
                n_disp,
                &mut self.disp_order,
                trailing.as_deref(),
            ) {
                Ok(s) => {
                    analysis.trailing = trailing.map_or(0, |dofs| dofs.len() + (n - n_disp));
                    analysis.ldlt = Some(s);
                }
                Err(_) => analysis.ldlt_failed = true,
            }
            self.times.symbolic += clock.elapsed();
        }
        if let Some((symbolic, mem)) = analysis.ldlt.as_mut() {
            self.factorizations += 1;
            let mat = SparseColMatRef::new(analysis.mat.as_ref(), &self.values);
            if solve_ldlt(
                symbolic,
                mem,
                &mut self.l_values,
                mat,
                n_disp,
                rhs,
                &mut self.x,
                &mut self.times,
                !self.decoupled,
            ) {
                rhs.copy_from_slice(&self.x);
                self.ldlt += 1;
                self.last = Some(Method::Ldlt);
                let clock = Instant::now();
                let schur = (analysis.trailing > 0)
                    .then(|| trailing::Factor::new(symbolic, &self.l_values, analysis.trailing))
                    .flatten()
                    .map(|f| (f.schur(), f.d_inv()));
                self.times.solve += clock.elapsed();
                self.schur = schur;
                return true;
            }
            analysis.ldlt_failed = true;
        }
        false
    }

    /// The system in `values` factored by faer's sparse LU (its analysis
    /// made on the pattern's first) and solved into `rhs`.
    fn solve_by_lu(&mut self, rhs: &mut [f64]) -> Result<(), LinearError> {
        let n = rhs.len();
        let analysis = self.analysis.as_mut().expect("set above");
        if analysis.lu.is_none() {
            let clock = Instant::now();
            self.analyses += 1;
            let lu = faer::sparse::linalg::lu::factorize_symbolic_lu(
                analysis.mat.as_ref(),
                Default::default(),
            )
            .map_err(|e| LinearError::Factorization(format!("{e:?}")))?;
            let req = lu.factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default());
            let mem = MemBuffer::try_new(req)
                .map_err(|e| LinearError::Factorization(format!("{e:?}")))?;
            analysis.lu = Some((lu, mem));
            self.lu_order = usize::MAX;
            self.times.symbolic += clock.elapsed();
        }
        let clock = Instant::now();
        let (lu, mem) = analysis.lu.as_mut().expect("set above");
        let mat = SparseColMatRef::new(analysis.mat.as_ref(), &self.values);
        self.factorizations += 1;
        // Into the last LU's arrays, on the same analysis: faer keeps the
        // column pointers of a larger factor it refills.
        if self.lu_order != n {
            self.lu_numeric = NumericLu::new();
            self.lu_order = n;
        }
        let f = lu
            .factorize_numeric_lu(
                &mut self.lu_numeric,
                mat,
                Par::Seq,
                MemStack::new(mem),
                Default::default(),
            )
            .map_err(|e| LinearError::Factorization(format!("{e:?}")))?;
        self.times.numeric += clock.elapsed();
        let clock = Instant::now();
        lu_solve(f, rhs, 1);
        self.times.solve += clock.elapsed();
        if rhs.iter().any(|v| !v.is_finite()) {
            return Err(LinearError::NonFinite);
        }
        self.lu += 1;
        self.last = Some(Method::Lu);
        Ok(())
    }

    /// Solves `A x = rhs` in place, A of order `rhs.len()` given as the CSC
    /// tangent `k` over `pattern` (the first `pattern.n` unknowns) plus the
    /// entries `extra` (row, col, value; duplicates are summed). The one
    /// policy: on the trailing block of the kept LDLT factor when the
    /// caller's tangent is the factored one (`new_tangent`) and A differs
    /// from the factored system inside the trailing set alone (`trailing`:
    /// the inner solves of a Newton iteration, and its first solve under a
    /// constant tangent), refined once and checked; else factored
    /// (`factor_and_solve`: LDLT, the unpivoted LDU or LU, each checked).
    pub fn solve(
        &mut self,
        pattern: &Pattern,
        k: &[f64],
        extra: &mut [(usize, usize, f64)],
        rhs: &mut [f64],
    ) -> Result<(), LinearError> {
        self.solve_watching(pattern, k, extra, rhs, None)
            .map(|_| ())
    }

    /// `solve`; with `watch` (displacement unknowns) a solve on the
    /// trailing block may stop short of the interior: `rhs` then holds the
    /// multipliers, the trailing set's and the watched unknowns' solution
    /// and NaN elsewhere, and the call returns false until `finish`
    /// completes it (the inner solves of an iteration need the contact
    /// nodes' motion alone until one is accepted; the interior's back
    /// substitution and the refinement are three passes over the factor).
    /// True: `rhs` holds the whole solution.
    pub fn solve_watching(
        &mut self,
        pattern: &Pattern,
        k: &[f64],
        extra: &mut [(usize, usize, f64)],
        rhs: &mut [f64],
        watch: Option<&[usize]>,
    ) -> Result<bool, LinearError> {
        let same_tangent = self.tangent.is_some() && self.trailing_work.k0_tangent == self.tangent;
        if same_tangent && self.solve_on_trailing_block(pattern, k, extra, rhs, watch) {
            return Ok(self.trailing_work.pending.is_none());
        }
        self.factor_and_solve(pattern, k, extra, rhs)?;
        Ok(true)
    }

    /// Completes into `rhs` the last solve when `solve_watching` left it
    /// partial (`pattern`, `k` and `extra` as given to it): the interior's
    /// back substitution, one step of refinement and the backward error
    /// check of every trailing solve; should that check fail, the system is
    /// factored. Nothing to do after a whole solve.
    pub fn finish(
        &mut self,
        pattern: &Pattern,
        k: &[f64],
        extra: &mut [(usize, usize, f64)],
        rhs: &mut [f64],
    ) -> Result<(), LinearError> {
        let Some(b) = self.deferred_rhs() else {
            return Ok(());
        };
        if self.complete(pattern, k, rhs) {
            return Ok(());
        }
        rhs.copy_from_slice(&b);
        self.factor_and_solve(pattern, k, extra, rhs)
    }

    /// `solve` on the trailing block of the kept LDLT factor alone
    /// (`trailing`), refined once against the system and accepted below
    /// the factored solves' backward error (`complete_trailing`). False
    /// when the factor has no trailing set, a multiplier finds no slot of
    /// the kept pattern, or the system differs from the factored one
    /// outside the trailing set.
    fn solve_on_trailing_block(
        &mut self,
        pattern: &Pattern,
        k: &[f64],
        extra: &[(usize, usize, f64)],
        rhs: &mut [f64],
        watch: Option<&[usize]>,
    ) -> bool {
        let clock = Instant::now();
        self.trailing_work.pending = None;
        let mut work = std::mem::take(&mut self.trailing_work);
        let done = self.trailing_into(pattern, k, extra, rhs, &mut work, watch);
        self.trailing_work = work;
        if done {
            self.trailing_solves += 1;
            self.deferred_solves += usize::from(self.trailing_work.pending.is_some());
        }
        self.times.solve += clock.elapsed();
        done
    }

    /// The right-hand side of a partial last solve, in the caller's order.
    fn deferred_rhs(&self) -> Option<Vec<f64>> {
        let p = self.trailing_work.pending.as_ref()?;
        let n_disp = self.analysis.as_ref()?.n_disp;
        let mut rhs = p.b[..n_disp].to_vec();
        rhs.extend(p.slot_of.iter().map(|&s| p.b[n_disp + s]));
        Some(rhs)
    }

    /// Finishes a partial last solve into `rhs` (`finish`); false when it
    /// fails its check or nothing is pending.
    fn complete(&mut self, pattern: &Pattern, k: &[f64], rhs: &mut [f64]) -> bool {
        let clock = Instant::now();
        let Some(pending) = self.trailing_work.pending.take() else {
            return false;
        };
        let (Some((_, d_inv)), Some(analysis)) = (&self.schur, &self.analysis) else {
            return false;
        };
        let Some(f) = (analysis.ldlt.as_ref()).and_then(|(symbolic, _)| {
            trailing::Factor::new(symbolic, &self.l_values, analysis.trailing)
        }) else {
            return false;
        };
        let done = complete_trailing(
            &f,
            d_inv,
            &pending,
            pattern,
            k,
            rhs,
            &mut self.trailing_work.correction,
        );
        self.times.solve += clock.elapsed();
        done
    }

    /// `solve_on_trailing_block` with its buffers (the caller has checked
    /// that the tangent is the factored one's).
    fn trailing_into(
        &self,
        pattern: &Pattern,
        k: &[f64],
        extra: &[(usize, usize, f64)],
        rhs: &mut [f64],
        work: &mut TrailingWork,
        watch: Option<&[usize]>,
    ) -> bool {
        let (Some((s0, d_inv)), Some(analysis)) = (&self.schur, &self.analysis) else {
            return false;
        };
        let Some((symbolic, _)) = analysis.ldlt.as_ref() else {
            return false;
        };
        let n = rhs.len();
        let n_disp = pattern.n.min(n);
        let Some(f) = trailing::Factor::new(symbolic, &self.l_values, analysis.trailing) else {
            return false;
        };
        if n_disp != analysis.n_disp || n == n_disp {
            return false;
        }
        let Some(slot_of) =
            slot_keys(extra, n_disp, n - n_disp).and_then(|keys| analysis.slot_groups.place(&keys))
        else {
            return false;
        };
        let order = analysis.mat.nrows();
        let TrailingWork {
            k0_tangent: _,
            k_rows,
            extra0,
            forward,
            correction,
            pending,
            bases,
        } = work;
        // The tangent is the factored one's; the entries beside it differ
        // (a merge of the two sorted lists): the change, which must lie
        // inside the trailing set, added to S0.
        let extra1 = summed(in_slots(extra, n_disp, &analysis.slots, &slot_of));
        let mut delta: Vec<(usize, usize, f64)> = Vec::new();
        for (i, j, d) in difference(&extra1, extra0) {
            let (pi, pj) = (f.inv[i], f.inv[j]);
            if pi < f.b || pj < f.b {
                return false;
            }
            delta.push((pi - f.b, pj - f.b, d));
        }
        // `|A1|_inf`, from the tangent and the entries.
        if k_rows.is_empty() {
            k_rows.resize(order, 0.0);
            for j in 0..pattern.n {
                for p in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
                    k_rows[pattern.row_idx[p]] += k[p].abs();
                }
            }
        }
        let mut rows = k_rows.clone();
        for &(i, _, v) in &extra1 {
            rows[i] += v.abs();
        }
        let norm_a = rows.iter().fold(0.0f64, |m, v| m.max(*v));
        let t = order - f.b;
        let dense = Dense::new(s0, bases, &delta, t);
        let mut b = vec![0.0; order];
        b[..n_disp].copy_from_slice(&rhs[..n_disp]);
        for (m, &s) in slot_of.iter().enumerate() {
            b[n_disp + s] = rhs[n_disp + m];
        }
        let mut y = forward_substituted(&f, &b, forward);
        dense.solve(&mut y[f.b..]);
        let solved = Pending {
            dense,
            y,
            b,
            extra1,
            slot_of,
            norm_a,
        };
        let Some(watch) = watch else {
            return complete_trailing(&f, d_inv, &solved, pattern, k, rhs, correction);
        };
        if !watched(&f, d_inv, &solved, watch, n_disp, rhs) {
            return false;
        }
        *pending = Some(solved);
        true
    }
}

impl Augmented {
    /// The unsymmetric system `values` over the kept analysis factored by
    /// the unpivoted LDU and solved in place (`solve_kept`), checked and
    /// refined as the unpivoted LDLT is (`refined_solve`): false, the
    /// system and `rhs` as given, when the pattern's factor is too dense
    /// for it or the solve fails its checks (then LU, as for the rest of
    /// the pattern).
    fn try_ldu(&mut self, n_disp: usize, rhs: &mut [f64], b: &[f64]) -> bool {
        if self.force_lu {
            return false;
        }
        let Some(analysis) = self.analysis.as_mut().filter(|a| !a.ldu_failed) else {
            return false;
        };
        if analysis.ldu.is_none() {
            let clock = Instant::now();
            self.analyses += 1;
            let usable = self
                .disp_order
                .as_ref()
                .is_some_and(|(f, _)| f.len() == n_disp)
                || amd_of_block(analysis.mat.as_ref(), n_disp)
                    .map(|o| self.disp_order = Some(o))
                    .is_ok();
            let symbolic = usable
                .then(|| {
                    let (disp, _) = self.disp_order.as_ref().expect("set above");
                    ldu::Symbolic::new(analysis.mat.as_ref(), n_disp, disp, LDU_FLOPS_PER_ENTRY)
                })
                .flatten();
            self.times.symbolic += clock.elapsed();
            match symbolic {
                Some(s) => analysis.ldu = Some(s),
                None => {
                    analysis.ldu_failed = true;
                    return false;
                }
            }
        }
        let symbolic = analysis.ldu.as_ref().expect("set above");
        let clock = Instant::now();
        self.factorizations += 1;
        let factored = symbolic.factor(&self.values, &mut self.ldu_numeric);
        self.times.numeric += clock.elapsed();
        let clock = Instant::now();
        let a = SparseColMatRef::new(analysis.mat.as_ref(), &self.values);
        let numeric = &self.ldu_numeric;
        let solved = factored
            && refined_solve(
                |x: &mut [f64]| symbolic.solve(numeric, x),
                n_disp,
                a,
                b,
                &mut self.x,
                !self.decoupled,
            );
        self.times.solve += clock.elapsed();
        if !solved {
            analysis.ldu_failed = true;
            return false;
        }
        rhs.copy_from_slice(&self.x);
        self.ldu += 1;
        self.last = Some(Method::Ldu);
        // Nothing is kept: an inner solve on this pattern is factored
        // again (the LDU takes only patterns whose factorization is cheap,
        // `LDU_FLOPS_PER_ENTRY`).
        true
    }
}

/// Multiply-adds per factor entry above which the LDU leaves a pattern to
/// LU: faer's own threshold for its supernodal factorizations
/// (`SupernodalThreshold::AUTO`, 40), where its dense kernels beat scalar
/// loops.
const LDU_FLOPS_PER_ENTRY: f64 = 40.0;

/// Solves `A X = B` in place with the LU factor `f`, `B` of `cols`
/// columns (column-major).
fn lu_solve(f: LuRef<'_, usize, f64>, b: &mut [f64], cols: usize) {
    let rows = f.symbolic().nrows();
    let req = f.symbolic().solve_in_place_scratch::<f64>(cols, Par::Seq);
    f.solve_in_place_with_conj(
        Conj::No,
        MatMut::from_column_major_slice_mut(b, rows, cols),
        Par::Seq,
        MemStack::new(&mut MemBuffer::new(req)),
    );
}

/// AMD of the leading `n_disp` block of `a`: (forward, inverse). Made on
/// the block's quotient graph of runs of consecutive columns with the same
/// rows (a node's two displacement equations), each run then kept together
/// in the order: the graph has a quarter of the entries, and AMD finds such
/// runs itself only after it has paid for scanning them (Hertz q4: 3.9 ms
/// to 2.1 ms at 1e4 unknowns, 42 ms to 23 ms at 1e5; the fill moves either
/// way with AMD's ties, docs/contact.md section 8).
fn amd_of_block(
    a: SymbolicSparseColMatRef<'_, usize>,
    n_disp: usize,
) -> Result<(Vec<usize>, Vec<usize>), FaerError> {
    // The displacement block's rows per column (sorted, so the rows <
    // n_disp lead).
    let rows = |j: usize| {
        let rows = a.row_idx_of_col_raw(j);
        &rows[..rows.partition_point(|&r| r < n_disp)]
    };
    // Runs of consecutive columns with the same rows.
    let mut run_of = vec![0usize; n_disp];
    let mut starts: Vec<usize> = Vec::new();
    for j in 0..n_disp {
        if j == 0 || rows(j) != rows(j - 1) {
            starts.push(j);
        }
        run_of[j] = starts.len() - 1;
    }
    let runs = starts.len();
    starts.push(n_disp);
    // The graph of the runs: run g meets the runs of its first column's rows.
    let mut ptr = Vec::with_capacity(runs + 1);
    let mut idx = Vec::new();
    ptr.push(0);
    for g in 0..runs {
        let from = idx.len();
        for &r in rows(starts[g]) {
            let h = run_of[r];
            if idx.len() == from || idx[idx.len() - 1] != h {
                idx.push(h);
            }
        }
        idx[from..].sort_unstable();
        let mut w = from;
        for q in from..idx.len() {
            if q == from || idx[q] != idx[w - 1] {
                idx[w] = idx[q];
                w += 1;
            }
        }
        idx.truncate(w);
        ptr.push(idx.len());
    }
    let graph = SymbolicSparseColMatRef::new_checked(runs, runs, &ptr, None, &idx);
    let mut run_fwd = vec![0usize; runs];
    let mut run_inv = vec![0usize; runs];
    let mut mem = MemBuffer::try_new(amd::order_scratch::<usize>(runs, idx.len()))
        .map_err(|_| FaerError::OutOfMemory)?;
    amd::order(
        &mut run_fwd,
        &mut run_inv,
        graph,
        amd::Control::default(),
        MemStack::new(&mut mem),
    )?;
    let fwd: Vec<usize> = run_fwd
        .iter()
        .flat_map(|&g| starts[g]..starts[g + 1])
        .collect();
    let mut inv = vec![0usize; n_disp];
    for (p, &j) in fwd.iter().enumerate() {
        inv[j] = p;
    }
    Ok((fwd, inv))
}

/// Symbolic LDLT of `a` (lower triangle) in the order AMD of the leading
/// `n_disp` block, then the remaining unknowns in their order; with the
/// workspace of the numeric factorization and the solve. The block's order
/// is `order` when given (of the same `n_disp`), else made here and kept
/// there.
fn analyse_ldlt(
    a: SymbolicSparseColMatRef<'_, usize>,
    n_disp: usize,
    order: &mut Option<(Vec<usize>, Vec<usize>)>,
    trailing: Option<&[usize]>,
) -> Result<(SymbolicCholesky<usize>, MemBuffer), FaerError> {
    let n = a.nrows();
    if order.as_ref().is_none_or(|(fwd, _)| fwd.len() != n_disp) {
        *order = Some(amd_of_block(a, n_disp)?);
    }
    let (block_fwd, block_inv) = order.as_ref().expect("set above");
    let mut fwd: Vec<usize> = (0..n).collect();
    let mut inv: Vec<usize> = (0..n).collect();
    fwd[..n_disp].copy_from_slice(block_fwd);
    inv[..n_disp].copy_from_slice(block_inv);
    let mut params = CholeskySymbolicParams::default();
    if let Some(dofs) = trailing {
        // The block's order with the trailing dofs moved behind the rest,
        // each part in its AMD order; supernodal (`trailing::Factor`).
        let mut last = vec![false; n_disp];
        for &d in dofs {
            last[d] = true;
        }
        let (mut head, tail): (Vec<usize>, Vec<usize>) = block_fwd.iter().partition(|&&d| !last[d]);
        head.extend(tail);
        fwd[..n_disp].copy_from_slice(&head);
        for (p, &d) in fwd.iter().enumerate() {
            inv[d] = p;
        }
        params.supernodal_flop_ratio_threshold =
            faer::sparse::linalg::SupernodalThreshold::FORCE_SUPERNODAL;
    }
    let perm = PermRef::new_checked(&fwd, &inv, n);
    let symbolic =
        factorize_symbolic_cholesky(a, Side::Lower, SymmetricOrdering::Custom(perm), params)?;
    let req = StackReq::any_of(&[
        symbolic.factorize_numeric_ldlt_scratch::<f64>(Par::Seq, Default::default()),
        symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
    ]);
    let mem = MemBuffer::try_new(req).map_err(|_| FaerError::OutOfMemory)?;
    Ok((symbolic, mem))
}

/// Numeric LDLT of `a` (lower triangle, no regularization) and the solve of
/// `a x = b` into `x`. False when a pivot is zero, a value is not finite or
/// the backward error exceeds [`LDLT_BACKWARD_ERROR`]; with `refine`, also
/// when one step of refinement exposes a near-null direction
/// ([`LDLT_REFINEMENT`]).
#[allow(clippy::too_many_arguments)]
fn solve_ldlt(
    symbolic: &SymbolicCholesky<usize>,
    mem: &mut MemBuffer,
    l_values: &mut Vec<f64>,
    a: SparseColMatRef<'_, usize, f64>,
    n_disp: usize,
    b: &[f64],
    x: &mut Vec<f64>,
    times: &mut LinearTimes,
    refine: bool,
) -> bool {
    let stack = MemStack::new(mem);
    let ldlt = factor_ldlt(symbolic, stack, l_values, a, times);
    let clock = Instant::now();
    let done = ldlt.is_some_and(|ldlt| {
        let solve = |x: &mut [f64]| {
            let n = x.len();
            ldlt.solve_in_place_with_conj(
                Conj::No,
                MatMut::from_column_major_slice_mut(x, n, 1),
                Par::Seq,
                &mut *stack,
            );
        };
        refined_solve(solve, n_disp, a, b, x, refine)
    });
    times.solve += clock.elapsed();
    done
}

/// The numeric LDLT factorization of `a` over `symbolic` into `l_values`
/// (timed as numeric); None when it fails.
fn factor_ldlt<'a>(
    symbolic: &'a SymbolicCholesky<usize>,
    stack: &mut MemStack,
    l_values: &'a mut Vec<f64>,
    a: SparseColMatRef<'_, usize, f64>,
    times: &mut LinearTimes,
) -> Option<faer::sparse::linalg::cholesky::LdltRef<'a, usize, f64>> {
    let clock = Instant::now();
    // faer zeroes the values itself: a buffer of another length is
    // replaced by zeroed pages, not written twice.
    if l_values.len() != symbolic.len_val() {
        *l_values = vec![0.0; symbolic.len_val()];
    }
    let ldlt = symbolic.factorize_numeric_ldlt(
        l_values,
        a,
        Side::Lower,
        LdltRegularization::default(),
        Par::Seq,
        stack,
        Default::default(),
    );
    times.numeric += clock.elapsed();
    ldlt.ok()
}

/// The solve of `a x = b` into `x` with an unpivoted factor of `a`
/// (`solve`, in place), checked and, with `refine`, refined (`solve_ldlt`,
/// `Augmented::try_ldu`).
fn refined_solve(
    mut solve: impl FnMut(&mut [f64]),
    n_disp: usize,
    a: SparseColMatRef<'_, usize, f64>,
    b: &[f64],
    x: &mut Vec<f64>,
    refine: bool,
) -> bool {
    let n = b.len();
    x.clear();
    x.extend_from_slice(b);
    solve(x);
    if x.iter().any(|v| !v.is_finite()) {
        return false;
    }
    // Backward error with the stored matrix: r = b - A x, |A|_inf (each
    // row's residual and magnitude side by side: one cache line per entry
    // instead of two).
    let mut rows: Vec<[f64; 2]> = b.iter().map(|&bi| [bi, 0.0]).collect();
    for j in 0..n {
        let xj = x[j];
        for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
            let row = &mut rows[i];
            row[0] -= v * xj;
            row[1] += v.abs();
        }
    }
    let inf = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let (r_inf, a_inf) = rows.iter().fold((0.0f64, 0.0f64), |(r, a), row| {
        (r.max(row[0].abs()), a.max(row[1]))
    });
    let denom = a_inf * inf(x) + inf(b);
    if r_inf > LDLT_BACKWARD_ERROR * denom {
        return false;
    }
    let mut r: Vec<f64> = rows.iter().map(|row| row[0]).collect();
    if !refine {
        return true;
    }
    // The normwise backward error hides a solve that went wrong along a
    // near-null direction of the stiffness (a body held by contact alone: a
    // tiny pivot, a huge x, |r| small beside |A| |x|). One step of iterative
    // refinement exposes it: its correction is then of the size of x
    // (measured 173 |x| on a layer resting on a rigid surface), against
    // round-off for a sound factor. A sound solve keeps the correction.
    solve(&mut r);
    if r.iter().any(|v| !v.is_finite()) || inf(&r[..n_disp]) > LDLT_REFINEMENT * inf(&x[..n_disp]) {
        return false;
    }
    for (xi, di) in x.iter_mut().zip(&r) {
        *xi += di;
    }
    true
}

mod factored_lu;
mod ldu;
mod linear;
mod pattern;
mod slots;
mod tangent;

pub use factored_lu::FactoredLu;
pub use linear::Linear;
use pattern::{
    SYMMETRY, asymmetry, bordered, bordered_new, is_symmetric, merge_pattern, scatter_into,
    values_in_pattern,
};
use slots::{SlotGroups, SlotKey, in_slots, new_slots, slot_keys, trailing_dofs};
pub use tangent::LinearSolver;
#[cfg(test)]
mod tests;
mod trailing;

use trailing::{
    Dense, DenseBases, Pending, TrailingWork, complete_trailing, difference, forward_substituted,
    summed, watched,
};
