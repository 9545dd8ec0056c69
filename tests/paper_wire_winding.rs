//! The snapped wire of the paper's Section 4.3 (scenes/wire_winding.toml):
//! the intact wound state in the first step, the snap at x = 0 in the next
//! two; the axial stress near the break against the friction shear-lag
//! estimate, the stick/slip zones, and the stresses far from the break
//! against the same scene left intact.

mod common;

use contact2d::newton::Solver;
use contact2d::results::{NodeState, PairNodes};

const SCENE: &str = "wire_winding.toml";
/// The scene's intact wound state, layer thickness, friction, modelled length.
const SIGMA0: f64 = 750.0;
const P: f64 = 300.0;
const H: f64 = 1.0;
const MU: f64 = 0.1;
const LENGTH: f64 = 40.0;
/// Element length along the interface (80 divisions of 40 mm).
const DX: f64 = 0.5;
/// The edit that keeps the wire intact: the x = 0 traction stays on.
const NO_SNAP: (&str, &str) = (
    "points = [[1.0, 1.0], [3.0, 0.0]]",
    "points = [[1.0, 1.0], [3.0, 1.0]]",
);

/// One converged step: element centres and stresses, the interface's nodes.
struct Step {
    time: f64,
    centre: Vec<[f64; 2]>,
    stress: Vec<[f64; 4]>,
    interface: PairNodes,
}

fn run(edits: &[(&str, &str)]) -> Vec<Step> {
    let problem = common::shipped_scene(SCENE, edits);
    let times = problem.times.clone();
    let mut solver = Solver::new(problem).unwrap();
    let mut steps = Vec::new();
    for &t in &times {
        let mut r = solver
            .advance(t, &mut |_, _| {})
            .unwrap_or_else(|e| panic!("{edits:?} at t = {t}: {e}"));
        let p = solver.problem();
        let centre = (p.mesh.elements.iter())
            .map(|e| {
                let n = e.nodes.len() as f64;
                let s = e.nodes.iter().fold([0.0; 2], |a, &k| {
                    [a[0] + p.mesh.nodes[k][0], a[1] + p.mesh.nodes[k][1]]
                });
                [s[0] / n, s[1] / n]
            })
            .collect();
        steps.push(Step {
            time: t,
            centre,
            stress: solver.element_stresses(),
            interface: r.pairs.remove(0).1.nodes,
        });
    }
    steps
}

/// Columns of the layer's elements (y > 0; a foundation body lies below)
/// along x: (x of the centre, sigma_xx averaged through the thickness,
/// sigma_xx of the element on the interface).
fn columns(s: &Step) -> Vec<(f64, f64, f64)> {
    let mut cols: Vec<(f64, Vec<(f64, f64)>)> = Vec::new();
    let layer = (s.centre.iter().zip(&s.stress)).filter(|(c, _)| c[1] > 0.0);
    for (c, st) in layer {
        match cols.iter_mut().find(|(x, _)| (x - c[0]).abs() < 1e-9) {
            Some((_, v)) => v.push((c[1], st[0])),
            None => cols.push((c[0], vec![(c[1], st[0])])),
        }
    }
    cols.sort_by(|a, b| a.0.total_cmp(&b.0));
    cols.into_iter()
        .map(|(x, mut v)| {
            v.sort_by(|a, b| a.0.total_cmp(&b.0));
            let mean = v.iter().map(|e| e.1).sum::<f64>() / v.len() as f64;
            (x, mean, v[0].1)
        })
        .collect()
}

/// The shear-lag estimate of the thickness-mean sigma_xx once the break has
/// released `released` of the intact tension: with the interface sliding
/// next to the break, d(sigma_xx h)/dx = mu p, so sigma_xx rises linearly
/// from sigma0 - released at the break to sigma0 at the recovery length
/// released h / (mu p), and stays there.
fn shear_lag(x: f64, released: f64) -> f64 {
    SIGMA0 - released + (MU * P * x / H).min(released)
}

/// The end of the slip zone: x of the last sliding node counted from the
/// break, after checking that the states are slip ... slip, stick ... stick.
fn slip_zone_end(nodes: &PairNodes) -> f64 {
    let mut order: Vec<usize> = (0..nodes.x.len()).collect();
    order.sort_by(|&a, &b| nodes.x[a].total_cmp(&nodes.x[b]));
    let states: Vec<NodeState> = order.iter().map(|&i| nodes.state[i]).collect();
    assert!(
        states.iter().all(|s| *s != NodeState::Open),
        "the layer stays pressed on: {states:?}"
    );
    let slipping = states.iter().take_while(|s| **s == NodeState::Slip).count();
    assert!(
        states[slipping..].iter().all(|s| *s == NodeState::Stick),
        "one slip zone next to the break, stick beyond: {states:?}"
    );
    for &i in &order[..slipping] {
        // Coulomb: a sliding node carries mu t_n, pointing to the break
        // (the layer shortens away from it). Near the break the free end
        // disturbs t_n, and the segment-wise friction rule holds the
        // segment's total, not each node's, to mu F_n: 15 % of mu p.
        let (tn, tt) = (nodes.tn[i], nodes.tt[i]);
        assert!(tt < 0.0, "x = {}: t_t = {tt}", nodes.x[i]);
        assert!(
            (tt.abs() - MU * tn).abs() <= 0.15 * MU * P,
            "x = {}: t_t = {tt}, mu t_n = {}",
            nodes.x[i],
            MU * tn
        );
    }
    nodes.x[order[slipping - 1]]
}

