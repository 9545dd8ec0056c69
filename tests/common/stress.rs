//! The contact stress suite (issue 11): scene variants generated from one
//! TOML per family (the element of every body, the mesh refined), runs of a
//! scene's load history or of FMU-like inputs through the `Solver` API, the
//! contact conditions checked after every converged increment, and the
//! assertions and table row shared by `tests/stress.rs` and
//! `benches/stress.rs`. The families themselves are in `stress/families.rs`.
//!
//! Sign conventions used here (src/results.rs, docs/contact.md section 8
//! item 5): a contactor node's `tn` is positive in compression; its `tt` is
//! the tangential traction the target exerts on it, positive from the node
//! toward the next contactor node; x, y are its current coordinates.

use contact2d::newton::Solver;
use contact2d::problem::{Problem, Target};
use contact2d::results::{LogCategory, NodeState, StepResult};
use std::fmt::Write as _;
use std::time::Instant;

pub mod families;

/// Newton iterations per increment allowed by issue 11: the median over a
/// run's increments and the largest.
pub const MEDIAN_ITERATIONS: f64 = 5.0;
pub const MAX_ITERATIONS: usize = 15;

/// A contact node in tension beyond this fraction of the largest normal
/// traction of its pair is a violation. The solver releases a node whose
/// contact force is in tension by more than 1e-8 of its pair's largest
/// (TENSION_TOLERANCE in src/contact/pairs.rs), and the converged
/// out-of-balance forces, which are the contact forces, carry the Newton
/// force tolerance (1e-8 of the first residual): below that the sign of a
/// node's force is round-off.
pub const TENSION_TOLERANCE: f64 = 1e-8;
/// A tangential traction below this fraction of the pair's largest normal
/// traction has no sign (round-off of the recovered forces; a frictionless
/// pair reports 1e-16 of it, tests/contact_scenes.rs).
pub const FRICTION_ROUND_OFF: f64 = 1e-8;
/// A slip over an increment below this fraction of the largest motion of the
/// pair's contactor nodes over the increment has no sign: the displacements
/// converge to 1e-8 of the first correction (the displacement tolerance),
/// and 1e-6 leaves two orders for how that error spreads to one node.
pub const SLIP_ROUND_OFF: f64 = 1e-6;
/// ... and below this fraction of the contactor's extent (coordinates are
/// subtracted: round-off of positions when nothing moves).
pub const POSITION_ROUND_OFF: f64 = 1e-10;

// ---------------------------------------------------------------------------
// Variants
// ---------------------------------------------------------------------------

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Element {
    Q4,
    Q8,
}

impl Element {
    pub fn keyword(self) -> &'static str {
        match self {
            Element::Q4 => "q4",
            Element::Q8 => "q8",
        }
    }
}

/// One variant of a family's scene: the element of every body and the
/// factor its `divisions` are multiplied by.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Variant {
    pub element: Element,
    pub refine: usize,
}

impl Variant {
    pub const Q4_1X: Variant = Variant::new(Element::Q4, 1);
    pub const Q4_2X: Variant = Variant::new(Element::Q4, 2);
    pub const Q4_4X: Variant = Variant::new(Element::Q4, 4);
    pub const Q8_1X: Variant = Variant::new(Element::Q8, 1);
    pub const Q8_2X: Variant = Variant::new(Element::Q8, 2);
    pub const Q8_4X: Variant = Variant::new(Element::Q8, 4);
    /// The tests' variants: both elements, base mesh and refined once.
    pub const TESTS: [Variant; 4] = [Self::Q4_1X, Self::Q4_2X, Self::Q8_1X, Self::Q8_2X];
    /// The bench adds the meshes refined twice.
    pub const BENCH: [Variant; 6] = [
        Self::Q4_1X,
        Self::Q4_2X,
        Self::Q4_4X,
        Self::Q8_1X,
        Self::Q8_2X,
        Self::Q8_4X,
    ];

    pub const fn new(element: Element, refine: usize) -> Variant {
        Variant { element, refine }
    }

