//! The stress suite's families (issue 11): each function runs one scene
//! variant and returns its `Outcome` (run, closed-form checks, findings).
//! The scenes are under scenes/stress/ (their headers give the closed forms
//! and tolerances) or are shipped scenes refined.

use super::{Check, Element, Frame, Outcome, Stepper, Variant, load, pair, reaction, run_scene};
use contact2d::problem::{MaterialSpec, Problem};
use contact2d::results::{NodeState, StepResult};
use std::f64::consts::PI;

// ---------------------------------------------------------------------------
// 1. Capstan
// ---------------------------------------------------------------------------

pub const CAPSTAN_HALF: &str = "stress/capstan_half_wrap.toml";
pub const CAPSTAN_QUARTER: &str = "stress/capstan_quarter_wrap.toml";
/// The capstan's friction coefficient and held-end tension (MPa on the
/// end face).
const CAPSTAN_MU: f64 = 0.25;
const CAPSTAN_PRESSURE: f64 = 10.0;

/// The inner and outer corner of an end face (node set `set`): its nodes
/// nearest to and farthest from the drum's centre (the origin).
fn end_corners(problem: &Problem, set: &str) -> (usize, usize) {
    let nodes = &problem.mesh.node_sets[set];
    let r = |n: &usize| problem.mesh.nodes[*n][0].hypot(problem.mesh.nodes[*n][1]);
    let inner = *nodes.iter().min_by(|a, b| r(a).total_cmp(&r(b))).unwrap();
    let outer = *nodes.iter().max_by(|a, b| r(a).total_cmp(&r(b))).unwrap();
    (inner, outer)
}

/// What the capstan formula needs from a converged capstan increment: the
/// held end's tension T1 (the follower pressure times its face's current
/// length), the pulled end's T2 (its driver's pull along -y) and the wrap
/// in contact, from the tangent point at 0 deg to the held end's inner
/// corner (its current polar angle).
pub struct Capstan {
    pub t1: f64,
    pub t2: f64,
    pub theta: f64,
}

pub fn capstan_state(problem: &Problem, frame: &super::Frame) -> Capstan {
    let (inner, outer) = end_corners(problem, "band.end");
    let (a, b) = (
        frame.position(problem, inner),
        frame.position(problem, outer),
    );
    let t1 = CAPSTAN_PRESSURE * (b[0] - a[0]).hypot(b[1] - a[1]);
    let t2 = -reaction(&frame.step, "tight")[1];
    Capstan {
        t1,
        t2,
        // In [0, 2 pi): the half wrap's held end may slide below the x axis.
        theta: a[1].atan2(a[0]).rem_euclid(2.0 * PI),
    }
}

/// The capstan scenes' tolerance on T2/T1 (their headers): the band's
/// thickness, bending where it leaves the drum (about 5 times the band's EI
/// for 4-node elements, shear locking), and the drum's polygon.
pub fn capstan_tolerance(theta: f64, mu: f64, element: Element) -> f64 {
    let (r, t, e, nu) = (100.0, 1.0, 1000.0, 0.3);
    // Plane strain bending stiffness per unit width.
    let ei = e / (1.0 - nu * nu) * t * t * t / 12.0;
    let t1 = CAPSTAN_PRESSURE * t;
    let locking = match element {
        Element::Q4 => 5.0,
        Element::Q8 => 1.0,
    };
    let thickness = mu * theta * t / (2.0 * r);
    let bending = locking * ei / (t1 * (mu * theta).exp() * r * r);
    let drum_segment = (225.0f64).to_radians() / 5120.0;
    let polygon = theta * drum_segment / 2.0;
    thickness + bending + polygon
}

/// The band slides over the whole wrap: no node of it sticks.
fn full_slip(step: &StepResult, out: &mut Vec<String>) {
    let p = pair(step, "wrap");
    if p.n_stick > 0 || p.n_slip == 0 {
        out.push(format!(
            "t = {}: the band does not slide over the whole wrap (stick/slip/open {}/{}/{})",
            step.time, p.n_stick, p.n_slip, p.n_open
        ));
    }
}

/// T2/T1 against exp(mu theta_eff) at the run's last increment (a run
/// that stopped early is not checked).
fn capstan_check(out: &mut Outcome, mu: f64, tolerance: f64) {
    let run = &out.run;
    if run.failure.is_some() {
        return;
    }
    let c = capstan_state(&run.problem, run.frames.last().unwrap());
    out.checks.push(Check::relative(
        "T2/T1",
        c.t2 / c.t1,
        (mu * c.theta).exp(),
        tolerance,
    ));
}

