//! Material laws, separate from the integrator that assembles them. A law
//! maps a strain (Voigt [11, 22, 33, 12], engineering shear) to stress and
//! the consistent tangent; it is built for the analysis kind, so a plane
//! stress law returns S33 = 0 and the condensed tangent.

pub mod linear_elastic;
pub mod mooney_rivlin;
pub mod von_mises;

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
    /// The equivalent plastic strain in a Gauss point's `history`, for a law
    /// that has one (None: the law is not plastic).
    fn equivalent_plastic_strain(&self, _history: &[f64]) -> Option<f64> {
        None
    }
    /// Stress linear in strain, no history: the tangent never changes.
    fn is_linear(&self) -> bool {
        false
    }
    /// Plane stress, total Lagrangian: the thickness stretch lambda3 the law
    /// implies at Green-Lagrange `strain`, when it defines one (None: the
    /// reported Cauchy stress takes lambda3 = 1).
    fn thickness_stretch(&self, _strain: &Voigt) -> Option<f64> {
        None
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
        MaterialSpec::MooneyRivlin { c1, c2 } => Box::new(mooney_rivlin::MooneyRivlin::new(c1, c2)),
        MaterialSpec::VonMises { e, nu, sigma_y, h } => {
            Box::new(von_mises::VonMises::new(e, nu, sigma_y, h, state))
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::{Tangent, Voigt};

    /// Largest difference between the law's tangent at `e` and central
    /// differences of its stress with step `h`, relative to the largest
    /// tangent entry. `f` evaluates the law from the same converged history
    /// at every call.
    pub fn check_tangent(f: impl Fn(&Voigt, &mut Voigt, &mut Tangent), e: &Voigt, h: f64) -> f64 {
        let (mut s, mut d) = ([0.0; 4], [[0.0; 4]; 4]);
        f(e, &mut s, &mut d);
        let scale = d.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        let mut err = 0.0f64;
        for j in 0..4 {
            let (mut ep, mut em) = (*e, *e);
            ep[j] += h;
            em[j] -= h;
            let (mut sp, mut sm, mut t) = ([0.0; 4], [0.0; 4], [[0.0; 4]; 4]);
            f(&ep, &mut sp, &mut t);
            f(&em, &mut sm, &mut t);
            for i in 0..4 {
                err = err.max(((sp[i] - sm[i]) / (2.0 * h) - d[i][j]).abs());
            }
        }
        err / scale
    }
}