    pub fn label(&self) -> String {
        format!("{} {}x", self.element.keyword(), self.refine)
    }
}

/// `text` with every `element = "q4"` / `element = "q8"` set to the
/// variant's element and every `divisions = n` or `divisions = [n, m]`
/// multiplied by its refinement (comments included; an entry that is not
/// a list of integers is left as it is).
pub fn variant_text(text: &str, v: Variant) -> String {
    let element = format!("element = \"{}\"", v.element.keyword());
    let text = text
        .replace("element = \"q4\"", &element)
        .replace("element = \"q8\"", &element);
    if v.refine == 1 {
        return text;
    }
    let key = "divisions";
    let mut out = String::with_capacity(text.len());
    let mut rest = text.as_str();
    while let Some(i) = rest.find(key) {
        let (head, tail) = rest.split_at(i + key.len());
        out.push_str(head);
        rest = tail;
        let Some(value) = tail.trim_start().strip_prefix('=') else {
            continue;
        };
        let value = value.trim_start();
        let gap = tail.len() - value.len();
        let (numbers, len, list) = if let Some(inner) = value.strip_prefix('[') {
            let Some(end) = inner.find(']') else { continue };
            (&inner[..end], end + 2, true)
        } else {
            let end = value
                .find(|c: char| !c.is_ascii_digit())
                .unwrap_or(value.len());
            (&value[..end], end, false)
        };
        let parsed: Result<Vec<usize>, _> = numbers
            .split(',')
            .map(|s| s.trim().parse::<usize>())
            .collect();
        let Ok(parsed) = parsed else { continue };
        let scaled: Vec<String> = parsed.iter().map(|n| (n * v.refine).to_string()).collect();
        out.push_str(&tail[..gap]);
        if list {
            write!(out, "[{}]", scaled.join(", ")).unwrap();
        } else {
            out.push_str(&scaled[0]);
        }
        rest = &value[len..];
    }
    out.push_str(rest);
    out
}

/// The scene `name` (a path under scenes/) with each `(old, new)` replaced
/// once (each must occur), then made into variant `v`.
pub fn load(name: &str, v: Variant, edits: &[(&str, &str)]) -> Problem {
    let (text, path) = super::scene_text(name, edits);
    let text = variant_text(&text, v);
    contact2d::scene::parse(&text, &path).unwrap_or_else(|e| panic!("{name} {}: {e}", v.label()))
}

// ---------------------------------------------------------------------------
// Converged states and the contact conditions
// ---------------------------------------------------------------------------

/// A converged increment with what the contact conditions need beside the
/// results: the displacements and the rigid targets' poses.
#[derive(Clone, Debug)]
pub struct Frame {
    pub step: StepResult,
    pub u: Vec<f64>,
    /// [ux, uy, theta] per rigid target (`Solver::state().rigid`).
    pub rigid: Vec<[f64; 3]>,
}

impl Frame {
    /// The solver's problem before its first increment.
    pub fn at_rest(solver: &Solver) -> Frame {
        let s = solver.state();
        Frame {
            step: contact2d::contact::outputs::rest_step(solver.problem(), s.time, &s.u),
            u: s.u.clone(),
            rigid: s.rigid.clone(),
        }
    }

    /// The solver's state after the increment that gave `step`.
    pub fn now(solver: &Solver, step: StepResult) -> Frame {
        let s = solver.state();
        Frame {
            step,
            u: s.u.clone(),
            rigid: s.rigid.clone(),
        }
    }

