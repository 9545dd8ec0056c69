//! The correction with contact rows or ties (Eq. (18)) and the inner solves
//! that settle the linearised problem's stick and slip states before the
//! next iteration; and a correction without contact rows on the slots of
//! the rows to come (docs/contact.md section 8).

use super::{
    INNER_FLIPS, Increment, InnerSolves, KeptSolve, MAX_INNER, Solver, Step, acts_on_free, largest,
};
use crate::assembly::PRESCRIBED;
use crate::contact::{self, ContactSystem, Flips, PairMemory, Switched};
use crate::linsolve::LinearError;
use crate::results::LogCategory;
use std::time::Instant;

impl Solver {
    /// The contact nodes that may touch in this increment (`contact::near_target`,
    /// within its prescribed motion `Increment::reach`), nearest first, as
    /// the multiplier slots their rows would take (`Linear::slots`): one
    /// per node, two with friction (a sticking node's), each keyed by the
    /// node's free equations (the rows against a rigid target act on the
    /// node alone). A node left out that touches gives the contact system
    /// a pattern of its own (an analysis and a factorization, as without
    /// the slots). Empty when no node may touch or a target is a body.
    pub(super) fn contact_slots(&self, inc: &Increment) -> Result<Vec<Vec<usize>>, String> {
        let near = contact::near_target(
            &self.problem,
            &self.targets,
            &inc.poses,
            &self.state.u,
            &inc.memory,
            inc.reach,
        )?;
        let Some(near) = near else {
            return Ok(Vec::new());
        };
        let mut nodes: Vec<(f64, usize, usize)> = (near.iter().enumerate())
            .flat_map(|(p, near)| near.iter().map(move |&(k, d)| (d, p, k)))
            .collect();
        nodes.sort_by(|a, b| a.0.total_cmp(&b.0).then((a.1, a.2).cmp(&(b.1, b.2))));
        let keys = nodes.into_iter().map(|(_, p, k)| {
            let pair = &self.problem.contacts[p];
            let node = pair.contactor[k];
            let eqs: Vec<usize> = [2 * node, 2 * node + 1]
                .into_iter()
                .filter(|&d| self.model.eq[d] != PRESCRIBED)
                .map(|d| self.model.eq[d] as usize)
                .collect();
            (eqs, if pair.mu_s > 0.0 { 2 } else { 1 })
        });
        Ok(self.linear.slots(self.model.free_dofs(), keys))
    }

    /// A correction without contact rows (`inc.rhs` in, the correction
    /// out) against rigid targets, on the tangent bordered by the slots of
    /// the contact rows to come (`contact_slots`, `Linear::solve_in_slots`),
    /// so that the iterations with contact rows solve on the same factor's
    /// trailing block or on its analysis: one symbolic analysis and one
    /// factorization where the plain tangent and then the contact system
    /// took two of each. False when this does not apply (no slots, the
    /// solver takes none, a failed solve): the tangent alone solves then.
    pub(super) fn solve_in_contact_slots(&mut self, inc: &mut Increment) -> Result<bool, String> {
        if self.problem.contacts.is_empty() || !self.linear.takes_slots() {
            return Ok(false);
        }
        if inc.slots.is_none() {
            inc.slots = Some(self.contact_slots(inc)?);
        }
        let slots = inc.slots.as_deref().unwrap_or_default();
        if slots.is_empty() {
            return Ok(false);
        }
        let (pattern, k) = (&self.model.pattern, &self.k);
        if !(self.linear).solve_in_slots(pattern, k, slots, &mut inc.extra, &mut inc.rhs) {
            inc.slots = Some(Vec::new());
            return Ok(false);
        }
        Ok(true)
    }

