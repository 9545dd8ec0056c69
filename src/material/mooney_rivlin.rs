//! Incompressible Mooney-Rivlin rubber in plane stress, for total Lagrangian
//! analysis: W = C1 (I1 - 3) + C2 (I2 - 3) with C33 = 1 / det(C_2x2), which
//! makes det C = 1 and S33 = 0 hold exactly and eliminates the pressure.
//! Derivation in docs/materials.md.

use super::{MaterialLaw, Tangent, Voigt};

/// Voigt slots of the in-plane components 11, 22, 12.
const SLOT: [usize; 3] = [0, 1, 3];

#[derive(Clone, Debug)]
pub struct MooneyRivlin {
    c1: f64,
    c2: f64,
}

impl MooneyRivlin {
    pub fn new(c1: f64, c2: f64) -> Self {
        MooneyRivlin { c1, c2 }
    }
}

impl MaterialLaw for MooneyRivlin {
    /// lambda3 = C33^1/2 = det(C_2x2)^-1/2 (det F = 1).
    fn thickness_stretch(&self, strain: &Voigt) -> Option<f64> {
        let det = (1.0 + 2.0 * strain[0]) * (1.0 + 2.0 * strain[1]) - strain[3] * strain[3];
        Some(1.0 / det.sqrt())
    }

