//! Newton on the frictionless Hertz scene (scenes/hertz_plane_strain.toml):
//! once the contact set of an increment has settled (no node changes state),
//! the residual ratios |r|/|r0| of the `LogCategory::Newton` lines must fall
//! quadratically to round-off.

mod common;

use contact2d::newton::Solver;
use contact2d::results::LogCategory;

/// Quadratic convergence: `r_{k+1} <= C r_k^2` (ratios to the increment's
/// first residual). For a Newton iteration with a consistent tangent, C is
/// of order one in these normalised units; 100 leaves room. A linear rate
/// rho violates it as soon as `r_k < rho / C`: for the rho ~ 1e-3 of a
/// fixed-point iteration, from r_k = 1e-5 on, and the force tolerance
/// (1e-8) takes every increment below that unless it converges at once.
const C: f64 = 100.0;
/// Round-off: ratios at or below this are converged (the log shows 1e-15 to
/// 5e-15 where an increment reaches round-off), no rate can be asked of them.
const ROUND_OFF: f64 = 1e-12;

/// One logged Newton iteration.
#[derive(Clone, Debug, PartialEq)]
struct Iteration {
    time: String,
    it: usize,
    ratio: f64,
    changed: usize,
}

/// Parses `t = 1.000000e0 it 3: |r|/F = 7.305e-8 ... NEQC 12  changed 0 ...`.
fn parse(line: &str) -> Option<Iteration> {
    let rest = line.strip_prefix("t = ")?;
    let (time, rest) = rest.split_once(" it ")?;
    let (it, rest) = rest.split_once(':')?;
    let ratio = rest.split("|r|/F = ").nth(1)?.split_whitespace().next()?;
    let changed = rest.split("changed ").nth(1)?.split_whitespace().next()?;
    Some(Iteration {
        time: time.to_string(),
        it: it.trim().parse().ok()?,
        ratio: ratio.parse().ok()?,
        changed: changed.parse().ok()?,
    })
}

/// The Newton attempts of the log (one per increment attempted), without
/// those that failed (a Warning `increment to t = ... failed` follows them).
/// The Newton and warning lines of the log of `problem` run over its
/// load history (`label` names the run in a failure).
fn newton_log(problem: contact2d::problem::Problem, label: &str) -> Vec<(LogCategory, String)> {
    let times = problem.times.clone();
    let mut solver = Solver::new(problem).unwrap();
    let mut log = Vec::new();
    for &t in &times {
        solver
            .advance(t, &mut |c, m| {
                if matches!(c, LogCategory::Newton | LogCategory::Warning) {
                    log.push((c, m.to_string()));
                }
            })
            .unwrap_or_else(|e| panic!("{label} t = {t}: {e}"));
    }
    log
}

fn attempts(log: &[(LogCategory, String)]) -> Vec<Vec<Iteration>> {
    let mut out: Vec<Vec<Iteration>> = Vec::new();
    let mut current: Vec<Iteration> = Vec::new();
    for (cat, line) in log {
        match cat {
            LogCategory::Newton => {
                if let Some(i) = parse(line) {
                    let new = current
                        .last()
                        .is_some_and(|l| l.time != i.time || i.it <= l.it);
                    if new {
                        out.push(std::mem::take(&mut current));
                    }
                    current.push(i);
                }
            }
            LogCategory::Warning if line.starts_with("increment to t = ") => {
                current.clear();
            }
            _ => {}
        }
    }
    if !current.is_empty() {
        out.push(current);
    }
    out
}

/// The ratios after the last iteration with `changed > 0`.
fn settled(attempt: &[Iteration]) -> Vec<f64> {
    let start = attempt
        .iter()
        .rposition(|i| i.changed > 0)
        .map_or(0, |p| p + 1);
    attempt[start..].iter().map(|i| i.ratio).collect()
}

/// Err for the first pair `r_k -> r_{k+1}` above round-off that is not
/// quadratic.
fn quadratic(ratios: &[f64]) -> Result<(), String> {
    for w in ratios.windows(2) {
        let (a, b) = (w[0], w[1]);
        if a <= ROUND_OFF {
            break;
        }
        if b > ROUND_OFF && b > C * a * a {
            return Err(format!(
                "{a:.3e} -> {b:.3e}: above C r^2 = {:.3e} (reduction {:.2e}, linear)",
                C * a * a,
                b / a
            ));
        }
    }
    Ok(())
}

