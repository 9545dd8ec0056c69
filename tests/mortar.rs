//! Mortar contact between two bodies whose meshes do not match, against
//! closed forms: the contact patch test (a uniform pressure through a flat
//! interface is carried exactly, node by node).

mod common;

use common::mortar::{hertz_fit, lame_pressure, shrink_fit, two_cylinders};
use contact2d::newton::Solver;
use contact2d::results::{LogCategory, NodeState, PairResult};

/// One patch test: two stacked 2 x 1 blocks, the upper one's bottom the
/// contactor against the lower one's top under the default formulation
/// (mortar, the pair's target being a body), the lower block's bottom
/// held vertically, the upper one's top pushed down by `press`.
#[derive(Clone, Copy, Debug)]
struct Patch {
    element: &'static str,
    /// Elements along the interface: upper (contactor), lower (target).
    divisions: [usize; 2],
    /// [E, nu] of the upper and lower blocks.
    materials: [[f64; 2]; 2],
    analysis: &'static str,
    kinematics: &'static str,
    /// Both blocks' sides held laterally (uniaxial strain); otherwise only
    /// their left sides, and they expand sideways.
    rollers: bool,
    press: f64,
}

impl Patch {
    fn scene(&self) -> String {
        let [[e1, nu1], [e2, nu2]] = self.materials;
        let [nu, nl] = self.divisions;
        let (element, analysis, kinematics, press) =
            (self.element, self.analysis, self.kinematics, self.press);
        let right = if self.rollers {
            "[[driver]]\nname = \"lower_right\"\nset = \"lower.right\"\nux = 0.0\n\
             [[driver]]\nname = \"upper_right\"\nset = \"upper.right\"\nux = 0.0\n"
        } else {
            ""
        };
        format!(
            r#"title = "patch"
[analysis]
kind = "{analysis}"
kinematics = "{kinematics}"
[[material]]
name = "upper"
model = "linear_elastic"
E = {e1:?}
nu = {nu1:?}
[[material]]
name = "lower"
model = "linear_elastic"
E = {e2:?}
nu = {nu2:?}
[[body]]
name = "lower"
material = "lower"
element = "{element}"
mesh = {{ generator = "rectangle", origin = [0.0, -1.0], size = [2.0, 1.0], divisions = [{nl}, 3] }}
[[body]]
name = "upper"
material = "upper"
element = "{element}"
mesh = {{ generator = "rectangle", origin = [0.0, 0.0], size = [2.0, 1.0], divisions = [{nu}, 3] }}
[[function]]
name = "press"
points = [[0.0, 0.0], [1.0, 1.0]]
[[driver]]
name = "base"
set = "lower.bottom"
uy = 0.0
[[driver]]
name = "lower_left"
set = "lower.left"
ux = 0.0
[[driver]]
name = "upper_left"
set = "upper.left"
ux = 0.0
{right}[[driver]]
name = "top"
set = "upper.top"
uy = {{ function = "press", scale = {:?} }}
[[contact]]
name = "interface"
contactor = "upper.bottom"
target = "lower.top"
[steps]
dt = 0.5
t_end = 1.0
"#,
            -press
        )
    }

    /// The pair's results and the top driver's vertical reaction after
    /// the last increment, with the Newton iterations of each increment.
    fn solve(&self) -> (PairResult, f64, Vec<usize>) {
        let text = self.scene();
        let problem = contact2d::scene::parse(&text, std::path::Path::new("patch.toml"))
            .unwrap_or_else(|e| panic!("{self:?}: {e}"));
        let times = problem.times.clone();
        let mut solver = Solver::new(problem).unwrap();
        let mut iterations = Vec::new();
        let mut last = None;
        for t in times {
            let mut quiet = |_: LogCategory, _: &str| {};
            let step = solver
                .advance(t, &mut quiet)
                .unwrap_or_else(|e| panic!("{self:?} at t = {t}: {e}"));
            iterations.push(step.iterations);
            last = Some(step);
        }
        let step = last.unwrap();
        let top = step.drivers.iter().find(|d| d.0 == "top").unwrap().1.ry;
        (step.pairs[0].1.clone(), top, iterations)
    }
}

