//! Finite element solves with the nonlinear laws against closed forms:
//! a plane stress Mooney-Rivlin strip stretched to lambda = 2 (total
//! Lagrangian), and von Mises blocks (materially-nonlinear-only) in uniaxial
//! stress and in simple shear, loaded past yield and unloaded. Each field is
//! homogeneous, so the elements reproduce it exactly and the reactions must
//! match the closed forms to the Newton tolerance.

mod common;

use contact2d::mesh::ElementKind;
use contact2d::newton::Solver;
use contact2d::problem::*;

fn driver(name: &str, nodes: Vec<usize>, ux: Option<Scaled>, uy: Option<Scaled>) -> Driver {
    Driver {
        name: name.into(),
        nodes,
        ux,
        uy,
        fx: None,
        fy: None,
        distribution: Default::default(),
    }
}

fn fixed() -> Option<Scaled> {
    Some(Scaled::constant(0.0))
}

fn follows(scale: f64) -> Option<Scaled> {
    Some(Scaled {
        scale,
        function: Some(0),
    })
}

/// Reaction Rx of the driver called `name`.
fn rx(step: &contact2d::results::StepResult, name: &str) -> f64 {
    step.drivers.iter().find(|d| d.0 == name).unwrap().1.rx
}

/// A strip [0, l] x [0, h] of thickness `t`: symmetry planes x = 0 (ux = 0)
/// and y = 0 (uy = 0), the face x = l moved by `ux` following function 0,
/// y free elsewhere: uniaxial stress in x. Function 0 is the stretch: ux = l f(t).
fn strip(
    kind: ElementKind,
    (nx, ny): (usize, usize),
    analysis: AnalysisKind,
    kinematics: Kinematics,
    spec: MaterialSpec,
) -> Problem {
    let (l, h) = (2.0, 1.0);
    let mesh = common::grid(kind, [0.0, 0.0], [l, h], nx, ny, |x, y| [x, y]);
    let mut p = common::problem(mesh, analysis, kinematics, 1.0, 0.0);
    p.materials[0].spec = spec;
    let left = common::nodes_where(&p.mesh, |x, _| x < 1e-12);
    let bottom = common::nodes_where(&p.mesh, |_, y| y < 1e-12);
    let right = common::nodes_where(&p.mesh, |x, _| (x - l).abs() < 1e-12);
    p.drivers = vec![
        driver("left", left, fixed(), None),
        driver("bottom", bottom, None, fixed()),
        driver("right", right, follows(l), None),
    ];
    p
}

