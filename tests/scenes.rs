//! The shipped verification scenes, run through the scene reader and the
//! solver, against their closed-form or published values.

mod common;

use contact2d::newton::Solver;
use contact2d::results::LogCategory;

/// The scene `name` with each `(old, new)` replaced once (a refined mesh),
/// solved through its load history; the Newton log lines are returned.
fn solve(name: &str, edits: &[(&str, &str)]) -> (Solver, Vec<String>) {
    let problem = common::shipped_scene(name, edits);
    let times = problem.times.clone();
    let mut solver = Solver::new(problem).unwrap();
    let mut lines = Vec::new();
    for t in times {
        let r = solver
            .advance(t, &mut |c, m| {
                if c == LogCategory::Newton {
                    lines.push(m.to_string())
                }
            })
            .unwrap_or_else(|e| panic!("{name} at t = {t}: {e}"));
        assert!(r.converged);
    }
    (solver, lines)
}

/// Lame: a = 1, b = 2, p = 100, E = 210000, nu = 0.3, axial strain zero.
mod lame {
    pub const A: f64 = 1.0;
    pub const B: f64 = 2.0;
    const P: f64 = 100.0;
    const E: f64 = 210000.0;
    const NU: f64 = 0.3;
    const K: f64 = P * A * A / (B * B - A * A);

    pub fn u_r(r: f64) -> f64 {
        (1.0 + NU) * K / E * ((1.0 - 2.0 * NU) * r + B * B / r)
    }

    /// Hoop stress averaged over the volume of r1 < r < r2 (weight r).
    pub fn hoop_average(r1: f64, r2: f64) -> f64 {
        let area = (r2 * r2 - r1 * r1) / 2.0;
        K * (area + B * B * (r2 / r1).ln()) / area
    }
}

/// Largest relative errors of nodal u_r and element hoop stress (the
/// latter against the exact volume average over the element).
fn lame_errors(element: &str, divisions: usize) -> (f64, f64) {
    let (s, _) = solve(
        "verification/lame_cylinder.toml",
        &[
            ("element = \"q8\"", &format!("element = \"{element}\"")),
            (
                "divisions = [8, 1]",
                &format!("divisions = [{divisions}, 1]"),
            ),
        ],
    );
    let p = s.problem();
    let mut eu: f64 = 0.0;
    for (n, x) in p.mesh.nodes.iter().enumerate() {
        let [ur, uz] = s.state().displacement(n);
        assert!(
            uz.abs() < 1e-12 * lame::u_r(lame::A),
            "u_z = {uz} at node {n}"
        );
        eu = eu.max((ur / lame::u_r(x[0]) - 1.0).abs());
    }
    let mut es: f64 = 0.0;
    for (e, stress) in p.mesh.elements.iter().zip(s.element_stresses()) {
        let r = e.nodes.iter().map(|&n| p.mesh.nodes[n][0]);
        let (r1, r2) = (
            r.clone().fold(f64::MAX, f64::min),
            r.fold(f64::MIN, f64::max),
        );
        es = es.max((stress[2] / lame::hoop_average(r1, r2) - 1.0).abs());
    }
    (eu, es)
}

#[test]
fn lame_cylinder_within_half_a_percent_and_converging() {
    // The shipped mesh: 8 Q8 across the wall. The issue asks for 0.5 %; Q8
    // reproduces the quadratic-plus-1/r field to about 1e-5 here, so 0.5 %
    // is a loose bound and the refinement below is the sharper check.
    let (eu, es) = lame_errors("q8", 8);
    assert!(eu < 5e-3 && es < 5e-3, "u_r {eu:.3e}, hoop {es:.3e}");
    // Q4 under refinement 4 -> 8 -> 16: the hoop-stress error against the
    // element's exact average falls like h^2 (ratio about 4 per halving,
    // asserted above 3); nodal u_r falls at least as fast.
    let errors: Vec<(f64, f64)> = [4, 8, 16].map(|n| lame_errors("q4", n)).to_vec();
    for w in errors.windows(2) {
        let (u, s) = (w[0].0 / w[1].0, w[0].1 / w[1].1);
        assert!(
            u > 3.0 && s > 3.0,
            "ratios u {u:.2}, hoop {s:.2}: {errors:?}"
        );
    }
    // Q8 refined 4 -> 8 also converges (faster than Q4).
    let (eu4, es4) = lame_errors("q8", 4);
    assert!(
        eu4 > eu && es4 > es,
        "Q8 4: {eu4:.2e} {es4:.2e}, 8: {eu:.2e} {es:.2e}"
    );
}

#[test]
fn cantilever_matches_the_elastica() {
    let (s, lines) = solve("verification/cantilever_tip_load.toml", &[]);
    let p = s.problem();
    let tip = p.mesh.node_sets["beam.tip"][0];
    assert_eq!(p.mesh.nodes[tip], [10.0, 0.1]);
    let [ux, uy] = s.state().displacement(tip);
    let (u, v) = (-ux / 10.0, -uy / 10.0);
    // Mattiasson (1981), k = 1: v/L = 0.30172, u/L = 0.05643. Tolerance
    // 0.2 %: the table's rounding (1e-4 relative on u), and the continuum's
    // own difference from the elastica (shear of the h/L = 1/50 beam, about
    // 2.4e-4 on v; stretching, P/EA = 3e-5). Refined to 200 x 8 the solution
    // settles at +3.0e-4 on v and +6.3e-4 on u (benches/refinement.rs); this
    // 50 x 2 mesh is within 2e-5 of that.
    assert!((v / 0.30172 - 1.0).abs() < 2e-3, "v/L = {v}");
    assert!((u / 0.05643 - 1.0).abs() < 2e-3, "u/L = {u}");
    // The log shows Newton's quadratic rate: some iteration's estimate
    // ln(r_k/r_k-1)/ln(r_k-1/r_k-2) is near 2 before round-off sets in.
    let best = common::rates(&lines).into_iter().fold(0.0f64, f64::max);
    assert!(best > 1.7, "best rate {best}\n{}", lines.join("\n"));
}