/// Uniaxial strain modulus E (1 - nu) / ((1 + nu)(1 - 2 nu)).
fn constrained_modulus([e, nu]: [f64; 2]) -> f64 {
    e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu))
}

/// Every node of the interface in contact with the traction `p`: within
/// 1e-9 relative. The exact solution lies in both meshes' interpolation
/// (a homogeneous strain), and mortar contact reproduces a uniform
/// traction exactly, so only the round-off of the solve remains (1e-13
/// measured); 1e-9 leaves room for the conditioning of finer meshes.
fn assert_uniform(case: &Patch, pair: &PairResult, p: f64) {
    let nodes = &pair.nodes;
    for (k, (&tn, &state)) in nodes.tn.iter().zip(&nodes.state).enumerate() {
        assert_ne!(state, NodeState::Open, "{case:?}: node {k} open");
        assert!(
            (tn - p).abs() <= 1e-9 * p,
            "{case:?}: node {k} at x = {}: t_n = {tn} against {p} ({:+.2e})",
            nodes.x[k],
            tn / p - 1.0
        );
    }
}

/// The contact patch test under small strain, laterally held blocks
/// (uniaxial strain, p = press / sum(h / M)): 4- and 8-node elements,
/// coarse over fine and fine over coarse, equal and unequal moduli, plane
/// strain and axisymmetric (the r-weighted integrals).
#[test]
fn patch_test_uniform_pressure_to_round_off() {
    for element in ["q4", "q8"] {
        for divisions in [[7, 5], [3, 8]] {
            for materials in [
                [[1000.0, 0.3], [1000.0, 0.3]],
                [[3000.0, 0.2], [1000.0, 0.35]],
            ] {
                for analysis in ["plane_strain", "axisymmetric"] {
                    let case = Patch {
                        element,
                        divisions,
                        materials,
                        analysis,
                        kinematics: "small_strain",
                        rollers: true,
                        press: 0.01,
                    };
                    let (pair, _, iterations) = case.solve();
                    let compliance: f64 = materials
                        .iter()
                        .map(|&m| 1.0 / constrained_modulus(m))
                        .sum();
                    assert_uniform(&case, &pair, case.press / compliance);
                    // A linear problem once the contact is closed: Newton
                    // needs the closing solve and one to confirm.
                    assert!(
                        iterations.iter().all(|&i| i <= 2),
                        "{case:?}: {iterations:?}"
                    );
                }
            }
        }
    }
}

/// Blocks free to expand sideways, of one material, so that the interface
/// stretches alike on both sides: the plane strain p = press / sum(h (1 -
/// nu^2) / E), both meshes non-matching and sliding along each other.
#[test]
fn patch_test_with_lateral_expansion() {
    for element in ["q4", "q8"] {
        for divisions in [[7, 5], [3, 8]] {
            let m = [1000.0, 0.3];
            let case = Patch {
                element,
                divisions,
                materials: [m, m],
                analysis: "plane_strain",
                kinematics: "small_strain",
                rollers: false,
                press: 0.01,
            };
            let (pair, _, _) = case.solve();
            let p = case.press / (2.0 * (1.0 - m[1] * m[1]) / m[0]);
            assert_uniform(&case, &pair, p);
        }
    }
}

/// Total Lagrangian kinematics, a 5 % compression: the Cauchy traction
/// is the top's reaction over the interface's current width (2: the
/// sides are held), the same at every node.
#[test]
fn patch_test_total_lagrangian() {
    for element in ["q4", "q8"] {
        for divisions in [[7, 5], [3, 8]] {
            let case = Patch {
                element,
                divisions,
                materials: [[3000.0, 0.2], [1000.0, 0.35]],
                analysis: "plane_strain",
                kinematics: "total_lagrangian",
                rollers: true,
                press: 0.1,
            };
            let (pair, top, _) = case.solve();
            assert_uniform(&case, &pair, -top / 2.0);
        }
    }
}