/// The foundation made elastic: the rigid replaced by the intact winding
/// under the layer, 4 mm of it, prestressed like the layer, held by the
/// cylinder below (uy = 0) and by symmetry about the break (ux = 0 at
/// x = 0, where the paper's model is constrained for y < 0) and at the far
/// end. Its top lies 1e-8 mm above the layer's bottom, as the rigid did.
/// (Before the linear solver's refinement check, src/linsolve.rs, this
/// needed 1e-6: with 1e-8 the overlap left after the first correction, at
/// the round-off of the coordinates, stayed above Newton's 1e-8 |du1|.)
const ELASTIC_FOUNDATION: (&str, &str) = (
    r#"[[rigid]]
name = "cylinder"
points = [[41.0, 1.0e-8], [-1.0, 1.0e-8]]"#,
    r#"[[body]]
name = "winding"
material = "steel"
mesh = { generator = "rectangle", origin = [0.0, -3.99999999], size = [40.0, 4.0], divisions = [80, 8] }

[[initial_stress]]
body = "winding"
xx = 750.0
yy = -300.0

[[driver]]
name = "symmetry"
set = "winding.left"
ux = 0.0

[[driver]]
name = "winding_far_end"
set = "winding.right"
ux = 0.0

[[driver]]
name = "cylinder"
set = "winding.bottom"
uy = 0.0"#,
);
/// The layer on the winding below it: against a body the default is
/// mortar (its contactor node at the far end, held along the interface on
/// both bodies, lies on a symmetry plane and sticks with no friction,
/// docs/contact.md section 11).
const ON_WINDING: (&str, &str) = (r#"target = "cylinder""#, r#"target = "winding.top""#);

/// Least-squares line through the points: (slope, value at x = 0).
fn fit(points: &[(f64, f64)]) -> (f64, f64) {
    let n = points.len() as f64;
    let (sx, sy) = points
        .iter()
        .fold((0.0, 0.0), |a, p| (a.0 + p.0, a.1 + p.1));
    let (mx, my) = (sx / n, sy / n);
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let slope = sxy / sxx;
    (slope, my - slope * mx)
}

/// The build-up fitted by least squares over the slip zone's columns
/// between 2 h from the break and 2 h before `until`: (slope, value at the
/// break), asserted to be mu p / h and what the break left (sigma0 -
/// released), 1 % each.
fn build_up(cols: &[(f64, f64, f64)], until: f64, released: f64, t: f64) -> (f64, f64) {
    let inner: Vec<(f64, f64)> = (cols.iter())
        .filter(|c| c.0 > 2.0 * H && c.0 < until - 2.0 * H)
        .map(|c| (c.0, c.1))
        .collect();
    let (slope, at_break) = fit(&inner);
    eprintln!(
        "t = {t}: build-up {at_break:.3} + {slope:.4} x MPa (mu p / h = {})",
        MU * P / H
    );
    assert!(
        (slope / (MU * P / H) - 1.0).abs() < 0.01,
        "t = {t}: slope {slope}"
    );
    assert!(
        (at_break - (SIGMA0 - released)).abs() < 0.01 * released,
        "t = {t}: {at_break} at the break"
    );
    (slope, at_break)
}

#[test]
fn snapped_wire_recovers_its_tension_by_friction() {
    let snapped = run(&[]);
    let intact = run(&[NO_SNAP]);
    assert_eq!(snapped.len(), 3);

    // Step 1 is the intact wound state: no displacement, so the stresses are
    // the initial ones, in every element and in both runs; every node sticks.
    // Tolerance 1e-5 sigma0 (7.5e-3 MPa): the rigid's 1e-8 mm overlap is
    // pushed out, a strain of ~1e-8 over the layer.
    let wound = |st: &[f64; 4]| {
        (st[0] - SIGMA0)
            .abs()
            .max((st[1] + P).abs())
            .max(st[3].abs())
    };
    for run in [&snapped, &intact] {
        for st in &run[0].stress {
            assert!(wound(st) < 1e-5 * SIGMA0, "step 1: {st:?}");
        }
        assert!(
            run[0]
                .interface
                .state
                .iter()
                .all(|s| *s == NodeState::Stick)
        );
    }
    // The intact run stays there.
    for st in &intact[2].stress {
        assert!(wound(st) < 1e-5 * SIGMA0, "intact, t = 3: {st:?}");
    }

    // t = 2 releases half the tension at the break, t = 3 all of it.
    for (step, released) in [(&snapped[1], SIGMA0 / 2.0), (&snapped[2], SIGMA0)] {
        let recovery = released * H / (MU * P);
        let cols = columns(step);
        let t = step.time;

        // The slip zone ends short of the recovery length by at most one
        // thickness plus one node spacing: at the stick zone's edge the
        // layer's elastic shear lag hands part of the load to the first
        // sticking nodes (their t_t decays over about a thickness), and the
        // transition falls between nodes.
        let end = slip_zone_end(&step.interface);
        eprintln!("t = {t}: slip zone ends at x = {end}, estimate {recovery}");
        assert!(
            end <= recovery && end >= recovery - H - DX,
            "t = {t}: {end} vs {recovery}"
        );

        // The thickness-mean sigma_xx follows the estimate. Within 2 h of the
        // break the free end's 2D stress field is not a bar's; within 2 h of
        // the slip zone's end the kink of the estimate is smoothed by the
        // layer's shear lag. Elsewhere: 1 % of sigma0 (the element average
        // of a linear field is its value at the centre, so what is left is
        // the discretised friction).
        let mut worst: f64 = 0.0;
        for &(x, mean, _) in &cols {
            if x < 2.0 * H || (x - recovery).abs() < 2.0 * H {
                continue;
            }
            let err = (mean - shear_lag(x, released)).abs();
            worst = worst.max(err);
            assert!(
                err <= 0.01 * SIGMA0,
                "t = {t}, x = {x}: sigma_xx = {mean}, shear lag {}",
                shear_lag(x, released)
            );
        }
        eprintln!("t = {t}: worst |mean sigma_xx - shear lag| = {worst:.3} MPa");

        // The build-up fitted by least squares over the middle of the slip
        // zone: slope mu p / h, at the break what the break left (0 at
        // t = 3), and it reaches the intact stress at the recovery length;
        // 1 % each.
        let (slope, at_break) = build_up(&cols, recovery, released, t);
        let reached = (SIGMA0 - at_break) / slope;
        eprintln!("t = {t}: back to the intact stress at x = {reached:.3}");
        assert!(
            (reached / recovery - 1.0).abs() < 0.01,
            "t = {t}: {reached}"
        );

        // Just below the contact surface the interface row carries the same
        // build-up: with the shear varying linearly through the thickness
        // dsigma_xx/dx = -dtau_xy/dy = mu p / h in every row, and the layer,
        // held between the top pressure and the base, does not bend. What is
        // left comes from the disturbed tractions next to the break (t_n is
        // 232 MPa at the corner node); measured 0.40 MPa, allowed 0.2 % of
        // sigma0 (1.5 MPa) over the same range.
        let mut offset: f64 = 0.0;
        for &(x, mean, bottom) in &cols {
            if x < 2.0 * H || (x - recovery).abs() < 2.0 * H {
                continue;
            }
            offset = offset.max((bottom - mean).abs());
            assert!(
                (bottom - mean).abs() <= 0.002 * SIGMA0,
                "t = {t}, x = {x}: interface row {bottom}, mean {mean}"
            );
        }
        eprintln!("t = {t}: interface row - thickness mean, largest {offset:.3} MPa");
    }

    // Far from the break (beyond the recovery length plus 3 h) the snapped
    // layer is back in the intact state: every stress component within
    // 0.2 % of sigma0 (1.5 MPa) of the intact run's. What is left there is
    // the layer's elastic shear lag behind the stick zone's edge, which
    // decays over about a thickness (measured 0.59 MPa at 3 h).
    let far = SIGMA0 * H / (MU * P) + 3.0 * H;
    let mut worst: f64 = 0.0;
    for ((c, s), i) in (snapped[2].centre.iter())
        .zip(&snapped[2].stress)
        .zip(&intact[2].stress)
    {
        if c[0] > far {
            let err = (0..4).map(|k| (s[k] - i[k]).abs()).fold(0.0, f64::max);
            worst = worst.max(err);
            assert!(err <= 0.002 * SIGMA0, "x = {:?}: {s:?} vs intact {i:?}", c);
        }
    }
    eprintln!("x > {far}: worst stress difference from the intact run {worst:.4} MPa");
    assert!(far < LENGTH - 5.0 * H, "the model is long enough to see it");
}

/// The build-up in the slip zone is equilibrium alone: on an elastic
/// foundation it has the same slope mu p / h as on the rigid one; only the
/// stick zone changes (the foundation yields under the released load, so
/// the slip zone is shorter and the transition smoother).
#[test]
fn build_up_does_not_depend_on_the_foundation() {
    let steps = run(&[ELASTIC_FOUNDATION, ON_WINDING]);
    let rigid = run(&[]);
    for (i, released) in [(1, SIGMA0 / 2.0), (2, SIGMA0)] {
        let t = steps[i].time;
        let end = slip_zone_end(&steps[i].interface);
        let rigid_end = slip_zone_end(&rigid[i].interface);
        eprintln!("elastic foundation, t = {t}: slip zone ends at {end} (rigid: {rigid_end})");
        build_up(&columns(&steps[i]), end, released, t);
        // Measured 10.0 and 21.5 mm against 11.5 and 24.0 mm on the rigid
        // foundation: shorter by more than a node spacing.
        assert!(
            end < rigid_end - DX,
            "t = {t}: {end} vs {rigid_end} on the rigid"
        );
    }
}