    /// The correction with contact rows or ties: Eq. (18), `[K + K_c, C^T;
    /// C, 0] [du; dlambda] = [r; overlap]`, the contact rows first, then the
    /// tie rows (`C u = 0`; `constraint_system`); under the nodal decisions
    /// solved again while the linearised problem decides a node's state
    /// otherwise than the iterate did (docs/contact.md section 8, inner
    /// solves: `next_inner_states`, `contact_update`), its rows changing,
    /// the tangent and the out-of-balance forces not. Returns `[du;
    /// multipliers]` and the contact system it solves.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn constrained_correction(
        &mut self,
        step: &Step,
        contact: Option<ContactSystem>,
        rhs_base: Option<&[f64]>,
        rhs: &[f64],
        memory: &mut Vec<PairMemory>,
        flips: &mut Flips,
        extra: &mut Vec<(usize, usize, f64)>,
        solves: &mut usize,
        log: &mut dyn FnMut(LogCategory, &str),
    ) -> Result<(Vec<f64>, Option<ContactSystem>), String> {
        let inner_solves = contact::inner_solves(&self.problem);
        let mut system: Option<ContactSystem> = contact;
        let mut rhs_now = rhs.to_vec();
        let mut inner = InnerSolves::default();
        // The solve before the decisions the linearised problem takes from
        // it, kept until the next solve shows those decisions hold.
        let mut kept: Option<KeptSolve> = None;
        // The solve of the iterate's own decisions, kept from the first
        // inner solve on where they may stand (`iterate_decides`): the
        // iteration goes on from it when the inner solves do not settle
        // (`unsettled`).
        let mut first: Option<KeptSolve> = None;
        let full = loop {
            let mut full = self.constraint_system(step, system.as_ref(), &rhs_now, extra);
            *solves += 1;
            let more =
                inner_solves && inner.count < MAX_INNER && system.is_some() && rhs_base.is_some();
            let neqc = system.as_ref().map_or(0, |c| c.rows.len());
            let b = more.then(|| full.clone());
            let (mut solved, mut partial) =
                self.solve_constraint_system(&mut full, extra, inner.count, more);
            if solved.is_ok()
                && !partial
                && let Some(sys) = system.as_ref()
                && self.contact_terms_turn_step(sys, &full)
            {
                // The pair's sliding gradient terms (Eq. 24) turn the
                // tangent's curvature along its own step non-positive: the
                // step heads for a saddle of the linearised problem, not
                // for an equilibrium. Solved again without them.
                log(LogCategory::Contact, &{
                    let (t, it) = (step.t, step.it);
                    format!(
                        "t = {t:.6e} it {it}: the contact's sliding gradient turns the \
                         tangent's curvature along the correction non-positive; solved \
                         without it"
                    )
                });
                // Its rows only: the contact's displacement block left out.
                full = self.constraint_system_with(step, system.as_ref(), &rhs_now, extra, false);
                (solved, partial) =
                    self.solve_constraint_system(&mut full, extra, inner.count, more);
            }
            let solved = solved.map_err(|e| format!("constraint system (NEQC {neqc}): {e}"));
            if let Some(previous) = kept.take()
                && let Some(x) =
                    self.rolled_back(previous, &solved, &full, memory, &mut system, extra)?
            {
                break x;
            }
            solved?;
            let Some((sys, rhs_base)) = system.as_ref().zip(rhs_base).filter(|_| more) else {
                if let Some(first) = first.take().filter(|_| inner.count >= MAX_INNER) {
                    break self.unsettled(first, step, memory, &mut system, extra, log)?;
                }
                break self.finish_inner(partial, full, extra)?;
            };
            let Some(switched) =
                self.next_inner_states(step, sys, &full, memory, &mut inner, log)?
            else {
                if let Some(first) = first.take().filter(|_| inner.wandered) {
                    break self.unsettled(first, step, memory, &mut system, extra, log)?;
                }
                break self.finish_inner(partial, full, extra)?;
            };
            let deferred = b.filter(|_| partial).map(|b| (b, extra.clone()));
            let states = memory.clone();
            let mut rebuilt =
                self.contact_update(step, Some((sys, &switched)), memory, flips, log)?;
            let clock = Instant::now();
            rebuilt.complete_tangent();
            self.times.contact += clock.elapsed();
            rhs_now.copy_from_slice(rhs_base);
            for &(d, f) in &rebuilt.force {
                if self.model.eq[d] != PRESCRIBED {
                    rhs_now[self.model.eq[d] as usize] += f;
                }
            }
            kept = Some(KeptSolve {
                full,
                memory: states,
                system: system.replace(rebuilt),
                deferred,
            });
            if first.is_none() && self.iterate_decides(step) {
                first = kept.clone();
            }
        };
        Ok((full, system))
    }

    /// One solve of the constraint system `full` (entries `extra` beside
    /// the tangent), the `inner`-th of its iteration (`Linear::solve`
    /// decides how). With `more` (another inner solve may follow) it may be
    /// left partial, the contact nodes' motion solved alone until one is
    /// accepted (`finish_inner`). Returns the solve's outcome and whether
    /// it was left partial so.
    fn solve_constraint_system(
        &mut self,
        full: &mut [f64],
        extra: &mut [(usize, usize, f64)],
        inner: usize,
        more: bool,
    ) -> (Result<(), LinearError>, bool) {
        let (pattern, k) = (&self.model.pattern, &self.k);
        match (self.linear).solve(pattern, k, extra, full, more, inner == 0) {
            Ok(whole) => (Ok(()), !whole),
            Err(e) => (Err(e), false),
        }
    }

    /// After an inner solve, whether the states the linearised problem chose
    /// before it leave no equilibrium near (every node of a free body
    /// sliding where the iterate's linearisation is poor: the solve failed,
    /// or moves a node by more than 1000 times the model's size). Then the
    /// solve before them (`previous`) is kept, its memory and rows restored
    /// (solved again in full if it was deferred), and the outer iteration
    /// decides: Some(that solve). None: the inner solve stands.
    fn rolled_back(
        &mut self,
        previous: KeptSolve,
        solved: &Result<(), String>,
        full: &[f64],
        memory: &mut Vec<PairMemory>,
        system: &mut Option<ContactSystem>,
        extra: &mut Vec<(usize, usize, f64)>,
    ) -> Result<Option<Vec<f64>>, String> {
        let n = self.model.free_dofs();
        let wild = solved.is_err()
            || largest(&full[..n]).is_nan()
            || largest(&full[..n]) > 1e3 * self.size;
        if !wild {
            return Ok(None);
        }
        self.restore_solve(previous, memory, system, extra)
            .map(Some)
    }

    /// The inner solves of an iteration where the iterate's decisions may
    /// stand (`iterate_decides`) cycled through every node of a pair's
    /// contact zone (`InnerSolves::wandered`), or `MAX_INNER` of them did
    /// not settle: the iteration
    /// goes on from its first solve, the iterate's own decisions
    /// (`first`), and the outer iteration decides. Keeping the last inner
    /// solve instead kept whichever state the wandering stopped at: a block
    /// of nu = 0.44 pressed with friction onto a stiffer strip moved its
    /// one-node stick zone four nodes and back at every iteration and
    /// failed its first increment (`scripts/press_sweep.py`,
    /// docs/performance-log.md, ninth session). Not at the predictor's
    /// iteration: there the iterate's decisions are the last increment's,
    /// which the new load may overturn at every node (the capstan of the
    /// stress suite, 2x: all 128 nodes alternated between stick and slip
    /// from iteration to iteration, and the increment bisected), and the
    /// linearised problem's last states are the better guess.
    fn unsettled(
        &mut self,
        first: KeptSolve,
        step: &Step,
        memory: &mut Vec<PairMemory>,
        system: &mut Option<ContactSystem>,
        extra: &mut Vec<(usize, usize, f64)>,
        log: &mut dyn FnMut(LogCategory, &str),
    ) -> Result<Vec<f64>, String> {
        let (t, it) = (step.t, step.it);
        log(
            LogCategory::Contact,
            &format!(
                "t = {t:.6e} it {it}: the inner solves did not settle; the iterate's own \
                 decisions stand"
            ),
        );
        self.restore_solve(first, memory, system, extra)
    }

    /// Whether the iterate's own decisions may stand when the inner solves
    /// do not settle (`unsettled`): past the predictor's iteration, and
    /// not in the fallback that leaves opening and closing to the iterate
    /// (`iterate_opens`). That fallback serves bodies far from
    /// equilibrium at their first iterates: the capstan's strip held on
    /// the drum by its end forces alone (`tests/force_driver.rs`) shows
    /// |r|/F of 0.2 to 1 there, its decisions are no guide, and going back
    /// to them failed the increment (13 stick/slip changes at a node,
    /// 6 bisections) where the last inner solve converges it in 7.
    fn iterate_decides(&self, step: &Step) -> bool {
        step.it > 0 && !self.iterate_opens
    }

    /// The solve `previous` with its memory and rows restored (solved again
    /// in full if it was left partial).
    fn restore_solve(
        &mut self,
        previous: KeptSolve,
        memory: &mut Vec<PairMemory>,
        system: &mut Option<ContactSystem>,
        extra: &mut Vec<(usize, usize, f64)>,
    ) -> Result<Vec<f64>, String> {
        *memory = previous.memory;
        *system = previous.system;
        let Some((rhs_prev, extra_prev)) = previous.deferred else {
            return Ok(previous.full);
        };
        // That solve was left partial: solved again in full.
        *extra = extra_prev;
        let mut x = rhs_prev;
        let (pattern, k) = (&self.model.pattern, &self.k);
        (self.linear.solve(pattern, k, extra, &mut x, false, false))
            .map_err(|e| format!("constraint system: {e}"))?;
        Ok(x)
    }

    /// The nodes the linearised problem decides otherwise than `sys`'s rows
    /// did, after the solve `full` (`linearised_states`), for the next inner
    /// solve: None when none changes, when each change would open or close a
    /// node once too often in this iteration (`INNER_FLIPS`; none while the
    /// increment leaves opening and closing to the iterate), or when the
    /// states were met before in this iteration (the decisions cycle; when
    /// the cycle changed every node of a pair's contact zone,
    /// `inner.wandered`, the outer iteration decides from the first solve,
    /// `unsettled`).
    fn next_inner_states(
        &mut self,
        step: &Step,
        sys: &ContactSystem,
        full: &[f64],
        memory: &[PairMemory],
        inner: &mut InnerSolves,
        log: &mut dyn FnMut(LogCategory, &str),
    ) -> Result<Option<Switched>, String> {
        let clock = Instant::now();
        let predicted = self.linearised_states(step, sys, full, memory);
        self.times.contact += clock.elapsed();
        let Some(mut switched) = predicted? else {
            return Ok(None);
        };
        let flips_allowed = if self.iterate_opens { 0 } else { INNER_FLIPS };
        switched.limit_flips(&mut inner.flipped, flips_allowed);
        if switched.count() == 0 {
            return Ok(None);
        }
        let key = contact::state_key(memory, &switched);
        let nodes = switched.nodes();
        if let Some(at) = inner.seen.iter().position(|&k| k == key) {
            // The changes that lead round the cycle, from the states met
            // before (reached by `changed[at]`) back to them.
            let mut round: Vec<(usize, usize)> = inner.changed[at + 1..].concat();
            round.extend(&nodes);
            round.sort_unstable();
            round.dedup();
            // Every node of a pair's contact zone changed on the way.
            inner.wandered = memory.iter().enumerate().any(|(p, m)| {
                let mut zone = (0..m.nodes())
                    .filter(|&k| m.state(k) != crate::results::NodeState::Open)
                    .peekable();
                zone.peek().is_some() && zone.all(|k| round.binary_search(&(p, k)).is_ok())
            });
            return Ok(None);
        }
        inner.seen.push(key);
        inner.changed.push(nodes);
        inner.count += 1;
        let [opened, closed, slips] = switched.counts();
        self.inner_flips += opened + closed;
        let (t, it, count) = (step.t, step.it, inner.count);
        log(LogCategory::Contact, &{
            format!(
                "t = {t:.6e} it {it}: solve {count}: the linearised problem opens {opened}, \
                 closes {closed} and changes {slips} between stick and slip"
            )
        });
        Ok(Some(switched))
    }

    /// The accepted inner solve `full`: as solved, or, when it was left
    /// partial, finished (`Linear::finish`; entries `extra`).
    fn finish_inner(
        &mut self,
        partial: bool,
        mut full: Vec<f64>,
        extra: &mut [(usize, usize, f64)],
    ) -> Result<Vec<f64>, String> {
        if partial {
            (self
                .linear
                .finish(&self.model.pattern, &self.k, extra, &mut full))
            .map_err(|e| format!("constraint system: {e}"))?;
        }
        Ok(full)
    }

    /// The nodes whose stick/slip state the linearised problem decides
    /// otherwise than the rows of `sys` did (`contact::predict`), from where
    /// its solution `full` goes and the out-of-balance force it leaves at
    /// each dof (K du = r_c - C^T x - r).
    fn linearised_states(
        &mut self,
        step: &Step,
        sys: &ContactSystem,
        full: &[f64],
        memory: &[PairMemory],
    ) -> Result<Option<Switched>, String> {
        let (eq, n) = (&self.model.eq, self.model.free_dofs());
        let mut u_new = step.u.to_vec();
        let mut force_new = vec![0.0; step.u.len()];
        for (dof, &q) in eq.iter().enumerate() {
            if q != PRESCRIBED {
                u_new[dof] += full[q as usize];
            } else if step.it == 0 {
                u_new[dof] += step.dup[dof];
            }
        }
        for &(d, f) in &sys.force {
            if eq[d] != PRESCRIBED {
                force_new[d] += f;
            }
        }
        for (i, row) in sys.rows.iter().enumerate() {
            for &(d, v) in row.acting() {
                if eq[d] != PRESCRIBED {
                    force_new[d] -= full[n + i] * v;
                }
            }
        }
        contact::predict(
            &self.problem,
            &self.targets,
            step.poses,
            [step.u, &u_new],
            &force_new,
            memory,
            sys,
            step.tolerance,
            step.settling || step.it == 0,
            &mut self.search_cache,
        )
    }

    /// The contact system at the iterate, from `r` (`contact::update`); with
    /// `keep` (an inner solve), the rows rebuilt at the same iterate with
    /// the switched nodes' states and every other node's decision kept in
    /// the system given: the tangent and `r` do not change.
    pub(super) fn contact_update(
        &mut self,
        step: &Step,
        keep: Option<(&ContactSystem, &Switched)>,
        memory: &mut [PairMemory],
        flips: &mut Flips,
        log: &mut dyn FnMut(LogCategory, &str),
    ) -> Result<ContactSystem, String> {
        let (t, it) = (step.t, step.it);
        let mut clog = |m: &str| log(LogCategory::Contact, &format!("t = {t:.6e} it {it}: {m}"));
        let start = contact::Start {
            u: &self.state.u,
            poses: &self.state.rigid,
            settling: step.settling,
            touching: self.close_touching,
            cache: &self.start_cache,
        };
        let clock = Instant::now();
        let updated = contact::update(
            &self.problem,
            &self.targets,
            step.poses,
            step.u,
            &self.r,
            &self.model.eq,
            &start,
            memory,
            flips,
            &mut clog,
            keep,
        );
        self.times.contact += clock.elapsed();
        updated
    }

    /// The constraint rows of Eq. (18) into `extra` (triplets beside K) and
    /// the full right-hand side `[rhs; row values]`: the contact system's
    /// sliding gradient entries and rows (a sliding node's multiplier with
    /// its own column), then the tie rows.
    fn constraint_system(
        &self,
        step: &Step,
        system: Option<&ContactSystem>,
        rhs_now: &[f64],
        extra: &mut Vec<(usize, usize, f64)>,
    ) -> Vec<f64> {
        self.constraint_system_with(step, system, rhs_now, extra, true)
    }

    /// Whether the contact's displacement block `sys.k` turns the
    /// curvature of the tangent along the solved correction `full`
    /// non-positive while the body's tangent alone keeps it positive:
    /// `du^T (K + K_c) du <= 0 < du^T K du`.
    fn contact_terms_turn_step(&self, sys: &ContactSystem, full: &[f64]) -> bool {
        if sys.k.is_empty() {
            return false;
        }
        let (eq, pattern, n) = (&self.model.eq, &self.model.pattern, self.model.free_dofs());
        let du = &full[..n];
        let mut body = 0.0;
        for (c, &du_c) in du.iter().enumerate().take(pattern.n) {
            for p in pattern.col_ptr[c]..pattern.col_ptr[c + 1] {
                body += du[pattern.row_idx[p]] * self.k[p] * du_c;
            }
        }
        let mut contact = 0.0;
        for &(a, b, v) in &sys.k {
            if eq[a] != PRESCRIBED && eq[b] != PRESCRIBED {
                contact += du[eq[a] as usize] * v * du[eq[b] as usize];
            }
        }
        body > 0.0 && body + contact <= 0.0
    }

    /// The constraint system, the contact's displacement block included
    /// (`gradient`) or not.
    fn constraint_system_with(
        &self,
        step: &Step,
        system: Option<&ContactSystem>,
        rhs_now: &[f64],
        extra: &mut Vec<(usize, usize, f64)>,
        gradient: bool,
    ) -> Vec<f64> {
        let (eq, n, it) = (&self.model.eq, self.model.free_dofs(), step.it);
        let (u, dup) = (step.u, step.dup);
        extra.clear();
        let mut full = rhs_now.to_vec();
        let contact_rows = system.map_or(&[][..], |c| &c.rows[..]);
        if let Some(c) = system.filter(|_| gradient) {
            for &(a, b, v) in &c.k {
                if eq[a] != PRESCRIBED && eq[b] != PRESCRIBED {
                    extra.push((eq[a] as usize, eq[b] as usize, v));
                }
            }
        }
        let ties = self.problem.ties.iter().flat_map(|t| &t.rows);
        let tie_rows = ties.map(|r| {
            let violation: f64 = r.dofs.iter().map(|&(d, v)| v * u[d]).sum();
            (&r.dofs[..], -violation)
        });
        let rows = contact_rows
            .iter()
            .map(|r| (&r.dofs[..], r.rhs, &r.column[..]));
        let tie_rows = tie_rows.map(|(dofs, b)| (dofs, b, &[][..]));
        for (i, (dofs, rhs_i, column)) in rows.chain(tie_rows).enumerate() {
            let mut b = rhs_i;
            let free = acts_on_free(dofs, eq);
            for &(d, v) in dofs {
                if eq[d] == PRESCRIBED {
                    if it == 0 {
                        b -= v * dup[d];
                    }
                } else if free {
                    extra.push((n + i, eq[d] as usize, v));
                    if column.is_empty() {
                        extra.push((eq[d] as usize, n + i, v));
                    }
                }
            }
            // A sliding node's friction: the multiplier's column
            // differs from its row.
            for &(d, v) in column.iter().filter(|_| free) {
                if eq[d] != PRESCRIBED {
                    extra.push((eq[d] as usize, n + i, v));
                }
            }
            if !free {
                // Every dof the row acts on is prescribed (a
                // sticking node on a symmetry plane against a
                // fixed target): the drivers already hold it; its
                // multiplier gets an identity row.
                extra.push((n + i, n + i, 1.0));
                b = 0.0;
            }
            full.push(b);
        }
        full
    }
}
