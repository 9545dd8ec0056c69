//! Cattaneo-Mindlin partial slip, scenes/verification/cattaneo_mindlin.toml:
//! a cylinder pressed onto a block of the same material, then pulled
//! sideways with the press held, against Johnson (Contact Mechanics, 7.2),
//! plane strain:
//!
//! - p(x) = p0 sqrt(1 - x^2/a^2), a = sqrt(4 P R / (pi E*)), p0 = 2 P / (pi a),
//!   1/E* = 2 (1 - nu^2) / E (two bodies of one material);
//! - q(x) = mu p(x) in the slip zones c <= |x| <= a, and
//!   q(x) = mu p(x) - (c/a) mu p0 sqrt(1 - x^2/c^2) in the stick zone |x| < c,
//!   c = a sqrt(1 - Q / (mu P)).
//!
//! P and Q are the loads the cylinder's top driver applies (-Ry, Rx), read
//! at each increment. x is each contactor node's reference abscissa: the
//! closed form is posed on the undeformed bodies (small strain), and the
//! stick zone moves with the cylinder (0.01 at the end), so current x would
//! show a spurious asymmetry of that size.
//!
//! The scene uses the lumped recovery, which reports at each node its
//! contact force over its tributary length: the mean of the traction
//! weighted by the node's hat function over its two segments. The closed
//! forms are compared in that same mean ([`hat_mean`]), so that what is
//! left is the solution's error, not the sampling of a curved profile.
//!
//! The same checks run on the shipped mesh and on a refined one (the
//! cylinder with 120 divisions instead of 80, on its matching block from
//! tests/data), with the same tolerances.
//!
//! Run with `cargo test --release --test contact_cattaneo -- --nocapture`
//! to see the measured numbers.

mod common;

use contact2d::newton::Solver;
use contact2d::problem::{Decisions, MaterialSpec, Problem, Target};
use contact2d::results::{NodeState, PairResult, StepResult};
use std::f64::consts::PI;

const SCENE: &str = "verification/cattaneo_mindlin.toml";
/// The cylinder's radius (the scene's disk generator).
const R: f64 = 20.0;
/// End of the press; the pull runs from here to the last increment.
const PULL_START: f64 = 1.0;
/// The refined variant: the cylinder's divisions and the block mesh that
/// matches them (`scripts/cattaneo_block_mesh.py --divisions 120`).
const REFINED: &[(&str, &str)] = &[
    ("divisions = 80", "divisions = 120"),
    (
        "file = \"meshes/cattaneo_block.msh\"",
        "file = \"../../tests/data/cattaneo_block_120.msh\"",
    ),
];

fn solve(edits: &[(&str, &str)]) -> (Problem, Vec<StepResult>) {
    let problem = common::shipped_scene(SCENE, edits);
    let times = problem.times.clone();
    let mut solver = Solver::new(problem.clone()).unwrap();
    let mut steps = Vec::new();
    for t in times {
        let r = solver
            .advance(t, &mut |_, _| {})
            .unwrap_or_else(|e| panic!("{SCENE} {edits:?} at t = {t}: {e}"));
        assert!(r.converged, "{SCENE} at t = {t}");
        steps.push(r);
    }
    (problem, steps)
}

fn pair(step: &StepResult) -> &PairResult {
    &step.pairs[0].1
}

/// The loads on the cylinder's top: P (downward) and Q (along +x).
fn loads(step: &StepResult) -> (f64, f64) {
    let d = &step.drivers.iter().find(|d| d.0 == "load").unwrap().1;
    (-d.ry, d.rx)
}

/// Reference x of the contactor nodes.
fn reference_x(problem: &Problem) -> Vec<f64> {
    problem.contacts[0]
        .contactor
        .iter()
        .map(|&n| problem.mesh.nodes[n][0])
        .collect()
}

/// Johnson's closed form at one load.
struct Closed {
    a: f64,
    p0: f64,
    c: f64,
    mu: f64,
}