#[test]
fn the_convergence_criterion_tells_quadratic_from_linear() {
    let line = "t = 1.000000e0 it 3: |r|/F = 7.305e-8  |du|/|du1| = 9.223e-5  \
                energy 1.002e-11  rate -14.64  NEQC 12  changed 0  overlap 5.905e-22";
    assert_eq!(
        parse(line),
        Some(Iteration {
            time: "1.000000e0".into(),
            it: 3,
            ratio: 7.305e-8,
            changed: 0
        })
    );
    let log = |lines: &[&str]| -> Vec<(LogCategory, String)> {
        lines
            .iter()
            .map(|l| {
                let cat = if l.starts_with("increment") {
                    LogCategory::Warning
                } else {
                    LogCategory::Newton
                };
                (cat, l.to_string())
            })
            .collect()
    };
    let a = attempts(&log(&[
        "t = 5.000000e-1 it 1: |r|/F = 1.0e-1  NEQC 2  changed 1  overlap 0",
        "increment to t = 0.5 failed (x); bisecting at t = 0.25",
        "t = 2.500000e-1 it 1: |r|/F = 1.0e-2  NEQC 2  changed 1  overlap 0",
        "t = 2.500000e-1 it 2: |r|/F = 1.0e-3  NEQC 2  changed 0  overlap 0",
        "t = 5.000000e-1 it 1: |r|/F = 2.0e-2  NEQC 2  changed 0  overlap 0",
    ]));
    assert_eq!(a.len(), 2);
    assert_eq!(settled(&a[0]), vec![1.0e-3]);
    assert_eq!(settled(&a[1]), vec![2.0e-2]);
    // Quadratic from 1e-2 to round-off passes; the linear rate 1e-3 that
    // the Hertz log showed while the frictionless force was taken in the
    // contactor segments' frame does not.
    assert!(quadratic(&[1e-2, 3e-4, 2e-7, 1e-13, 2e-15]).is_ok());
    assert!(quadratic(&[2.037e-5, 7.305e-8, 1.411e-10]).is_err());
    assert!(quadratic(&[4.4e-5, 2.1e-8, 2.0e-11]).is_err());
}

#[test]
fn hertz_newton_converges_quadratically_once_the_contact_set_settles() {
    let problem = common::shipped_scene("hertz_plane_strain.toml", &[]);
    let times = problem.times.clone();
    let log = newton_log(problem, "hertz");
    let attempts = attempts(&log);
    assert!(attempts.len() >= times.len(), "{log:?}");
    let mut failures = Vec::new();
    for a in &attempts {
        let ratios = settled(a);
        // Convergence needs no change in the last iteration.
        assert!(!ratios.is_empty(), "t = {}: {a:?}", a[0].time);
        let shown: Vec<String> = ratios.iter().map(|r| format!("{r:.3e}")).collect();
        eprintln!("t = {}: settled |r|/F {}", a[0].time, shown.join(", "));
        if let Err(e) = quadratic(&ratios) {
            failures.push(format!("t = {}: {e}", a[0].time));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// With friction (the default nodal decisions): the sliding block dragged
/// in large increments, and the same block held while its rigid plane moves.
/// Once the stick/slip states settle, every reduction above round-off is
/// quadratic: a sliding node's friction `mu_d p_n` follows its normal force
/// within the solve (docs/contact.md section 8). The paper's decisions hold
/// the friction over the iteration and reduce by a constant factor (about
/// 10 per iteration on this scene), which `quadratic` rejects.
#[test]
fn frictional_newton_converges_quadratically_once_the_states_settle() {
    // The shipped steps, replaced by steps of 0.5 (the rest of the line
    // becomes a comment).
    let times = (
        "times = [0.5, 1.0, 1.02",
        "times = [0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0]\n# [1.02",
    );
    // Total Lagrangian and a press of 0.05 (5 % of the height): nonlinear,
    // so the settled iterations reduce from above round-off.
    let tl = (
        "kinematics = \"small_strain\"",
        "kinematics = \"total_lagrangian\"",
    );
    let press = ("scale = -0.01 }", "scale = -0.05 }");
    let moving = [
        (
            "ux = { function = \"drag\", scale = 0.2 }\nuy = { function = \"press\", scale = -0.01 }",
            "ux = 0.0\nuy = 0.0",
        ),
        tl,
        (
            "points = [[10.0, 0.0], [-10.0, 0.0]]",
            "points = [[10.0, 0.0], [-10.0, 0.0]]\nuy = { function = \"press\", scale = 0.05 }\nux = { function = \"drag\", scale = -0.2 }",
        ),
        times,
    ];
    let dragged = [tl, press, times];
    for (label, edits) in [
        ("block dragged", &dragged[..]),
        ("plane moving", &moving[..]),
    ] {
        let mut problem = common::shipped_scene("verification/sliding_block.toml", edits);
        problem.solver.max_bisections = 0;
        let log = newton_log(problem, label);
        let mut checked = 0;
        for a in attempts(&log) {
            let ratios = settled(&a);
            checked += ratios.windows(2).filter(|w| w[0] > ROUND_OFF).count();
            let shown: Vec<String> = ratios.iter().map(|r| format!("{r:.3e}")).collect();
            eprintln!(
                "{label} t = {}: settled |r|/F {}",
                a[0].time,
                shown.join(", ")
            );
            quadratic(&ratios).unwrap_or_else(|e| panic!("{label} t = {}: {e}", a[0].time));
        }
        // Reductions from above round-off were seen, not only one-step
        // increments.
        assert!(checked >= 3, "{label}: {checked} reductions checked");
    }
}
