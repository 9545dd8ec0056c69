//! Material laws, separate from the integrator that assembles them. A law
//! maps a strain (Voigt [11, 22, 33, 12], engineering shear) to stress and
//! the consistent tangent; it is built for the analysis kind, so a plane
//! stress law returns S33 = 0 and the condensed tangent.

pub mod linear_elastic;

use crate::problem::{AnalysisKind, MaterialSpec};

pub type Voigt = [f64; 4];
pub type Tangent = [[f64; 4]; 4];

/// The stress state a law must honour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StressState {
    /// E33 is given by the kinematics (0 in plane strain, u/r axisymmetric).
    Prescribed33,
    /// S33 = 0; the law finds E33 itself.
    PlaneStress,
}

impl StressState {
    pub fn of(kind: AnalysisKind) -> Self {
        match kind {
            AnalysisKind::PlaneStress { .. } => StressState::PlaneStress,
            _ => StressState::Prescribed33,
        }
    }
}

/// A constitutive law: strain to stress and tangent at one Gauss point.
/// `history` holds the converged internal variables on entry and the
/// updated ones on return (length `history_len`).
pub trait MaterialLaw: Send + Sync + std::fmt::Debug {
    fn history_len(&self) -> usize {
        0
    }
    fn evaluate(
        &self,
        strain: &Voigt,
        history: &mut [f64],
        stress: &mut Voigt,
        tangent: &mut Tangent,
    );
}

/// The law for a material given in the scene.
pub fn build(spec: &MaterialSpec, kind: AnalysisKind) -> Box<dyn MaterialLaw> {
    let state = StressState::of(kind);
    match *spec {
        MaterialSpec::LinearElastic { e, nu } => {
            Box::new(linear_elastic::LinearElastic::new(e, nu, state))
        }
    }
}
