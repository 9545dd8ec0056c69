//! Checks of Section 3 against independent computations: consistent loads are integrated
//! here by 3-point Gauss quadrature (exact for the cubic integrands of a linear traction
//! times a linear radius), and reference recoveries are dense solves of the system of
//! Eqs. (26)/(27) assembled from the paper's formulas. Tolerances are relative to the
//! largest value compared.

use std::f64::consts::{PI, TAU};

use nalgebra::{DMatrix, DVector};

use super::*;

const TOL: f64 = 1e-12;
const H: f64 = 0.7;
const PLANAR: Geometry = Geometry::Planar { thickness: H };
const AXI: Geometry = Geometry::Axisymmetric;

// ---------------------------------------------------------------- helpers

fn segment_nodes(m: usize, closed: bool) -> Vec<[usize; 2]> {
    let count = if closed { m } else { m - 1 };
    (0..count).map(|j| [j, (j + 1) % m]).collect()
}

/// Consistent nodal loads of the traction linear between the nodal values `t`, by Gauss
/// quadrature: `int N_a t (h | 2 pi r) ds`.
fn gauss_loads(geometry: Geometry, closed: bool, x: &[[f64; 2]], t: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let g = (0.6f64).sqrt() / 2.0;
    let points = [
        (0.5 - g, 5.0 / 18.0),
        (0.5, 8.0 / 18.0),
        (0.5 + g, 5.0 / 18.0),
    ];
    let mut f = vec![[0.0; 2]; x.len()];
    for [a, b] in segment_nodes(x.len(), closed) {
        let d = (x[b][0] - x[a][0]).hypot(x[b][1] - x[a][1]);
        for (s, w) in points {
            let n = [1.0 - s, s];
            let r = n[0] * x[a][0] + n[1] * x[b][0];
            let measure = match geometry {
                Geometry::Planar { thickness } => thickness * d,
                Geometry::Axisymmetric => TAU * r * d,
            };
            for c in 0..2 {
                let tc = n[0] * t[a][c] + n[1] * t[b][c];
                f[a][c] += w * n[0] * tc * measure;
                f[b][c] += w * n[1] * tc * measure;
            }
        }
    }
    f
}

/// The full matrix of Eq. (26) (planar) or Eq. (27) times 2 pi (axisymmetric), written
/// from the paper's weights.
fn paper_matrix(geometry: Geometry, closed: bool, x: &[[f64; 2]]) -> DMatrix<f64> {
    let m = x.len();
    let mut a = DMatrix::zeros(m, m);
    for [p, q] in segment_nodes(m, closed) {
        let d = (x[q][0] - x[p][0]).hypot(x[q][1] - x[p][1]);
        let (app, apq, aqq) = match geometry {
            Geometry::Planar { thickness } => (
                thickness * d / 3.0,
                thickness * d / 6.0,
                thickness * d / 3.0,
            ),
            Geometry::Axisymmetric => {
                let (xp, xq) = (x[p][0], x[q][0]);
                (
                    TAU * d / 12.0 * (3.0 * xp + xq),
                    TAU * d / 12.0 * (xp + xq),
                    TAU * d / 12.0 * (xp + 3.0 * xq),
                )
            }
        };
        a[(p, p)] += app;
        a[(q, q)] += aqq;
        a[(p, q)] += apq;
        a[(q, p)] += apq;
    }
    a
}

/// Reference consistent recovery: dense LU of the rows and columns of the active nodes.
fn dense_recovery(
    geometry: Geometry,
    closed: bool,
    x: &[[f64; 2]],
    active: &[bool],
    force: &[[f64; 2]],
) -> Vec<[f64; 2]> {
    let full = paper_matrix(geometry, closed, x);
    let idx: Vec<usize> = (0..x.len()).filter(|&k| active[k]).collect();
    let n = idx.len();
    let a = DMatrix::from_fn(n, n, |i, j| full[(idx[i], idx[j])]);
    let lu = a.lu();
    let mut t = vec![[0.0; 2]; x.len()];
    for c in 0..2 {
        let rhs = DVector::from_fn(n, |i, _| force[idx[i]][c]);
        let sol = lu.solve(&rhs).expect("reference system is regular");
        for i in 0..n {
            t[idx[i]][c] = sol[i];
        }
    }
    t
}

fn max_abs(v: &[[f64; 2]]) -> f64 {
    v.iter().flatten().fold(0.0, |a: f64, b| a.max(b.abs()))
}

fn assert_close2(got: &[[f64; 2]], want: &[[f64; 2]], tol: f64, what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: lengths");
    let scale = max_abs(want).max(1e-300);
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        for c in 0..2 {
            let err = (g[c] - w[c]).abs() / scale;
            assert!(
                err <= tol,
                "{what}: node {k} component {c}: got {}, want {} (rel {err:e})",
                g[c],
                w[c]
            );
        }
    }
}

fn assert_rel(got: f64, want: f64, tol: f64, what: &str) {
    let err = (got - want).abs() / want.abs().max(1e-300);
    assert!(err <= tol, "{what}: got {got}, want {want} (rel {err:e})");
}

/// A curved open chain with uneven spacing.
fn curved_chain(m: usize) -> Vec<[f64; 2]> {
    let mut s: f64 = 0.0;
    (0..m)
        .map(|k| {
            let p = [s, 0.3 * (0.8 * s).sin()];
            s += 0.25 + 0.6 * ((k * 7 % 5) as f64) / 4.0;
            p
        })
        .collect()
}

/// An irregular convex polygon (counter-clockwise, body inside: on the left), centred at
/// `(cx, 0)`.
fn ring(m: usize, cx: f64, radius: f64) -> Vec<[f64; 2]> {
    let mut angles: Vec<f64> = (0..m)
        .map(|k| k as f64 + 0.35 * ((k * 3 % 4) as f64 - 1.5) / 1.5)
        .collect();
    let total = m as f64;
    for a in &mut angles {
        *a *= TAU / total;
    }
    angles
        .iter()
        .map(|a| [cx + radius * a.cos(), radius * a.sin()])
        .collect()
}

/// Arbitrary nodal tractions.
fn some_tractions(m: usize) -> Vec<[f64; 2]> {
    (0..m)
        .map(|k| {
            let k = k as f64;
            [1.0 + 0.5 * k - 0.07 * k * k, -0.3 + 0.2 * (1.3 * k).sin()]
        })
        .collect()
}