    pub fn position(&self, problem: &Problem, node: usize) -> [f64; 2] {
        let x = problem.mesh.nodes[node];
        [x[0] + self.u[2 * node], x[1] + self.u[2 * node + 1]]
    }
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

fn rotate(v: [f64; 2], theta: f64) -> [f64; 2] {
    let (s, c) = theta.sin_cos();
    [c * v[0] - s * v[1], s * v[0] + c * v[1]]
}

/// Where the target material point that lay under contactor node position
/// `x_prev` in frame `prev` is in frame `cur`: for a rigid target, `x_prev`
/// carried by the rigid motion between the two poses; for a body target,
/// the nearest point of its surface in `prev` (segment and parameter),
/// moved with the segment's ends.
fn target_point(
    problem: &Problem,
    target: &Target,
    prev: &Frame,
    cur: &Frame,
    x_prev: [f64; 2],
) -> [f64; 2] {
    match target {
        Target::Rigid(r) => {
            let reference = problem.rigids[*r].reference;
            let [ux0, uy0, th0] = prev.rigid[*r];
            let [ux1, uy1, th1] = cur.rigid[*r];
            // Back to the rigid's own (reference) frame, then forward.
            let local = rotate(sub(x_prev, [reference[0] + ux0, reference[1] + uy0]), -th0);
            let moved = rotate(local, th1);
            [reference[0] + ux1 + moved[0], reference[1] + uy1 + moved[1]]
        }
        Target::Body { segments, .. } => {
            let mut best = (f64::INFINITY, [0.0; 2]);
            for &[a, b] in segments {
                let (pa, pb) = (prev.position(problem, a), prev.position(problem, b));
                let ab = sub(pb, pa);
                let beta = (dot(sub(x_prev, pa), ab) / dot(ab, ab)).clamp(0.0, 1.0);
                let foot = [pa[0] + beta * ab[0], pa[1] + beta * ab[1]];
                let d = sub(x_prev, foot);
                let dist = dot(d, d);
                if dist < best.0 {
                    let (ca, cb) = (cur.position(problem, a), cur.position(problem, b));
                    best = (
                        dist,
                        [
                            (1.0 - beta) * ca[0] + beta * cb[0],
                            (1.0 - beta) * ca[1] + beta * cb[1],
                        ],
                    );
                }
            }
            best.1
        }
    }
}

/// The contact conditions of a converged increment `prev -> cur`, for every
/// pair:
///
/// - no node in contact (stick or slip) with a normal traction in tension
///   beyond `TENSION_TOLERANCE` of the pair's largest `tn`;
/// - no sliding node whose friction does work along its slip: its `tt` and
///   its slip over the increment relative to the target's material point
///   (the target's motion taken out: rigid poses, or the target body's
///   surface) along the contactor must not have the same sign, beyond
///   `FRICTION_ROUND_OFF` (traction) and `SLIP_ROUND_OFF` /
///   `POSITION_ROUND_OFF` (slip). Only nodes in contact in both frames:
///   a node that touched during the increment has no material point of
///   the target to slip from.
///
/// Returns every violation, one line each. From any test:
///
/// ```ignore
/// let mut prev = Frame::at_rest(&solver);
/// for t in times {
///     let step = solver.advance(t, &mut |_, _| {})?;
///     let cur = Frame::now(&solver, step);
///     check_contact_conditions(solver.problem(), &prev, &cur)?;
///     prev = cur;
/// }
/// ```
pub fn check_contact_conditions(
    problem: &Problem,
    prev: &Frame,
    cur: &Frame,
) -> Result<(), String> {
    let mut out = Vec::new();
    for (p, pair) in problem.contacts.iter().enumerate() {
        let (name, now) = (&cur.step.pairs[p].0, &cur.step.pairs[p].1);
        let before = &prev.step.pairs[p].1;
        let n = &now.nodes;
        let m = n.x.len();
        let tn_max = n.tn.iter().copied().fold(0.0f64, f64::max);
        // Tension: on the nodes' normal contact forces, the multipliers the
        // conditions hold on (an 8-node side's reported traction is a
        // quadratic fit of them, which may dip below zero between positive
        // forces at the edge of the contact).
        let pn_max = n.pn.iter().copied().fold(0.0f64, f64::max);
        for k in 0..m {
            if n.state[k] != NodeState::Open && n.pn[k] < -TENSION_TOLERANCE * pn_max {
                // The neighbours' tractions tell an oscillation of the
                // recovery (alternating signs) from a node pulled off.
                let around: Vec<String> = (k.saturating_sub(1)..(k + 2).min(m))
                    .map(|j| format!("{:.3e}", n.tn[j]))
                    .collect();
                out.push(format!(
                    "t = {}: pair {name} node {k} (mesh {}) is {:?} in tension: p_n = {:.3e} \
                     (largest {:.3e}), tn = {:.3e} (largest tn {:.3e}; tn of nodes {}..={}: {})",
                    cur.step.time,
                    pair.contactor[k],
                    n.state[k],
                    n.pn[k],
                    pn_max,
                    n.tn[k],
                    tn_max,
                    k.saturating_sub(1),
                    (k + 1).min(m - 1),
                    around.join(", ")
                ));
            }
        }
        // Friction against slip (a frictionless pair has none: its
        // reported tt is the recovery's, e.g. 1e-3 of tn on 8-node sides
        // against a curved rigid target).
        if pn_max <= 0.0 || (pair.mu_s == 0.0 && pair.mu_d == 0.0) {
            continue;
        }
        let position = |f: &Frame, k: usize| f.position(problem, pair.contactor[k]);
        let motion = (0..m)
            .map(|k| {
                let d = sub(position(cur, k), position(prev, k));
                dot(d, d).sqrt()
            })
            .fold(0.0f64, f64::max);
        let (lo, hi) = (0..m).fold(
            ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
            |(lo, hi), k| {
                let x = position(cur, k);
                (
                    [lo[0].min(x[0]), lo[1].min(x[1])],
                    [hi[0].max(x[0]), hi[1].max(x[1])],
                )
            },
        );
        let extent = (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
        let slip_tol = SLIP_ROUND_OFF * motion + POSITION_ROUND_OFF * extent;
        for k in 0..m {
            if n.state[k] != NodeState::Slip || before.nodes.state[k] == NodeState::Open {
                continue;
            }
            // The node's friction force (an 8-node side's reported tt is a
            // quadratic fit of these).
            let tt = n.pt[k];
            if tt.abs() <= FRICTION_ROUND_OFF * pn_max {
                continue;
            }
            // The contactor's direction at k: toward the next node.
            let (a, b) = match (k, pair.closed) {
                (0, false) => (0, 1),
                (k, false) if k == m - 1 => (m - 2, m - 1),
                (k, _) => ((k + m - 1) % m, (k + 1) % m),
            };
            let along = sub(position(cur, b), position(cur, a));
            let along = {
                let l = dot(along, along).sqrt();
                [along[0] / l, along[1] / l]
            };
            let carried = target_point(problem, &pair.target, prev, cur, position(prev, k));
            let slip = dot(sub(position(cur, k), carried), along);
            if slip.abs() > slip_tol && slip * tt > 0.0 {
                out.push(format!(
                    "t = {}: pair {name} node {k} (mesh {}) slides with its friction along its slip: \
                     friction force {tt:.3e} (p_n {:.3e}, tt {:.3e}), slip {slip:.3e} over the \
                     increment (round-off {slip_tol:.1e})",
                    cur.step.time, pair.contactor[k], n.pn[k], n.tt[k]
                ));
            }
        }
    }
    if out.is_empty() {
        Ok(())
    } else {
        Err(out.join("\n"))
    }
}

// ---------------------------------------------------------------------------
// Runs
// ---------------------------------------------------------------------------

/// The converged increments of a run (frame 0 is the state at rest), and
/// the first failure, where it stopped.
pub struct Run {
    pub problem: Problem,
    pub frames: Vec<Frame>,
    pub failure: Option<(f64, String)>,
    /// Warnings and errors the solver logged (bisections, failures).
    pub warnings: Vec<String>,
    /// Wall time of the `advance` calls.
    pub seconds: f64,
    pub dofs: usize,
}

impl Run {
    /// The converged increments' results.
    pub fn steps(&self) -> impl Iterator<Item = &StepResult> {
        self.frames[1..].iter().map(|f| &f.step)
    }

    pub fn last(&self) -> &StepResult {
        &self.frames.last().unwrap().step
    }

    /// The converged increment ending at t (within 1e-9).
    pub fn at(&self, t: f64) -> Option<&Frame> {
        self.frames[1..]
            .iter()
            .find(|f| (f.step.time - t).abs() <= 1e-9 * t.abs().max(1.0))
    }
}

/// Steps a solver and records a `Run`: the scene's own times, or inputs
/// set through the API between increments as the FMU does.
pub struct Stepper {
    pub solver: Solver,
    pub frames: Vec<Frame>,
    failure: Option<(f64, String)>,
    warnings: Vec<String>,
    seconds: f64,
}

impl Stepper {
    pub fn new(problem: Problem) -> Stepper {
        let solver = Solver::new(problem).unwrap_or_else(|e| panic!("{e}"));
        let frames = vec![Frame::at_rest(&solver)];
        Stepper {
            solver,
            frames,
            failure: None,
            warnings: Vec::new(),
            seconds: 0.0,
        }
    }

    pub fn failed(&self) -> bool {
        self.failure.is_some()
    }

    /// The time of the last converged increment.
    pub fn time(&self) -> f64 {
        self.solver.state().time
    }

    /// One increment to time t; nothing once a run has failed. Returns
    /// whether it converged.
    pub fn advance(&mut self, t: f64) -> bool {
        if self.failed() {
            return false;
        }
        let warnings = &mut self.warnings;
        let start = Instant::now();
        let r = self.solver.advance(t, &mut |c, m| {
            if matches!(c, LogCategory::Warning | LogCategory::Error) {
                warnings.push(format!("{}: {m}", c.fmi_name()));
            }
        });
        self.seconds += start.elapsed().as_secs_f64();
        match r {
            Ok(step) => {
                self.frames.push(Frame::now(&self.solver, step));
                true
            }
            Err(e) => {
                self.failure = Some((t, e.to_string()));
                false
            }
        }
    }

    /// Every increment of the problem's own load history.
    pub fn scene_times(&mut self) {
        for t in self.solver.problem().times.clone() {
            if !self.advance(t) {
                break;
            }
        }
    }

    fn driver(&self, name: &str) -> usize {
        let p = self.solver.problem();
        p.drivers
            .iter()
            .position(|d| d.name == name)
            .unwrap_or_else(|| panic!("no driver {name}"))
    }

    /// Override driver `name`'s component (0: ux, 1: uy) for the next
    /// increments (`Solver::set_input`).
    pub fn set_input(&mut self, name: &str, component: usize, value: f64) {
        let d = self.driver(name);
        self.solver.set_input(d, component, Some(value));
    }

    /// Override rigid `name`'s pose component (0: ux, 1: uy, 2: theta).
    pub fn set_rigid_input(&mut self, name: &str, component: usize, value: f64) {
        let p = self.solver.problem();
        let r = p
            .rigids
            .iter()
            .position(|r| r.name == name)
            .unwrap_or_else(|| panic!("no rigid {name}"));
        self.solver.set_rigid_input(r, component, Some(value));
    }

    pub fn last(&self) -> &Frame {
        self.frames.last().unwrap()
    }

    pub fn finish(self) -> Run {
        let dofs = self.solver.dofs();
        Run {
            problem: self.solver.problem().clone(),
            frames: self.frames,
            failure: self.failure,
            warnings: self.warnings,
            seconds: self.seconds,
            dofs,
        }
    }
}

/// The problem solved over its own load history.
pub fn run_scene(problem: Problem) -> Run {
    let mut s = Stepper::new(problem);
    s.scene_times();
    s.finish()
}

// ---------------------------------------------------------------------------
// Results: helpers
// ---------------------------------------------------------------------------

/// A driver's or rigid's reaction [Rx, Ry] by name.
pub fn reaction(step: &StepResult, name: &str) -> [f64; 2] {
    let d = &step
        .drivers
        .iter()
        .find(|d| d.0 == name)
        .unwrap_or_else(|| panic!("no driver or rigid {name}"))
        .1;
    [d.rx, d.ry]
}

pub fn pair<'a>(step: &'a StepResult, name: &str) -> &'a contact2d::results::PairResult {
    &step
        .pairs
        .iter()
        .find(|p| p.0 == name)
        .unwrap_or_else(|| panic!("no pair {name}"))
        .1
}