/// Non-matching axisymmetric shrink fits, tube and solid hubs: every
/// node's pressure equals Lame's within the radial mesh's error. The
/// solution does not vary along the axis, so every node carries the same
/// pressure (to 1e-9) and what is left is the two rings' radial compliance
/// on the mesh: 8 radial 4-node elements measured 3.8e-4 (tube) and 3.6e-4
/// (solid), 4 radial 8-node elements 1.5e-6 and 1.2e-6; tolerances 1e-3
/// and 1e-5. (Node-to-segment on the same meshes: -20 % .. +15 % with
/// 4-node elements, -69 % .. +136 % with 8-node ones.)
#[test]
fn shrink_fit_nodal_pressures_follow_lame() {
    for (element, radial, tolerance) in [("q4", 8, 1e-3), ("q8", 4, 1e-5)] {
        for a in [50.0, 0.0] {
            let text = shrink_fit(element, a, radial);
            let problem = contact2d::scene::parse(&text, std::path::Path::new("fit.toml"))
                .unwrap_or_else(|e| panic!("{e}"));
            let mut solver = Solver::new(problem).unwrap();
            let step = solver.advance(1.0, &mut |_, _| {}).unwrap();
            let nodes = &step.pairs[0].1.nodes;
            let p = lame_pressure(a);
            let first = nodes.tn[0];
            for (k, &tn) in nodes.tn.iter().enumerate() {
                assert!(
                    (tn - first).abs() <= 1e-9 * p,
                    "{element} a = {a}: node {k} {tn} against node 0 {first}"
                );
                assert!(
                    (tn / p - 1.0).abs() <= tolerance,
                    "{element} a = {a}: node {k} {tn} against Lame {p} ({:+.2e})",
                    tn / p - 1.0
                );
            }
        }
    }
}

/// Hertz between two flexible cylinders whose meshes do not match, 4- and
/// 8-node elements: the contact edge a falls between the last node in
/// contact and the next (the mesh's resolution); within 0.8 a the nodal
/// pressures follow Hertz and do not swing from node to node. Measured
/// (deviation, swing): 4-node 0.76 %, 0.64 %; 8-node 0.65 %, 0.31 %; the
/// same meshes under node-to-segment contact swing by 3.6 % (4-node) and
/// 29 % (8-node; `cargo bench --bench mortar`). Tolerances: the swing 1.5 %, half the
/// 3 % of p0 the issue allows; the deviation 1.5 %, twice the measured,
/// which is the meshes' (a / h of 10 on the target, 20 on the contactor).
#[test]
fn two_cylinders_follow_hertz_without_swing() {
    for (element, disk, ring) in [("q4", 60, [16, 480]), ("q8", 40, [10, 320])] {
        let fit = hertz_fit(&two_cylinders(element, "mortar", disk, ring));
        let [inside, outside] = fit.edge;
        assert!(
            inside <= fit.a && fit.a <= outside,
            "{element}: a = {} not between the last node in contact at {inside} and the next at {outside}",
            fit.a
        );
        assert!(
            fit.swing <= 0.015,
            "{element}: swing {:.4} of p0",
            fit.swing
        );
        assert!(
            fit.deviation <= 0.015,
            "{element}: deviation {:.4} of p0",
            fit.deviation
        );
        // Newton with the inner solves: as node-to-segment on this scene.
        assert!(
            fit.iterations.iter().all(|&i| i <= 5),
            "{element}: {:?}",
            fit.iterations
        );
    }
}