/// The capstan scene over its own load history: T2/T1 = exp(mu theta) at
/// the last increment, every node sliding there. `mu = 0`: the same scene
/// frictionless (T2 = T1).
pub fn capstan(scene: &str, frictionless: bool, v: Variant) -> Outcome {
    let half = scene == CAPSTAN_HALF;
    let edits: &[(&str, &str)] = if frictionless {
        &[("mu_s = 0.25\nmu_d = 0.25", "mu_s = 0.0\nmu_d = 0.0")]
    } else {
        &[]
    };
    let problem = load(scene, v, edits);
    let run = run_scene(problem);
    let case = format!(
        "capstan {}{}",
        if half { "pi" } else { "pi/2" },
        if frictionless { " mu=0" } else { "" }
    );
    let mut out = Outcome::new(case, v.label(), run);
    let mu = if frictionless { 0.0 } else { CAPSTAN_MU };
    let tolerance = capstan_tolerance(if half { PI } else { PI / 2.0 }, mu, v.element);
    capstan_check(&mut out, mu, tolerance);
    if out.run.failure.is_none() {
        let mut p = Vec::new();
        full_slip(out.run.last(), &mut p);
        out.problems.extend(p);
    }
    out
}

/// The four capstan scenes by name (tests and bench).
pub fn capstan_half_wrap(v: Variant) -> Outcome {
    capstan(CAPSTAN_HALF, false, v)
}
pub fn capstan_quarter_wrap(v: Variant) -> Outcome {
    capstan(CAPSTAN_QUARTER, false, v)
}
pub fn capstan_half_wrap_frictionless(v: Variant) -> Outcome {
    capstan(CAPSTAN_HALF, true, v)
}
pub fn capstan_quarter_wrap_frictionless(v: Variant) -> Outcome {
    capstan(CAPSTAN_QUARTER, true, v)
}

// ---------------------------------------------------------------------------
// 2. Interference (shrink) fit
// ---------------------------------------------------------------------------

pub const SHRINK_FIT: &str = "stress/shrink_fit.toml";

/// Lame's interface pressure on the hub (the scene's header): the contact
/// force per radian F from the overlap, over the hub's radius b + delta.
pub fn shrink_fit_pressure(problem: &Problem) -> f64 {
    let (a, b, c, delta) = (50.0, 75.0, 100.0, 0.05);
    let (bi, bo) = (b + delta, b);
    let constants = |name: &str| {
        let m = problem.materials.iter().find(|m| m.name == name).unwrap();
        let MaterialSpec::LinearElastic { e, nu } = m.spec else {
            panic!("{name} is linear elastic")
        };
        (e / (1.0 - nu * nu), nu / (1.0 - nu))
    };
    let (ei, nui) = constants("steel");
    let (eo, nuo) = constants("aluminium");
    let compliance = ((c * c + bo * bo) / (c * c - bo * bo) + nuo) / eo
        + ((bi * bi + a * a) / (bi * bi - a * a) - nui) / ei;
    delta / compliance / bi
}

/// The shrink fit, frictionless or with mu = 0.3: the interface pressure
/// against Lame's, from the contact force on the hub (-Fx over its radius
/// b + delta; -Fy gives the same).
///
/// With friction every node sticks, and p is the frictionless one: the
/// contactor's end nodes lie on the symmetry planes, where their tangent
/// is the plane's normal and they carry no friction
/// (`Surface::hold_symmetry_planes`). Before 2026-11-28 (sixth session)
/// their tangent was their one side's, pi / 4n off the plane's normal, and
/// they read the removal of the initial overlap as slip and slid with mu
/// tn into the symmetry drivers: p +1.7e-2 on Q4 1x, +8.0e-3 on 2x, Q8
/// +4.9e-3 and +2.5e-3, so the pair was pinned to node-to-segment.
pub fn shrink_fit(friction: bool, v: Variant) -> Outcome {
    let edits: &[(&str, &str)] = if friction {
        &[("mu_s = 0.0", "mu_s = 0.3")]
    } else {
        &[]
    };
    let problem = load(SHRINK_FIT, v, edits);
    let reference = shrink_fit_pressure(&problem);
    let run = run_scene(problem);
    let case = format!("shrink fit{}", if friction { " mu=0.3" } else { "" });
    let mut out = Outcome::new(case, v.label(), run);
    if out.run.frames.len() > 1 {
        let p = pair(out.run.last(), "fit");
        let radius = 75.05;
        // The header's tolerance: 4-node (pi / 4n)^2 for n = 16 x refine
        // facets round the quarter (the mesh's error falls as h^2, h the
        // facet's half angle), 8-node 1e-4.
        let tolerance = match v.element {
            Element::Q4 => (std::f64::consts::PI / (64.0 * v.refine as f64)).powi(2),
            Element::Q8 => 1e-4,
        };
        out.checks.push(Check::relative(
            "p (-Fx/b_i)",
            -p.fx / radius,
            reference,
            tolerance,
        ));
        out.checks.push(Check::relative(
            "p (-Fy/b_i)",
            -p.fy / radius,
            reference,
            tolerance,
        ));
        if p.n_open > 0 {
            out.problems.push(format!(
                "{} interface nodes open (every node is pressed)",
                p.n_open
            ));
        }
    }
    out
}