pub fn median(values: &[usize]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let mut v = values.to_vec();
    v.sort_unstable();
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2] as f64
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2]) as f64
    }
}

// ---------------------------------------------------------------------------
// Outcomes: what a test asserts and what the bench prints
// ---------------------------------------------------------------------------

/// A computed value against its closed form, with the relative tolerance
/// the scene's header justifies (absolute when `absolute`).
#[derive(Clone, Debug)]
pub struct Check {
    pub what: String,
    pub computed: f64,
    pub reference: f64,
    pub tolerance: f64,
    pub absolute: bool,
}

impl Check {
    pub fn relative(
        what: impl Into<String>,
        computed: f64,
        reference: f64,
        tolerance: f64,
    ) -> Check {
        Check {
            what: what.into(),
            computed,
            reference,
            tolerance,
            absolute: false,
        }
    }

    pub fn absolute(
        what: impl Into<String>,
        computed: f64,
        reference: f64,
        tolerance: f64,
    ) -> Check {
        Check {
            absolute: true,
            ..Check::relative(what, computed, reference, tolerance)
        }
    }

    pub fn error(&self) -> f64 {
        if self.absolute {
            self.computed - self.reference
        } else {
            self.computed / self.reference - 1.0
        }
    }

    pub fn ok(&self) -> bool {
        self.error().abs() <= self.tolerance
    }
}

