//! The one linear solver Newton hands its systems to: the tangent alone
//! (`LinearSolver`), and Eq. (18)'s bordered systems (`Augmented`). Which
//! factor serves, the fill-reducing order they share, the multipliers'
//! slots, the trailing block and the LU fallback are decided here; Newton
//! asks for solutions and reads the counters.

use super::{Augmented, LinearError, LinearSolver, slots::trailing_fits};
use crate::assembly::Pattern;
use crate::results::LinearCounts;

pub struct Linear {
    tangent: LinearSolver,
    bordered: Augmented,
    /// Every contact pair's target is rigid: the tangent and the bordered
    /// systems' displacement block share one AMD order, the multipliers
    /// keep slots (`Augmented::slots`) and a partial solve gives the
    /// watched equations. Against a deformable target the block has
    /// contact couplings and its own order, and a sliding node's row
    /// changes key with its segment: the buried pipe (a steel pipe in soft
    /// soil, held by contact alone, its LU solves good to about 1e-9 of the
    /// right-hand side) stalled at |r|/F = 4.8e-4 in its first increment
    /// and bisected under either; its stick/slip path depends on round-off
    /// (docs/contact.md section 8).
    rigid_targets: bool,
    /// The free equations a partial solve must give (`solve`'s `partial`):
    /// every contactor node's, with rigid targets.
    watched: Vec<usize>,
    /// Solves whose iteration's first took the kept factor's trailing
    /// block instead of a factorization.
    reused: usize,
}

impl Linear {
    /// The solver for systems on `pattern` (symmetric tangents or not),
    /// `watched` the equations a partial solve gives (empty: every solve
    /// is whole).
    pub fn new(
        pattern: &Pattern,
        symmetric: bool,
        rigid_targets: bool,
        watched: Vec<usize>,
    ) -> Result<Linear, LinearError> {
        let mut bordered = Augmented::with_slots(rigid_targets);
        bordered.symmetric_tangent = symmetric;
        Ok(Linear {
            tangent: LinearSolver::new(pattern, symmetric)?,
            bordered,
            rigid_targets,
            watched: if rigid_targets { watched } else { Vec::new() },
            reused: 0,
        })
    }

    /// An increment starts: the multipliers' slots start afresh, so that
    /// its round-off depends on its start state alone (a restored state
    /// continues bit for bit).
    pub fn restart(&mut self) {
        self.bordered.restart();
    }

    /// The tangent is about to change (said before it is written: an
    /// assembly that fails half way has changed it too).
    pub fn new_tangent(&mut self) {
        self.bordered.new_tangent();
    }

    /// Solves `K x = rhs` in place, the tangent `k` factored first when
    /// `factor` (else the last factor of it serves).
    pub fn solve_tangent(
        &mut self,
        k: &[f64],
        factor: bool,
        rhs: &mut [f64],
    ) -> Result<(), LinearError> {
        if factor {
            if self.rigid_targets {
                self.tangent.share_order(self.bordered.order());
            }
            self.tangent.factorize(k)?;
            if self.rigid_targets {
                self.bordered.share_order(self.tangent.order());
            }
        }
        self.tangent.solve(rhs)
    }

    /// Whether a solve without contact rows may take the slots of the rows
    /// to come (`solve_in_slots`).
    pub fn takes_slots(&self) -> bool {
        let b = &self.bordered;
        self.rigid_targets && !b.force_lu && !b.no_trailing && b.slots
    }