    /// `strain` is the Green-Lagrange strain; its 33 entry is ignored (the
    /// law sets C33 itself). Returns the in-plane 2nd Piola-Kirchhoff stress
    /// (S33 = 0) and dS/dE.
    fn evaluate(
        &self,
        strain: &Voigt,
        _history: &mut [f64],
        stress: &mut Voigt,
        tangent: &mut Tangent,
    ) {
        let (c1, c2) = (self.c1, self.c2);
        // In-plane right Cauchy-Green tensor C = I + 2E as [11, 22, 12].
        let c = [1.0 + 2.0 * strain[0], 1.0 + 2.0 * strain[1], strain[3]];
        let tr = c[0] + c[1];
        let det = c[0] * c[1] - c[2] * c[2];
        // adj C = tr(C) I - C (2x2), so d(det C)/dC = adj C and d(adj C)/dC = I x I - II.
        let adj = [c[1], c[0], -c[2]];
        let id = [1.0, 1.0, 0.0];
        // Reduced energy W(C) = C1 (tr + 1/det - 3) + C2 (det + tr/det - 3):
        // S = 2 dW/dC = 2 C1 (I - adj/det^2) + 2 C2 (adj + I/det - tr adj/det^2).
        let (d1, d2, d3) = (1.0 / det, 1.0 / (det * det), 1.0 / (det * det * det));
        let a = c1 + c2 * tr;
        *stress = [0.0; 4];
        for k in 0..3 {
            stress[SLOT[k]] =
                2.0 * c1 * id[k] + 2.0 * c2 * (adj[k] + id[k] * d1) - 2.0 * a * adj[k] * d2;
        }
        // dS/dE = 2 dS/dC = 4 { [C2 - a/det^2] (I x I - II) + 2 a/det^3 adj x adj
        //                       - C2/det^2 (I x adj + adj x I) },  a = C1 + C2 tr C.
        // II in Voigt form with engineering shear: diag(1, 1, 1/2).
        let ii = [1.0, 1.0, 0.5];
        let g = c2 - a * d2;
        *tangent = [[0.0; 4]; 4];
        for k in 0..3 {
            for l in 0..3 {
                let mut v = g * id[k] * id[l] + 2.0 * a * d3 * adj[k] * adj[l]
                    - c2 * d2 * (id[k] * adj[l] + adj[k] * id[l]);
                if k == l {
                    v -= g * ii[k];
                }
                tangent[SLOT[k]][SLOT[l]] = 4.0 * v;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::tests::check_tangent;

    fn eval(m: &MooneyRivlin, e: &Voigt) -> (Voigt, Tangent) {
        let (mut s, mut t) = ([0.0; 4], [[0.0; 4]; 4]);
        m.evaluate(e, &mut [], &mut s, &mut t);
        (s, t)
    }

    /// Green-Lagrange strain of F = [[f11, f12], [f21, f22]] (Voigt, engineering shear).
    fn green(f: [[f64; 2]; 2]) -> Voigt {
        let c11 = f[0][0] * f[0][0] + f[1][0] * f[1][0];
        let c22 = f[0][1] * f[0][1] + f[1][1] * f[1][1];
        let c12 = f[0][0] * f[0][1] + f[1][0] * f[1][1];
        [0.5 * (c11 - 1.0), 0.5 * (c22 - 1.0), 0.0, c12]
    }

    #[test]
    fn small_strain_limit_is_incompressible_plane_stress_elasticity() {
        // mu = 2 (C1 + C2), E = 3 mu, nu = 1/2: D = E/(1 - nu^2) [1 nu; nu 1], G = mu.
        let m = MooneyRivlin::new(0.3, 0.1);
        let mu = 2.0 * 0.4;
        let (s, t) = eval(&m, &[0.0; 4]);
        assert!(
            s.iter().all(|v| v.abs() < 1e-15),
            "stress-free reference: {s:?}"
        );
        let expect = [
            [4.0 * mu, 2.0 * mu, 0.0, 0.0],
            [2.0 * mu, 4.0 * mu, 0.0, 0.0],
            [0.0; 4],
            [0.0, 0.0, 0.0, mu],
        ];
        for i in 0..4 {
            for j in 0..4 {
                assert!(
                    (t[i][j] - expect[i][j]).abs() < 1e-14,
                    "D[{i}][{j}] = {}",
                    t[i][j]
                );
            }
        }
    }

    #[test]
    fn tangent_matches_central_differences_of_the_stress() {
        let m = MooneyRivlin::new(0.25, 0.07);
        let cases = [
            green([[2.0, 0.0], [0.0, 1.0 / 2f64.sqrt()]]), // lambda = 2, uniaxial
            green([[1.0, 0.8], [0.0, 1.0]]),               // simple shear, gamma = 0.8
            green([[1.3, 0.4], [-0.2, 0.7]]),              // general
            green([[0.6, -0.3], [0.1, 1.9]]),              // compression in x
            green([[3.0, 0.0], [0.0, 3.0]]),               // equibiaxial lambda = 3
        ];
        for e in &cases {
            // Central differences with h = 1e-6: truncation O(h^2 |S'''|) ~ 1e-12,
            // round-off ~ 1e-16 |S| / h ~ 1e-10 of the tangent's scale.
            let err = check_tangent(|e, s, t| m.evaluate(e, &mut [], s, t), e, 1e-6);
            eprintln!("mooney-rivlin tangent vs FD at {e:?}: {err:.2e}");
            assert!(err < 1e-8, "strain {e:?}: relative tangent error {err:e}");
        }
    }

    #[test]
    fn uniaxial_stress_matches_the_closed_form() {
        // A sheet stretched by lambda in x with y and z free: lambda2 = lambda3
        // = lambda^-1/2, S22 = 0 and P11 = lambda S11 = 2 (C1 + C2/lambda)(lambda - lambda^-2).
        let (c1, c2) = (0.25, 0.07);
        let m = MooneyRivlin::new(c1, c2);
        for lambda in [0.5, 0.8, 1.0, 1.5, 2.0, 4.0] {
            let l2 = 1.0 / f64::sqrt(lambda);
            let (s, _) = eval(&m, &green([[lambda, 0.0], [0.0, l2]]));
            let p11 = 2.0 * (c1 + c2 / lambda) * (lambda - lambda.powi(-2));
            assert!(
                (lambda * s[0] - p11).abs() < 1e-13 * (1.0 + p11.abs()),
                "lambda {lambda}"
            );
            assert!(
                s[1].abs() < 1e-13 && s[2] == 0.0 && s[3].abs() < 1e-13,
                "lambda {lambda}: {s:?}"
            );
        }
    }
}