impl Closed {
    fn new(problem: &Problem, p: f64, q: f64) -> Self {
        // One material for both bodies.
        assert_eq!(problem.materials.len(), 1);
        let MaterialSpec::LinearElastic { e, nu } = problem.materials[0].spec else {
            panic!("the Cattaneo scene is linear elastic")
        };
        let e_star = e / (2.0 * (1.0 - nu * nu));
        let a = (4.0 * p * R / (PI * e_star)).sqrt();
        let mu = problem.contacts[0].mu_s;
        Closed {
            a,
            p0: 2.0 * p / (PI * a),
            c: a * (1.0 - q / (mu * p)).max(0.0).sqrt(),
            mu,
        }
    }
    fn pressure(&self, x: f64) -> f64 {
        self.p0 * (1.0 - (x / self.a).powi(2)).max(0.0).sqrt()
    }
    fn shear(&self, x: f64) -> f64 {
        let mut q = self.mu * self.pressure(x);
        if x.abs() < self.c {
            q -= self.c / self.a * self.mu * self.p0 * (1.0 - (x / self.c).powi(2)).sqrt();
        }
        q
    }
}

/// The mean of f over [xl, xr] weighted by the hat function that is 1 at x
/// and 0 at xl and xr (midpoint rule, 400 points a side).
fn hat_mean(f: impl Fn(f64) -> f64, xl: f64, x: f64, xr: f64) -> f64 {
    let n = 400;
    let (mut num, mut den) = (0.0, 0.0);
    for (lo, hi, rising) in [(xl, x, true), (x, xr, false)] {
        let h = (hi - lo) / n as f64;
        for i in 0..n {
            let s = lo + (i as f64 + 0.5) * h;
            let w = if rising { s - lo } else { hi - s } / (hi - lo);
            num += f(s) * w * h;
            den += w * h;
        }
    }
    num / den
}

/// The contact edges' error bound for a traction that falls like sqrt(a - x)
/// on a segment of length h reaching past the edge: the largest gap between
/// p0 sqrt(2 s / a) and its chord on [0, h], p0 sqrt(2 h / a) / 4 (at
/// s = h / 4), relative to p0. Linear elements cannot follow the square
/// root on the segment that holds the edge, so both of its nodes are allowed
/// this much.
fn edge_bound(h: f64, a: f64) -> f64 {
    (2.0 * h / a).sqrt() / 4.0
}

/// A node in contact: its index, reference x, its neighbours' x, and the
/// length of its segment that holds a contact edge x = +-a, if one does.
struct ContactNode {
    k: usize,
    x: f64,
    xl: f64,
    xr: f64,
    edge: Option<f64>,
}

fn closed_nodes(xs: &[f64], pr: &PairResult, a: f64) -> Vec<ContactNode> {
    (1..xs.len() - 1)
        .filter(|&k| pr.nodes.state[k] != NodeState::Open)
        .map(|k| {
            let (xl, x, xr) = (xs[k - 1], xs[k], xs[k + 1]);
            let holds = |u: f64, v: f64| (u.abs() - a) * (v.abs() - a) <= 0.0;
            let edge = if holds(xl, x) {
                Some(x - xl)
            } else if holds(x, xr) {
                Some(xr - x)
            } else {
                None
            };
            ContactNode { k, x, xl, xr, edge }
        })
        .collect()
}

/// Every contactor node within |x| < 1.2 (the contact zone is |x| < 0.71)
/// has a block top node at its x: the mesh file and the disk generator agree
/// (scripts/cattaneo_block_mesh.py mirrors the generator).
fn check_meshes_match(problem: &Problem) {
    let Target::Body { segments, .. } = &problem.contacts[0].target else {
        panic!("a body target expected")
    };
    let targets: Vec<f64> = segments
        .iter()
        .flat_map(|s| s.iter().map(|&n| problem.mesh.nodes[n][0]))
        .collect();
    let xs = reference_x(problem);
    let near: Vec<f64> = xs.iter().copied().filter(|x| x.abs() < 1.2).collect();
    assert!(
        near.len() >= 40,
        "{} contactor nodes near the centre",
        near.len()
    );
    for x in near {
        let gap = targets
            .iter()
            .map(|t| (t - x).abs())
            .fold(f64::INFINITY, f64::min);
        assert!(
            gap < 1e-9,
            "contactor node at x = {x}: nearest target node {gap} away"
        );
    }
}

#[test]
fn meshes_match_in_the_contact_zone() {
    check_meshes_match(&common::shipped_scene(SCENE, &[]));
    check_meshes_match(&common::shipped_scene(SCENE, REFINED));
}