fn eval(
    geometry: Geometry,
    recovery: Recovery,
    friction: (f64, f64, FrictionRule),
    closed: bool,
    x: &[[f64; 2]],
    active: &[bool],
    force: &[[f64; 2]],
    previous: &[SegmentState],
    ever_slid: &[bool],
) -> Evaluation {
    evaluate(
        geometry,
        recovery,
        friction.0,
        friction.1,
        friction.2,
        closed,
        x,
        active,
        force,
        previous,
        ever_slid,
        &vec![0.0; previous.len()],
    )
    .expect("valid input")
}

const STICKY: (f64, f64, FrictionRule) = (10.0, 8.0, FrictionRule::MuDAfterSlip);

/// One straight segment from (0, 0) to (2, 0): the body is above it, nu = (0, 1),
/// tau = (1, 0), so t = (t_t, t_n). Planar with thickness 1: T = d/2 (t_a + t_b) = t_a + t_b.
fn one_segment(
    tt: [f64; 2],
    tn: [f64; 2],
    friction: (f64, f64, FrictionRule),
    previous: SegmentState,
    ever_slid: bool,
) -> (Evaluation, Vec<[f64; 2]>) {
    let x = [[0.0, 0.0], [2.0, 0.0]];
    let t = [[tt[0], tn[0]], [tt[1], tn[1]]];
    let geometry = Geometry::Planar { thickness: 1.0 };
    let force = gauss_loads(geometry, false, &x, &t);
    let ev = eval(
        geometry,
        Recovery::Consistent,
        friction,
        false,
        &x,
        &[true, true],
        &force,
        &[previous],
        &[ever_slid],
    );
    (ev, force)
}

// ---------------------------------------------------------------- step 1: recovery

#[test]
fn consistent_recovery_reproduces_linear_traction_planar() {
    let x = curved_chain(9);
    let t = some_tractions(9);
    let force = gauss_loads(PLANAR, false, &x, &t);
    let chain = Chain::new(PLANAR, false, &x).unwrap();
    let got = recover_tractions(&chain, Recovery::Consistent, &[true; 9], &force).unwrap();
    assert_close2(&got, &t, TOL, "planar consistent recovery");
}

#[test]
fn consistent_recovery_reproduces_linear_traction_axisymmetric() {
    // A curved meridian from the axis (node 0 at r = 0) outwards, uneven spacing.
    let x = [
        [0.0, 1.0],
        [0.4, 0.95],
        [1.1, 0.8],
        [1.5, 0.55],
        [2.3, 0.1],
        [2.6, -0.3],
    ];
    let t = some_tractions(x.len());
    let force = gauss_loads(AXI, false, &x, &t);
    let chain = Chain::new(AXI, false, &x).unwrap();
    let got = recover_tractions(&chain, Recovery::Consistent, &[true; 6], &force).unwrap();
    assert_close2(&got, &t, TOL, "axisymmetric consistent recovery");
    // The weights carry 2 pi: the planar weights with the same loads give a different field.
    let wrong = Chain::new(Geometry::Planar { thickness: 1.0 }, false, &x).unwrap();
    let other = recover_tractions(&wrong, Recovery::Consistent, &[true; 6], &force).unwrap();
    assert!((other[3][0] - t[3][0]).abs() > 1e-3);
}

#[test]
fn lumped_recovery_of_uniform_traction_on_uniform_chain() {
    let t0 = [2.0, -3.0];
    // Planar: exact at every node (the ends have the half tributary h d / 2).
    let x: Vec<[f64; 2]> = (0..6).map(|k| [0.5 * k as f64, 1.0]).collect();
    let t = vec![t0; 6];
    let force = gauss_loads(PLANAR, false, &x, &t);
    let chain = Chain::new(PLANAR, false, &x).unwrap();
    let got = recover_tractions(&chain, Recovery::Lumped, &[true; 6], &force).unwrap();
    assert_close2(&got, &t, TOL, "planar lumped");

    // Axisymmetric flat annulus, even spacing d = 0.25 from r = 1: at interior nodes the
    // tributary is 2 pi x_k d, and the recovery is exact there (and at the ends too,
    // because the tributary is the row sum of the consistent weights).
    let x: Vec<[f64; 2]> = (0..7).map(|k| [1.0 + 0.25 * k as f64, 0.0]).collect();
    let t = vec![t0; 7];
    let force = gauss_loads(AXI, false, &x, &t);
    let chain = Chain::new(AXI, false, &x).unwrap();
    let got = recover_tractions(&chain, Recovery::Lumped, &[true; 7], &force).unwrap();
    assert_close2(&got, &t, TOL, "axisymmetric lumped");
    for k in 1..6 {
        let w = TAU * x[k][0] * 0.25;
        assert_rel(force[k][0] / w, t0[0], TOL, "interior tributary 2 pi x d");
    }
}

#[test]
fn lumped_recovery_is_force_over_tributary() {
    let x = curved_chain(5);
    let force = some_tractions(5);
    let chain = Chain::new(PLANAR, false, &x).unwrap();
    let active = [true, true, false, true, true];
    let got = recover_tractions(&chain, Recovery::Lumped, &active, &force).unwrap();
    let d: Vec<f64> = chain.segments().iter().map(|s| s.length).collect();
    let trib = [
        H * d[0] / 2.0,
        H * (d[0] + d[1]) / 2.0,
        0.0,
        H * (d[2] + d[3]) / 2.0,
        H * d[3] / 2.0,
    ];
    for k in 0..5 {
        for c in 0..2 {
            let want = if active[k] {
                force[k][c] / trib[k]
            } else {
                0.0
            };
            assert_rel(got[k][c] + 1.0, want + 1.0, TOL, "lumped f / tributary");
        }
    }
}

#[test]
fn runs_of_active_nodes_match_dense_solve() {
    let active = [
        false, true, true, false, true, true, true, false, false, true,
    ];
    for geometry in [PLANAR, AXI] {
        let x: Vec<[f64; 2]> = curved_chain(10)
            .iter()
            .map(|p| [p[0] + 0.2, p[1]])
            .collect();
        let force = some_tractions(10);
        let chain = Chain::new(geometry, false, &x).unwrap();
        let got = recover_tractions(&chain, Recovery::Consistent, &active, &force).unwrap();
        let want = dense_recovery(geometry, false, &x, &active, &force);
        assert_close2(&got, &want, TOL, "runs vs dense");
        for k in (0..10).filter(|&k| !active[k]) {
            assert_eq!(got[k], [0.0, 0.0], "inactive node {k} has t = 0");
        }
        // An inactive node's segment still adds its M_kk to the neighbour's diagonal: the
        // isolated active node 9 has t = f / (h d / 3) (planar).
        if geometry == PLANAR {
            let d = chain.segments()[8].length;
            assert_rel(
                got[9][0],
                force[9][0] / (H * d / 3.0),
                TOL,
                "isolated end node",
            );
        }
    }
}

