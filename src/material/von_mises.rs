//! Small-strain von Mises elasto-plasticity with linear isotropic hardening:
//! radial return and its consistent (algorithmic) tangent, for
//! materially-nonlinear-only analysis. Plane stress finds eps33 by a local
//! Newton iteration on sigma33 = 0. Derivation in docs/materials.md.

use super::{MaterialLaw, StressState, Tangent, Voigt};

/// History per Gauss point: plastic strain [11, 22, 33, 12 engineering],
/// then the equivalent plastic strain.
pub const HISTORY: usize = 5;

#[derive(Clone, Debug)]
pub struct VonMises {
    /// Bulk and shear moduli.
    k: f64,
    g: f64,
    sigma_y: f64,
    h: f64,
    state: StressState,
}

impl VonMises {
    pub fn new(e: f64, nu: f64, sigma_y: f64, h: f64, state: StressState) -> Self {
        VonMises {
            k: e / (3.0 * (1.0 - 2.0 * nu)),
            g: e / (2.0 * (1.0 + nu)),
            sigma_y,
            h,
            state,
        }
    }

    /// The 3D return mapping at total strain `eps` from the converged
    /// `history`: stress, tangent, and the updated history.
    fn return_map(
        &self,
        eps: &Voigt,
        history: &[f64],
        stress: &mut Voigt,
        tangent: &mut Tangent,
    ) -> [f64; HISTORY] {
        let (k, g) = (self.k, self.g);
        let mut ee = [0.0; 4];
        for i in 0..4 {
            ee[i] = eps[i] - history[i];
        }
        let vol = ee[0] + ee[1] + ee[2];
        // Trial deviatoric stress (tensor components; s[3] = G gamma_e).
        let s = [
            2.0 * g * (ee[0] - vol / 3.0),
            2.0 * g * (ee[1] - vol / 3.0),
            2.0 * g * (ee[2] - vol / 3.0),
            g * ee[3],
        ];
        let norm = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2] + 2.0 * s[3] * s[3]).sqrt();
        let q = f64::sqrt(1.5) * norm;
        let alpha = history[4];
        let f = q - (self.sigma_y + self.h * alpha);
        let mut out = [0.0; HISTORY];
        out.copy_from_slice(&history[..HISTORY]);
        // Elastic (and the deviatoric projector's weights) by default.
        let (mut beta, mut gbar) = (1.0, 0.0);
        if f > 0.0 {
            // Radial return: q = q_trial - 3G dgamma on the hardened surface.
            let dgamma = f / (3.0 * g + self.h);
            beta = 1.0 - 3.0 * g * dgamma / q;
            gbar = 3.0 * g / (3.0 * g + self.h) - (1.0 - beta);
            // d eps_p = dgamma (3/2) s / q; engineering shear doubles the 12 entry.
            let w = 1.5 * dgamma / q;
            for i in 0..3 {
                out[i] += w * s[i];
            }
            out[3] += 2.0 * w * s[3];
            out[4] += dgamma;
        }
        let p = k * vol;
        for i in 0..3 {
            stress[i] = p + beta * s[i];
        }
        stress[3] = beta * s[3];
        // D = K 1x1 + 2G beta I_dev - 2G gbar n x n, n = s / |s| (tensor
        // components, so n . d eps with engineering shear is the contraction).
        let n = if gbar != 0.0 {
            s.map(|v| v / norm)
        } else {
            [0.0; 4]
        };
        *tangent = [[0.0; 4]; 4];
        for i in 0..4 {
            for j in 0..4 {
                let one = if i < 3 && j < 3 { 1.0 } else { 0.0 };
                let dev = if i == j {
                    if i < 3 { 1.0 - 1.0 / 3.0 } else { 0.5 }
                } else {
                    -one / 3.0
                };
                tangent[i][j] = k * one + 2.0 * g * beta * dev - 2.0 * g * gbar * n[i] * n[j];
            }
        }
        out
    }
}

impl MaterialLaw for VonMises {
    fn history_len(&self) -> usize {
        HISTORY
    }

    fn equivalent_plastic_strain(&self, history: &[f64]) -> Option<f64> {
        history.get(4).copied()
    }