/// The stick zone read off the node states, on each side from the centre
/// out. The outermost node in contact on each side is not read: its state
/// is set by its segment toward the first open node, which carries that
/// node's traction alone, and a node that has just closed sticks by the
/// paper's rule whatever its force (on the refined mesh a node at
/// x = 0.711, beyond a = 0.702, closes at t = 1.25 with tn = 0.05 % of p0
/// and sticks). Among the other nodes the sticking ones must form one run;
/// c_left = -x of its first node, c_right = x of its last, each with the
/// longer of that node's two segments as the element size h. By Table 1 a
/// node sticks when one of its segments sticks, so a segment that holds
/// the stick-slip boundary (its friction below capacity) makes both of its
/// nodes stick, and the outermost sticking node may lie up to one segment
/// outside c; a segment whose mean friction reaches capacity slides, and
/// the node may lie up to one segment inside.
fn stick_zone(xs: &[f64], pr: &PairResult, nodal: bool) -> [(f64, f64); 2] {
    let closed: Vec<usize> = (0..xs.len())
        .filter(|&k| pr.nodes.state[k] != NodeState::Open)
        .collect();
    assert!(closed.len() >= 3, "{} nodes in contact", closed.len());
    let inner = &closed[1..closed.len() - 1];
    let stick: Vec<usize> = inner
        .iter()
        .copied()
        .filter(|&k| pr.nodes.state[k] == NodeState::Stick)
        .collect();
    assert!(!stick.is_empty(), "no sticking node");
    let (first, last) = (stick[0], *stick.last().unwrap());
    assert_eq!(
        last - first + 1,
        stick.len(),
        "the sticking nodes are not one run"
    );
    let h = |k: usize| (xs[k] - xs[k - 1]).max(xs[k + 1] - xs[k]);
    if nodal {
        // Nodal decisions: each node sticks or slides on its own traction,
        // the hat-weighted mean over its two segments, so the stick edge
        // lies between the outermost sticking node and its sliding
        // neighbour: read at their midpoint (as tests/stress.rs reads the
        // node-to-segment nodal decisions), within h of c.
        let left = 0.5 * (xs[first] + xs[first - 1]);
        let right = 0.5 * (xs[last] + xs[last + 1]);
        return [(-left, h(first)), (right, h(last))];
    }
    [(-xs[first], h(first)), (xs[last], h(last))]
}

/// Check the stick zone at every increment of the pull; returns the largest
/// |c_side - c| / h.
fn check_stick_zone(label: &str, problem: &Problem, steps: &[StepResult]) -> f64 {
    let xs = reference_x(problem);
    let nodal = problem.contacts[0].decisions == Decisions::Nodal;
    let mut worst: f64 = 0.0;
    for s in steps.iter().filter(|s| s.time > PULL_START + 1e-9) {
        let (p, q) = loads(s);
        let cf = Closed::new(problem, p, q);
        let [(cl, hl), (cr, hr)] = stick_zone(&xs, pair(s), nodal);
        println!(
            "{label} t = {:.3}: Q/(mu P) = {:.3}  c = {:.4}  c_left = {cl:.4} (h {hl:.4})  c_right = {cr:.4} (h {hr:.4})  stick/slip/open = {}/{}/{}",
            s.time,
            q / (cf.mu * p),
            cf.c,
            pair(s).n_stick,
            pair(s).n_slip,
            pair(s).n_open
        );
        for (side, c_side, h) in [("left", cl, hl), ("right", cr, hr)] {
            assert!(
                (c_side - cf.c).abs() <= h,
                "{label} t = {}: {side} stick edge at {c_side}, c = {}, h = {h}",
                s.time,
                cf.c
            );
            worst = worst.max((c_side - cf.c).abs() / h);
        }
    }
    worst
}