#[test]
fn closed_chain_fully_active_matches_dense_solve() {
    for (geometry, m) in [
        (PLANAR, 7),
        (AXI, 7),
        (PLANAR, 3),
        (AXI, 200),
        (PLANAR, 1000),
    ] {
        // The ring sits at r in [2, 4] so every radius is positive.
        let x = ring(m, 3.0, 1.0);
        let force = some_tractions(m);
        let active = vec![true; m];
        let chain = Chain::new(geometry, true, &x).unwrap();
        let got = recover_tractions(&chain, Recovery::Consistent, &active, &force).unwrap();
        let want = dense_recovery(geometry, true, &x, &active, &force);
        assert_close2(&got, &want, TOL, &format!("closed chain m = {m}"));
    }
}

#[test]
fn closed_chain_run_wrapping_past_node_zero_matches_dense_solve() {
    let x = ring(9, 3.0, 1.0);
    let force = some_tractions(9);
    let active = [true, true, false, false, true, false, true, true, true];
    for geometry in [PLANAR, AXI] {
        let chain = Chain::new(geometry, true, &x).unwrap();
        let got = recover_tractions(&chain, Recovery::Consistent, &active, &force).unwrap();
        let want = dense_recovery(geometry, true, &x, &active, &force);
        assert_close2(&got, &want, TOL, "wrapping run");
    }
}

#[test]
fn long_chain_is_recovered_in_linear_time() {
    let m = 200_000;
    let x: Vec<[f64; 2]> = (0..m).map(|k| [1.0 + k as f64 * 1e-3, 0.0]).collect();
    let t: Vec<[f64; 2]> = (0..m)
        .map(|k| [(k % 7) as f64, 1.0 + (k % 3) as f64])
        .collect();
    let force = gauss_loads(AXI, false, &x, &t);
    let chain = Chain::new(AXI, false, &x).unwrap();
    let got = recover_tractions(&chain, Recovery::Consistent, &vec![true; m], &force).unwrap();
    assert_close2(&got, &t, 1e-10, "long chain");
}

// ---------------------------------------------------------------- steps 2 and 4

#[test]
fn stick_round_trip_returns_the_forces_and_spills_onto_inactive_neighbours() {
    for geometry in [PLANAR, AXI] {
        let m = 9;
        let x: Vec<[f64; 2]> = curved_chain(m).iter().map(|p| [p[0] + 0.5, p[1]]).collect();
        let chain = Chain::new(geometry, false, &x).unwrap();
        // Compressive (t = p nu plus a little friction) at active nodes 2..=6.
        let active: Vec<bool> = (0..m).map(|k| (2..=6).contains(&k)).collect();
        let t: Vec<[f64; 2]> = (0..m)
            .map(|k| {
                if !active[k] {
                    return [0.0; 2];
                }
                let nu = chain.segments()[k.min(m - 2)].normal;
                let p = 3.0 + k as f64;
                [p * nu[0] + 0.1 * nu[1], p * nu[1] - 0.1 * nu[0]]
            })
            .collect();
        // Forces at active nodes (the inactive entries are garbage and must be ignored).
        let mut force = gauss_loads(geometry, false, &x, &t);
        for k in (0..m).filter(|&k| !active[k]) {
            force[k] = [f64::NAN, 1e300];
        }
        let ev = eval(
            geometry,
            Recovery::Consistent,
            STICKY,
            false,
            &x,
            &active,
            &force,
            &vec![SegmentState::Stick; m - 1],
            &vec![false; m - 1],
        );
        let states: Vec<SegmentState> = ev.segments.iter().map(|s| s.state).collect();
        use SegmentState::{Open, Stick};
        assert_eq!(
            states,
            [Open, Stick, Stick, Stick, Stick, Stick, Stick, Open]
        );
        assert_close2(&ev.traction, &t, TOL, "recovered field");
        let scale = max_abs(&t) * 10.0;
        for k in 2..=6 {
            for c in 0..2 {
                assert!(
                    (ev.forces[k][c] - force[k][c]).abs() <= TOL * scale,
                    "active node {k}"
                );
            }
        }
        // Spill: node 1 gets M_12 t_2, node 7 gets M_76 t_6; nodes 0, 8 get nothing.
        let w = |j: usize| chain.segments()[j].weights[0][1];
        for c in 0..2 {
            assert_rel(ev.forces[1][c], w(1) * t[2][c], TOL, "spill at node 1");
            assert_rel(ev.forces[7][c], w(6) * t[6][c], TOL, "spill at node 7");
        }
        if geometry == PLANAR {
            let d = chain.segments()[1].length;
            assert_rel(w(1), H * d / 6.0, TOL, "planar spill weight h d / 6");
        }
        assert_eq!(ev.forces[0], [0.0, 0.0]);
        assert_eq!(ev.forces[8], [0.0, 0.0]);
        // Node states: Table 1 for active nodes, inactive nodes Open.
        for k in 0..m {
            let want = if active[k] {
                NodeState::Stick
            } else {
                NodeState::Open
            };
            assert_eq!(ev.node_states[k], want, "node {k}");
        }
        // Fx, Fy sum every nodal force, spill included.
        for (c, total) in [ev.fx, ev.fy].into_iter().enumerate() {
            let active_sum: f64 = (2..=6).map(|k| force[k][c]).sum();
            let spill = ev.forces[1][c] + ev.forces[7][c];
            assert!(
                (total - (active_sum + spill)).abs() <= TOL * scale,
                "Fx/Fy include the spill"
            );
            assert!(spill.abs() > 1e-3 * scale, "the spill is not negligible");
        }
    }
}

#[test]
fn inactive_node_between_two_runs_receives_both_spills() {
    let x = curved_chain(5);
    let chain = Chain::new(PLANAR, false, &x).unwrap();
    let active = [true, true, false, true, true];
    let t: Vec<[f64; 2]> = (0..5)
        .map(|k| {
            if active[k] {
                [0.2, 2.0 + k as f64]
            } else {
                [0.0; 2]
            }
        })
        .collect();
    let force = gauss_loads(PLANAR, false, &x, &t);
    let ev = eval(
        PLANAR,
        Recovery::Consistent,
        STICKY,
        false,
        &x,
        &active,
        &force,
        &[SegmentState::Stick; 4],
        &[false; 4],
    );
    let s = chain.segments();
    for c in 0..2 {
        let want = H * s[1].length / 6.0 * t[1][c] + H * s[2].length / 6.0 * t[3][c];
        assert_rel(ev.forces[2][c], want, TOL, "spill from both sides");
        for k in [0, 1, 3, 4] {
            assert_rel(ev.forces[k][c], force[k][c], TOL, "active");
        }
    }
}

