//! Contact after Bathe & Chaudhary (1984): contactor nodes against target
//! segments, enforced by Lagrange multipliers in Eq. (18). The derivation is
//! in docs/contact.md.
//!
//! Per pair and iteration the contact runs in phases: search (where the
//! contactor meets the target: `search`), forces (recovered from the
//! out-of-balance forces, or multipliers), decisions (open / stick / slip),
//! rows (Eq. 18) and report (`report`). A formulation is one implementation
//! of these phases behind [`Formulation`]; `formulation` names the one a
//! pair uses, and the registry's types below hold each formulation's own
//! data. Newton sees only this module's functions, `PairMemory` and the
//! types of `system`.

pub mod checks;
mod memory;
mod mortar;
mod node_to_segment;
pub mod outputs;
mod report;
mod search;
pub mod segment;
pub mod sensitivity;
mod system;

pub use memory::begin_increment;
pub use search::{
    NearNodes, RigidSegments, SearchCache, near_target, rigid_reference, scene_poses,
};
pub use segment::{ContactPoint, NodeMat, NodeVec, Segment, Sliding, Sticking};
pub use system::{
    ContactSystem, Entries, Flips, Row, Start, StartCache, Switched, state_key, touches_prescribed,
};

use crate::problem::{ContactFormulation, ContactPair, Decisions, Problem};
use crate::results::PairResult;
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use system::{Forced, Iterate};

/// Errors of the contact kernel, carrying the offending values.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ContactError {
    /// A target segment needs two distinct, finite end points.
    #[error(
        "degenerate target segment from ({}, {}) to ({}, {}): length {length}",
        xa[0], xa[1], xb[0], xb[1]
    )]
    DegenerateSegment {
        xa: [f64; 2],
        xb: [f64; 2],
        length: f64,
    },
}

/// What a linearised problem's solution says about one pair, for the
/// decisions it predicts (`Formulation::predict`): the displacements now and
/// after the solve, the out-of-balance force per dof the solve leaves, and
/// the iteration's tolerances [force, length].
pub(crate) struct Prediction<'a> {
    pub problem: &'a Problem,
    pub targets: &'a RigidSegments,
    pub poses: &'a [[f64; 3]],
    pub u_now: &'a [f64],
    pub u_new: &'a [f64],
    pub force_new: &'a [f64],
    pub tolerance: [f64; 2],
    /// The iterate has not settled (`Start::settling`).
    pub settling: bool,
}

/// A contact formulation: one pair's contact at an iterate, in the phases
/// of the module's header. Adding one is a folder beside `node_to_segment`
/// and its registration below (docs/contact.md section 10).
pub(crate) trait Formulation: Sync {
    /// The pair at the iterate `at`: its nodes decided (or, with `keep`, the
    /// kept decisions with the switched nodes' states), its forces, gradient
    /// entries and rows added to `out`, its memory updated, its results
    /// returned. `out.kept` receives what `predict`, a later `update` with
    /// `keep`, `linearise` and a deferred tangent read back.
    #[allow(clippy::too_many_arguments)]
    fn update(
        &self,
        at: &Iterate,
        pair: (usize, &ContactPair),
        mem: &mut PairMemory,
        counters: [&mut [usize]; 2],
        log: &mut dyn FnMut(&str),
        out: &mut ContactSystem,
        keep: Option<(&Kept, &[(usize, Forced)])>,
    ) -> Result<PairResult, String>;

    /// Whether the linearised problem's decisions (inner solves) apply.
    fn inner_solves(&self) -> bool;

    /// The nodes the linearised problem decides otherwise than the kept
    /// decisions did (`kept`, from `update`); None: this formulation has
    /// no inner solves.
    fn predict(
        &self,
        at: &Prediction,
        pair: (usize, &ContactPair),
        mem: &PairMemory,
        kept: &Kept,
        cache: &mut SearchCache,
    ) -> Result<Option<Vec<(usize, Forced)>>, String>;

    /// Whether `linearise` answers for `pair` (the FMU then provides
    /// directional derivatives).
    fn sensitivities(&self, pair: &ContactPair) -> bool;