/// The shrink fit with the rim's bore divided into 23 facets against the
/// hub's 16 (refined alike): no contactor node faces a target node, so the
/// iteration must place nodes on facets and over the bore's vertices,
/// frictionless or with mu = 0.3. There is no closed form to check: the
/// bore's polygon is inscribed in its circle, and its facets' sagitta
/// b (1 - cos(pi / 92)) = 0.044 mm is as large as the overlap (0.05 mm),
/// so the interference a hub node meets depends on where it faces a facet
/// (between 0.05 and 0.094 mm), and the nodes that meet the least come
/// free (7 of 17 stay pressed on 4 x 16 / 23, frictionless). What the
/// suite asserts here is what it asserts everywhere: every increment
/// converges within its limits, and the contact conditions hold.
pub fn shrink_fit_nonmatching(friction: bool, v: Variant) -> Outcome {
    let mut edits = vec![(
        "r_outer = 100.0, angles = [0.0, 90.0], divisions = [4, 16]",
        "r_outer = 100.0, angles = [0.0, 90.0], divisions = [4, 23]",
    )];
    if friction {
        edits.push(("mu_s = 0.0", "mu_s = 0.3"));
    }
    let problem = load(SHRINK_FIT, v, &edits);
    let run = run_scene(problem);
    let case = format!("shrink fit 16/23{}", if friction { " mu=0.3" } else { "" });
    Outcome::new(case, v.label(), run)
}

pub fn shrink_fit_frictionless(v: Variant) -> Outcome {
    shrink_fit(false, v)
}
pub fn shrink_fit_with_friction(v: Variant) -> Outcome {
    shrink_fit(true, v)
}
pub fn shrink_fit_nonmatching_frictionless(v: Variant) -> Outcome {
    shrink_fit_nonmatching(false, v)
}
pub fn shrink_fit_nonmatching_with_friction(v: Variant) -> Outcome {
    shrink_fit_nonmatching(true, v)
}

// ---------------------------------------------------------------------------
// 3. Moving rigid targets with friction
// ---------------------------------------------------------------------------

pub const MOVING_PLANE: &str = "stress/moving_plane.toml";
pub const INCLINE: &str = "stress/incline.toml";

/// Every node of pair `name` slides at `step`.
fn all_slip(step: &StepResult, name: &str, out: &mut Vec<String>) {
    let p = pair(step, name);
    if p.n_slip != p.nodes.x.len() {
        out.push(format!(
            "t = {}: not every node of {name} slides (stick/slip/open {}/{}/{})",
            step.time, p.n_stick, p.n_slip, p.n_open
        ));
    }
}

/// |Ft| = mu_d Fn of pair `name`, and the driver's |Rx| = mu_d |Ry|, at
/// `step` (steady sliding on a flat target).
fn sliding_checks(out: &mut Outcome, step_index: usize, pair_name: &str, driver: &str, mu_d: f64) {
    let step = &out.run.frames[step_index].step;
    let p = pair(step, pair_name);
    let r = reaction(step, driver);
    let t = step.time;
    let (ft, rx) = (p.ft.abs() / p.fn_, r[0].abs() / r[1].abs());
    out.checks
        .push(Check::relative(format!("|Ft|/Fn t={t}"), ft, mu_d, 1e-6));
    out.checks
        .push(Check::relative(format!("|Rx|/|Ry| t={t}"), rx, mu_d, 1e-6));
}

/// The block held at its top, pressed and dragged by the moving plane:
/// steady sliding at mu_d from t = 1.3 on.
pub fn moving_plane(v: Variant) -> Outcome {
    let run = run_scene(load(MOVING_PLANE, v, &[]));
    let mut out = Outcome::new("moving plane drag", v.label(), run);
    let steady: Vec<usize> = (1..out.run.frames.len())
        .filter(|&i| out.run.frames[i].step.time >= 1.3 - 1e-9)
        .collect();
    let mut problems = Vec::new();
    for &i in &steady {
        all_slip(&out.run.frames[i].step, "base", &mut problems);
    }
    out.problems.extend(problems);
    if let Some(&last) = steady.last() {
        sliding_checks(&mut out, last, "base", "top", 0.2);
    }
    out
}

/// The tilt of the incline scene's plane at time t, degrees.
fn tilt(t: f64) -> f64 {
    (t - 1.0).max(0.0)
}

/// The block on the tilting plane: it sticks up to atan(mu_s) and the
/// increment past it fails (no static equilibrium). The last converged
/// tilt and the first failed one must bracket the onset, each within the
/// angle increment (0.25 deg).
pub fn incline(v: Variant) -> Outcome {
    let run = run_scene(load(INCLINE, v, &[]));
    let mut out = Outcome::new("incline onset", v.label(), run);
    out.failure_expected = Some("past the onset of sliding there is no static equilibrium");
    let onset = 0.3f64.atan().to_degrees();
    let step = 0.25;
    let last = tilt(out.run.last().time);
    match &out.run.failure {
        None => out.problems.push(format!(
            "the block never slid: every tilt up to {last} deg converged (onset {onset:.3} deg)"
        )),
        Some((t, _)) => {
            let failed = tilt(*t);
            out.checks
                .push(Check::absolute("last stuck tilt (deg)", last, onset, step));
            out.checks.push(Check::absolute(
                "first failed tilt (deg)",
                failed,
                onset,
                step,
            ));
            if !(last < onset && failed > onset) {
                out.problems.push(format!(
                    "the onset {onset:.3} deg is not between the last converged tilt {last} deg \
                     and the first failed one {failed} deg"
                ));
            }
        }
    }
    out
}