impl std::fmt::Display for Check {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(
            f,
            "{}: {:.6} vs {:.6}, {} error {:+.2e} (tolerance {:.1e})",
            self.what,
            self.computed,
            self.reference,
            if self.absolute {
                "absolute"
            } else {
                "relative"
            },
            self.error(),
            self.tolerance
        )
    }
}

/// One scene variant's run with its checks.
pub struct Outcome {
    pub case: String,
    pub mesh: String,
    pub run: Run,
    pub checks: Vec<Check>,
    /// Findings of the family's own assertions (held inputs, states).
    pub problems: Vec<String>,
    /// Bisections are allowed, and why.
    pub bisections_allowed: Option<&'static str>,
    /// The run is expected to stop with a failed increment, and why (an
    /// increment past a loss of static equilibrium); the family checks where.
    pub failure_expected: Option<&'static str>,
}

/// The figures of a run that the table prints.
pub struct Stats {
    pub increments: usize,
    pub median: f64,
    pub max: usize,
    /// Linear solves over the run, and the most in one increment (Newton
    /// iterations plus the inner solves of the linearised problem's
    /// contact states).
    pub solves: usize,
    pub max_solves: usize,
    /// Numeric factorizations over the run, and the most in one increment
    /// (an inner solve done with its iteration's factorization adds none).
    pub factorizations: usize,
    pub max_factorizations: usize,
    pub bisections: usize,
    pub failures: usize,
}