    /// The exact linearisation of the pair's contact conditions at a
    /// converged state (`sensitivity::linearise`), into `out`.
    fn linearise(
        &self,
        at: &sensitivity::At,
        pair: (usize, &ContactPair),
        kept: &Kept,
        out: &mut sensitivity::Linearised,
    ) -> Result<(), String>;

    /// What the pair's memory `mem` at an increment that did not converge
    /// says a user could change (appended to the failure's reason); None
    /// by default.
    fn failure_hint(&self, _pair: &ContactPair, _mem: &PairMemory) -> Option<String> {
        None
    }
}

/// The formulation a pair uses: the registration of every formulation,
/// with the types below that hold each one's own data.
fn formulation(pair: &ContactPair) -> &'static dyn Formulation {
    match (pair.formulation, pair.decisions) {
        (ContactFormulation::Mortar, _) => &mortar::Mortar,
        (ContactFormulation::NodeToSegment, Decisions::Nodal) => &node_to_segment::Nodal,
        (ContactFormulation::NodeToSegment, Decisions::Paper) => &node_to_segment::Paper,
    }
}

/// What a pair carries from one iteration, and one increment, to the next,
/// in its formulation's own type (`memory::Remembered` is what the shared
/// phases read of it).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum PairMemory {
    NodeToSegment(node_to_segment::Memory),
    Mortar(mortar::Memory),
}

impl PairMemory {
    /// The memory of a pair before its first increment.
    pub fn new(pair: &ContactPair) -> Self {
        match pair.formulation {
            ContactFormulation::NodeToSegment => {
                Self::NodeToSegment(node_to_segment::Memory::new(pair))
            }
            ContactFormulation::Mortar => Self::Mortar(mortar::Memory::new(pair)),
        }
    }

    /// Whether it has the shape of `pair`'s memory (its formulation, an
    /// entry per contactor node and per contactor segment): a restored
    /// state's check.
    pub fn fits(&self, pair: &ContactPair) -> bool {
        match (self, Self::new(pair)) {
            (Self::NodeToSegment(m), Self::NodeToSegment(f)) => {
                m.nodes.len() == f.nodes.len() && m.segments.len() == f.segments.len()
            }
            (Self::Mortar(m), Self::Mortar(f)) => m.nodes.len() == f.nodes.len(),
            _ => false,
        }
    }
}

/// The shared phases read and shift a pair's memory as `Remembered`.
impl std::ops::Deref for PairMemory {
    type Target = dyn memory::Remembered;
    fn deref(&self) -> &Self::Target {
        match self {
            Self::NodeToSegment(m) => m,
            Self::Mortar(m) => m,
        }
    }
}

impl std::ops::DerefMut for PairMemory {
    fn deref_mut(&mut self) -> &mut Self::Target {
        match self {
            Self::NodeToSegment(m) => m,
            Self::Mortar(m) => m,
        }
    }
}

/// What a formulation keeps of one pair's decisions at an iterate: the
/// inner solves at that iterate and the linearisation of a converged state
/// read it back.
#[derive(Clone, Default)]
pub(crate) enum Kept {
    /// Nothing kept: the formulation has no inner solves.
    #[default]
    None,
    Nodal(Arc<node_to_segment::Decided>),
    Mortar(Arc<mortar::Decided>),
}

impl Kept {
    /// The tangent entries its formulation deferred to a solve that needs
    /// them (`ContactSystem::defer_tangent`).
    fn add_tangent(&self, k: &mut Vec<(usize, usize, f64)>) {
        match self {
            Kept::Mortar(decided) => decided.add_tangent(k),
            Kept::None | Kept::Nodal(_) => {}
        }
    }
}

impl std::fmt::Debug for Kept {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Kept(..)")
    }
}

/// What a formulation derives from an increment's start alone, per pair
/// (`StartCache`).
#[derive(Clone)]
pub(crate) enum StartData {
    Mortar(Arc<mortar::AtStart>),
}

/// A pair's memory or kept data of another formulation than its own: a
/// state restored into a problem it was not saved from.
fn mismatch(pair: &ContactPair, what: &str) -> String {
    format!("pair '{}': its {what} is another formulation's", pair.name)
}

