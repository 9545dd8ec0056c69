//! Contact after Bathe & Chaudhary (1984): contactor nodes against target segments,
//! enforced by Lagrange multipliers in Eq. (18). `segment` is the pure kernel (geometry
//! and one node's contributions); the derivation is in docs/contact.md.

pub mod checks;
mod nodal;
pub mod outputs;
pub mod pairs;
pub mod segment;
pub mod sensitivity;
pub mod traction;

pub use pairs::PairMemory;
pub use segment::{ContactPoint, NodeMat, NodeVec, Segment, Sliding, Sticking};

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
