//! More shipped contact scenes, solved, against closed forms and invariants:
//! Hertz's sphere (axisymmetric) and a contact made, released and made again.

mod common;

use contact2d::newton::Solver;
use contact2d::results::{NodeState, PairResult, StepResult};
use std::f64::consts::PI;

/// Every increment of the scene `name` with each `(old, new)` replaced once
/// (a refined mesh, another coefficient); each increment must converge.
fn solve(name: &str, edits: &[(&str, &str)]) -> (Solver, Vec<StepResult>) {
    let problem = common::shipped_scene(name, edits);
    let times = problem.times.clone();
    let mut solver = Solver::new(problem).unwrap();
    let mut steps = Vec::new();
    for t in times {
        let r = solver
            .advance(t, &mut |_, _| {})
            .unwrap_or_else(|e| panic!("{name} {edits:?} at t = {t}: {e}"));
        assert!(r.converged, "{name} at t = {t}");
        steps.push(r);
    }
    (solver, steps)
}

fn driver(step: &StepResult, name: &str) -> [f64; 2] {
    let d = &step.drivers.iter().find(|d| d.0 == name).unwrap().1;
    [d.rx, d.ry]
}

fn at(steps: &[StepResult], t: f64) -> &StepResult {
    steps.iter().find(|s| (s.time - t).abs() < 1e-12).unwrap()
}

// ---------------------------------------------------------------------------
// Hertz, sphere on a rigid flat (scenes/hertz_axisymmetric.toml)
// ---------------------------------------------------------------------------

const SPHERE_R: f64 = 100.0;
const E_STAR: f64 = 200000.0 / (1.0 - 0.3 * 0.3);
const SHIPPED_MESH: &str = "divisions = 30, ratio = 100.0";

/// What the sphere scene gives at its last increment, against Hertz.
struct Sphere {
    p: f64,
    a: f64,
    /// Reference radius of the last closed and of the first open node.
    last_closed: f64,
    first_open: f64,
    /// RMS over the closed nodes of (tn - p(X)) / p0, X the node's reference
    /// radius, tn as reported (p = 0 beyond a).
    rms: f64,
    /// The same over the interior nodes X < 0.8 a only.
    rms_interior: f64,
    /// The same over X < 0.8 a, with tn taken per unit REFERENCE area.
    rms_interior_reference: f64,
    /// (tn - p0) / p0 at the contact point, as reported and per reference area.
    centre: f64,
    centre_reference: f64,
}

/// Equilibrium, node states and NEQC at every increment of a frictionless
/// press on the rigid flat.
fn check_frictionless_press(steps: &[StepResult]) {
    for step in steps {
        let pair = &step.pairs[0].1;
        let press = driver(step, "press");
        let flat = driver(step, "flat");
        // The rigid flat's reaction is the force the press applies (the
        // symmetry driver acts along x only): the contact forces are the
        // converged out-of-balance forces, equal to round-off.
        assert!(
            (flat[1] - press[1]).abs() <= 1e-9 * press[1].abs(),
            "t = {}: flat {flat:?} press {press:?}",
            step.time
        );
        assert!((pair.fy + flat[1]).abs() <= 1e-9 * press[1].abs());
        assert!(pair.fy > 0.0 && pair.n_slip > 0);
        // Frictionless: every closed node slides, one equation each.
        assert_eq!(pair.n_stick, 0, "t = {}", step.time);
        assert_eq!(step.neqc, pair.n_slip, "t = {}", step.time);
        // Fx is the sum of the nodes' radial forces: frictionless, each is
        // along the flat's normal, so Fx is round-off (measured 1e-14 of Fy;
        // bound 1e-12 as in the plane-strain test).
        assert!(
            pair.fx.abs() <= 1e-12 * pair.fy,
            "t = {}: Fx {} Fy {}",
            step.time,
            pair.fx,
            pair.fy
        );
        assert!(
            (pair.fn_ - pair.fy).abs() <= 1e-6 * pair.fy,
            "flat target: Fn = Fy"
        );
    }
}

