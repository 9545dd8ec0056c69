//! One contactor node's decision at an iterate (open, stick or slip, where
//! it meets the target and the force its rows carry): what `nodal` decides
//! and `linearise` differentiates.

use crate::contact::segment::ContactPoint;
use crate::results::NodeState;
use nalgebra::Vector2;

/// What one node is, after this iteration's decision.
#[derive(Clone, Debug)]
pub(super) struct Decision {
    pub(super) state: NodeState,
    /// Target segment and contact point (None when open).
    pub(super) point: Option<(usize, ContactPoint)>,
    /// The node's contact force for the rows (zero for a new contact).
    pub(super) lambda: Vector2<f64>,
    /// Normal force (compression positive) of a sliding node.
    pub(super) p_n: f64,
    pub(super) slip_sign: f64,
    /// Where its slip is measured from (segment, beta): see `nodal::decide`.
    pub(super) anchor: Option<(usize, f64)>,
    /// Frictionless, held at a reflex corner of the target (two rows).
    pub(super) corner: bool,
    /// Kept in contact after the predictor though its force pulls
    /// (`Start::settling`): the iteration has not converged while any is.
    pub(super) held_back: bool,
}

impl Decision {
    /// Open, with the normal force that released it (zero for a node that
    /// has not touched).
    pub(super) fn open(p_n: f64) -> Self {
        Decision {
            state: NodeState::Open,
            point: None,
            lambda: Vector2::zeros(),
            p_n,
            slip_sign: 0.0,
            anchor: None,
            corner: false,
            held_back: false,
        }
    }
}
