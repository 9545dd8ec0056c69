//! Where the time of a run went (assembly, contact, the linear solves by
//! phase) and how its solves went: what the benchmarks print.

use crate::results::LinearTimes;
use std::time::Duration;

/// Where a solver's time went since it was made, by phase (the benchmarks'
/// split, issue 14). `total` is the wall time inside `advance`; what the
/// phases leave of it is the iteration's own work (residual norms,
/// convergence tests, copies of the iterate).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Phases {
    /// Element internal forces and tangents.
    pub assembly: Duration,
    /// Contact search, force recovery, decisions and rows, and the inner
    /// solves' predictions of the linearised problem's states.
    pub contact: Duration,
    /// Building, ordering, factoring and solving the linear systems.
    pub linear: LinearTimes,
    pub total: Duration,
    /// Numeric factorizations of the increments' systems (the
    /// sensitivities' not counted).
    pub factorizations: usize,
    /// Symbolic analyses of bordered systems (a new contact pattern).
    pub analyses: usize,
    /// Bordered systems solved by LDLT, by LU, by the unpivoted LDU, and
    /// without a factorization of their own, on the last LDLT factor's
    /// trailing block.
    pub ldlt: usize,
    pub lu: usize,
    pub ldu: usize,
    pub trailing: usize,
    /// Of those, the ones whose interior waited until an inner solve was
    /// accepted.
    pub deferred: usize,
    /// Newton iterations whose first solve took the last factor's trailing
    /// block instead of a factorization (a constant tangent, its contact
    /// rows changed on the trailing set alone).
    pub reused: usize,
    /// Assemblies of the tangent (one per solver for a constant one).
    pub tangents: usize,
}

impl Phases {
    /// The phases as percentages of the time inside `advance`, one line.
    pub fn split(&self) -> String {
        let total = self.total.as_secs_f64().max(f64::MIN_POSITIVE);
        let parts = [
            ("assembly", self.assembly),
            ("contact", self.contact),
            ("system", self.linear.system),
            ("symbolic", self.linear.symbolic),
            ("numeric", self.linear.numeric),
            ("solve", self.linear.solve),
        ];
        let named: Duration = parts.iter().map(|(_, d)| *d).sum();
        let rest = self.total.saturating_sub(named);
        (parts.iter().chain([&("rest", rest)]))
            .map(|(name, d)| format!("{name} {:.1}", 100.0 * d.as_secs_f64() / total))
            .collect::<Vec<_>>()
            .join("  ")
    }

    /// `split` and the counts, one line (the CLI's `-v` and the benchmark).
    pub fn summary(&self) -> String {
        format!(
            "{}; {} factorizations ({} LDLT, {} LU, {} LDU), {} solves on the trailing block ({} deferred, {} first of an iteration), {} symbolic analyses",
            self.split(),
            self.factorizations,
            self.ldlt,
            self.lu,
            self.ldu,
            self.trailing,
            self.deferred,
            self.reused,
            self.analyses
        )
    }
}

/// The solver's own part of [`Phases`].
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct SolverTimes {
    pub(super) tangents: usize,
    pub(super) assembly: Duration,
    pub(super) contact: Duration,
    pub(super) total: Duration,
}