    /// The slots for contact rows to come: `nodes` gives, nearest first,
    /// each node's free equations and the rows it may take (one, two with
    /// friction); nodes are taken while the slots and their equations stay
    /// few enough for the dense solves on the factor's trailing block
    /// (`trailing_fits`, `n` free equations). A slot is keyed by its
    /// node's equations; a row on prescribed dofs alone (a sticking node's
    /// tangential row on a symmetry plane) is an identity row with an
    /// empty key.
    pub fn slots(
        &self,
        n: usize,
        nodes: impl IntoIterator<Item = (Vec<usize>, usize)>,
    ) -> Vec<Vec<usize>> {
        let mut slots = Vec::new();
        let mut dofs = 0;
        for (eqs, rows) in nodes {
            let empty = usize::from(eqs.len() < 2);
            let added = if eqs.is_empty() { 0 } else { rows };
            // A node in two pairs counts its equations twice: the set is
            // overestimated, never under.
            let (t, m) = (dofs + eqs.len(), slots.len() + empty + added);
            if !trailing_fits(t + m, n + m) {
                break;
            }
            dofs = t;
            slots.extend(std::iter::repeat_n(Vec::new(), empty));
            slots.extend(std::iter::repeat_n(eqs, added));
        }
        slots
    }

    /// Solves `K x = rhs` in place on the LDLT factor of the tangent
    /// bordered by `slots` (`slots`), every slot empty (an identity row,
    /// its entries on its node zero), their nodes and slots ordered last:
    /// the iterations with contact rows then solve on the same factor's
    /// trailing block (under a constant tangent) or on its analysis. False
    /// (the slots forgotten, `rhs` unchanged) when the solve fails.
    /// `extra` is scratch for the border's entries.
    pub fn solve_in_slots(
        &mut self,
        pattern: &Pattern,
        k: &[f64],
        slots: &[Vec<usize>],
        extra: &mut Vec<(usize, usize, f64)>,
        rhs: &mut [f64],
    ) -> bool {
        let n = rhs.len();
        extra.clear();
        for (m, eqs) in slots.iter().enumerate() {
            for &q in eqs {
                extra.push((n + m, q, 0.0));
                extra.push((q, n + m, 0.0));
            }
            extra.push((n + m, n + m, 1.0));
        }
        let mut full = rhs.to_vec();
        full.resize(n + slots.len(), 0.0);
        if self
            .solve(pattern, k, extra, &mut full, false, true)
            .is_err()
        {
            self.bordered.restart();
            return false;
        }
        rhs.copy_from_slice(&full[..n]);
        true
    }

    /// Solves the bordered system (the tangent `k` on `pattern`, `extra`
    /// beside it) in place. With `partial` it may stop short of the
    /// interior: `full` then holds the multipliers and the watched
    /// equations' solution, and the call returns false until `finish`
    /// completes it. `first`: the iteration's first solve (counted in
    /// `reused` when the trailing block serves it).
    pub fn solve(
        &mut self,
        pattern: &Pattern,
        k: &[f64],
        extra: &mut [(usize, usize, f64)],
        full: &mut [f64],
        partial: bool,
        first: bool,
    ) -> Result<bool, LinearError> {
        let watch = partial.then_some(&self.watched[..]);
        let trailing = self.bordered.trailing_solves;
        let solved = self.bordered.solve_watching(pattern, k, extra, full, watch);
        if first {
            self.reused += self.bordered.trailing_solves - trailing;
        }
        solved
    }

    /// Completes a solve `solve` left partial (arguments as given to it).
    pub fn finish(
        &mut self,
        pattern: &Pattern,
        k: &[f64],
        extra: &mut [(usize, usize, f64)],
        full: &mut [f64],
    ) -> Result<(), LinearError> {
        self.bordered.finish(pattern, k, extra, full)
    }

    /// What the solves have cost and how they went, summed.
    pub fn counts(&self) -> LinearCounts {
        let (t, b) = (&self.tangent, &self.bordered);
        LinearCounts {
            times: t.times.plus(b.times),
            factorizations: t.factorizations + b.factorizations,
            analyses: b.analyses,
            ldlt: b.ldlt,
            lu: b.lu,
            ldu: b.ldu,
            trailing: b.trailing_solves,
            deferred: b.deferred_solves,
            reused: self.reused,
        }
    }
}