/// Whether a converged state has sensitivities (the FMU's directional
/// derivatives): every pair's formulation linearises.
pub fn sensitivities(problem: &Problem) -> bool {
    problem
        .contacts
        .iter()
        .all(|p| formulation(p).sensitivities(p))
}

/// Whether the inner solves apply: every pair's formulation has them.
pub fn inner_solves(problem: &Problem) -> bool {
    problem
        .contacts
        .iter()
        .all(|p| formulation(p).inner_solves())
}

/// The contact part of the system at displacements `u` and rigid target
/// poses `poses` ([ux, uy, theta] per rigid target), from the out-of-balance
/// forces `r` (F_int - R_ext, contact excluded) and the memory after the
/// previous iteration, which it updates. `eq` maps dofs to equations
/// (PRESCRIBED for prescribed dofs).
///
/// `keep`: the system `update` built at this same iterate (from these `u`
/// and `r`) and the nodes the linearised problem switched (`predict`): those
/// get their new states, every other node keeps its decision, giving the
/// rows of the linearised problem's next active set.
#[allow(clippy::too_many_arguments)]
pub fn update(
    problem: &Problem,
    targets: &RigidSegments,
    poses: &[[f64; 3]],
    u: &[f64],
    r: &[f64],
    eq: &[u32],
    start: &Start,
    memory: &mut [PairMemory],
    flips: &mut Flips,
    log: &mut dyn FnMut(&str),
    keep: Option<(&ContactSystem, &Switched)>,
) -> Result<ContactSystem, String> {
    let mut out = ContactSystem {
        rigid: vec![[0.0; 3]; problem.rigids.len()],
        ..Default::default()
    };
    flips.fit(memory);
    let at = Iterate {
        problem,
        targets,
        poses,
        u,
        r,
        eq,
        start,
    };
    for (p, pair) in problem.contacts.iter().enumerate() {
        let keep = keep.map(|(previous, switched)| (&previous.kept[p], &switched.0[p][..]));
        let counters = [&mut flips.counts[p][..], &mut flips.slips[p][..]];
        let result = formulation(pair).update(
            &at,
            (p, pair),
            &mut memory[p],
            counters,
            log,
            &mut out,
            keep,
        )?;
        out.pairs.push(result);
    }
    Ok(out)
}

/// The nodes whose state the linearised problem decides otherwise than
/// `system`'s rows did: after solving with them, `u_new` the displacements
/// reached and `force_new` the out-of-balance force per dof there as the
/// solve predicts it (zero at prescribed dofs). Tolerances [force, length]
/// as the iteration's equilibrium. None when every pair keeps its states,
/// or when a pair's formulation has no inner solves.
#[allow(clippy::too_many_arguments)]
pub fn predict(
    problem: &Problem,
    targets: &RigidSegments,
    poses: &[[f64; 3]],
    [u_now, u_new]: [&[f64]; 2],
    force_new: &[f64],
    memory: &[PairMemory],
    system: &ContactSystem,
    tolerance: [f64; 2],
    settling: bool,
    cache: &mut SearchCache,
) -> Result<Option<Switched>, String> {
    if system.kept.len() != problem.contacts.len() {
        return Ok(None);
    }
    let at = Prediction {
        problem,
        targets,
        poses,
        u_now,
        u_new,
        force_new,
        tolerance,
        settling,
    };
    let mut out = Vec::with_capacity(problem.contacts.len());
    for (p, pair) in problem.contacts.iter().enumerate() {
        let Some(switched) =
            formulation(pair).predict(&at, (p, pair), &memory[p], &system.kept[p], cache)?
        else {
            return Ok(None);
        };
        out.push(switched);
    }
    let switched = Switched(out);
    Ok((switched.count() > 0).then_some(switched))
}

/// The pairs' hints on an increment that did not converge
/// (`Formulation::failure_hint`), from their memory at its last iterate:
/// empty, or "; " and the hints.
pub fn failure_hints(problem: &Problem, memory: &[PairMemory]) -> String {
    (problem.contacts.iter().zip(memory))
        .filter_map(|(pair, mem)| formulation(pair).failure_hint(pair, mem))
        .map(|hint| format!("; {hint}"))
        .collect()
}