    fn evaluate(
        &self,
        strain: &Voigt,
        history: &mut [f64],
        stress: &mut Voigt,
        tangent: &mut Tangent,
    ) {
        let updated = match self.state {
            StressState::Prescribed33 => self.return_map(strain, history, stress, tangent),
            StressState::PlaneStress => self.plane_stress(strain, history, stress, tangent),
        };
        history.copy_from_slice(&updated);
    }
}

impl VonMises {
    /// Plane stress: Newton on eps33 until sigma33 = 0 (the input eps33 is
    /// ignored), then the tangent condensed on sigma33 = 0.
    fn plane_stress(
        &self,
        strain: &Voigt,
        history: &[f64],
        stress: &mut Voigt,
        tangent: &mut Tangent,
    ) -> [f64; HISTORY] {
        let (k, g) = (self.k, self.g);
        // Elastic plane-stress guess: sigma33 = 0 with the plastic strain frozen.
        let nu_ratio = (3.0 * k - 2.0 * g) / (3.0 * k + 4.0 * g); // nu / (1 - nu)
        let mut eps = *strain;
        eps[2] = history[2] - nu_ratio * (strain[0] - history[0] + strain[1] - history[1]);
        // sigma33 is converged when it is round-off against the stress scale.
        let scale = self.sigma_y + 3.0 * k * (strain[0].abs() + strain[1].abs() + strain[3].abs());
        let mut out = [0.0; HISTORY];
        let mut converged = false;
        for _ in 0..50 {
            out = self.return_map(&eps, history, stress, tangent);
            if stress[2].abs() <= 1e-13 * scale {
                converged = true;
                break;
            }
            eps[2] -= stress[2] / tangent[2][2];
        }
        if !converged {
            // Reported by the assembly as a non-finite stress: Newton bisects.
            *stress = [f64::NAN; 4];
            return out;
        }
        let d22 = tangent[2][2];
        let row2 = tangent[2];
        for i in 0..4 {
            let col = tangent[i][2];
            for j in 0..4 {
                tangent[i][j] -= col * row2[j] / d22;
            }
        }
        for v in tangent[2].iter_mut() {
            *v = 0.0;
        }
        for row in tangent.iter_mut() {
            row[2] = 0.0;
        }
        stress[2] = 0.0;
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::tests::check_tangent;

    const E: f64 = 200e3;
    const NU: f64 = 0.3;
    const SY: f64 = 250.0;
    const H: f64 = 10e3;

    fn law(state: StressState) -> VonMises {
        VonMises::new(E, NU, SY, H, state)
    }

    /// Evaluates from `history` and returns (stress, tangent, updated history).
    fn eval(m: &VonMises, e: &Voigt, history: &[f64; HISTORY]) -> (Voigt, Tangent, [f64; HISTORY]) {
        let (mut s, mut t, mut h) = ([0.0; 4], [[0.0; 4]; 4], *history);
        m.evaluate(e, &mut h, &mut s, &mut t);
        (s, t, h)
    }

    #[test]
    fn tangent_matches_central_differences_elastic_and_plastic() {
        let ey = SY / E;
        // A converged plastic history to start some cases from.
        let pre = law(StressState::Prescribed33);
        let (_, _, h1) = eval(&pre, &[3.0 * ey, -ey, -0.5 * ey, 2.0 * ey], &[0.0; HISTORY]);
        assert!(h1[4] > 0.0);
        // (strain, converged history, plastic in plane strain/axisymmetric, in plane stress)
        let cases: [(Voigt, [f64; HISTORY], bool, bool); 5] = [
            (
                [0.3 * ey, -0.1 * ey, 0.05 * ey, 0.2 * ey],
                [0.0; HISTORY],
                false,
                false,
            ),
            (
                [4.0 * ey, -ey, -1.5 * ey, 1.0 * ey],
                [0.0; HISTORY],
                true,
                true,
            ),
            ([1.4 * ey, 0.0, 0.0, 0.0], [0.0; HISTORY], true, true),
            ([3.5 * ey, -1.2 * ey, -0.4 * ey, 3.0 * ey], h1, true, true),
            ([2.0 * ey, -ey, -0.5 * ey, 1.0 * ey], h1, false, false),
        ];
        for state in [StressState::Prescribed33, StressState::PlaneStress] {
            let m = law(state);
            for (e, h, plastic3, plastic_ps) in &cases {
                // The case is the state it claims to be.
                let plastic = if state == StressState::PlaneStress {
                    plastic_ps
                } else {
                    plastic3
                };
                assert_eq!(eval(&m, e, h).2[4] > h[4], *plastic, "{state:?} {e:?}");
                // h = 1e-7 ey on strains ~ ey: truncation O(h^2) ~ 1e-14 relative,
                // round-off ~ 1e-16 / 1e-7 ~ 1e-9 relative (plane stress adds its
                // local-iteration tolerance 1e-13 / 1e-7 = 1e-6 of the scale).
                let err = check_tangent(
                    |e, s, t| {
                        let mut hh = *h;
                        m.evaluate(e, &mut hh, s, t)
                    },
                    e,
                    1e-7 * ey,
                );
                eprintln!("von mises {state:?} tangent vs FD at {e:?}: {err:.2e}");
                assert!(
                    err < 1e-5,
                    "{state:?} strain {e:?}: relative tangent error {err:e}"
                );
            }
        }
    }

    #[test]
    fn tangent_of_perfect_plasticity_matches_central_differences() {
        // H = 0: the same check, in the states where the tangent is singular
        // along the flow direction.
        let ey = SY / E;
        for state in [StressState::Prescribed33, StressState::PlaneStress] {
            let m = VonMises::new(E, NU, SY, 0.0, state);
            for e in [
                [4.0 * ey, -ey, -1.5 * ey, ey],
                [1.4 * ey, 0.0, 0.0, 2.0 * ey],
            ] {
                let h = [0.0; HISTORY];
                assert!(eval(&m, &e, &h).2[4] > 0.0, "{state:?} {e:?} must flow");
                // As above: h = 1e-7 eps_y, round-off ~ 1e-9 of the tangent.
                let err = check_tangent(
                    |e, s, t| {
                        let mut hh = h;
                        m.evaluate(e, &mut hh, s, t)
                    },
                    &e,
                    1e-7 * ey,
                );
                eprintln!("von mises H = 0 {state:?} tangent vs FD at {e:?}: {err:.2e}");
                assert!(err < 1e-5, "{state:?} {e:?}: {err:e}");
            }
        }
    }

    /// Uniaxial stress at axial strain `e11`: the lateral strains found by
    /// Newton (with the law's tangent) so that sigma22 = sigma33 = 0
    /// (sigma22 only in plane stress, where the law meets sigma33 = 0).
    fn uniaxial(m: &VonMises, e11: f64, history: &[f64; HISTORY]) -> (Voigt, [f64; HISTORY]) {
        let mut e = [e11, -0.5 * e11, -0.5 * e11, 0.0];
        let plane = m.state == StressState::PlaneStress;
        for _ in 0..50 {
            let (s, t, h) = eval(m, &e, history);
            // Converged when the lateral stresses are round-off against sigma_y.
            if s[1].abs() < 1e-12 * SY && s[2].abs() < 1e-12 * SY {
                return (s, h);
            }
            if plane {
                e[1] -= s[1] / t[1][1];
            } else {
                let det = t[1][1] * t[2][2] - t[1][2] * t[2][1];
                e[1] -= (t[2][2] * s[1] - t[1][2] * s[2]) / det;
                e[2] -= (t[1][1] * s[2] - t[2][1] * s[1]) / det;
            }
        }
        panic!("uniaxial stress iteration did not converge at e11 = {e11}");
    }

    /// Closed form, uniaxial stress under monotonic loading: sigma = E eps up to
    /// sigma_y, then sigma_y + E H / (E + H) (eps - sigma_y / E).
    fn uniaxial_closed_form(eps: f64) -> f64 {
        let ey = SY / E;
        if eps <= ey {
            E * eps
        } else {
            SY + E * H / (E + H) * (eps - ey)
        }
    }

    #[test]
    fn uniaxial_stress_path_loading_and_elastic_unloading() {
        let ey = SY / E;
        for state in [StressState::Prescribed33, StressState::PlaneStress] {
            let m = law(state);
            let mut h = [0.0; HISTORY];
            let mut worst = 0.0f64;
            // Load to 8 eps_y in 40 steps, committing the history at each.
            for k in 1..=40 {
                let eps = 8.0 * ey * k as f64 / 40.0;
                let (s, h1) = uniaxial(&m, eps, &h);
                h = h1;
                worst = worst.max((s[0] - uniaxial_closed_form(eps)).abs());
                // Equivalent plastic strain = axial plastic strain in uniaxial stress.
                let alpha = (eps - s[0] / E).max(0.0);
                assert!(
                    (h[4] - alpha).abs() < 1e-12 * ey,
                    "{state:?} eps {eps}: alpha {}",
                    h[4]
                );
            }
            let sigma_max = uniaxial_closed_form(8.0 * ey);
            // Unload by 1.8 sigma_max / E: elastic (slope E) down to -0.8 sigma_max,
            // inside the hardened surface |sigma| <= sigma_max.
            let alpha = h[4];
            for k in 1..=18 {
                let eps = 8.0 * ey - 0.1 * sigma_max / E * k as f64;
                let (s, h1) = uniaxial(&m, eps, &h);
                h = h1;
                worst = worst.max((s[0] - (sigma_max - E * (8.0 * ey - eps))).abs());
                assert_eq!(h[4], alpha, "{state:?}: unloading must not flow");
            }
            eprintln!(
                "von mises {state:?} uniaxial path: max |sigma - closed form| = {worst:.2e} (sigma_y = {SY})"
            );
            // Newton on the lateral stresses to 1e-12 sigma_y; the return is exact
            // on a proportional path, so only round-off remains.
            assert!(worst < 1e-9 * SY, "{state:?}: {worst:e}");
        }
    }

    #[test]
    fn pure_shear_path_loading_and_elastic_unloading() {
        // tau = G gamma up to tau_y = sigma_y / sqrt(3), then
        // tau = tau_y + G H / (3G + H) (gamma - tau_y / G).
        let g = E / (2.0 * (1.0 + NU));
        let tau_y = SY / 3f64.sqrt();
        let closed = |gamma: f64| {
            if gamma <= tau_y / g {
                g * gamma
            } else {
                tau_y + g * H / (3.0 * g + H) * (gamma - tau_y / g)
            }
        };
        let gmax = 10.0 * tau_y / g;
        for state in [StressState::Prescribed33, StressState::PlaneStress] {
            let m = law(state);
            let mut h = [0.0; HISTORY];
            let mut worst = 0.0f64;
            for k in 1..=40 {
                let gamma = gmax * k as f64 / 40.0;
                let (s, _, h1) = eval(&m, &[0.0, 0.0, 0.0, gamma], &h);
                h = h1;
                worst = worst.max((s[3] - closed(gamma)).abs());
                assert!(
                    s[..3].iter().all(|v| v.abs() < 1e-9 * SY),
                    "{state:?}: {s:?}"
                );
                // Plastic shear strain gamma_p = sqrt(3) alpha.
                assert!((h[3] - 3f64.sqrt() * h[4]).abs() < 1e-12 * gmax);
            }
            let tau_max = closed(gmax);
            let alpha = h[4];
            for k in 1..=18 {
                let gamma = gmax - 0.1 * tau_max / g * k as f64;
                let (s, _, h1) = eval(&m, &[0.0, 0.0, 0.0, gamma], &h);
                h = h1;
                worst = worst.max((s[3] - (tau_max - g * (gmax - gamma))).abs());
                assert_eq!(h[4], alpha, "{state:?}: unloading must not flow");
            }
            eprintln!(
                "von mises {state:?} pure shear path: max |tau - closed form| = {worst:.2e} (tau_y = {tau_y:.3})"
            );
            // The return is exact on this proportional path: round-off only.
            assert!(worst < 1e-9 * SY, "{state:?}: {worst:e}");
        }
    }
}