impl Outcome {
    pub fn new(case: impl Into<String>, mesh: impl Into<String>, run: Run) -> Outcome {
        Outcome {
            case: case.into(),
            mesh: mesh.into(),
            run,
            checks: Vec::new(),
            problems: Vec::new(),
            bisections_allowed: None,
            failure_expected: None,
        }
    }

    pub fn stats(&self) -> Stats {
        let iterations: Vec<usize> = self.run.steps().map(|s| s.iterations).collect();
        Stats {
            increments: iterations.len(),
            median: median(&iterations),
            max: iterations.iter().copied().max().unwrap_or(0),
            solves: self.run.steps().map(|s| s.solves).sum(),
            max_solves: self.run.steps().map(|s| s.solves).max().unwrap_or(0),
            factorizations: self.run.steps().map(|s| s.factorizations).sum(),
            max_factorizations: (self.run.steps())
                .map(|s| s.factorizations)
                .max()
                .unwrap_or(0),
            bisections: self.run.steps().map(|s| s.substeps).sum(),
            failures: usize::from(self.run.failure.is_some()),
        }
    }

    /// Contact-condition violations over the run's converged increments.
    pub fn violations(&self) -> Vec<String> {
        self.run
            .frames
            .windows(2)
            .filter_map(|w| check_contact_conditions(&self.run.problem, &w[0], &w[1]).err())
            .collect()
    }