// ---------------------------------------------------------------------------
// 4. Load paths through the Solver API (as the FMU drives it)
// ---------------------------------------------------------------------------

pub const SLIDING_BLOCK: &str = "verification/sliding_block.toml";

/// What a held input must leave unchanged: the displacements (to the
/// Newton tolerance, 1e-8 of the largest), the contact tractions (1e-8 of
/// the largest tn) and node states, and it must take 0 or 1 iterations.
fn held_checks(problem: &Problem, before: &Frame, after: &Frame, out: &mut Vec<String>) {
    let t = after.step.time;
    if after.step.iterations > 1 {
        out.push(format!(
            "t = {t}: a held input took {} Newton iterations (0 or 1)",
            after.step.iterations
        ));
    }
    let scale = before.u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let du = before
        .u
        .iter()
        .zip(&after.u)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    if du > 1e-8 * scale {
        out.push(format!(
            "t = {t}: a held input moved the nodes by {du:.3e} (largest displacement {scale:.3e})"
        ));
    }
    for (p, c) in problem.contacts.iter().enumerate() {
        let (a, b) = (&before.step.pairs[p].1.nodes, &after.step.pairs[p].1.nodes);
        let tn_max = a.tn.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let dt = (0..a.tn.len())
            .map(|k| (a.tn[k] - b.tn[k]).abs().max((a.tt[k] - b.tt[k]).abs()))
            .fold(0.0f64, f64::max);
        if dt > 1e-8 * tn_max {
            out.push(format!(
                "t = {t}: a held input changed the tractions of {} by {dt:.3e} (largest tn {tn_max:.3e})",
                c.name
            ));
        }
        if a.state != b.state {
            let changed: Vec<usize> = (0..a.state.len())
                .filter(|&k| a.state[k] != b.state[k])
                .collect();
            out.push(format!(
                "t = {t}: a held input changed the states of {} at nodes {changed:?} ({:?} -> {:?})",
                c.name,
                changed.iter().map(|&k| a.state[k]).collect::<Vec<_>>(),
                changed.iter().map(|&k| b.state[k]).collect::<Vec<_>>()
            ));
        }
    }
}

/// A tiny increment must change the tractions by no more than 1e-6 of the
/// largest tn (a change of 1e-9 of an increment; 1e-6 leaves room for the
/// Newton tolerance) and leave the node states as they were.
fn tiny_checks(problem: &Problem, before: &Frame, after: &Frame, out: &mut Vec<String>) {
    let t = after.step.time;
    for (p, c) in problem.contacts.iter().enumerate() {
        let (a, b) = (&before.step.pairs[p].1.nodes, &after.step.pairs[p].1.nodes);
        let tn_max = a.tn.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let dt = (0..a.tn.len())
            .map(|k| (a.tn[k] - b.tn[k]).abs().max((a.tt[k] - b.tt[k]).abs()))
            .fold(0.0f64, f64::max);
        if dt > 1e-6 * tn_max {
            out.push(format!(
                "t = {t}: a tiny increment changed the tractions of {} by {dt:.3e} (largest tn {tn_max:.3e})",
                c.name
            ));
        }
        if a.state != b.state {
            let changed: Vec<usize> = (0..a.state.len())
                .filter(|&k| a.state[k] != b.state[k])
                .collect();
            out.push(format!(
                "t = {t}: a tiny increment changed the states of {} at nodes {changed:?}",
                c.name
            ));
        }
    }
}

/// The load paths: `Held` repeats the last input 3 times, `Tiny` changes
/// it twice by 1e-9 of the increment before, `Large` applies the whole
/// load in one step, `Reversal` drives back, `LiftOff` lifts the block
/// off the plane and presses it back.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Path {
    Held,
    Tiny,
    Large,
    Reversal,
    LiftOff,
}

impl Path {
    fn name(self) -> &'static str {
        match self {
            Path::Held => "held",
            Path::Tiny => "tiny",
            Path::Large => "large",
            Path::Reversal => "reversal",
            Path::LiftOff => "lift-off",
        }
    }
}

