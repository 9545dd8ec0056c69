//! Node-to-segment contact (the paper's formulation): each contactor node
//! is held on the target segment it meets by the rows of Eq. (18). Its
//! states are decided node by node on the iterate (`nodal`, the default)
//! or by the paper's Section 3 on recovered segment tractions (`paper`);
//! both build their rows with `rows` and report with `contact::report`.

mod decision;
mod linearise;
mod memory;
mod nodal;
mod paper;
mod reported;
mod rows;
mod traction;

pub use memory::Memory;
pub(crate) use nodal::Decided;

/// A node's contact force counts as tension above this fraction of the
/// largest contact force of its pair (round-off at a node just touching).
const TENSION_TOLERANCE: f64 = 1e-8;

/// Node-to-segment contact decided node by node (`decisions = "nodal"`).
pub(super) struct Nodal;
/// Node-to-segment contact decided by the paper's Section 3
/// (`decisions = "paper"`).
pub(super) struct Paper;