    /// Everything that is not as issue 11 demands, one entry each.
    pub fn findings(&self) -> Vec<String> {
        let mut out = Vec::new();
        // The solver's message names the failed increment.
        if let Some((_, e)) = &self.run.failure
            && self.failure_expected.is_none()
        {
            out.push(e.clone());
        }
        if self.bisections_allowed.is_none() {
            for s in self.run.steps().filter(|s| s.substeps > 0) {
                out.push(format!(
                    "increment to t = {} bisected {} times",
                    s.time, s.substeps
                ));
            }
        }
        let st = self.stats();
        if st.median > MEDIAN_ITERATIONS {
            out.push(format!(
                "median Newton iterations per increment {} > {MEDIAN_ITERATIONS}",
                st.median
            ));
        }
        if st.max > MAX_ITERATIONS {
            let worst = self.run.steps().max_by_key(|s| s.iterations).unwrap();
            out.push(format!(
                "{} Newton iterations to t = {} (at most {MAX_ITERATIONS})",
                worst.iterations, worst.time
            ));
        }
        out.extend(
            self.violations()
                .iter()
                .flat_map(|v| v.lines().map(str::to_string)),
        );
        out.extend(
            self.checks
                .iter()
                .filter(|c| !c.ok())
                .map(|c| format!("closed form: {c}")),
        );
        out.extend(self.problems.iter().cloned());
        out
    }

    /// Print the row and the checks, then fail with every finding.
    pub fn assert(&self) {
        println!("{}", Self::header());
        println!("{}", self.row());
        for c in &self.checks {
            println!("  {c}");
        }
        if !self.run.warnings.is_empty() {
            println!(
                "  {} solver warnings, the first: {}",
                self.run.warnings.len(),
                self.run.warnings[0]
            );
        }
        let findings = self.findings();
        assert!(
            findings.is_empty(),
            "{} ({}): {} finding(s):\n{}",
            self.case,
            self.mesh,
            findings.len(),
            findings.join("\n")
        );
    }

    pub fn header() -> String {
        format!(
            "{:<34} {:<12} {:>6} {:>5} {:>7} {:>4} {:>4} {:>4} {:>4} {:>5} {:>8}  check: computed / reference (rel. error, tolerance)",
            "case", "mesh", "dofs", "incr", "it med", "max", "slv", "fac", "bis", "fail", "wall s"
        )
    }

    pub fn row(&self) -> String {
        let st = self.stats();
        let mut row = format!(
            "{:<34} {:<12} {:>6} {:>5} {:>7.1} {:>4} {:>4} {:>4} {:>4} {:>5} {:>8.3}",
            self.case,
            self.mesh,
            self.run.dofs,
            st.increments,
            st.median,
            st.max,
            st.max_solves,
            st.max_factorizations,
            st.bisections,
            match &self.run.failure {
                None => "0".to_string(),
                Some((t, _)) => format!("1@{t}"),
            },
            self.run.seconds
        );
        if self.checks.is_empty() {
            row.push_str("  -");
        }
        for c in &self.checks {
            write!(
                row,
                "  {}: {:.5} / {:.5} ({:+.1e}, {:.0e}){}",
                c.what,
                c.computed,
                c.reference,
                c.error(),
                c.tolerance,
                if c.ok() { "" } else { " FAIL" }
            )
            .unwrap();
        }
        row
    }
}