/// The sliding block (scenes/verification/sliding_block.toml) driven
/// through its top driver's inputs (ux, uy), one `advance` per step, the
/// time a step counter.
pub fn block_path(path: Path, v: Variant) -> Outcome {
    let problem = load(SLIDING_BLOCK, v, &[]);
    let mut s = Stepper::new(problem);
    let mut t = 0.0;
    let mut to = |s: &mut Stepper, ux: f64, uy: f64| {
        t += 1.0;
        s.set_input("top", 0, ux);
        s.set_input("top", 1, uy);
        s.advance(t)
    };
    let (mu_d, press) = (0.2, -0.01);
    let mut problems = Vec::new();
    // Index of the frame the closed form is read at.
    let mut check_at = Vec::new();
    // Press (two steps), then drag in steps of 0.01 (the block breaks away
    // within the first: Ft = mu_s Fn at a drag of about 0.008).
    let press_and_drag =
        |s: &mut Stepper, to: &mut dyn FnMut(&mut Stepper, f64, f64) -> bool, n: usize| {
            to(s, 0.0, 0.5 * press);
            to(s, 0.0, press);
            for k in 1..=n {
                to(s, 0.01 * k as f64, press);
            }
        };
    match path {
        Path::Held => {
            press_and_drag(&mut s, &mut to, 5);
            for _ in 0..3 {
                to(&mut s, 0.05, press);
            }
            if !s.failed() {
                let n = s.frames.len();
                for i in n - 3..n {
                    held_checks(
                        s.solver.problem(),
                        &s.frames[i - 1],
                        &s.frames[i],
                        &mut problems,
                    );
                }
                check_at.push(n - 1);
            }
        }
        Path::Tiny => {
            press_and_drag(&mut s, &mut to, 5);
            for k in 1..=2 {
                to(&mut s, 0.05 + 1e-9 * 0.01 * k as f64, press);
            }
            if !s.failed() {
                let n = s.frames.len();
                for i in n - 2..n {
                    tiny_checks(
                        s.solver.problem(),
                        &s.frames[i - 1],
                        &s.frames[i],
                        &mut problems,
                    );
                }
                check_at.push(n - 1);
            }
        }
        Path::Large => {
            to(&mut s, 0.1, press);
            check_at.push(1);
        }
        Path::Reversal => {
            press_and_drag(&mut s, &mut to, 5);
            check_at.push(s.frames.len() - 1);
            for k in 1..=5 {
                to(&mut s, 0.05 - 0.01 * k as f64, press);
            }
            check_at.push(s.frames.len() - 1);
        }
        Path::LiftOff => {
            press_and_drag(&mut s, &mut to, 3);
            // Lift the block 0.01 above the plane, then press it back and
            // drag on.
            to(&mut s, 0.03, 0.01);
            if !s.failed() {
                let p = pair(&s.last().step, "base");
                if p.n_open != p.nodes.x.len() || p.fn_ != 0.0 {
                    problems.push(format!(
                        "t = {}: lifted 0.01 above the plane, yet stick/slip/open {}/{}/{}, Fn {}",
                        s.last().step.time,
                        p.n_stick,
                        p.n_slip,
                        p.n_open,
                        p.fn_
                    ));
                }
            }
            to(&mut s, 0.03, press);
            for k in 1..=3 {
                to(&mut s, 0.03 + 0.01 * k as f64, press);
            }
            check_at.push(s.frames.len() - 1);
        }
    }
    let run = s.finish();
    let mut out = Outcome::new(format!("block path {}", path.name()), v.label(), run);
    out.problems.extend(problems);
    if out.run.failure.is_none() {
        for i in check_at {
            let step = out.run.frames[i].step.clone();
            let mut p = Vec::new();
            all_slip(&step, "base", &mut p);
            out.problems.extend(p);
            sliding_checks(&mut out, i, "base", "top", mu_d);
        }
    }
    out
}

/// The quarter-wrap capstan driven through its pulled end's input (uy of
/// driver `tight`), the held end's tension following the scene's time
/// function (full from t = 1 on): the band is tensioned over t in [0, 1]
/// with the pulled end held, then pulled by -3 (full slip after -0.62).
pub fn capstan_path(path: Path, v: Variant) -> Outcome {
    let problem = load(CAPSTAN_QUARTER, v, &[]);
    let theta = PI / 2.0;
    let mut s = Stepper::new(problem);
    s.set_input("tight", 1, 0.0);
    for t in [0.25, 0.5, 0.75, 1.0] {
        s.advance(t);
    }
    let mut t = 1.0;
    let mut to = |s: &mut Stepper, uy: f64| {
        t += 0.25;
        s.set_input("tight", 1, uy);
        s.advance(t)
    };
    let mut problems = Vec::new();
    // (frame index, the sign of the slide: +1 toward the pulled end).
    let mut check_at: Vec<(usize, f64)> = Vec::new();
    let pull = |s: &mut Stepper, to: &mut dyn FnMut(&mut Stepper, f64) -> bool| {
        for k in 1..=4 {
            to(s, -0.75 * k as f64);
        }
    };
    match path {
        Path::Held => {
            pull(&mut s, &mut to);
            for _ in 0..3 {
                to(&mut s, -3.0);
            }
            if !s.failed() {
                let n = s.frames.len();
                for i in n - 3..n {
                    held_checks(
                        s.solver.problem(),
                        &s.frames[i - 1],
                        &s.frames[i],
                        &mut problems,
                    );
                }
                check_at.push((n - 1, 1.0));
            }
        }
        Path::Tiny => {
            pull(&mut s, &mut to);
            for k in 1..=2 {
                to(&mut s, -3.0 - 1e-9 * 0.75 * k as f64);
            }
            if !s.failed() {
                let n = s.frames.len();
                for i in n - 2..n {
                    tiny_checks(
                        s.solver.problem(),
                        &s.frames[i - 1],
                        &s.frames[i],
                        &mut problems,
                    );
                }
                check_at.push((n - 1, 1.0));
            }
        }
        Path::Large => {
            to(&mut s, -3.0);
            check_at.push((s.frames.len() - 1, 1.0));
        }
        Path::Reversal => {
            pull(&mut s, &mut to);
            check_at.push((s.frames.len() - 1, 1.0));
            // Back by 2 (reverse full slip after 0.62).
            for k in 1..=4 {
                to(&mut s, -3.0 + 0.5 * k as f64);
            }
            check_at.push((s.frames.len() - 1, -1.0));
        }
        Path::LiftOff => unreachable!("the capstan's held end is force-driven: see capstan_path"),
    }
    let run = s.finish();
    let mut out = Outcome::new(format!("capstan pi/2 path {}", path.name()), v.label(), run);
    out.problems.extend(problems);
    if out.run.failure.is_none() {
        let tolerance = capstan_tolerance(theta, CAPSTAN_MU, v.element);
        for (i, sign) in check_at {
            let frame = &out.run.frames[i];
            let mut p = Vec::new();
            full_slip(&frame.step, &mut p);
            out.problems.extend(p);
            let c = capstan_state(&out.run.problem, frame);
            out.checks.push(Check::relative(
                format!("T2/T1 t={}", frame.step.time),
                c.t2 / c.t1,
                (sign * CAPSTAN_MU * c.theta).exp(),
                tolerance,
            ));
        }
    }
    out
}