/// The block of scenes/verification/flexible_target.toml dragged over the
/// coarse flexible strip with Coulomb friction (mu = 0.2) under mortar
/// contact, 4- and 8-node elements. Once the drag has started every node
/// in contact slides, and each one's friction is mu times its pressure
/// against its slip: the slip over the step (the summary's, measured from
/// positions against the target's material point it touched) and tt of
/// opposite signs. No node in tension; no bisection; Newton within the
/// issue's bounds (median <= 5, max <= 15 iterations per increment;
/// measured with 4-node elements median 2, max 3).
///
/// Also with mu_s = 0.3 above mu_d = 0.2 under either rule (the usual
/// one, and the experiment's mu_s throughout, which re-decides each node
/// that slid before as sticking at an increment's first decision): the
/// nodes slide with mu_d.
#[test]
fn drag_over_a_flexible_strip_slides_with_coulomb_friction() {
    let cases = [
        ("q4", 0.2, "mu_d_after_slip"),
        ("q8", 0.2, "mu_d_after_slip"),
        ("q4", 0.3, "mu_d_after_slip"),
        ("q4", 0.3, "always_mu_s"),
    ];
    for (element, mu_s, rule) in cases {
        let mu = 0.2;
        let friction =
            format!("mu_s = {mu_s}\nmu_d = {mu}\nrule = \"{rule}\"\nformulation = \"mortar\"");
        let q8 = format!("element = \"{element}\"");
        let q8_block =
            format!("element = \"{element}\"\nmesh = {{ generator = \"rectangle\", origin = [3.0");
        let problem = common::shipped_scene(
            "verification/flexible_target.toml",
            // Both bodies' elements (each edit replaces once).
            &[
                ("mu_s = 0.0", &friction),
                ("element = \"q4\"", &q8),
                (
                    "element = \"q4\"\nmesh = { generator = \"rectangle\", origin = [3.0",
                    &q8_block,
                ),
            ],
        );
        let times = problem.times.clone();
        let mut solver = Solver::new(problem).unwrap();
        let mut iterations = Vec::new();
        let mut sliding = 0;
        for t in times {
            let step = solver
                .advance(t, &mut |_, _| {})
                .unwrap_or_else(|e| panic!("{element} at t = {t}: {e}"));
            assert_eq!(step.substeps, 0, "{element} t = {t}: bisected");
            iterations.push(step.iterations);
            let nodes = &step.pairs[0].1.nodes;
            for k in 0..nodes.state.len() {
                let (tn, tt, slip) = (nodes.tn[k], nodes.tt[k], nodes.slip[k]);
                if nodes.state[k] != NodeState::Open {
                    assert!(tn >= 0.0, "{element} t = {t} node {k}: tn = {tn}");
                }
                // Past the press and the first drag increment (the stick
                // zones' release).
                if t < 1.1 {
                    continue;
                }
                if nodes.state[k] == NodeState::Stick {
                    panic!("{element} t = {t} node {k} sticks during the drag");
                }
                if nodes.state[k] != NodeState::Slip || tn <= 0.0 {
                    continue;
                }
                assert!(
                    (tt.abs() - mu * tn).abs() <= 1e-12 * tn,
                    "{element} t = {t} node {k}: tt = {tt}, mu tn = {}",
                    mu * tn
                );
                assert!(
                    tt * slip < 0.0 && slip.abs() > 0.1,
                    "{element} t = {t} node {k}: tt = {tt} along its slip {slip}"
                );
                sliding += 1;
            }
        }
        assert!(sliding > 100, "{element}: {sliding} sliding node values");
        let mut sorted = iterations.clone();
        sorted.sort_unstable();
        let (median, max) = (sorted[sorted.len() / 2], sorted[sorted.len() - 1]);
        println!(
            "{element} mu_s {mu_s} {rule}: iterations median {median}, max {max}; \
             {sliding} sliding node values"
        );
        assert!(
            median <= 5 && max <= 15,
            "{element}: iterations {iterations:?}"
        );
    }
}