/// Hertz's pressure at the reference radius x (zero beyond a).
fn hertz_p(p0: f64, a: f64, x: f64) -> f64 {
    if x < a {
        p0 * (1.0 - x * x / (a * a)).sqrt()
    } else {
        0.0
    }
}

fn sphere(mesh: &str) -> Sphere {
    let (s, steps) = solve("hertz_axisymmetric.toml", &[(SHIPPED_MESH, mesh)]);
    check_frictionless_press(&steps);
    let problem = s.problem();
    let pair: &PairResult = &steps.last().unwrap().pairs[0].1;
    let n = &pair.nodes;
    // Forces are totals over the circle: P is Fy itself.
    let p = pair.fy;
    let a = (3.0 * p * SPHERE_R / (4.0 * E_STAR)).cbrt();
    let p0 = 3.0 * p / (2.0 * PI * a * a);
    let reference: Vec<[f64; 2]> = problem.contacts[0]
        .contactor
        .iter()
        .map(|&c| problem.mesh.nodes[c])
        .collect();
    let closed: Vec<usize> = (0..n.x.len())
        .filter(|&k| n.state[k] != NodeState::Open)
        .collect();
    // The contact zone is one run of nodes from the axis on.
    assert_eq!(closed, (0..closed.len()).collect::<Vec<_>>());
    let last = closed.len() - 1;
    let error = |k: usize, tn: f64| (tn - hertz_p(p0, a, reference[k][0])) / p0;
    let rms = |ks: &[usize], tn: &dyn Fn(usize) -> f64| {
        (ks.iter().map(|&k| error(k, tn(k)).powi(2)).sum::<f64>() / ks.len() as f64).sqrt()
    };
    // The reported tn is force per unit CURRENT area (the recovery runs on
    // the current positions). Per unit reference area it is tn times the
    // ratio of the area elements 2 pi x ds: (x / X) (ds / dS) from the
    // neighbouring nodes, (x_1 / X_1)^2 on the axis. Under the Hertz
    // pressure the surface contracts radially by (1 - 2 nu)(1 + nu) p0 / (2 E)
    // at the centre (0.36 % here), so the two measures differ by 0.7 % of p0.
    let chord = |p: &[[f64; 2]], i: usize, j: usize| (p[j][0] - p[i][0]).hypot(p[j][1] - p[i][1]);
    let current: Vec<[f64; 2]> = (0..n.x.len()).map(|k| [n.x[k], n.y[k]]).collect();
    let per_reference_area = |k: usize| {
        let ratio = if k == 0 {
            (current[1][0] / reference[1][0]).powi(2)
        } else {
            current[k][0] / reference[k][0] * chord(&current, k - 1, k + 1)
                / chord(&reference, k - 1, k + 1)
        };
        n.tn[k] * ratio
    };
    let interior: Vec<usize> = closed
        .iter()
        .copied()
        .filter(|&k| reference[k][0] < 0.8 * a)
        .collect();
    assert!(interior.len() >= 10, "{} interior nodes", interior.len());
    let m = Sphere {
        p,
        a,
        last_closed: reference[last][0],
        first_open: reference[last + 1][0],
        rms: rms(&closed, &|k| n.tn[k]),
        rms_interior: rms(&interior, &|k| n.tn[k]),
        rms_interior_reference: rms(&interior, &per_reference_area),
        centre: error(0, n.tn[0]),
        centre_reference: error(0, per_reference_area(0)),
    };
    println!(
        "hertz sphere, {mesh}: P {:.1}, a {:.4} (a/R {:.4}), p0 {p0:.1}; {} nodes closed, \
         last closed X = {:.4}, first open X = {:.4}\n  \
         RMS (tn - p(X))/p0 over the closed nodes {:.3e}; over X < 0.8 a {:.3e}, \
         per reference area {:.3e}; centre {:+.3e}, per reference area {:+.3e}\n  \
         per node (X, tn, p(X), error/p0): {:?}",
        m.p,
        m.a,
        m.a / SPHERE_R,
        closed.len(),
        m.last_closed,
        m.first_open,
        m.rms,
        m.rms_interior,
        m.rms_interior_reference,
        m.centre,
        m.centre_reference,
        closed
            .iter()
            .map(|&k| {
                let x = reference[k][0];
                (
                    (x * 1e4).round() / 1e4,
                    n.tn[k].round(),
                    hertz_p(p0, a, x).round(),
                    (error(k, n.tn[k]) * 1e4).round() / 1e4,
                )
            })
            .collect::<Vec<_>>()
    );
    m
}