pub fn block_held(v: Variant) -> Outcome {
    block_path(Path::Held, v)
}
pub fn block_tiny(v: Variant) -> Outcome {
    block_path(Path::Tiny, v)
}
pub fn block_large(v: Variant) -> Outcome {
    block_path(Path::Large, v)
}
pub fn block_reversal(v: Variant) -> Outcome {
    block_path(Path::Reversal, v)
}
pub fn block_lift_off(v: Variant) -> Outcome {
    block_path(Path::LiftOff, v)
}
pub fn capstan_held(v: Variant) -> Outcome {
    capstan_path(Path::Held, v)
}
pub fn capstan_tiny(v: Variant) -> Outcome {
    capstan_path(Path::Tiny, v)
}
pub fn capstan_large(v: Variant) -> Outcome {
    capstan_path(Path::Large, v)
}
pub fn capstan_reversal(v: Variant) -> Outcome {
    capstan_path(Path::Reversal, v)
}

// ---------------------------------------------------------------------------
// 5. Refined versions of the shipped frictional scenes
// ---------------------------------------------------------------------------

/// scenes/rubber_sheet.toml (mu = 0.15): 2x is the 80 x 8 mesh of
/// docs/contact.md item 12. No closed form (the paper's figures).
///
/// Checked: at t = 8, 14 and 24 the whole contact zone slides (the paper's
/// Fig. 12; tests/paper_rubber_sheet.rs checks it under the paper's
/// decisions), so each node in contact carries |q| = mu_d p_n and the
/// wall is straight: |Ft| / Fn = mu_d, to the force tolerance of the
/// iteration (1e-6 of F; 1e-5 is asserted).
pub fn rubber_sheet(v: Variant) -> Outcome {
    let run = run_scene(load("rubber_sheet.toml", v, &[]));
    let mesh = format!("{} {}x{}", v.element.keyword(), 40 * v.refine, 4 * v.refine);
    let mut out = Outcome::new("rubber sheet", mesh, run);
    if out.run.failure.is_none() {
        let mu_d = out.run.problem.contacts[0].mu_d;
        let ratios: Vec<(f64, f64)> = (out.run.steps())
            .filter(|s| [8.0, 14.0, 24.0].iter().any(|t| (s.time - t).abs() < 1e-9))
            .map(|s| {
                let p = pair(s, "channel");
                (s.time, p.ft.abs() / p.fn_)
            })
            .collect();
        for (t, ratio) in ratios {
            out.checks.push(Check::relative(
                format!("|Ft|/Fn at t = {t}"),
                ratio,
                mu_d,
                1e-5,
            ));
        }
    }
    out
}

/// scenes/hertz_plane_strain.toml with mu_s = 0.3, mu_d = 0.2 (the edit
/// of tests/contact_scenes_friction.rs): partial slip, no closed form
/// (Spence's); the shipped mesh is 8-node, 60 divisions (2x: 120, the same
/// grading ratio).
pub fn hertz_friction(v: Variant) -> Outcome {
    let problem = load(
        "hertz_plane_strain.toml",
        v,
        &[("mu_s = 0.0", "mu_s = 0.3\nmu_d = 0.2")],
    );
    let run = run_scene(problem);
    let mesh = format!("{} {} div", v.element.keyword(), 60 * v.refine);
    Outcome::new("hertz friction", mesh, run)
}

/// scenes/hertz_plane_strain.toml (frictionless) pressed in one increment
/// instead of four: the contact zone is closed from nothing in one go, so
/// the Newton iterations against refinement show whether the search and
/// the decisions settle independently of the mesh (issue 11 measured 11,
/// 23 and 56 iterations on Gmsh meshes of 27k to 130k unknowns, then 6 to
/// 11 on the disk generator's from 60 to 360 divisions; now 2 or 3). The
/// bench runs it up to 360 divisions (8-node: 270k unknowns); the tests
/// run 60 and 120.
pub fn hertz_one_increment(v: Variant) -> Outcome {
    let problem = load("hertz_plane_strain.toml", v, &[("dt = 0.25", "dt = 1.0")]);
    let run = run_scene(problem);
    let mesh = format!("{} {} div", v.element.keyword(), 60 * v.refine);
    Outcome::new("hertz, one increment", mesh, run)
}

