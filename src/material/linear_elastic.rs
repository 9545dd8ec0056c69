//! Isotropic linear elasticity (St. Venant-Kirchhoff in total Lagrangian
//! analysis: the same constants relate Green-Lagrange strain and 2nd PK).

use super::{MaterialLaw, StressState, Tangent, Voigt};

#[derive(Clone, Debug)]
pub struct LinearElastic {
    d: Tangent,
}

impl LinearElastic {
    pub fn new(e: f64, nu: f64, state: StressState) -> Self {
        let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        let mu = e / (2.0 * (1.0 + nu));
        let mut d = [[0.0; 4]; 4];
        match state {
            StressState::Prescribed33 => {
                for i in 0..3 {
                    for j in 0..3 {
                        d[i][j] = lambda;
                    }
                    d[i][i] += 2.0 * mu;
                }
            }
            StressState::PlaneStress => {
                // Condensed so that S33 = 0 (finite even at nu = 0.5).
                let c = e / (1.0 - nu * nu);
                d[0][0] = c;
                d[1][1] = c;
                d[0][1] = c * nu;
                d[1][0] = c * nu;
            }
        }
        d[3][3] = mu;
        LinearElastic { d }
    }
}

impl MaterialLaw for LinearElastic {
    fn is_linear(&self) -> bool {
        true
    }
    fn evaluate(
        &self,
        strain: &Voigt,
        _history: &mut [f64],
        stress: &mut Voigt,
        tangent: &mut Tangent,
    ) {
        for i in 0..4 {
            stress[i] = (0..4).map(|j| self.d[i][j] * strain[j]).sum();
        }
        *tangent = self.d;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniaxial_stress_in_plane_stress_and_strain() {
        let (e, nu) = (210.0, 0.3);
        // Plane stress, uniaxial: eps = [1, -nu, *, 0] gives S = [E, 0, 0, 0].
        let m = LinearElastic::new(e, nu, StressState::PlaneStress);
        let (mut s, mut t) = ([0.0; 4], [[0.0; 4]; 4]);
        m.evaluate(&[1.0, -nu, 0.0, 0.0], &mut [], &mut s, &mut t);
        assert!((s[0] - e).abs() < 1e-12 && s[1].abs() < 1e-12 && s[2] == 0.0);
        // 3D law: uniaxial strain state eps = [1, -nu, -nu] gives S = [E, 0, 0].
        let m = LinearElastic::new(e, nu, StressState::Prescribed33);
        m.evaluate(&[1.0, -nu, -nu, 0.0], &mut [], &mut s, &mut t);
        assert!((s[0] - e).abs() < 1e-12 && s[1].abs() < 1e-12 && s[2].abs() < 1e-12);
        // Shear: S12 = G * gamma.
        m.evaluate(&[0.0, 0.0, 0.0, 1.0], &mut [], &mut s, &mut t);
        assert!((s[3] - e / (2.0 * (1.0 + nu))).abs() < 1e-12);
    }
}
