//! Newton-Raphson, bisection and rollback on a total Lagrangian cantilever
//! under a large tip load (programmatic mesh; the shipped scene is tested in
//! tests/scenes.rs).

mod common;

use contact2d::mesh::ElementKind;
use contact2d::newton::Solver;
use contact2d::problem::*;
use contact2d::results::LogCategory;

/// Cantilever L = 10, h = 0.5, Q8 20x2, clamped left end, dead tip load
/// P = k EI / L^2 at the mid-height node of the free end, ramped over t in [0, 1].
fn cantilever(k: f64) -> (Solver, usize) {
    let (l, h, e) = (10.0, 0.5, 1.2e7);
    let mesh = common::grid(ElementKind::Q8, [0.0, 0.0], [l, h], 20, 2, |x, y| [x, y]);
    let mut p = common::problem(
        mesh,
        AnalysisKind::PlaneStress { thickness: 1.0 },
        Kinematics::TotalLagrangian,
        e,
        0.0,
    );
    let left = common::nodes_where(&p.mesh, |x, _| x < 1e-12);
    p.drivers.push(Driver {
        name: "clamp".into(),
        nodes: left,
        ux: Some(Scaled::constant(0.0)),
        uy: Some(Scaled::constant(0.0)),
        fx: None,
        fy: None,
        distribution: Default::default(),
    });
    let tip = common::nodes_where(&p.mesh, |x, y| {
        (x - l).abs() < 1e-12 && (y - h / 2.0).abs() < 1e-12
    });
    let ei = e * h.powi(3) / 12.0;
    p.forces.push(NodalForce {
        nodes: tip.clone(),
        fx: Scaled::constant(0.0),
        fy: Scaled {
            scale: -k * ei / (l * l),
            function: Some(0),
        },
    });
    (Solver::new(p).unwrap(), tip[0])
}

#[test]
fn newton_converges_quadratically_and_the_log_shows_it() {
    let (mut s, _) = cantilever(2.0);
    for i in 1..=4 {
        let mut lines = Vec::new();
        let r = s
            .advance(i as f64 / 4.0, &mut |c, m| {
                if c == LogCategory::Newton {
                    lines.push(m.to_string())
                }
            })
            .unwrap();
        assert!(r.converged && r.substeps == 0);
        // Full Newton from a rotated configuration: a handful of iterations.
        assert!(
            r.iterations <= 7,
            "increment {i}: {} iterations\n{}",
            r.iterations,
            lines.join("\n")
        );
        // The asymptotic rate estimate ln(r_k/r_k-1)/ln(r_k-1/r_k-2) reaches ~2
        // before round-off; a tangent missing its geometric part gives ~1.
        let best = common::rates(&lines).into_iter().fold(0.0f64, f64::max);
        assert!(
            best > 1.7,
            "increment {i}: best rate {best}\n{}",
            lines.join("\n")
        );
        assert!(r.residual <= 1e-8);
    }
}

#[test]
fn a_failed_increment_bisects_and_a_hopeless_one_leaves_the_state_untouched() {
    // Reference: four increments.
    let (mut a, tip) = cantilever(4.0);
    for i in 1..=4 {
        a.advance(i as f64 / 4.0, &mut common::silent()).unwrap();
    }
    // One increment with few iterations allowed: bisection has to cut it.
    let (mut b, _) = cantilever(4.0);
    b.settings_mut().max_iterations = 7;
    let mut warnings = 0;
    let r = b
        .advance(1.0, &mut |c, _| {
            if c == LogCategory::Warning {
                warnings += 1
            }
        })
        .unwrap();
    assert!(
        r.substeps > 0 && warnings == r.substeps,
        "substeps {} warnings {warnings}",
        r.substeps
    );
    // Elastic, path independent: same end state to the Newton tolerance.
    let (ua, ub) = (a.state().displacement(tip), b.state().displacement(tip));
    assert!(
        (ua[1] - ub[1]).abs() < 1e-7 * ua[1].abs(),
        "{ua:?} vs {ub:?}"
    );
    assert!(ua[1] < -4.0, "a large deflection: {ua:?}");
    // No bisection allowed and too few iterations: an error, state kept.
    let (mut c, _) = cantilever(4.0);
    c.advance(0.25, &mut common::silent()).unwrap();
    let before = c.state().clone();
    c.settings_mut().max_iterations = 2;
    c.settings_mut().max_bisections = 1;
    let mut errors = Vec::new();
    let err = c
        .advance(1.0, &mut |cat, m| {
            if cat == LogCategory::Error {
                errors.push(m.to_string())
            }
        })
        .unwrap_err();
    assert!(err.to_string().contains("t = 1"), "{err}");
    assert_eq!(errors.len(), 1);
    assert_eq!(c.state(), &before);
    // And the master can go on from there with smaller steps.
    c.settings_mut().max_iterations = 25;
    c.advance(0.5, &mut common::silent()).unwrap();
    assert_eq!(c.state().time, 0.5);
}

/// Bisection stops where the midpoint would round onto an end of the
/// increment (issue 13, defect 5: the same increment was tried again, and
/// one Discard took 51 s): late in time (t = 1.7e9, where the spacing of
/// doubles is 2.4e-7), a step of 1e-6 that cannot converge is given up
/// after at most two halvings, however many bisections the settings allow,
/// and the message says why.
#[test]
fn bisection_stops_when_the_midpoint_rounds_onto_an_end() {
    let (mut c, _) = cantilever(4.0);
    let mut state = c.state().clone();
    state.time = 1.7e9;
    c.restore(state);
    let before = c.state().clone();
    // The clamp moved by a tenth of the length, with one iteration allowed:
    // every increment fails.
    c.set_input(0, 1, Some(-1.0));
    c.settings_mut().max_iterations = 1;
    c.settings_mut().max_bisections = 1000;
    let mut warnings = 0;
    let err = c
        .advance(1.7e9 + 1e-6, &mut |cat, _| {
            if cat == LogCategory::Warning {
                warnings += 1
            }
        })
        .unwrap_err();
    assert!(warnings <= 2, "{warnings} bisections");
    assert!(
        err.to_string().contains("cannot be halved further"),
        "{err}"
    );
    assert_eq!(c.state(), &before);
}