#[test]
fn segment_tractions_in_the_segment_frames() {
    // Two segments at right angles: along +x, then along +y; t = (1, 2) at the corner.
    let x = [[0.0, 0.0], [1.0, 0.0], [1.0, 3.0]];
    let chain = Chain::new(PLANAR, false, &x).unwrap();
    let t = [[0.0, 0.0], [1.0, 2.0], [-1.0, 0.5]];
    let s = segment_tractions(&chain, &[false, true, true], &t).unwrap();
    // Segment 0: tau = (1, 0), nu = (0, 1). Segment 1: tau = (0, 1), nu = (-1, 0).
    assert_eq!(s[0].tn, [0.0, 2.0]);
    assert_eq!(s[0].tt, [0.0, 1.0]);
    assert_eq!(s[1].tn, [-1.0, 1.0]);
    assert_eq!(s[1].tt, [2.0, 0.5]);
    assert_rel(s[0].tn_total, H * 1.0 / 2.0 * 2.0, TOL, "Eq. 28");
    assert_rel(s[1].tt_total, H * 3.0 / 2.0 * 2.5, TOL, "Eq. 29");
    assert!(s[0].in_contact && s[1].in_contact);

    // Axisymmetric, Eqs. (30), (31) times 2 pi.
    let chain = Chain::new(AXI, false, &x).unwrap();
    let s = segment_tractions(&chain, &[false, true, true], &t).unwrap();
    let (xa, xb, d) = (1.0, 1.0, 3.0);
    let (tna, tnb) = (-1.0, 1.0);
    let eq30 = TAU * d / 6.0 * (2.0 * (xa * tna + xb * tnb) + (xb * tna + xa * tnb));
    assert!((s[1].tn_total - eq30).abs() < 1e-14);
    let (xa, xb, d) = (0.0, 1.0, 1.0);
    let (tta, ttb) = (0.0, 1.0);
    let eq31 = TAU * d / 6.0 * (2.0 * (xa * tta + xb * ttb) + (xb * tta + xa * ttb));
    assert_rel(s[0].tt_total, eq31, TOL, "Eq. 31");
}

#[test]
fn uniform_pressure_on_straight_chain_planar() {
    // Along +x, body above (on the left): nu = (0, 1); pressure p pushes into the body.
    let p = 2.5;
    let x = [[0.0, 1.0], [0.4, 1.0], [1.5, 1.0], [1.9, 1.0], [3.0, 1.0]];
    let t = [[0.0, p]; 5];
    let force = gauss_loads(PLANAR, false, &x, &t);
    let ev = eval(
        PLANAR,
        Recovery::Consistent,
        (0.3, 0.2, FrictionRule::MuDAfterSlip),
        false,
        &x,
        &[true; 5],
        &force,
        &[SegmentState::Open; 4],
        &[false; 4],
    );
    assert_rel(ev.fn_, p * H * 3.0, TOL, "Fn = p h L");
    assert!(ev.ft.abs() < 1e-14);
    assert_rel(ev.fy, p * H * 3.0, TOL, "Fy");
    assert!(ev.fx.abs() < 1e-14);
    for s in &ev.segments {
        assert_eq!(
            s.state,
            SegmentState::Stick,
            "a new contact starts sticking"
        );
        assert_rel(s.tf, 0.3 * s.tn_total, TOL, "capacity mu_s T_n");
    }
    for k in 0..5 {
        assert_eq!(ev.node_states[k], NodeState::Stick);
        assert_rel(ev.node_tn[k], p, TOL, "node t_n");
        assert!(ev.node_tt[k].abs() < 1e-14);
    }
}

#[test]
fn uniform_pressure_on_flat_annulus_axisymmetric() {
    let p = 1.5;
    for (a, b, m) in [(0.5, 2.0, 7), (0.0, 1.0, 4)] {
        let x: Vec<[f64; 2]> = (0..m)
            .map(|k| {
                let s = k as f64 / (m - 1) as f64;
                [a + (b - a) * s * s.sqrt(), -2.0]
            })
            .collect();
        let t = vec![[0.0, p]; m];
        let force = gauss_loads(AXI, false, &x, &t);
        let ev = eval(
            AXI,
            Recovery::Consistent,
            (0.3, 0.2, FrictionRule::MuDAfterSlip),
            false,
            &x,
            &vec![true; m],
            &force,
            &vec![SegmentState::Stick; m - 1],
            &vec![false; m - 1],
        );
        let want = p * PI * (b * b - a * a);
        assert_rel(ev.fn_, want, TOL, "Fn = p pi (b^2 - a^2)");
        assert_rel(ev.fy, want, TOL, "Fy");
        assert!(ev.ft.abs() < 1e-13 && ev.fx.abs() < 1e-13);
        assert_close2(&ev.traction, &t, TOL, "uniform pressure recovered");
    }
}

#[test]
fn closed_ring_under_uniform_pressure_has_zero_net_force() {
    let m = 48;
    let x = ring(m, 0.0, 2.0);
    let chain = Chain::new(PLANAR, true, &x).unwrap();
    // A uniform pressure on a polygon: its consistent loads are p h (d_{j-1} nu_{j-1} +
    // d_j nu_j) / 2 per node.
    let p = 4.0;
    let mut force = vec![[0.0; 2]; m];
    for s in chain.segments() {
        for &k in &s.nodes {
            for c in 0..2 {
                force[k][c] += p * H * s.length / 2.0 * s.normal[c];
            }
        }
    }
    let ev = eval(
        PLANAR,
        Recovery::Consistent,
        STICKY,
        true,
        &x,
        &[true; 48],
        &force,
        &[SegmentState::Stick; 48],
        &[false; 48],
    );
    assert!(ev.fx.abs() < 1e-12 && ev.fy.abs() < 1e-12);
    let perimeter: f64 = chain.segments().iter().map(|s| s.length).sum();
    // The recovered field is not p nu on every segment (the nodal tractions are continuous
    // while the normals turn by up to ~11 degrees here), but it carries the same loads. Its
    // normal resultant falls short of p h P by about cos^2 of half the turn (on a regular
    // m-gon t_k = p cos(pi / m) along the bisector, so Fn = cos^2(pi / m) p h P).
    assert_close2(&ev.forces, &force, TOL, "closed round trip");
    assert_rel(ev.fn_, p * H * perimeter, 0.01, "Fn about p h perimeter");
    assert!(ev.fn_ < p * H * perimeter);
    assert!(ev.node_states.iter().all(|&s| s == NodeState::Stick));
}