/// Hertz pressed in one increment with mu_s = mu_d = 10 to uy = -0.03
/// (P = 1267 on the quarter): the contact zone closes from nothing and
/// nearly every node sticks (a few slide at the edges on the refined
/// meshes). Issue 11 found it bisecting twice (a node alternating between
/// open and contact): with mu = 10 a sticking node pulled off the target
/// and sent sliding first predicted ten times its pull along the target.
/// No closed form (the contact of a sticking cylinder is not Hertz's);
/// the contact conditions and the iteration demands are what it checks.
pub fn hertz_high_friction(v: Variant) -> Outcome {
    let edits = [
        ("mu_s = 0.0", "mu_s = 10.0\nmu_d = 10.0"),
        ("scale = -0.07", "scale = -0.03"),
        ("dt = 0.25", "dt = 1.0"),
    ];
    let problem = load("hertz_plane_strain.toml", v, &edits);
    let run = run_scene(problem);
    let mesh = format!("{} {} div", v.element.keyword(), 60 * v.refine);
    Outcome::new("hertz mu=10, one increment", mesh, run)
}

pub const CATTANEO: &str = "verification/cattaneo_mindlin.toml";

/// scenes/verification/cattaneo_mindlin.toml on the shipped mesh (80
/// divisions) or refined (`refined`: 120 divisions on
/// tests/data/cattaneo_block_120.msh, as tests/contact_cattaneo.rs), or
/// with 8-node elements on both bodies (`q8_block`: a block mesh written
/// by `scripts/cattaneo_block_mesh.py --q8`, its path). Closed form: the
/// stick zone at the last increment, |x| < c = a sqrt(1 - Q / (mu P))
/// (Johnson 7.2): its half-width against c and its centre against 0, each
/// within one contactor segment h.
///
/// Each edge is read as the midpoint between the last sticking node and the
/// first sliding one: under the nodal decisions a node sticks when its own
/// force is under capacity, so the edge lies between the two, and the
/// midpoint reads it to h/2. The rest of the bound is the solution's error
/// near the edge, where the traction's distance from capacity falls like
/// the square root of the distance to c, so that a small error in the shear
/// moves the edge by a good part of a segment. Width and centre are checked
/// apart because the finite model is not the half-spaces of the closed
/// form: the 40 x 20 block and the clamped half-disk carry a shear that is
/// not symmetric about the centre (the shear at mirror nodes differs by 7 %
/// of mu p at 0.85 c, measured on the 80- and 120-division meshes and under
/// the paper's decisions alike), which shifts the stick zone right of
/// centre, toward the pull: by 0.016 on the 120-division Q4 mesh (0.5 h)
/// and 0.012 on the 8-node one (0.6 h); the half-widths are 0.2 h to 0.5 h
/// from c.
pub fn cattaneo(refined: bool, q8_block: Option<&str>) -> Outcome {
    // The default decisions (the shipped scene keeps the paper's).
    let mut edits: Vec<(&str, String)> =
        vec![("decisions = \"paper\"", "decisions = \"nodal\"".into())];
    if refined {
        edits.push(("divisions = 80", "divisions = 120".into()));
        edits.push((
            "file = \"meshes/cattaneo_block.msh\"",
            "file = \"../../tests/data/cattaneo_block_120.msh\"".into(),
        ));
    }
    let v = if let Some(path) = q8_block {
        edits.push((
            "file = \"meshes/cattaneo_block.msh\"",
            format!("file = \"{path}\""),
        ));
        Variant::Q8_1X
    } else {
        Variant::Q4_1X
    };
    let edits: Vec<(&str, &str)> = edits.iter().map(|(a, b)| (*a, b.as_str())).collect();
    let problem = load(CATTANEO, v, &edits);
    let run = run_scene(problem);
    let mesh = format!(
        "{} {} div",
        v.element.keyword(),
        if refined { 120 } else { 80 }
    );
    let mut out = Outcome::new("cattaneo-mindlin", mesh, run);
    if out.run.failure.is_none() {
        cattaneo_checks(&mut out);
    }
    out
}