#[test]
fn mooney_rivlin_strip_stretched_to_twice_its_length() {
    // Plane stress, y free: S22 = S33 = 0, so lambda2 = lambda3 = lambda^-1/2
    // (the law's C33 = 1 / det C_2x2 makes lambda3 = 1 / (lambda lambda2),
    // which equals lambda2 only then). The nominal stress is
    // P11 = 2 (C1 + C2/lambda)(lambda - lambda^-2), and the reaction is P11
    // times the reference area h t: TL integrates over the reference volume.
    let (c1, c2, t) = (0.25, 0.07, 0.1);
    let thin = AnalysisKind::PlaneStress { thickness: t };
    for (kind, grid) in [(ElementKind::Q4, (1, 1)), (ElementKind::Q8, (3, 2))] {
        let mut p = strip(
            kind,
            grid,
            thin,
            Kinematics::TotalLagrangian,
            MaterialSpec::MooneyRivlin { c1, c2 },
        );
        p.times = (1..=10).map(|k| k as f64 / 10.0).collect();
        let top = common::nodes_where(&p.mesh, |x, y| x > 1.99 && y > 0.99)[0];
        let mut s = Solver::new(p).unwrap();
        let (mut worst_p, mut worst_y) = (0.0f64, 0.0f64);
        for k in 1..=10 {
            let time = k as f64 / 10.0;
            let step = s.advance(time, &mut common::silent()).unwrap();
            let lambda = 1.0 + time;
            let p11 = 2.0 * (c1 + c2 / lambda) * (lambda - lambda.powi(-2));
            worst_p = worst_p.max((rx(&step, "right") / (1.0 * t) - p11).abs() / p11);
            let lambda2 = 1.0 + s.state().u[2 * top + 1] / 1.0;
            worst_y = worst_y.max((lambda2 - lambda.powf(-0.5)).abs());
        }
        // Cauchy stress at lambda = 2: sigma11 = lambda P11 (J = 1), the rest 0.
        let p11 = 2.0 * (c1 + c2 / 2.0) * (2.0 - 0.25);
        let mut worst_c = 0.0f64;
        for sigma in s.element_stresses() {
            let expect = [2.0 * p11, 0.0, 0.0, 0.0];
            for i in 0..4 {
                worst_c = worst_c.max((sigma[i] - expect[i]).abs() / (2.0 * p11));
            }
        }
        eprintln!(
            "mooney-rivlin strip {kind:?} {grid:?}: max |R/(h t) - P11| / P11 = {worst_p:.2e}, max |lambda2 - lambda^-1/2| = {worst_y:.2e}, max |sigma - (lambda P11, 0, 0, 0)| / (lambda P11) = {worst_c:.2e}"
        );
        assert!(worst_c < 1e-8, "{kind:?}: {worst_c:e}");
        // Newton stops at |r|/|r0| <= 1e-8; the reaction and the contraction
        // carry an error of that order relative to the load and the motion.
        assert!(worst_p < 1e-8, "{kind:?}: {worst_p:e}");
        assert!(worst_y < 1e-8, "{kind:?}: {worst_y:e}");
    }
}

const E: f64 = 200e3;
const NU: f64 = 0.3;
const SY: f64 = 250.0;
const H: f64 = 10e3;

fn von_mises() -> MaterialSpec {
    MaterialSpec::VonMises {
        e: E,
        nu: NU,
        sigma_y: SY,
        h: H,
    }
}

/// The unit square in plane strain, n x n Q8, von Mises, MNO, no drivers.
fn plastic_block(n: usize) -> Problem {
    let mesh = common::grid(ElementKind::Q8, [0.0, 0.0], [1.0, 1.0], n, n, |x, y| [x, y]);
    let mut p = common::problem(
        mesh,
        AnalysisKind::PlaneStrain { thickness: 1.0 },
        Kinematics::MaterialNonlinearOnly,
        1.0,
        0.0,
    );
    p.materials[0].spec = von_mises();
    p
}

/// Up to `peak` then back by `back` (function 0 of the problem), in `n`
/// increments each way.
fn load_and_unload(p: &mut Problem, peak: f64, back: f64, n: usize) {
    p.functions[0].points = vec![(0.0, 0.0), (1.0, peak), (2.0, peak - back)];
    p.times = (1..=2 * n).map(|k| k as f64 / n as f64).collect();
}