#[test]
fn pair_resultants_are_the_sum_of_segment_resultant_vectors() {
    // A curved chain with mixed states: check Fx, Fy against sum(T_n nu + T_t' tau) with
    // T_t' = T_t sticking and sign(T_t) T_f sliding.
    for geometry in [PLANAR, AXI] {
        let m = 8;
        let x: Vec<[f64; 2]> = curved_chain(m).iter().map(|p| [p[0] + 0.3, p[1]]).collect();
        let chain = Chain::new(geometry, false, &x).unwrap();
        let t: Vec<[f64; 2]> = (0..m)
            .map(|k| {
                let nu = chain.segments()[k.min(m - 2)].normal;
                let tau = chain.segments()[k.min(m - 2)].tangent;
                let (pn, pt) = (2.0 + k as f64, if k < 4 { 0.1 } else { -4.0 });
                [pn * nu[0] + pt * tau[0], pn * nu[1] + pt * tau[1]]
            })
            .collect();
        let force = gauss_loads(geometry, false, &x, &t);
        let ev = eval(
            geometry,
            Recovery::Consistent,
            (0.3, 0.25, FrictionRule::MuDAfterSlip),
            false,
            &x,
            &vec![true; m],
            &force,
            &vec![SegmentState::Stick; m - 1],
            &vec![false; m - 1],
        );
        let states: Vec<SegmentState> = ev.segments.iter().map(|s| s.state).collect();
        assert!(states.contains(&SegmentState::Stick) && states.contains(&SegmentState::Slide));
        let (mut fx, mut fy, mut ft) = (0.0, 0.0, 0.0);
        for (s, e) in chain.segments().iter().zip(&ev.segments) {
            let tt = match e.state {
                SegmentState::Stick => e.tt_total,
                SegmentState::Slide => e.tf * e.tt_total.signum(),
                SegmentState::Open => unreachable!(),
            };
            fx += e.tn_total * s.normal[0] + tt * s.tangent[0];
            fy += e.tn_total * s.normal[1] + tt * s.tangent[1];
            ft += tt;
        }
        let scale = ev.fn_.abs();
        assert!((ev.fx - fx).abs() <= TOL * scale, "Fx");
        assert!((ev.fy - fy).abs() <= TOL * scale, "Fy");
        assert!((ev.ft - ft).abs() <= TOL * scale, "Ft");
    }
}

// ---------------------------------------------------------------- step 3: decisions

#[test]
fn segment_in_tension_is_released() {
    let (ev, _) = one_segment([0.0, 0.0], [-1.0, -2.0], STICKY, SegmentState::Stick, false);
    let s = ev.segments[0];
    assert_eq!(s.state, SegmentState::Open);
    assert_rel(s.tn_total, -3.0, TOL, "T_n kept for diagnosis");
    assert_eq!((s.tn, s.tt, s.tf), ([0.0; 2], [0.0; 2], 0.0));
    assert_eq!(ev.forces, vec![[0.0, 0.0]; 2]);
    assert_eq!(ev.node_states, vec![NodeState::Open; 2]);
    assert_eq!((ev.fx, ev.fy, ev.fn_, ev.ft), (0.0, 0.0, 0.0, 0.0));
    assert_eq!(
        (ev.node_tn.clone(), ev.node_tt.clone()),
        (vec![0.0; 2], vec![0.0; 2])
    );

    // T_n < 0 wins over t_n > 0 at one end: (-3 + 1) < 0.
    let (ev, _) = one_segment([0.0, 0.0], [-3.0, 1.0], STICKY, SegmentState::Slide, true);
    assert_eq!(ev.segments[0].state, SegmentState::Open);
    assert!(
        ev.segments[0].ever_slid,
        "ever_slid is kept through a release"
    );
}

#[test]
fn release_of_some_segments_and_table_1() {
    // Straight chain, nodes 0..3, t_n = [-2, -2, 1, 1] p: segment 0 and 1 release
    // (T_n proportional to -4 and -1), segment 2 sticks.
    let x = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0]];
    let t = [[0.0, -2.0], [0.0, -2.0], [0.0, 1.0], [0.0, 1.0]];
    let force = gauss_loads(PLANAR, false, &x, &t);
    let ev = eval(
        PLANAR,
        Recovery::Consistent,
        STICKY,
        false,
        &x,
        &[true; 4],
        &force,
        &[SegmentState::Stick; 3],
        &[false; 3],
    );
    use SegmentState::{Open, Stick};
    let states: Vec<SegmentState> = ev.segments.iter().map(|s| s.state).collect();
    assert_eq!(states, [Open, Open, Stick]);
    assert_eq!(
        ev.node_states,
        [
            NodeState::Open,
            NodeState::Open,
            NodeState::Stick,
            NodeState::Stick
        ]
    );
    // Only segment 2 loads its nodes: h d / 6 [2 1; 1 2] (1, 1) = h d / 2 each.
    assert_eq!(ev.forces[0], [0.0, 0.0]);
    assert_eq!(ev.forces[1], [0.0, 0.0]);
    assert_rel(ev.forces[2][1], H / 2.0, TOL, "node 2");
    assert_rel(ev.forces[3][1], H / 2.0, TOL, "node 3");
    assert_rel(ev.fn_, H, TOL, "Fn over the sticking segment only");
    // Node 2's output traction comes from segment 2 only.
    assert_rel(ev.node_tn[2], 1.0, TOL, "node t_n");
    assert_eq!(ev.node_tn[1], 0.0);
}