fn cattaneo_checks(out: &mut Outcome) {
    let problem = &out.run.problem;
    let step = out.run.last();
    let MaterialSpec::LinearElastic { e, nu } = problem.materials[0].spec else {
        panic!("the Cattaneo scene is linear elastic")
    };
    let (radius, mu) = (20.0, problem.contacts[0].mu_s);
    let r = reaction(step, "load");
    let (p, q) = (-r[1], r[0]);
    let e_star = e / (2.0 * (1.0 - nu * nu));
    let a = (4.0 * p * radius / (PI * e_star)).sqrt();
    let c = a * (1.0 - q / (mu * p)).max(0.0).sqrt();
    let xs: Vec<f64> = problem.contacts[0]
        .contactor
        .iter()
        .map(|&n| problem.mesh.nodes[n][0])
        .collect();
    let nodes = &pair(step, "interface").nodes;
    let closed: Vec<usize> = (0..xs.len())
        .filter(|&k| nodes.state[k] != NodeState::Open)
        .collect();
    if closed.len() < 3 {
        out.problems
            .push(format!("{} nodes in contact", closed.len()));
        return;
    }
    // The outermost closed nodes are not read (a node that closes at the
    // contact edge sticks by the rule for new contacts).
    let stick: Vec<usize> = closed[1..closed.len() - 1]
        .iter()
        .copied()
        .filter(|&k| nodes.state[k] == NodeState::Stick)
        .collect();
    if stick.is_empty() {
        out.problems.push("no sticking node".into());
        return;
    }
    let (first, last) = (stick[0], *stick.last().unwrap());
    if last - first + 1 != stick.len() {
        out.problems
            .push(format!("the sticking nodes are not one run: {stick:?}"));
    }
    // `first` and `last` are inner closed nodes, so their outer neighbours
    // are in contact; they are not sticking (the run ends there).
    let left = 0.5 * (xs[first] + xs[first - 1]);
    let right = 0.5 * (xs[last] + xs[last + 1]);
    let h = (xs[first] - xs[first - 1]).max(xs[last + 1] - xs[last]);
    out.checks.push(Check::absolute(
        "stick half-width",
        0.5 * (right - left),
        c,
        h,
    ));
    out.checks.push(Check::absolute(
        "stick zone centre",
        0.5 * (right + left),
        0.0,
        h,
    ));
    // The pair's reported zone lengths (current configuration, half a
    // segment per node: the same midpoint reading, so each edge within h):
    // the stick zone 2c, the two slip zones 2 (a - c).
    let p = pair(step, "interface");
    out.checks.push(Check::absolute(
        "stick length",
        p.stick_length,
        2.0 * c,
        2.0 * h,
    ));
    out.checks.push(Check::absolute(
        "slip length",
        p.slip_length,
        2.0 * (a - c),
        4.0 * h,
    ));
}

pub fn cattaneo_shipped(_: Variant) -> Outcome {
    cattaneo(false, None)
}
pub fn cattaneo_refined(_: Variant) -> Outcome {
    cattaneo(true, None)
}

// ---------------------------------------------------------------------------
// The registry (the bench)
// ---------------------------------------------------------------------------

/// A case and the variants it runs in the bench.
pub struct Case {
    pub name: &'static str,
    pub run: fn(Variant) -> Outcome,
    pub variants: &'static [Variant],
}

const ALL: &[Variant] = &Variant::BENCH;
const ONE: &[Variant] = &[Variant::Q4_1X];
/// Hertz: 8-node meshes refined twice have 120000 unknowns.
const HERTZ: &[Variant] = &[
    Variant::Q4_1X,
    Variant::Q4_2X,
    Variant::Q4_4X,
    Variant::Q8_1X,
    Variant::Q8_2X,
];

/// Hertz in one increment: 60 to 360 divisions.
const HERTZ_ONE: &[Variant] = &[
    Variant::Q4_1X,
    Variant::Q4_2X,
    Variant::Q4_4X,
    Variant::new(Element::Q4, 6),
    Variant::Q8_1X,
    Variant::Q8_2X,
    Variant::Q8_4X,
    Variant::new(Element::Q8, 6),
];

pub fn cases() -> Vec<Case> {
    let case = |name, run, variants| Case {
        name,
        run,
        variants,
    };
    vec![
        case(
            "capstan_half_wrap",
            capstan_half_wrap as fn(Variant) -> Outcome,
            ALL,
        ),
        case("capstan_quarter_wrap", capstan_quarter_wrap, ALL),
        case(
            "capstan_half_wrap_frictionless",
            capstan_half_wrap_frictionless,
            ALL,
        ),
        case(
            "capstan_quarter_wrap_frictionless",
            capstan_quarter_wrap_frictionless,
            ALL,
        ),
        case("shrink_fit_frictionless", shrink_fit_frictionless, ALL),
        case("shrink_fit_with_friction", shrink_fit_with_friction, ALL),
        case(
            "shrink_fit_nonmatching_frictionless",
            shrink_fit_nonmatching_frictionless,
            ALL,
        ),
        case(
            "shrink_fit_nonmatching_with_friction",
            shrink_fit_nonmatching_with_friction,
            ALL,
        ),
        case("moving_plane", moving_plane, ALL),
        case("incline", incline, ALL),
        case("block_held", block_held, ALL),
        case("block_tiny", block_tiny, ALL),
        case("block_large", block_large, ALL),
        case("block_reversal", block_reversal, ALL),
        case("block_lift_off", block_lift_off, ALL),
        case("capstan_held", capstan_held, ALL),
        case("capstan_tiny", capstan_tiny, ALL),
        case("capstan_large", capstan_large, ALL),
        case("capstan_reversal", capstan_reversal, ALL),
        case("rubber_sheet", rubber_sheet, ALL),
        case("hertz_friction", hertz_friction, HERTZ),
        case("hertz_one_increment", hertz_one_increment, HERTZ_ONE),
        case("hertz_high_friction", hertz_high_friction, HERTZ_ONE),
        case("cattaneo_shipped", cattaneo_shipped, ONE),
        case("cattaneo_refined", cattaneo_refined, ONE),
    ]
}