#[test]
fn von_mises_strip_in_uniaxial_stress_loaded_past_yield_and_unloaded() {
    // sigma = E eps up to sigma_y, then sigma_y + E H/(E + H)(eps - sigma_y/E);
    // unloading elastic with slope E. Lateral strain -nu sigma/E - alpha/2
    // (plastic flow is isochoric, alpha = axial plastic strain).
    let ey = SY / E;
    let peak = 8.0 * ey;
    let sigma_peak = SY + E * H / (E + H) * (peak - ey);
    let back = 1.8 * sigma_peak / E;
    let plane_stress = AnalysisKind::PlaneStress { thickness: 1.0 };
    for (kind, grid) in [(ElementKind::Q4, (1, 1)), (ElementKind::Q8, (4, 2))] {
        let mut p = strip(
            kind,
            grid,
            plane_stress,
            Kinematics::MaterialNonlinearOnly,
            von_mises(),
        );
        load_and_unload(&mut p, peak, back, 16);
        let times = p.times.clone();
        let top = common::nodes_where(&p.mesh, |x, y| x > 1.99 && y > 0.99)[0];
        let mut s = Solver::new(p).unwrap();
        let (mut worst_s, mut worst_e) = (0.0f64, 0.0f64);
        let mut iterations = 0;
        for &time in &times {
            let step = s.advance(time, &mut common::silent()).unwrap();
            iterations += step.iterations;
            let eps = s.problem().functions[0].value(time);
            let sigma = if time <= 1.0 {
                if eps <= ey {
                    E * eps
                } else {
                    SY + E * H / (E + H) * (eps - ey)
                }
            } else {
                sigma_peak - E * (peak - eps)
            };
            let alpha = if time <= 1.0 {
                (eps - sigma / E).max(0.0)
            } else {
                peak - sigma_peak / E
            };
            worst_s = worst_s.max((rx(&step, "right") / 1.0 - sigma).abs());
            let eps22 = s.state().u[2 * top + 1] / 1.0;
            worst_e = worst_e.max((eps22 - (-NU * sigma / E - alpha / 2.0)).abs());
        }
        eprintln!(
            "von mises strip {kind:?} {grid:?}: max |R/A - sigma| = {worst_s:.2e} (sigma_y = {SY}), max |eps22 - closed form| = {worst_e:.2e} (eps_y = {ey:e}), {iterations} iterations in {} increments",
            times.len()
        );
        // Newton to |r|/|r0| <= 1e-8 of an increment's load (~ 100): the
        // reaction error is below 1e-6 sigma_y and the strain error below 1e-6 eps_y.
        assert!(worst_s < 1e-6 * SY, "{kind:?}: {worst_s:e}");
        assert!(worst_e < 1e-6 * ey, "{kind:?}: {worst_e:e}");
    }
}

#[test]
fn von_mises_block_in_plane_strain_simple_shear_loaded_past_yield_and_unloaded() {
    // Every boundary node moved by ux = gamma y, uy = 0: pure shear stress,
    // tau = G gamma up to tau_y = sigma_y/sqrt(3), then
    // tau_y + G H/(3G + H)(gamma - tau_y/G); unloading with slope G. The top
    // face (length 1, thickness 1) carries Rx = tau.
    let g = E / (2.0 * (1.0 + NU));
    let tau_y = SY / 3f64.sqrt();
    let gy = tau_y / g;
    let peak = 10.0 * gy;
    let tau_peak = tau_y + g * H / (3.0 * g + H) * (peak - gy);
    let back = 1.8 * tau_peak / g;
    let mut p = plastic_block(2);
    let top = common::nodes_where(&p.mesh, |_, y| y > 1.0 - 1e-12);
    p.drivers.push(driver("top", top, follows(1.0), fixed()));
    let sides = common::nodes_where(&p.mesh, |x, y| {
        y < 1.0 - 1e-12 && (!(1e-12..=1.0 - 1e-12).contains(&x) || y < 1e-12)
    });
    for n in sides {
        let y = p.mesh.nodes[n][1];
        p.drivers
            .push(driver(&format!("n{n}"), vec![n], follows(y), fixed()));
    }
    load_and_unload(&mut p, peak, back, 20);
    let times = p.times.clone();
    let mut s = Solver::new(p).unwrap();
    assert!(s.dofs() > 0, "the interior nodes are free");
    let mut worst = 0.0f64;
    for &time in &times {
        let step = s.advance(time, &mut common::silent()).unwrap();
        let gamma = s.problem().functions[0].value(time);
        let tau = if time <= 1.0 {
            if gamma <= gy {
                g * gamma
            } else {
                tau_y + g * H / (3.0 * g + H) * (gamma - gy)
            }
        } else {
            tau_peak - g * (peak - gamma)
        };
        worst = worst.max((rx(&step, "top") - tau).abs());
    }
    eprintln!("von mises simple shear Q8 2x2: max |Rx - tau| = {worst:.2e} (tau_y = {tau_y:.3})");
    // As for the strip: Newton tolerance 1e-8 of loads ~ 100.
    assert!(worst < 1e-6 * SY, "{worst:e}");
}