#[test]
fn stick_turns_to_slide_above_mu_s_with_mu_d_capacity() {
    let f = (0.4, 0.3, FrictionRule::MuDAfterSlip);
    // T_n = 1 + 1 = 2 (p = 1), T_t = 2 q.
    for q in [0.5, -0.5] {
        let (ev, force) = one_segment([q, q], [1.0, 1.0], f, SegmentState::Stick, false);
        let s = ev.segments[0];
        assert_eq!(s.state, SegmentState::Slide);
        assert!(s.ever_slid);
        assert_rel(s.tf, 0.3 * s.tn_total, TOL, "T_f = mu_d T_n");
        // Tangential (x) forces: total sign(q) mu_d T_n, uniform: half at each node.
        let total = ev.forces[0][0] + ev.forces[1][0];
        assert_rel(total, q.signum() * 0.3 * 2.0, TOL, "tangential total");
        assert_rel(ev.forces[0][0], ev.forces[1][0], TOL, "uniform split");
        assert_rel(ev.ft, q.signum() * 0.6, TOL, "Ft = sign(T_t) T_f");
        // Normal (y) forces unaltered.
        assert_rel(ev.forces[0][1], force[0][1], TOL, "normal at 0");
        assert_rel(ev.forces[1][1], force[1][1], TOL, "normal at 1");
        assert_eq!(ev.node_states, [NodeState::Slip; 2]);
    }
    // A linear tangential traction is replaced by a uniform one (Fig. 5b): t_t = (0.2, 1.0)
    // would load node 1 more than node 0, the uniform one loads them equally.
    let (ev, force) = one_segment([0.2, 1.0], [1.0, 1.0], f, SegmentState::Open, false);
    assert_eq!(ev.segments[0].state, SegmentState::Slide);
    assert!(force[1][0] > force[0][0] + 0.2);
    assert_rel(ev.forces[0][0], 0.3, TOL, "uniform, node 0");
    assert_rel(ev.forces[1][0], 0.3, TOL, "uniform, node 1");
    // Just below the capacity: sticks.
    let (ev, force) = one_segment(
        [0.4 * (1.0 - 1e-9); 2],
        [1.0, 1.0],
        f,
        SegmentState::Stick,
        false,
    );
    assert_eq!(ev.segments[0].state, SegmentState::Stick);
    assert_rel(ev.segments[0].tf, 0.4 * 2.0, TOL, "capacity mu_s T_n");
    assert_close2(&ev.forces, &force, TOL, "sticking forces unaltered");
    // Just above: slides.
    let (ev, _) = one_segment(
        [0.4 * (1.0 + 1e-9); 2],
        [1.0, 1.0],
        f,
        SegmentState::Stick,
        false,
    );
    assert_eq!(ev.segments[0].state, SegmentState::Slide);
}

#[test]
fn sliding_forces_axisymmetric_follow_eq_32() {
    // Flat annulus r in [1, 3] at y = 0, body above: tau = (1, 0) (radial), nu = (0, 1).
    let x = [[1.0, 0.0], [3.0, 0.0]];
    let t = [[0.5, 1.0], [0.9, 2.0]];
    let force = gauss_loads(AXI, false, &x, &t);
    let ev = eval(
        AXI,
        Recovery::Consistent,
        (0.2, 0.1, FrictionRule::MuDAfterSlip),
        false,
        &x,
        &[true, true],
        &force,
        &[SegmentState::Stick],
        &[false],
    );
    let s = ev.segments[0];
    assert_eq!(s.state, SegmentState::Slide);
    // T_n = 2 pi int t_n r ds with t_n = 1 + (r - 1) / 2: 2 pi (4 + 26/6 - 2) ... by Eq. 30.
    let (xa, xb, d) = (1.0, 3.0, 2.0);
    let tn = TAU * d / 6.0 * (2.0 * (xa * 1.0 + xb * 2.0) + (xb * 1.0 + xa * 2.0));
    assert_rel(s.tn_total, tn, TOL, "Eq. 30");
    let tf = 0.1 * tn;
    assert_rel(s.tf, tf, TOL, "T_f");
    // Eq. 32 with T_f: tbar = 2 T_f / (2 pi d (xa + xb)); its loads 2 pi tbar int N_a r ds.
    let tbar = 2.0 * tf / (TAU * d * (xa + xb));
    let la = TAU * tbar * d * (2.0 * xa + xb) / 6.0;
    let lb = TAU * tbar * d * (xa + 2.0 * xb) / 6.0;
    assert_rel(ev.forces[0][0], la, TOL, "node a");
    assert_rel(ev.forces[1][0], lb, TOL, "node b");
    assert_rel(la / tf, 5.0 / 12.0, TOL, "split 5/12");
    assert_rel(ev.forces[0][0] + ev.forces[1][0], tf, TOL, "total T_f");
    assert_rel(ev.forces[0][1], force[0][1], TOL, "normal unaltered a");
    assert_rel(ev.forces[1][1], force[1][1], TOL, "normal unaltered b");
}

/// A sliding segment slides on at any `|T_t|` up to its capacity: its return
/// to sticking is kinematic (the caller's), never on force grounds.
#[test]
fn a_sliding_segment_does_not_return_to_stick_on_force_grounds() {
    let f = (0.5, 0.3, FrictionRule::MuDAfterSlip);
    let slide = SegmentState::Slide;
    // |T_t| = T_f (to round-off), just below it, and far below it: sliding,
    // with the capacity mu_d T_n.
    for tt in [0.3, 0.3 * (1.0 - 1e-12), -0.3 * 0.5, 0.0] {
        let (ev, _) = one_segment([tt; 2], [1.0, 1.0], f, slide, true);
        let s = ev.segments[0];
        assert_eq!(s.state, SegmentState::Slide, "t_t = {tt}");
        assert_rel(s.tf, 0.3 * s.tn_total, TOL, "mu_d capacity");
    }
    // mu_d < |T_t| / T_n < mu_s: a sliding segment keeps sliding (mu_d is used) ...
    let (ev, _) = one_segment([0.4, 0.4], [1.0, 1.0], f, slide, true);
    assert_eq!(ev.segments[0].state, SegmentState::Slide);
    // ... while a sticking one that never slid keeps sticking (mu_s).
    let (ev, _) = one_segment([0.4, 0.4], [1.0, 1.0], f, SegmentState::Stick, false);
    assert_eq!(ev.segments[0].state, SegmentState::Stick);
    // Direct check, whatever the margin below the capacity.
    let seg = SegmentTractions {
        in_contact: true,
        tn: [1.0; 2],
        tt: [0.3; 2],
        tn_total: 2.0,
        tt_total: 0.6 * 0.5,
    };
    let fr = Friction::new(0.5, 0.3, FrictionRule::MuDAfterSlip).unwrap();
    assert_eq!(
        decide_segment(&fr, slide, true, &seg).state,
        SegmentState::Slide
    );
}