#[test]
fn hertz_sphere_equilibrium_contact_radius_and_pressure() {
    let shipped = sphere(SHIPPED_MESH);
    // The load the scene states (P = 23505, a/R = 0.020).
    assert!(
        (shipped.p / 23505.0 - 1.0).abs() < 1e-3,
        "P = {}",
        shipped.p
    );
    // The contact edge lies between the last closed and the first open node:
    // Hertz's a must fall there (reference radii).
    assert!(
        shipped.last_closed <= shipped.a && shipped.a <= shipped.first_open,
        "a = {}, last closed {}, first open {}",
        shipped.a,
        shipped.last_closed,
        shipped.first_open
    );

    // Every element halved (the grading ratio kept).
    let fine = sphere("divisions = 60, ratio = 100.0");
    // Refined, the FE edge may fall one node beyond a (measured: a = 2.004,
    // last closed at 2.053): within one node spacing, as in the plane case.
    let spacing = fine.first_open - fine.last_closed;
    assert!(
        fine.last_closed - spacing <= fine.a && fine.a <= fine.first_open,
        "a = {}, last closed {}, first open {}",
        fine.a,
        fine.last_closed,
        fine.first_open
    );

    // The measure, RMS over the contact zone of (tn - p(X)) / p0,
    // does NOT reach 1 % here: 3.7e-2 on this mesh, 3.0e-2 refined (5.6e-3
    // at 120 divisions). It is set by the one or two closed nodes next to
    // the edge (errors of 5-15 % of p0 there, where Hertz's p falls like
    // sqrt(a - x) and the last closed node may lie beyond a, in tension) and
    // jumps with where the edge falls between two nodes, not monotone under
    // refinement: at uy = -0.044 the 30, 60, 120 division meshes give 2.4e-2,
    // 9.2e-3, 4.5e-2; at -0.036 1.2e-2, 6.3e-3, 1.1e-2; at -0.04 with ratio
    // 200, 40 and 80 divisions give 8.4e-3 and 2.1e-2. Neither the 1 % nor a
    // decrease under refinement is asserted for it (the numbers are printed).
    //
    // Away from the edge the solution converges to Hertz once the traction
    // is taken per unit reference area (Hertz's linear theory): RMS over
    // X < 0.8 a measured 7.5e-3 here, 2.1e-3 refined, 5.9e-4 at 120
    // divisions (about h^2; 5.8e-3, 9.1e-4, 4.5e-4 at uy = -0.036). Asserted:
    // below 1 % here (25 % margin) and at least halved by the refinement
    // (measured: a factor 3.6).
    assert!(
        shipped.rms_interior_reference < 1e-2,
        "interior RMS per reference area {:.3e}",
        shipped.rms_interior_reference
    );
    assert!(
        fine.rms_interior_reference < 0.5 * shipped.rms_interior_reference,
        "interior RMS per reference area: {:.3e} -> {:.3e}",
        shipped.rms_interior_reference,
        fine.rms_interior_reference
    );
    // The reported tn (per current area) carries in addition the 0.7 % of p0
    // the contracted surface adds at the centre: measured +1.08e-2 here,
    // +0.83e-2 refined, +0.65e-2 at 120 divisions; per reference area
    // +3.4e-3, +1.0e-3, -0.7e-3. Asserted: per reference area within 0.5 %
    // of p0 on both meshes.
    assert!(shipped.centre_reference.abs() < 5e-3 && fine.centre_reference.abs() < 5e-3);
}

// ---------------------------------------------------------------------------
// Contact made, released and made again (scenes/verification/lift_off.toml)
// ---------------------------------------------------------------------------

/// Times at which the block of lift_off.toml is clear of the flat: its bottom
/// at 0.004 + 0.014 f(t) > 0 (0.0005, 0.0005, 0.004, 0.0005).
const CLEAR: [f64; 4] = [0.25, 1.75, 2.0, 2.25];