#[test]
fn von_mises_punch_converges_quadratically() {
    // An inhomogeneous plastic zone: a plane strain block on a fixed base,
    // the left half of its top pressed down by 8 yield strains of its height.
    // With the consistent tangent Newton converges quadratically; the
    // continuum (elastic-plastic) tangent would give a rate near 1.
    let mut p = plastic_block(6);
    let base = common::nodes_where(&p.mesh, |_, y| y < 1e-12);
    let punch = common::nodes_where(&p.mesh, |x, y| y > 1.0 - 1e-12 && x < 0.5 + 1e-12);
    p.drivers = vec![
        driver("base", base, fixed(), fixed()),
        driver("punch", punch, fixed(), follows(-8.0 * SY / E)),
    ];
    p.times = vec![0.25, 0.5, 0.75, 1.0];
    let mut s = Solver::new(p).unwrap();
    let mut plastic_increments = 0;
    for &time in &[0.25, 0.5, 0.75, 1.0] {
        let mut lines = Vec::new();
        let r = s
            .advance(time, &mut |c, m| {
                if c == contact2d::results::LogCategory::Newton {
                    lines.push(m.to_string())
                }
            })
            .unwrap();
        assert!(r.converged && r.substeps == 0);
        // The estimate ln(r_k/r_k-1)/ln(r_k-1/r_k-2) of the last two
        // iterations, where the set of yielding points has settled (earlier
        // ones jump as points start or stop flowing): ~2, as in tests/newton.rs.
        let rates = common::rates(&lines);
        let last = rates.iter().rev().take(2).fold(0.0f64, |m, &v| m.max(v));
        eprintln!(
            "punch t = {time}: {} iterations, rates {rates:.2?}",
            r.iterations
        );
        if r.iterations >= 4 {
            plastic_increments += 1;
            assert!(
                last > 1.7,
                "t = {time}: rates {rates:?}\n{}",
                lines.join("\n")
            );
        }
        assert!(
            r.iterations <= 10,
            "t = {time}: {} iterations",
            r.iterations
        );
    }
    let alpha = s
        .state()
        .history
        .chunks(5)
        .map(|h| h[4])
        .fold(0.0f64, f64::max);
    eprintln!("punch: max equivalent plastic strain {alpha:.3e}");
    assert!(alpha > SY / E, "the block must flow well past yield");
    assert!(
        plastic_increments >= 2,
        "too few increments to measure a rate"
    );
}

/// The shipped scene `name` solved through its load history: (time, result).
fn shipped(name: &str) -> (Solver, Vec<(f64, contact2d::results::StepResult)>) {
    let problem = common::shipped_scene(name, &[]);
    let times = problem.times.clone();
    let mut s = Solver::new(problem).unwrap();
    let steps = times
        .iter()
        .map(|&t| (t, s.advance(t, &mut common::silent()).unwrap()))
        .collect();
    (s, steps)
}

#[test]
fn shipped_rubber_strip_scene() {
    let (s, steps) = shipped("verification/rubber_strip.toml");
    let MaterialSpec::MooneyRivlin { c1, c2 } = s.problem().materials[0].spec else {
        panic!("the rubber strip is Mooney-Rivlin")
    };
    let mut worst = 0.0f64;
    for (t, step) in &steps {
        let lambda = 1.0 + t;
        let p11 = 2.0 * (c1 + c2 / lambda) * (lambda - lambda.powi(-2));
        worst = worst.max((rx(step, "pull") / (1.0 * 0.1) - p11).abs() / p11);
    }
    eprintln!(
        "rubber_strip.toml: {} increments, max |R/(h t) - P11| / P11 = {worst:.2e}",
        steps.len()
    );
    assert_eq!(steps.len(), 10);
    // Newton tolerance 1e-8 (as above).
    assert!(worst < 1e-8, "{worst:e}");
}