#[test]
fn mu_d_after_slip_versus_always_mu_s() {
    // mu_s = 0.5 > |T_t| / T_n = 0.4 > mu_d = 0.3, previously sticking.
    let after = (0.5, 0.3, FrictionRule::MuDAfterSlip);
    let always = (0.5, 0.3, FrictionRule::AlwaysMuS);
    let tt = [0.4, 0.4];
    let tn = [1.0, 1.0];
    // A segment that has slid before: MuDAfterSlip uses mu_d and slides ...
    let (ev, _) = one_segment(tt, tn, after, SegmentState::Stick, true);
    assert_eq!(ev.segments[0].state, SegmentState::Slide);
    assert_rel(ev.segments[0].tf, 0.3 * 2.0, TOL, "mu_d T_n");
    // ... AlwaysMuS keeps mu_s and sticks.
    let (ev, _) = one_segment(tt, tn, always, SegmentState::Stick, true);
    assert_eq!(ev.segments[0].state, SegmentState::Stick);
    assert_rel(ev.segments[0].tf, 0.5 * 2.0, TOL, "mu_s T_n");
    assert!(ev.segments[0].ever_slid);
    // The same holds for a segment that comes back into contact (previously Open).
    let (ev, _) = one_segment(tt, tn, after, SegmentState::Open, true);
    assert_eq!(ev.segments[0].state, SegmentState::Slide);
    // A segment that never slid sticks under both rules.
    for rule in [after, always] {
        let (ev, _) = one_segment(tt, tn, rule, SegmentState::Stick, false);
        assert_eq!(ev.segments[0].state, SegmentState::Stick);
        assert!(!ev.segments[0].ever_slid);
    }
}

#[test]
fn frictionless_segments_slide_with_zero_tangential_force() {
    let free = (0.0, 0.0, FrictionRule::MuDAfterSlip);
    for previous in [SegmentState::Open, SegmentState::Stick, SegmentState::Slide] {
        let (ev, force) = one_segment([0.7, -0.2], [1.0, 3.0], free, previous, false);
        let s = ev.segments[0];
        assert_eq!(s.state, SegmentState::Slide);
        assert_eq!(s.tf, 0.0);
        assert!(s.ever_slid);
        assert_eq!(ev.forces[0][0], 0.0);
        assert_eq!(ev.forces[1][0], 0.0);
        assert_eq!(ev.ft, 0.0);
        assert_rel(ev.forces[0][1], force[0][1], TOL, "normal at 0");
        assert_rel(ev.forces[1][1], force[1][1], TOL, "normal at 1");
        assert_eq!(ev.node_states, [NodeState::Slip; 2]);
    }
    // Zero tangential traction: still sliding (not sticking) when frictionless.
    let (ev, _) = one_segment([0.0, 0.0], [1.0, 1.0], free, SegmentState::Open, false);
    assert_eq!(ev.segments[0].state, SegmentState::Slide);
}

#[test]
fn table_1_node_states() {
    use NodeState as N;
    use SegmentState::{Open, Slide, Stick};
    let x = curved_chain(10);
    let chain = Chain::new(PLANAR, false, &x).unwrap();
    // Nodes 1..8 see the pairs (s_{k-1}, s_k).
    let states = [Stick, Stick, Slide, Slide, Open, Open, Stick, Slide, Stick];
    let want = [
        N::Stick, // end: stick
        N::Stick, // stick + stick
        N::Stick, // stick + slide
        N::Slip,  // slide + slide
        N::Slip,  // slide + open
        N::Open,  // open + open
        N::Stick, // open + stick
        N::Stick, // stick + slide
        N::Stick, // slide + stick
        N::Stick, // end: stick
    ];
    let got = node_states(&chain, &[true; 10], &states).unwrap();
    assert_eq!(got, want);
    // Inactive nodes are Open whatever their segments.
    let mut active = [true; 10];
    active[1] = false;
    active[3] = false;
    let got = node_states(&chain, &active, &states).unwrap();
    assert_eq!(got[1], N::Open);
    assert_eq!(got[3], N::Open);
    assert_eq!(got[2], N::Stick);
    // Ends with slide / open.
    let got = node_states(
        &chain,
        &[true; 10],
        &[Slide, Open, Open, Open, Open, Open, Open, Open, Open],
    )
    .unwrap();
    assert_eq!(got[0], N::Slip);
    assert_eq!(got[1], N::Slip);
    assert_eq!(got[9], N::Open);
    // Closed chain: node 0 sees segments m-1 and 0.
    let x = ring(4, 0.0, 1.0);
    let chain = Chain::new(PLANAR, true, &x).unwrap();
    let got = node_states(&chain, &[true; 4], &[Open, Open, Open, Slide]).unwrap();
    assert_eq!(got, [N::Slip, N::Open, N::Open, N::Slip]);
}

#[test]
fn segment_without_active_node_is_open() {
    let x = curved_chain(4);
    let force = vec![[1.0, 1.0]; 4];
    let ev = eval(
        PLANAR,
        Recovery::Consistent,
        STICKY,
        false,
        &x,
        &[true, false, false, true],
        &force,
        &[SegmentState::Stick; 3],
        &[false; 3],
    );
    assert_eq!(ev.segments[1].state, SegmentState::Open);
    assert_eq!(ev.segments[1].tn_total, 0.0);
}

// ---------------------------------------------------------------- validation

fn err(
    geometry: Geometry,
    closed: bool,
    x: &[[f64; 2]],
    active: &[bool],
    force: &[[f64; 2]],
    mu: (f64, f64),
) -> TractionError {
    let segs = if closed {
        x.len()
    } else {
        x.len().saturating_sub(1)
    };
    evaluate(
        geometry,
        Recovery::Consistent,
        mu.0,
        mu.1,
        FrictionRule::MuDAfterSlip,
        closed,
        x,
        active,
        force,
        &vec![SegmentState::Stick; segs],
        &vec![false; segs],
        &vec![0.0; segs],
    )
    .expect_err("invalid input")
}