/// Solve the scene with `edits` and check it against Johnson (`matching`:
/// the meshes match in the contact zone).
fn verify(label: &str, edits: &[(&str, &str)], matching: bool) -> Vec<StepResult> {
    let (problem, steps) = solve(edits);
    let xs = reference_x(&problem);
    let pressed = steps
        .iter()
        .position(|s| (s.time - PULL_START).abs() < 1e-12)
        .unwrap();
    let (p_press, _) = loads(&steps[pressed]);

    // The normal load is held while Q grows: P changes by 0.01 % (measured)
    // through the pull with the top's vertical displacement fixed, as the
    // uncoupling of elastically similar bodies says (a rigid flat would
    // shift it). Bound 0.1 %.
    for s in &steps[pressed..] {
        let (p, _) = loads(s);
        assert!(
            ((p - p_press) / p_press).abs() < 1e-3,
            "{label} t = {}: P = {p}, {p_press} at the end of the press",
            s.time
        );
    }

    // Ft = Q. Fx, the sum of the nodal contact forces along x, balances the
    // top's Rx to round-off (equilibrium of the cylinder: 1e-9 Q). Ft sums
    // them along each node's own target segment, and those tilt, so Ft
    // takes a share of the pressure:
    // - the shear tilts the interface: on a half-space a tangential traction
    //   q gives the surface the slope (1 - 2 nu)(1 + nu) q / E (Johnson,
    //   Eq. 2.19b, plane strain), and with elastically similar bodies both
    //   surfaces tilt together; so Ft - Q = (1 - 2 nu)(1 + nu) / E
    //   * int p q dx, at most `tilt` = (1 - 2 nu)(1 + nu) / E * mu * int p^2
    //   dx = (1 - 2 nu)(1 + nu) mu (4/3) a p0^2 / E (q <= mu p): 2.7 N here;
    // - a contactor node on a target node (matching meshes) sits on a kink
    //   of the target and reports on one of its two segments: the offset
    //   |Ft| at Q = 0, the end of the press (0.80 N shipped, 0.48 N refined).
    // Bound: their sum. Measured: |Ft| - Q up to 0.87 N = 4.1e-4 P (shipped),
    // 1.29 N = 6.1e-4 P (refined), at the end (Q/(mu P) = 0.85). From Q = 0
    // to the end Ft + Q moves by -1.67 N (shipped) and -1.77 N (refined);
    // the tilt with Johnson's p and q predicts -2.25 N.
    let ft_offset = pair(&steps[pressed]).ft.abs();
    let MaterialSpec::LinearElastic { e, nu } = problem.materials[0].spec else {
        panic!("the Cattaneo scene is linear elastic")
    };
    for s in &steps[pressed + 1..] {
        let (p, q) = loads(s);
        let pr = pair(s);
        let cf = Closed::new(&problem, p, q);
        let tilt = (1.0 - 2.0 * nu) * (1.0 + nu) / e * cf.mu * 4.0 / 3.0 * cf.a * cf.p0 * cf.p0;
        assert!(
            (pr.fx + q).abs() <= 1e-9 * q,
            "{label} t = {}: Fx = {}, Q = {q}",
            s.time,
            pr.fx
        );
        assert!(
            (pr.ft.abs() - q).abs() <= tilt + ft_offset,
            "{label} t = {}: Ft = {}, Q = {q}; bound {tilt} + {ft_offset}",
            s.time,
            pr.ft
        );
        println!(
            "{label} t = {:.3}: P = {p:.2}  Q = {q:.2}  Fx = {:.2}  Ft = {:.2}  |Ft| - Q = {:.3} (bound {:.3})  (|Ft| - Q)/P = {:.2e}",
            s.time,
            pr.fx,
            pr.ft,
            pr.ft.abs() - q,
            tilt + ft_offset,
            (pr.ft.abs() - q) / p
        );
    }

    // The pressure against Hertz, at the end of the press and at the end of
    // the pull, in the hat-weighted mean. Interior nodes: within 1.5 % of
    // p0 (measured 0.9 % at most, RMS 0.5 % on both meshes: the finite
    // cylinder, a / R = 0.035, raises the centre by about 0.27 a / R = 1 %
    // against a rigid flat, and the block shares the indentation; the
    // refinement does not change it). The two nodes of the segment holding
    // each contact edge: within edge_bound (10.7 % of p0 on the shipped
    // mesh; measured 5 %).
    //
    // On non-matching meshes (mortar) the nodes are checked so at the end
    // of the press, and the interior nodes' RMS error there against 0.5 %
    // of p0, the accuracy of the rigid-target Hertz cases (RMS 0.3-0.5 %;
    // issue 33's measure for Cattaneo-Mindlin between two bodies). At the
    // end of the pull they are reported, not checked: the pull adds a
    // shift antisymmetric in x that both formulations show on matching
    // meshes too (the finite bodies bend: -0.7 % .. +0.7 % of p0 across
    // the zone), on top of the non-matching meshes' own error; the shear
    // check below holds the sliding nodes' pressure (tt = mu tn) to 3 %.
    let mut rms_report = Vec::new();
    for (i, s) in [&steps[pressed], steps.last().unwrap()]
        .into_iter()
        .enumerate()
    {
        let (p, q) = loads(s);
        let cf = Closed::new(&problem, p, q);
        let pr = pair(s);
        let (mut sum2, mut n, mut worst) = (0.0, 0, 0.0f64);
        for node in closed_nodes(&xs, pr, cf.a) {
            let want = hat_mean(|x| cf.pressure(x), node.xl, node.x, node.xr);
            let err = (pr.nodes.tn[node.k] - want) / cf.p0;
            let bound = node.edge.map_or(0.015, |h| edge_bound(h, cf.a));
            if node.edge.is_none() {
                worst = worst.max(err.abs());
            }
            if !matching && i == 1 {
                if node.edge.is_none() {
                    sum2 += err * err;
                    n += 1;
                }
                continue;
            }
            assert!(
                err.abs() <= bound,
                "{label} t = {}: x = {}: tn = {}, Hertz (hat mean) {want}: {:.2} % of p0 > {:.2} %",
                s.time,
                node.x,
                pr.nodes.tn[node.k],
                100.0 * err,
                100.0 * bound
            );
            if node.edge.is_none() {
                sum2 += err * err;
                n += 1;
            }
        }
        let rms = (sum2 / n as f64).sqrt();
        if !matching && i == 0 {
            assert!(
                rms <= 0.005,
                "{label} t = {}: pressure RMS error {:.2} % of p0 > 0.5 %",
                s.time,
                100.0 * rms
            );
        }
        rms_report.push((s.time, rms, worst, cf.a, cf.p0));
    }
    for (t, rms, worst, a, p0) in rms_report {
        println!(
            "{label} t = {t:.3}: a = {a:.4}, p0 = {p0:.1}; pressure RMS error (interior nodes) {:.2} % of p0, largest {:.2} %",
            100.0 * rms,
            100.0 * worst
        );
    }

    // The stick zone at every increment of the pull.
    let worst = check_stick_zone(label, &problem, &steps);
    let nodal = problem.contacts[0].decisions == Decisions::Nodal;
    println!("{label}: largest |c_side - c| / h = {worst:.2}");

    // The shear traction in the slip zones against q = mu p, in the
    // hat-weighted mean: every sliding node at every increment of the pull,
    // the friction acting against the pull (tt < 0 along +x). Interior
    // nodes within 3 % of mu p0 (measured 1.3 % shipped, 1.5 % refined: the
    // pressure error above, times mu, plus the uniform friction per segment
    // of Fig. 5 against the curved mu p); the two nodes of the segment
    // holding each contact edge within edge_bound (as for the pressure;
    // measured 4.7 % shipped, 3.8 % refined).
    let mut worst_interior: f64 = 0.0;
    let mut worst_edge: f64 = 0.0;
    let mut worst_stick: f64 = 0.0;
    let mut checked = 0;
    for s in steps.iter().filter(|s| s.time > PULL_START + 1e-9) {
        let (p, q) = loads(s);
        let cf = Closed::new(&problem, p, q);
        let pr = pair(s);
        for node in closed_nodes(&xs, pr, cf.a) {
            if pr.nodes.state[node.k] != NodeState::Slip {
                // Reported, not checked: the stick zone's shear away from
                // its edges (both segments within |x| < c).
                if node.xl > -cf.c && node.xr < cf.c {
                    let want = hat_mean(|x| cf.shear(x), node.xl, node.x, node.xr);
                    let err = (-pr.nodes.tt[node.k] - want) / (cf.mu * cf.p0);
                    worst_stick = worst_stick.max(err.abs());
                }
                continue;
            }
            let tt = pr.nodes.tt[node.k];
            assert!(
                tt < 0.0,
                "{label} t = {}: x = {}: tt = {tt}",
                s.time,
                node.x
            );
            let want = hat_mean(|x| cf.shear(x), node.xl, node.x, node.xr);
            let err = (-tt - want) / (cf.mu * cf.p0);
            // Under nodal decisions a sliding node carries mu times its own
            // pressure: where its segments reach into the stick zone
            // (|x| < c), Johnson's mean takes the stick zone's deficit
            // `mu p - q` over that part, which the node cannot: allowed
            // on top, its hat mean there (zero for a node whose segments
            // both slide).
            let deficit = if nodal {
                hat_mean(
                    |x| cf.mu * cf.pressure(x) - cf.shear(x),
                    node.xl,
                    node.x,
                    node.xr,
                ) / (cf.mu * cf.p0)
            } else {
                0.0
            };
            let bound = node.edge.map_or(0.03, |h| edge_bound(h, cf.a)) + deficit;
            assert!(
                err.abs() <= bound,
                "{label} t = {}: x = {}: -tt = {}, Johnson (hat mean) {want}: {:.2} % of mu p0 > {:.2} %",
                s.time,
                node.x,
                -tt,
                100.0 * err,
                100.0 * bound
            );
            // Reported beyond the stick zone's deficit.
            let beyond = err.abs() - deficit;
            if node.edge.is_some() {
                worst_edge = worst_edge.max(beyond);
            } else {
                worst_interior = worst_interior.max(beyond);
            }
            checked += 1;
        }
    }
    println!(
        "{label}: slip zones: {checked} node values; largest |q - Johnson| {:.2} % of mu p0 (interior), {:.2} % (edge segments), beyond the stick zone's deficit under nodal decisions",
        100.0 * worst_interior,
        100.0 * worst_edge
    );
    println!(
        "{label}: stick zones (not checked): largest |q - Johnson| {:.2} % of mu p0 at nodes with both segments inside |x| < c",
        100.0 * worst_stick
    );
    // At the end, Q/(mu P) = 0.86: slip zones 0.44 wide on both sides.
    let last = pair(steps.last().unwrap());
    for side in [-1.0, 1.0] {
        let n = (0..xs.len())
            .filter(|&k| last.nodes.state[k] == NodeState::Slip && xs[k] * side > 0.0)
            .count();
        assert!(
            n >= 7,
            "{label}: {n} sliding nodes on the {side} side at the end"
        );
    }
    steps
}