/// The cylinder of `scenes/hertz_plane_strain.toml` pressed onto its flat:
/// the nodal pressures within 0.8 a against Hertz (`common::hertz`), as
/// RMS and largest node-to-node change of the error, both over p0.
fn hertz_on_flat(edits: &[(&str, &str)]) -> [f64; 2] {
    let ran = common::mortar::run(common::shipped_scene("hertz_plane_strain.toml", edits));
    let hertz = common::hertz(&ran.solver, 10.0, 200000.0 / (1.0 - 0.09));
    let problem = ran.solver.problem();
    let nodes = &ran.last.pairs[0].1.nodes;
    let errors: Vec<f64> = (problem.contacts[0].contactor.iter().zip(&nodes.tn))
        .map(|(&c, tn)| (problem.mesh.nodes[c][0], tn))
        .filter(|(x, _)| *x < 0.8 * hertz.a)
        .map(|(x, tn)| (tn - common::hertz_pressure(hertz.p0, hertz.a, x)) / hertz.p0)
        .collect();
    let swing = (errors.windows(2)).fold(0.0, |m: f64, w| m.max((w[1] - w[0]).abs()));
    [hertz.rms_interior, swing]
}

/// Why node-to-segment stays the default against a rigid target (mortar
/// against a rigid is not built): against a rigid there are no target
/// nodes between contactor nodes to penetrate and no target shape
/// functions for the forces to follow, so node-to-segment is as accurate
/// as mortar. Hertz on the rigid flat (node-to-segment) against Hertz on
/// a flat body 1e5 times stiffer than the cylinder, meshed with 8-node
/// elements that do not match it, under mortar: measured RMS 0.055 % and
/// 0.060 % of p0, node-to-node change 0.053 % and 0.19 %. The test fails
/// if mortar against a near-rigid flat becomes the more accurate by more
/// than a tenth of node-to-segment's error, which would call for mortar
/// against rigid targets and a new default.
#[test]
fn against_a_stiff_flat_mortar_is_no_more_accurate_than_node_to_segment_on_the_rigid() {
    const RIGID: &str = "[[rigid]]\nname = \"flat\"\n# The floor lies below y = 0: walking from +x to -x it is on the left.\npoints = [[12.0, 0.0], [-2.0, 0.0]]\n";
    const STIFF_FLAT: &str = r#"[[material]]
name = "stiff"
model = "linear_elastic"
E = 2.0e10
nu = 0.3

[[body]]
name = "flat"
material = "stiff"
element = "q8"
mesh = { generator = "rectangle", origin = [0.0, -1.0], size = [3.0, 1.0], divisions = [130, 4] }

[[driver]]
name = "ground"
set = "flat.bottom"
ux = 0.0
uy = 0.0

[[driver]]
name = "flat_axis"
set = "flat.left"
ux = 0.0
"#;
    let [rms_rigid, swing_rigid] = hertz_on_flat(&[]);
    let [rms_mortar, swing_mortar] = hertz_on_flat(&[
        (RIGID, STIFF_FLAT),
        ("target = \"flat\"", "target = \"flat.top\""),
    ]);
    println!(
        "node-to-segment on the rigid flat: RMS {rms_rigid:.5}, swing {swing_rigid:.5}; \
         mortar on the stiff flat: RMS {rms_mortar:.5}, swing {swing_mortar:.5}"
    );
    // The Hertz scene's accuracy away from the edge, as
    // tests/contact_hertz.rs bounds it (what is left is Hertz's half-space
    // against a finite cylinder, not the mesh).
    assert!(rms_rigid < 1e-3 && rms_mortar < 1e-3);
    assert!(
        rms_mortar >= 0.9 * rms_rigid && swing_mortar >= 0.9 * swing_rigid,
        "mortar on the stiff flat: RMS {rms_mortar}, swing {swing_mortar}"
    );
}