#[test]
fn shipped_plastic_strip_scene() {
    let (s, steps) = shipped("verification/plastic_strip.toml");
    let ey = SY / E;
    let sigma_peak = SY + E * H / (E + H) * (8.0 * ey - ey);
    let mut worst = 0.0f64;
    for (t, step) in &steps {
        let eps = s.problem().functions[0].value(*t) / 2.0;
        let sigma = if *t <= 1.0 {
            if eps <= ey {
                E * eps
            } else {
                SY + E * H / (E + H) * (eps - ey)
            }
        } else {
            sigma_peak - E * (8.0 * ey - eps)
        };
        worst = worst.max((rx(step, "pull") - sigma).abs());
    }
    eprintln!(
        "plastic_strip.toml: {} increments, max |R/A - sigma| = {worst:.2e}",
        steps.len()
    );
    assert_eq!(steps.len(), 16);
    // Newton tolerance 1e-8 of loads ~ 100 (as above).
    assert!(worst < 1e-6 * SY, "{worst:e}");
    // The scene's constants are the ones of the closed form.
    assert_eq!(s.problem().materials[0].spec, von_mises());
}

#[test]
fn constants_by_name_and_their_range_checks() {
    let mut p = common::shipped_scene("verification/rubber_strip.toml", &[]);
    assert_eq!(p.materials[0].constants(), vec![("C1", 0.25), ("C2", 0.07)]);
    p.materials[0].set_constant("C2", 0.0).unwrap();
    assert_eq!(p.check_parameters(), Ok(()));
    p.materials[0].set_constant("C1", 0.0).unwrap();
    assert_eq!(
        p.check_parameters(),
        Err("rubber.C1 = 0.0: C1 must be positive and finite".into())
    );
    assert!(p.materials[0].set_constant("E", 1.0).is_err());

    let mut p = common::shipped_scene("verification/plastic_strip.toml", &[]);
    let names: Vec<&str> = p.materials[0].constants().iter().map(|c| c.0).collect();
    assert_eq!(names, ["E", "nu", "sigma_y", "H"]);
    for (name, value, message) in [
        (
            "H",
            -1.0,
            "steel.H = -1.0: the hardening modulus must be finite and not negative",
        ),
        (
            "sigma_y",
            0.0,
            "steel.sigma_y = 0.0: the yield stress must be positive and finite",
        ),
        (
            "nu",
            0.5,
            "steel.nu = 0.5: Poisson's ratio must satisfy -1 < nu < 0.5 for von_mises",
        ),
        (
            "E",
            -1.0,
            "steel.E = -1.0: Young's modulus must be positive and finite",
        ),
    ] {
        let mut q = p.clone();
        q.materials[0].set_constant(name, value).unwrap();
        assert_eq!(q.check_parameters(), Err(message.into()));
    }
    p.materials[0].set_constant("H", 0.0).unwrap();
    assert_eq!(p.check_parameters(), Ok(()));
    // A law outside its analysis is refused by the solver too.
    p.kinematics = Kinematics::TotalLagrangian;
    let e = Solver::new(p)
        .err()
        .expect("von_mises under total Lagrangian");
    assert!(e.to_string().contains("von_mises needs"), "{e}");
}

