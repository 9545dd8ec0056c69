//! Node-to-segment contact (the paper's formulation): each contactor node
//! is held on the target segment it meets by the rows of Eq. (18). Its
//! states are decided node by node on the iterate (`nodal`, the default)
//! or by the paper's Section 3 on recovered segment tractions (`paper`);
//! both build their rows with `rows` and report with `contact::report`.

mod linearise;
mod nodal;
mod paper;
mod rows;

use super::memory::PairMemory;
use super::search::SearchCache;
use super::sensitivity::{At, Linearised};
use super::system::{ContactSystem, Forced, Iterate, Kept};
use super::{Formulation, Prediction};
use crate::problem::ContactPair;
use crate::results::PairResult;

/// A node's contact force counts as tension above this fraction of the
/// largest contact force of its pair (round-off at a node just touching).
const TENSION_TOLERANCE: f64 = 1e-8;

/// Node-to-segment contact decided node by node (`decisions = "nodal"`).
pub(super) struct Nodal;
/// Node-to-segment contact decided by the paper's Section 3
/// (`decisions = "paper"`).
pub(super) struct Paper;

pub(super) const NODAL: Nodal = Nodal;
pub(super) const PAPER: Paper = Paper;

impl Formulation for Nodal {
    fn update(
        &self,
        at: &Iterate,
        pair: &ContactPair,
        mem: &mut PairMemory,
        counters: [&mut [usize]; 2],
        log: &mut dyn FnMut(&str),
        out: &mut ContactSystem,
        keep: Option<(&Kept, &[(usize, Forced)])>,
    ) -> Result<PairResult, String> {
        let plan = match keep {
            Some((kept, forced)) => {
                let kept = kept
                    .get::<nodal::Decided>()
                    .ok_or("inner solve without nodal decisions")?;
                nodal::Plan::Keep { kept, forced }
            }
            None => nodal::Plan::Decide,
        };
        nodal::update_pair(at, pair, mem, counters, log, out, plan)
    }

    fn inner_solves(&self) -> bool {
        true
    }

    fn predict(
        &self,
        at: &Prediction,
        (p, pair): (usize, &ContactPair),
        mem: &PairMemory,
        kept: &Kept,
        cache: &mut SearchCache,
    ) -> Result<Option<Vec<(usize, Forced)>>, String> {
        let Some(kept) = kept.get::<nodal::Decided>() else {
            return Ok(None);
        };
        nodal::predict_pair(at, (p, pair), mem, kept, cache).map(Some)
    }

    fn linearise(
        &self,
        at: &At,
        pair: (usize, &ContactPair),
        kept: &Kept,
        out: &mut Linearised,
    ) -> Result<(), String> {
        let kept = kept.get::<nodal::Decided>().ok_or_else(|| {
            format!(
                "contact pair '{}': no decisions at this state (internal)",
                pair.1.name
            )
        })?;
        linearise::linearise_pair(at, pair, &kept.decisions, out)
    }
}

impl Formulation for Paper {
    fn update(
        &self,
        at: &Iterate,
        pair: &ContactPair,
        mem: &mut PairMemory,
        [flips, _]: [&mut [usize]; 2],
        log: &mut dyn FnMut(&str),
        out: &mut ContactSystem,
        _keep: Option<(&Kept, &[(usize, Forced)])>,
    ) -> Result<PairResult, String> {
        let result = paper::paper_pair(at, pair, mem, flips, log, out)?;
        out.kept.push(Kept::default());
        Ok(result)
    }

    fn inner_solves(&self) -> bool {
        false
    }

    fn predict(
        &self,
        _at: &Prediction,
        _pair: (usize, &ContactPair),
        _mem: &PairMemory,
        _kept: &Kept,
        _cache: &mut SearchCache,
    ) -> Result<Option<Vec<(usize, Forced)>>, String> {
        Ok(None)
    }

    fn linearise(
        &self,
        _at: &At,
        (_, pair): (usize, &ContactPair),
        _kept: &Kept,
        _out: &mut Linearised,
    ) -> Result<(), String> {
        Err(format!(
            "contact pair '{}' uses the paper's decisions (decisions = \"paper\"): its \
             friction is a fixed point of the recovered segment resultants, which has no \
             derivative; the nodal decisions (the default) have one",
            pair.name
        ))
    }
}