/// A sphere (axisymmetric, 8-node) pressed with friction onto a block whose
/// top is the contactor, its sides longer than the contact radius: the
/// zone lies within the block's first side, whose corner on the axis has no
/// weight (`int N 2 pi r` vanishes there) and takes the state and the
/// tractions of the side's mid-side node. It reported the dual basis
/// field's value there instead, -lambda_mid (tension, -229 against +229).
#[test]
fn an_axis_node_of_no_weight_reports_its_side_s_traction() {
    let text = r#"title = "sphere on a block"
[analysis]
kind = "axisymmetric"
kinematics = "small_strain"
[[material]]
name = "a"
model = "linear_elastic"
E = 17419.5
nu = 0.35
[[material]]
name = "b"
model = "linear_elastic"
E = 21345.2
nu = 0.21
[[body]]
name = "sphere"
material = "a"
element = "q8"
mesh = { generator = "disk", center = [0.0, 13.466], radius = 13.466, divisions = 32, ratio = 4.0, half = false }
[[body]]
name = "block"
material = "b"
element = "q8"
mesh = { generator = "rectangle", origin = [0.0, -5.734], size = [14.787, 5.734], divisions = [23, 4] }
[[function]]
name = "press"
points = [[0.0, 0.0], [1.0, 1.0]]
[[driver]]
name = "base"
set = "block.bottom"
ux = 0.0
uy = 0.0
[[driver]]
name = "axis"
set = "sphere.axis"
ux = 0.0
[[driver]]
name = "block_axis"
set = "block.left"
ux = 0.0
[[driver]]
name = "press"
set = "sphere.top"
uy = { function = "press", scale = -0.03 }
[[contact]]
name = "interface"
contactor = "block.top"
target = "sphere.arc"
mu_s = 0.387
mu_d = 0.387
[steps]
dt = 0.25
t_end = 1.0
"#;
    let problem = contact2d::scene::parse(text, std::path::Path::new("sphere.toml")).unwrap();
    let times = problem.times.clone();
    let mut solver = Solver::new(problem).unwrap();
    for t in times {
        let step = solver.advance(t, &mut |_, _| {}).unwrap();
        let nodes = &step.pairs[0].1.nodes;
        let axis = (0..nodes.x.len()).find(|&k| nodes.x[k] == 0.0).unwrap();
        let next = (0..nodes.x.len())
            .filter(|&k| k != axis)
            .min_by(|&a, &b| nodes.x[a].total_cmp(&nodes.x[b]))
            .unwrap();
        assert_ne!(nodes.state[axis], NodeState::Open, "t = {t}");
        assert_eq!(nodes.state[axis], nodes.state[next], "t = {t}");
        assert!(nodes.tn[axis] > 0.0, "t = {t}: axis tn {}", nodes.tn[axis]);
        assert_eq!(
            (nodes.tn[axis], nodes.tt[axis]),
            (nodes.tn[next], nodes.tt[next]),
            "t = {t}"
        );
    }
}

/// A frictional mortar pair's state (its memory in mortar's own type)
/// written as the FMU writes it (JSON) and read back continues as the
/// state itself does, bit for bit.
#[test]
fn a_frictional_mortar_state_read_back_continues_bit_for_bit() {
    let edits = [(
        "mu_s = 0.0",
        "mu_s = 0.2\nmu_d = 0.2\nformulation = \"mortar\"",
    )];
    let scene = || common::shipped_scene("verification/flexible_target.toml", &edits);
    let times = scene().times.clone();
    let (before, after) = times.split_at(times.len() / 2);
    let mut solver = Solver::new(scene()).unwrap();
    for &t in before {
        solver.advance(t, &mut |_, _| {}).unwrap();
    }
    let state = solver.state().clone();
    let json = serde_json::to_string(&state).unwrap();
    let [mut kept, mut read] = [(); 2].map(|_| Solver::new(scene()).unwrap());
    kept.restore(state);
    read.restore(serde_json::from_str(&json).unwrap());
    assert_eq!(read.state(), kept.state());
    for &t in after {
        let [a, b] = [&mut kept, &mut read].map(|s| s.advance(t, &mut |_, _| {}).unwrap());
        let key = |s: &contact2d::results::StepResult| {
            format!("{:?}", (s.iterations, &s.drivers, &s.pairs))
        };
        assert_eq!(key(&a), key(&b), "t = {t}");
    }
}