#[test]
fn von_mises_ring_in_equibiaxial_stress_axisymmetric() {
    // A ring r in [1, 2], height 1, both faces moved by u_r = eps r, the base
    // on rollers, the top free: eps_r = eps_theta = eps, sigma_zz = 0, so
    // sigma_rr = sigma_thth = sigma and q = sigma. Elastic: sigma = E eps /
    // (1 - nu). Plastic: d eps_p,r = d alpha (3/2)(sigma/3)/sigma = d alpha / 2,
    // eps = (1 - nu) sigma / E + alpha / 2 with sigma = sigma_y + H alpha, so
    // sigma = sigma_y + (eps - eps_y) / ((1 - nu)/E + 1/(2H)), eps_y = (1 - nu)
    // sigma_y / E; unloading with slope E / (1 - nu). The outer face carries
    // Rx = sigma 2 pi r_o h over the full circle.
    let mesh = common::grid(ElementKind::Q8, [1.0, 0.0], [1.0, 1.0], 3, 2, |x, y| [x, y]);
    let mut p = common::problem(
        mesh,
        AnalysisKind::Axisymmetric,
        Kinematics::MaterialNonlinearOnly,
        1.0,
        0.0,
    );
    p.materials[0].spec = von_mises();
    let inner = common::nodes_where(&p.mesh, |x, _| x < 1.0 + 1e-12);
    let outer = common::nodes_where(&p.mesh, |x, _| x > 2.0 - 1e-12);
    let base = common::nodes_where(&p.mesh, |_, y| y < 1e-12);
    p.drivers = vec![
        driver("inner", inner, follows(1.0), None),
        driver("outer", outer, follows(2.0), None),
        driver("base", base, None, fixed()),
    ];
    let ey = (1.0 - NU) * SY / E;
    let slope = 1.0 / ((1.0 - NU) / E + 1.0 / (2.0 * H));
    let peak = 8.0 * ey;
    let sigma_peak = SY + slope * (peak - ey);
    load_and_unload(&mut p, peak, 1.8 * sigma_peak * (1.0 - NU) / E, 16);
    let times = p.times.clone();
    let mut s = Solver::new(p).unwrap();
    let mut worst = 0.0f64;
    for &time in &times {
        let step = s.advance(time, &mut common::silent()).unwrap();
        let eps = s.problem().functions[0].value(time);
        let sigma = if time <= 1.0 {
            if eps <= ey {
                E * eps / (1.0 - NU)
            } else {
                SY + slope * (eps - ey)
            }
        } else {
            sigma_peak - E / (1.0 - NU) * (peak - eps)
        };
        let area = 2.0 * std::f64::consts::PI * 2.0 * 1.0;
        worst = worst.max((rx(&step, "outer") / area - sigma).abs());
    }
    eprintln!(
        "von mises axisymmetric ring Q8 3x2: max |Rx / (2 pi r_o h) - sigma| = {worst:.2e} (sigma_y = {SY})"
    );
    // Newton tolerance 1e-8 of loads ~ 100 (as above).
    assert!(worst < 1e-6 * SY, "{worst:e}");
}

#[test]
fn linear_elastic_bodies_do_not_pay_for_the_nonlinear_laws() {
    // No history, and small strain keeps its one factorization for all increments.
    let plane_stress = AnalysisKind::PlaneStress { thickness: 1.0 };
    let mut p = strip(
        ElementKind::Q8,
        (4, 2),
        plane_stress,
        Kinematics::SmallStrain,
        MaterialSpec::LinearElastic { e: E, nu: NU },
    );
    p.times = vec![0.25, 0.5, 0.75, 1.0];
    let mut s = Solver::new(p).unwrap();
    for t in [0.25, 0.5, 0.75, 1.0] {
        s.advance(t, &mut common::silent()).unwrap();
    }
    assert!(s.state().history.is_empty());
    assert_eq!(s.factorizations(), 1);
    // The plastic strip: 5 numbers at each of the 9 Gauss points of 8 Q8.
    let p = strip(
        ElementKind::Q8,
        (4, 2),
        plane_stress,
        Kinematics::MaterialNonlinearOnly,
        von_mises(),
    );
    assert_eq!(Solver::new(p).unwrap().state().history.len(), 5 * 9 * 8);
}