#[test]
fn invalid_inputs_are_errors() {
    use TractionError as E;
    let x = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]];
    let f = [[0.0, 1.0]; 3];
    let on = [true; 3];
    let ok = (0.3, 0.2);
    assert!(matches!(
        err(
            PLANAR,
            false,
            &[[0.0, 0.0], [f64::NAN, 0.0]],
            &[true; 2],
            &f[..2],
            ok
        ),
        E::NonFinitePosition { node: 1, .. }
    ));
    assert!(matches!(
        err(PLANAR, false, &[[0.0, 0.0], [1.0, 0.0], [1.0, 0.0]], &on, &f, ok),
        E::DegenerateSegment { segment: 1, length, .. } if length == 0.0
    ));
    assert!(matches!(
        err(
            PLANAR,
            true,
            &[[0.0, 0.0], [1.0, 0.0], [0.0, 0.0]],
            &on,
            &f,
            ok
        ),
        E::DegenerateSegment { segment: 2, .. }
    ));
    let bad_force = [[0.0, 1.0], [f64::INFINITY, 1.0], [0.0, 1.0]];
    assert!(matches!(
        err(PLANAR, false, &x, &on, &bad_force, ok),
        E::NonFiniteForce { node: 1, .. }
    ));
    // ... but a non-finite force at an inactive node is never read.
    assert!(
        evaluate(
            PLANAR,
            Recovery::Consistent,
            0.3,
            0.2,
            FrictionRule::MuDAfterSlip,
            false,
            &x,
            &[true, false, true],
            &bad_force,
            &[SegmentState::Open; 2],
            &[false; 2],
            &[0.0; 2]
        )
        .is_ok()
    );
    assert!(matches!(
        err(
            AXI,
            false,
            &[[-1e-3, 0.0], [1.0, 0.0]],
            &[true; 2],
            &f[..2],
            ok
        ),
        E::NegativeRadius { node: 0, .. }
    ));
    // A segment lying on the axis of revolution has no area.
    assert!(matches!(
        err(
            AXI,
            false,
            &[[0.0, 0.0], [0.0, 1.0]],
            &[true; 2],
            &f[..2],
            ok
        ),
        E::SingularRecovery { node: 0, .. }
    ));
    let chain = Chain::new(AXI, false, &[[0.0, 0.0], [0.0, 1.0]]).unwrap();
    assert!(matches!(
        recover_tractions(&chain, Recovery::Lumped, &[true, false], &f[..2]),
        Err(E::SingularRecovery { node: 0, .. })
    ));
    assert!(matches!(
        err(Geometry::Planar { thickness: 0.0 }, false, &x, &on, &f, ok),
        E::InvalidThickness { .. }
    ));
    assert!(matches!(
        err(PLANAR, false, &x, &on, &f, (-0.1, 0.0)),
        E::InvalidFriction { .. }
    ));
    assert!(matches!(
        err(PLANAR, false, &x, &on, &f, (0.1, f64::NAN)),
        E::InvalidFriction { .. }
    ));
    assert!(matches!(
        err(PLANAR, false, &x, &on[..2], &f, ok),
        E::LengthMismatch {
            what: "active",
            expected: 3,
            found: 2
        }
    ));
    assert!(matches!(
        err(PLANAR, true, &x[..2], &on[..2], &f[..2], ok),
        E::TooFewNodes {
            nodes: 2,
            closed: true
        }
    ));
    assert!(matches!(
        err(PLANAR, false, &x[..1], &on[..1], &f[..1], ok),
        E::TooFewNodes { .. }
    ));
    let e = evaluate(
        PLANAR,
        Recovery::Consistent,
        0.3,
        0.2,
        FrictionRule::MuDAfterSlip,
        false,
        &x,
        &on,
        &f,
        &[SegmentState::Stick; 3],
        &[false; 2],
        &[0.0; 2],
    )
    .unwrap_err();
    assert!(matches!(
        e,
        E::LengthMismatch {
            expected: 2,
            found: 3,
            ..
        }
    ));
    // Overflow is an error, not an infinity or a NaN.
    let tiny = Geometry::Planar { thickness: 1e-300 };
    let huge = [[1e300, 1e300]; 3];
    assert!(matches!(
        err(tiny, false, &x, &on, &huge, ok),
        E::NonFinite { .. }
    ));
    // Messages carry the values.
    let msg = err(
        PLANAR,
        false,
        &[[0.0, 0.0], [0.0, 0.0]],
        &[true; 2],
        &f[..2],
        ok,
    )
    .to_string();
    assert!(
        msg.contains("segment 0") && msg.contains("length 0"),
        "{msg}"
    );
}

// ------------------------------------------- sticking runs next to sliding segments

/// Two unit segments on y = 0 (body above), planar, thickness 1, uniform t_n = 1
/// (T_n = 1 each), mu_s = mu_d = 0.3. Segment 0 was sliding (friction +x, T_f = 0.3),
/// segment 1 sticking; node 1 carries a tangential force of 0.5, the others none. The
/// recovery splits it evenly (T_t = 0.25 on both segments), so the paper's check lets
/// segment 1 stick; but segment 0 applies only 0.15 at node 1, and the 0.35 left there is
/// segment 1's to carry, above its capacity 0.3: it slides.
#[test]
fn a_sticking_segment_is_checked_on_what_a_sliding_neighbour_leaves_it() {
    let geometry = Geometry::Planar { thickness: 1.0 };
    let x = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]];
    let force = [[0.0, 0.5], [0.5, 1.0], [0.0, 0.5]];
    let run = |previous: [SegmentState; 2], directions: [f64; 2]| {
        evaluate(
            geometry,
            Recovery::Consistent,
            0.3,
            0.3,
            FrictionRule::MuDAfterSlip,
            false,
            &x,
            &[true; 3],
            &force,
            &previous,
            &[true, false],
            &directions,
        )
        .unwrap()
    };
    let ev = run([SegmentState::Slide, SegmentState::Stick], [1.0, 0.0]);
    assert!((ev.segments[1].tt_total - 0.25).abs() < 1e-12);
    assert!((ev.segments[1].tn_total - 1.0).abs() < 1e-12);
    assert_eq!(ev.segments[0].state, SegmentState::Slide);
    assert_eq!(ev.segments[1].state, SegmentState::Slide);
    assert_eq!(ev.node_states, vec![NodeState::Slip; 3]);
    // Both slide at mu: the pair applies exactly mu Fn.
    assert!((ev.ft - 0.3 * ev.fn_).abs() < 1e-12);
    // With no sliding neighbour the paper's check stands: both stick.
    let ev = run([SegmentState::Stick, SegmentState::Stick], [0.0, 0.0]);
    assert_eq!(ev.segments[0].state, SegmentState::Stick);
    assert_eq!(ev.segments[1].state, SegmentState::Stick);
}

/// A segment that was sliding keeps the direction of its friction while it slides,
/// whatever the sign of the T_t recovered in this iteration, and does not return to
/// sticking on force grounds.
#[test]
fn a_sliding_segment_keeps_its_direction_and_slides_on() {
    let geometry = Geometry::Planar { thickness: 1.0 };
    let x = [[0.0, 0.0], [2.0, 0.0]];
    // t_n = 1, t_t = 0.05: T_n = 2, T_t = 0.1, well below mu_d T_n = 0.4.
    let force = gauss_loads(geometry, false, &x, &[[0.05, 1.0], [0.05, 1.0]]);
    let ev = evaluate(
        geometry,
        Recovery::Consistent,
        0.3,
        0.2,
        FrictionRule::MuDAfterSlip,
        false,
        &x,
        &[true; 2],
        &force,
        &[SegmentState::Slide],
        &[true],
        &[-1.0],
    )
    .unwrap();
    assert_eq!(ev.segments[0].state, SegmentState::Slide);
    assert_eq!(ev.segments[0].sign, -1.0);
    assert!((ev.ft + 0.2 * 2.0).abs() < 1e-12, "ft = {}", ev.ft);
}