fn check_lift_off(edits: &[(&str, &str)]) {
    let (_, steps) = solve("verification/lift_off.toml", edits);
    let pressed = at(&steps, 1.0);
    let p1 = &pressed.pairs[0].1;
    let force = p1.fy;
    assert!(force > 0.0 && p1.n_open == 0, "pressed at t = 1: {p1:?}");
    for step in &steps {
        let (pair, press, flat) = (
            &step.pairs[0].1,
            driver(step, "press"),
            driver(step, "flat"),
        );
        // Equilibrium of the block: the flat takes what the press applies.
        for c in 0..2 {
            assert!(
                (flat[c] - press[c]).abs() <= 1e-9 * force,
                "t = {}: flat {flat:?} press {press:?}",
                step.time
            );
        }
        println!(
            "t = {}: iterations {}, bisections {}, Fn {:e}, Fx {:e}, Fy {:e}, \
             stick/slip/open {}/{}/{}, press {press:?}",
            step.time,
            step.iterations,
            step.substeps,
            pair.fn_,
            pair.fx,
            pair.fy,
            pair.n_stick,
            pair.n_slip,
            pair.n_open
        );
    }
    // Clear of the flat (before the first contact and after the release):
    // every node open, no contact force at all (exactly: nothing is summed),
    // no constraint, and the press holds a stress-free block (its reaction
    // is round-off of the element forces, 1e-12 of the pressed force).
    for t in CLEAR {
        let step = at(&steps, t);
        let pair = &step.pairs[0].1;
        let m = pair.nodes.x.len();
        assert_eq!(
            (pair.n_open, pair.n_stick, pair.n_slip),
            (m, 0, 0),
            "t = {t}: a node is still closed: y {:?}, tn {:?}, Fn {}",
            pair.nodes.y,
            pair.nodes.tn,
            pair.fn_
        );
        assert_eq!(step.neqc, 0, "t = {t}");
        assert_eq!([pair.fn_, pair.ft, pair.fx, pair.fy], [0.0; 4], "t = {t}");
        assert_eq!(driver(step, "flat"), [0.0; 2], "t = {t}");
        let press = driver(step, "press");
        assert!(
            press[0].abs() <= 1e-12 * force && press[1].abs() <= 1e-12 * force,
            "t = {t}: press {press:?}"
        );
        assert!(pair.nodes.y.iter().all(|&y| y > 0.0));
    }
    // Pressed again to the same depth along the same increments: the first
    // contact has left nothing behind (measured: equal to 1e-14).
    for (t1, t3) in [(0.5, 2.5), (0.75, 2.75), (1.0, 3.0)] {
        let (a, b) = (&at(&steps, t1).pairs[0].1, &at(&steps, t3).pairs[0].1);
        for (x, y) in [(a.fn_, b.fn_), (a.ft, b.ft), (a.fx, b.fx), (a.fy, b.fy)] {
            assert!((x - y).abs() <= 1e-8 * a.fy, "t = {t1} vs {t3}: {x} vs {y}");
        }
        assert_eq!(a.nodes.state, b.nodes.state, "t = {t1} vs {t3}");
        for (x, y) in a.nodes.tn.iter().zip(&b.nodes.tn) {
            assert!(
                (x - y).abs() <= 1e-8 * a.fy,
                "t = {t1} vs {t3}: tn {x} vs {y}"
            );
        }
        assert_eq!(at(&steps, t1).neqc, at(&steps, t3).neqc);
    }
}

#[test]
fn lift_off_releases_completely_and_remakes_the_same_contact() {
    check_lift_off(&[]);
}

/// The same history with Coulomb friction (mu_s = mu_d = 0.3). It once
/// failed: a node released in tension, lying on the flat to round-off
/// (overlap +2e-17), was re-captured by the penetration search in the same
/// iteration and held the body in tension (Fn = -1.80 with the block 0.004
/// clear). A node released in an iteration is not searched again in it.
#[test]
fn lift_off_with_friction_releases_completely() {
    check_lift_off(&[("\nmu_s = 0.0", "\nmu_s = 0.3\nmu_d = 0.3")]);
}