#[test]
fn shipped_mesh_against_johnson() {
    verify("shipped", &[], true);
}

#[test]
fn refined_mesh_against_johnson() {
    // The cylinder with 120 divisions instead of 80 (segments 0.026-0.043 in
    // the contact zone instead of 0.039-0.066), on its matching block.
    verify("refined", REFINED, true);
}

#[test]
fn consistent_recovery_finds_the_same_stick_zone() {
    // The paper's consistent recovery of Eq. (26): the same stick zone to
    // within one element at every increment of the pull (its nodal tractions
    // oscillate at the kinks, so q is checked with the lumped one only).
    let (problem, steps) = solve(&[("recovery = \"lumped\"", "recovery = \"consistent\"")]);
    let worst = check_stick_zone("consistent", &problem, &steps);
    println!("consistent: largest |c_side - c| / h = {worst:.2}");
}

/// Mortar contact (`formulation = "mortar"`, its own nodal decisions in
/// place of the paper's): the same checks and tolerances. A mortar node's
/// traction is the hat-weighted mean of the traction field (its dual-basis
/// multiplier: the node's force over the integral of its shape function),
/// the mean the checks compare in.
const MORTAR: (&str, &str) = ("decisions = \"paper\"", "formulation = \"mortar\"");

#[test]
fn mortar_against_johnson() {
    let steps = verify("mortar", &[MORTAR], true);
    // The linearised problem settles each node in one switch: at most two
    // solves per iteration in every increment (measured: 8 solves in the
    // first increment's 4 iterations, at most two per iteration in the
    // others).
    // A node kept in contact while the iterate settles though it pulls
    // slides on: when it stuck again, the press's six edge nodes switched
    // between stick and slip at every inner solve (11 solves in 4).
    for s in &steps {
        assert!(
            s.solves <= 2 * s.iterations,
            "t = {}: {} solves in {} iterations",
            s.time,
            s.solves,
            s.iterations
        );
    }
}

#[test]
fn mortar_fine_over_coarse_against_johnson() {
    // The cylinder of 120 divisions on the block that matches 80: in the
    // contact zone no contactor node lies on a target node but at the
    // centre.
    verify("mortar, fine over coarse", &[MORTAR, REFINED[0]], false);
}

#[test]
fn mortar_coarse_over_fine_against_johnson() {
    // The cylinder of 80 divisions on the block that matches 120.
    verify("mortar, coarse over fine", &[MORTAR, REFINED[1]], false);
}
