//! The contact patch test over its family (issue 33): two stacked blocks
//! whose interface meshes do not match, drawn at random: 4- or 8-node
//! elements, 1 to 12 elements along the interface on either side, 1 to 4
//! through each block, block heights, widths and (axisymmetric) inner radii,
//! either material's E and nu, plane strain, plane stress or axisymmetric,
//! small strain or total Lagrangian. Under the default formulation (mortar,
//! the target a body) every node of the interface carries the exact uniform
//! pressure. Bounded for CI (`cases` below); `PROPTEST_CASES=2000 cargo
//! test --release --test mortar_patch_family` runs a longer campaign.
//!
//! Also a block dragged along a strip over the same family, with friction
//! (Coulomb at every node): ignored, it finds a failure not yet fixed
//! (`a_block_dragged_..._coulomb_friction`); the case it found first is a
//! test of its own (`a_frictional_press_of_unlike_poisson_ratios_...`).

use contact2d::newton::Solver;
use contact2d::results::{LogCategory, NodeState};
use proptest::prelude::*;

#[derive(Clone, Debug)]
struct Case {
    element: &'static str,
    /// Elements along the interface: upper (contactor), lower (target).
    along: [usize; 2],
    /// Elements through each block's height: upper, lower.
    through: [usize; 2],
    /// Heights: upper, lower.
    heights: [f64; 2],
    width: f64,
    /// Where the blocks start along x (the inner radius, axisymmetric).
    x0: f64,
    /// [E, nu] of the upper and lower blocks.
    materials: [[f64; 2]; 2],
    analysis: &'static str,
    kinematics: &'static str,
    /// The top's downward motion as a fraction of the stack's height.
    strain: f64,
}

impl Case {
    fn scene(&self) -> String {
        let [[e1, nu1], [e2, nu2]] = self.materials;
        let [au, al] = self.along;
        let [tu, tl] = self.through;
        let [hu, hl] = self.heights;
        let (w, x0) = (self.width, self.x0);
        let press = self.strain * (hu + hl);
        format!(
            r#"title = "patch family"
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
mesh = {{ generator = "rectangle", origin = [{x0:?}, {:?}], size = [{w:?}, {hl:?}], divisions = [{al}, {tl}] }}
[[body]]
name = "upper"
material = "upper"
element = "{element}"
mesh = {{ generator = "rectangle", origin = [{x0:?}, 0.0], size = [{w:?}, {hu:?}], divisions = [{au}, {tu}] }}
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
[[driver]]
name = "lower_right"
set = "lower.right"
ux = 0.0
[[driver]]
name = "upper_right"
set = "upper.right"
ux = 0.0
[[driver]]
name = "top"
set = "upper.top"
uy = {{ function = "press", scale = {:?} }}
[[contact]]
name = "interface"
contactor = "upper.bottom"
target = "lower.top"
[solver]
force_tolerance = 1e-13
displacement_tolerance = 1e-13
energy_tolerance = 1e-26
[steps]
dt = 0.5
t_end = 1.0
"#,
            -hl,
            -press,
            analysis = self.analysis,
            kinematics = self.kinematics,
            element = self.element,
        )
    }
}

/// The modulus of uniaxial strain (the sides held): E (1 - nu) / ((1 + nu)
/// (1 - 2 nu)) in plane strain and axisymmetry (the sides' rollers hold
/// u_r = 0 everywhere, so the hoop strain is zero too), E / (1 - nu^2) in
/// plane stress.
fn modulus(analysis: &str, [e, nu]: [f64; 2]) -> f64 {
    if analysis == "plane_stress" {
        e / (1.0 - nu * nu)
    } else {
        e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu))
    }
}

fn case() -> impl Strategy<Value = Case> {
    let material = (2.0..5.0f64, 0.0..0.45f64).prop_map(|(lg, nu)| [10f64.powf(lg), nu]);
    (
        prop_oneof![Just("q4"), Just("q8")],
        (1..=12usize, 1..=12usize),
        (1..=4usize, 1..=4usize),
        (0.3..2.0f64, 0.3..2.0f64, 0.5..3.0f64, 0.0..2.0f64),
        (material.clone(), material),
        prop_oneof![
            Just("plane_strain"),
            Just("plane_stress"),
            Just("axisymmetric")
        ],
        prop_oneof![Just("small_strain"), Just("total_lagrangian")],
        -4.0..-1.3f64,
    )
        .prop_filter("the meshes do not match", |c| c.1.0 != c.1.1)
        .prop_map(
            |(element, along, through, (hu, hl, width, x0), materials, analysis, kinematics, s)| {
                Case {
                    element,
                    along: [along.0, along.1],
                    through: [through.0, through.1],
                    heights: [hu, hl],
                    width,
                    x0,
                    materials: [materials.0, materials.1],
                    analysis,
                    kinematics,
                    strain: 10f64.powf(s),
                }
            },
        )
}

/// Solves `case` and checks every interface node: in contact, and its
/// normal traction the uniform pressure.
///
/// - Small strain: the exact solution is a homogeneous strain in either
///   block, p = press / sum(h / M), and lies in both meshes'
///   interpolation, so only the solve's round-off remains: 1e-9 relative
///   (the fixed patch tests in tests/mortar.rs measure 1e-13; the factor
///   leaves room for stiffness contrasts up to 1e3 and elements of aspect
///   ratio up to 24 here).
/// - Total Lagrangian: the Cauchy traction is the top's reaction over the
///   interface's current area (the sides held, so it does not change) and
///   the same at every node, to the same 1e-9. Newton is run to 1e-13
///   (`[solver]`): at the default 1e-8 it may stop with the tractions
///   2e-9 off (measured).
fn check(case: &Case) -> Result<(), TestCaseError> {
    let text = case.scene();
    let problem = contact2d::scene::parse(&text, std::path::Path::new("patch.toml"))
        .map_err(|e| TestCaseError::fail(format!("{case:?}: {e}")))?;
    let times = problem.times.clone();
    let mut solver = Solver::new(problem).map_err(|e| TestCaseError::fail(e.to_string()))?;
    let mut last = None;
    for t in times {
        let mut quiet = |_: LogCategory, _: &str| {};
        let step = solver
            .advance(t, &mut quiet)
            .map_err(|e| TestCaseError::fail(format!("{case:?} at t = {t}: {e}")))?;
        last = Some(step);
    }
    let step = last.unwrap();
    let top = step.drivers.iter().find(|d| d.0 == "top").unwrap().1.ry;
    let p = if case.kinematics == "small_strain" {
        let compliance: f64 = (case.heights.iter().zip(&case.materials))
            .map(|(h, &m)| h / modulus(case.analysis, m))
            .sum();
        case.strain * case.heights.iter().sum::<f64>() / compliance
    } else if case.analysis == "axisymmetric" {
        let (r0, r1) = (case.x0, case.x0 + case.width);
        -top / (std::f64::consts::PI * (r1 * r1 - r0 * r0))
    } else {
        -top / case.width
    };
    let nodes = &step.pairs[0].1.nodes;
    for (k, (&tn, &state)) in nodes.tn.iter().zip(&nodes.state).enumerate() {
        prop_assert_ne!(state, NodeState::Open, "{:?}: node {} open", case, k);
        prop_assert!(
            (tn - p).abs() <= 1e-9 * p,
            "{:?}: node {} at x = {:?}: t_n = {} against {} ({:+.2e})",
            case,
            k,
            nodes.x[k],
            tn,
            p,
            tn / p - 1.0
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    #[test]
    fn a_uniform_pressure_crosses_any_non_matching_flat_interface_exactly(case in case()) {
        check(&case)?;
    }
}

/// A block pressed onto a longer strip and dragged along it by its top,
/// the two meshes non-matching, with Coulomb friction (mu_s = mu_d).
#[derive(Clone, Debug)]
struct Drag {
    element: &'static str,
    /// Elements along the interface: block (contactor), strip (target,
    /// three times as long).
    along: [usize; 2],
    /// Heights: block, strip (each two elements through).
    heights: [f64; 2],
    width: f64,
    /// [E, nu] of the block and the strip.
    materials: [[f64; 2]; 2],
    analysis: &'static str,
    kinematics: &'static str,
    mu: f64,
}

impl Drag {
    fn scene(&self) -> String {
        let [[e1, nu1], [e2, nu2]] = self.materials;
        let [ab, as_] = self.along;
        let [hb, hs] = self.heights;
        let w = self.width;
        let mu = self.mu;
        // Pressed by a thousandth of the stack's height over t in [0, 1],
        // then dragged by the block's width over t in [1, 3] in ten
        // increments (a tenth of the width each, far beyond the elastic
        // shear that takes the whole interface to sliding).
        format!(
            r#"title = "drag family"
[analysis]
kind = "{analysis}"
kinematics = "{kinematics}"
[[material]]
name = "block"
model = "linear_elastic"
E = {e1:?}
nu = {nu1:?}
[[material]]
name = "strip"
model = "linear_elastic"
E = {e2:?}
nu = {nu2:?}
[[body]]
name = "strip"
material = "strip"
element = "{element}"
mesh = {{ generator = "rectangle", origin = [0.0, {:?}], size = [{:?}, {hs:?}], divisions = [{as_}, 2] }}
[[body]]
name = "block"
material = "block"
element = "{element}"
mesh = {{ generator = "rectangle", origin = [{:?}, 0.0], size = [{w:?}, {hb:?}], divisions = [{ab}, 2] }}
[[function]]
name = "press"
points = [[0.0, 0.0], [1.0, 1.0]]
[[function]]
name = "drag"
points = [[0.0, 0.0], [1.0, 0.0], [3.0, 1.0]]
[[driver]]
name = "base"
set = "strip.bottom"
ux = 0.0
uy = 0.0
[[driver]]
name = "top"
set = "block.top"
ux = {{ function = "drag", scale = {w:?} }}
uy = {{ function = "press", scale = {:?} }}
[[contact]]
name = "interface"
contactor = "block.bottom"
target = "strip.top"
mu_s = {mu:?}
mu_d = {mu:?}
[steps]
times = [0.5, 1.0, 1.2, 1.4, 1.6, 1.8, 2.0, 2.2, 2.4, 2.6, 2.8, 3.0]
"#,
            -hs,
            3.0 * w,
            0.5 * w,
            -1e-3 * (hb + hs),
            analysis = self.analysis,
            kinematics = self.kinematics,
            element = self.element,
        )
    }
}

impl Drag {
    /// `scene` with the pair's `formulation` set.
    fn scene_as(&self, formulation: &str) -> String {
        self.scene().replace(
            "target = \"strip.top\"",
            &format!("target = \"strip.top\"\nformulation = \"{formulation}\""),
        )
    }
}

fn drag(element: &'static str) -> impl Strategy<Value = Drag> {
    let material = (2.0..5.0f64, 0.0..0.45f64).prop_map(|(lg, nu)| [10f64.powf(lg), nu]);
    (
        Just(element),
        (2..=10usize, 1..=10usize),
        (0.3..2.0f64, 0.3..2.0f64, 0.5..3.0f64),
        (material.clone(), material),
        prop_oneof![Just("plane_strain"), Just("plane_stress")],
        prop_oneof![Just("small_strain"), Just("total_lagrangian")],
        0.1..0.6f64,
    )
        .prop_map(
            |(element, along, (hb, hs, width), materials, analysis, kinematics, mu)| Drag {
                element,
                along: [along.0, along.1],
                heights: [hb, hs],
                width,
                materials: [materials.0, materials.1],
                analysis,
                kinematics,
                mu,
            },
        )
}

/// Runs `case` and checks Coulomb's law at every node of every increment:
/// no node in contact in tension; once the drag has begun (after its first
/// increment, in which the stick zone releases), no node sticks, and every
/// sliding node carries |t_t| = mu t_n against its slip (where the output
/// measures one). The friction of a
/// sliding node is mu times its multiplier by construction, so the equality
/// holds to round-off (1e-12, as tests/mortar.rs's drag); no bisection, and
/// Newton within the issue's median 5 and max 15 iterations.
fn check_drag(case: &Drag) -> Result<(), TestCaseError> {
    check_drag_scene(case, &case.scene(), 1e-12)
}

/// `check_drag` on the scene `text` (`case`'s, edited), |t_t| = mu t_n
/// within `coulomb` relative.
fn check_drag_scene(case: &Drag, text: &str, coulomb: f64) -> Result<(), TestCaseError> {
    let problem = contact2d::scene::parse(text, std::path::Path::new("drag.toml"))
        .map_err(|e| TestCaseError::fail(format!("{case:?}: {e}")))?;
    let times = problem.times.clone();
    let mut solver = Solver::new(problem).map_err(|e| TestCaseError::fail(e.to_string()))?;
    let mut iterations = Vec::new();
    let mut sliding = 0;
    for t in times {
        let mut quiet = |_: LogCategory, _: &str| {};
        let step = solver
            .advance(t, &mut quiet)
            .map_err(|e| TestCaseError::fail(format!("{case:?} at t = {t}: {e}")))?;
        prop_assert_eq!(step.substeps, 0, "{:?} t = {}: bisected", case, t);
        iterations.push(step.iterations);
        let nodes = &step.pairs[0].1.nodes;
        for k in 0..nodes.state.len() {
            let (tn, tt, slip, state) = (nodes.tn[k], nodes.tt[k], nodes.slip[k], nodes.state[k]);
            if state != NodeState::Open {
                prop_assert!(tn >= 0.0, "{:?} t = {} node {}: tn = {}", case, t, k, tn);
            }
            if t < 1.3 {
                continue;
            }
            prop_assert_ne!(state, NodeState::Stick, "{:?} t = {} node {}", case, t, k);
            if state != NodeState::Slip || tn <= 0.0 {
                continue;
            }
            prop_assert!(
                (tt.abs() - case.mu * tn).abs() <= coulomb * case.mu * tn,
                "{:?} t = {} node {}: tt = {}, mu tn = {}",
                case,
                t,
                k,
                tt,
                case.mu * tn
            );
            // (The output's slip is zero for a node that was open when
            // the increment began: the stiff block's middle node lifts off
            // a coarse strip's vertex for an increment.)
            prop_assert!(
                slip == 0.0 || tt * slip < 0.0,
                "{:?} t = {} node {}: tt = {} along its slip {}",
                case,
                t,
                k,
                tt,
                slip
            );
            sliding += 1;
        }
    }
    prop_assert!(sliding > 0, "{:?}: no sliding node", case);
    let mut sorted = iterations.clone();
    sorted.sort_unstable();
    let (median, max) = (sorted[sorted.len() / 2], sorted[sorted.len() - 1]);
    prop_assert!(
        median <= 5 && max <= 15,
        "{:?}: iterations {:?}",
        case,
        iterations
    );
    Ok(())
}

/// The family's first failure, now a fixed case under both formulations: a
/// block of nu = 0.446 pressed onto a strip of nu = 0.066 (nearly equal E)
/// with mu = 0.157, then dragged. The block spreads more than the strip
/// under the press, so its bottom slides outward from a stick zone that
/// shrinks to the nodes round the slip's zero; released together, those
/// two neighbours made the slip's zero move past them and back without end
/// and the press failed at its first increment (13 stick/slip changes, 6
/// bisections), node-to-segment and mortar alike. Now one is held an
/// iteration longer (`nodal::parting`, `decide::parting`).
#[test]
fn a_frictional_press_of_unlike_poisson_ratios_settles_its_stick_zone() {
    for formulation in ["mortar", "node_to_segment"] {
        let case = Drag {
            element: "q4",
            along: [9, 5],
            heights: [1.2859, 1.6094],
            width: 1.3018,
            materials: [[1658.8, 0.4461], [1382.6, 0.0663]],
            analysis: "plane_strain",
            kinematics: "total_lagrangian",
            mu: 0.1573,
        };
        let text = case.scene_as(formulation);
        let problem = contact2d::scene::parse(&text, std::path::Path::new("drag.toml")).unwrap();
        let mut solver = Solver::new(problem).unwrap();
        let mut quiet = |_: LogCategory, _: &str| {};
        // The press: the stick zone in the middle, the rest sliding outward.
        let step = solver
            .advance(0.5, &mut quiet)
            .unwrap_or_else(|e| panic!("{formulation}: {e}"));
        assert_eq!(step.substeps, 0, "{formulation}: bisected");
        assert!(step.iterations <= 5, "{formulation}: {}", step.iterations);
        let nodes = &step.pairs[0].1.nodes;
        let stick = nodes
            .state
            .iter()
            .filter(|&&s| s == NodeState::Stick)
            .count();
        let slip = nodes
            .state
            .iter()
            .filter(|&&s| s == NodeState::Slip)
            .count();
        assert!(
            stick >= 1 && slip >= 2,
            "{formulation}: stick {stick}, slip {slip}"
        );
        // Coulomb at every node: within the cone, on it when sliding.
        // Mortar reports its multipliers, and a sliding node's friction is
        // mu times its normal one by construction: round-off (1e-12).
        // Node-to-segment reports each node's out-of-balance force, which
        // holds the converged residual too (up to 1e-8 of the force scale,
        // the default tolerance; a node carries a tenth of it here): 1e-6.
        let coulomb = if formulation == "mortar" { 1e-12 } else { 1e-6 };
        for k in 0..nodes.state.len() {
            let (tn, tt) = (nodes.tn[k], nodes.tt[k]);
            assert!(tn > 0.0, "{formulation} node {k}: tn = {tn}");
            assert!(
                tt.abs() <= case.mu * tn * (1.0 + coulomb),
                "{formulation} node {k}: tt = {tt}, mu tn = {}",
                case.mu * tn
            );
            if nodes.state[k] == NodeState::Slip {
                assert!(
                    (tt.abs() - case.mu * tn).abs() <= coulomb * case.mu * tn,
                    "{formulation} node {k}: tt = {tt}, mu tn = {}",
                    case.mu * tn
                );
            }
        }
        // And the drag: Coulomb at every node of every increment.
        check_drag_scene(&case, &text, coulomb).unwrap_or_else(|e| panic!("{formulation}: {e}"));
    }
}

/// A block of nu = 0.44 pressed with friction onto a stiffer strip (E 314
/// on 18262), then dragged, under both formulations and with 4- and
/// 8-node elements: its stick zone shrinks to a node or two round the
/// slip's zero. The inner solves of an iteration wandered through stick
/// and slip patterns (a one-node stick zone four nodes left, then back)
/// and the last one stood: the press failed its first increment after 6
/// bisections, every one of these four. Now the iterate's own decisions
/// stand when the inner solves do not settle (`Solver::unsettled`), and
/// the outer iteration narrows the zone. The press takes 7 to 12
/// iterations (it is the first increment of a proportional load: no
/// earlier state to start from), the drag after it 2 to 6.
#[test]
fn a_frictional_press_of_a_nearly_incompressible_block_settles_when_the_inner_solves_wander() {
    for (element, along, mu) in [("q4", [20, 5], 0.15), ("q8", [10, 5], 0.15)] {
        for formulation in ["mortar", "node_to_segment"] {
            let case = Drag {
                element,
                along,
                heights: [1.01, 0.3],
                width: 0.5,
                materials: [[314.0, 0.44], [18262.0, 0.0]],
                analysis: "plane_strain",
                kinematics: "small_strain",
                mu,
            };
            let text = case.scene_as(formulation);
            // Coulomb on the reported tractions: mortar's are its
            // multipliers (round-off); node-to-segment's on 4-node sides
            // each node's out-of-balance force over its length, which
            // holds the converged residual too (1e-6, as above). On 8-node
            // sides node-to-segment reports the quadratic fit of the nodal
            // forces, which does not keep Coulomb node by node (docs,
            // performance log, eighth session): that case is checked for
            // convergence and the contact states alone (`coulomb` infinite).
            let coulomb = match (formulation, element) {
                ("mortar", _) => 1e-12,
                (_, "q4") => 1e-6,
                _ => f64::INFINITY,
            };
            check_drag_scene(&case, &text, coulomb)
                .unwrap_or_else(|e| panic!("{element} {formulation}: {e}"));
        }
    }
}

/// The family's second failure, now a fixed case: a block dragged with mu
/// = 0.44 over a strip of another material, a strip vertex under the side
/// at the block's trailing corner. Released there (it pulled), the corner
/// node's weighted gap was zero or more but its hat-weighted gap -5.7e-8,
/// so the inner solve closed it again at every iteration, and mortar
/// failed at t = 2.0 after 6 bisections. Next to a node in contact a node
/// now closes on its weighted gap alone (`decide::enters`).
#[test]
fn a_dragged_block_s_trailing_corner_leaves_over_a_strip_vertex() {
    let case = Drag {
        element: "q4",
        along: [7, 5],
        heights: [0.96464, 1.23857],
        width: 0.74606,
        materials: [[1620.69, 0.24042], [859.954, 0.41947]],
        analysis: "plane_strain",
        kinematics: "total_lagrangian",
        mu: 0.43846,
    };
    check_drag(&case).unwrap_or_else(|e| panic!("{e}"));
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    /// Ignored: fails (`-- --ignored`, 2026-11-29) on cases proptest
    /// reduced (docs/performance-log.md, eighth session), both 8-node
    /// under mortar; node-to-segment runs them:
    /// - block 4 sides (E 9579, nu 0) over strip 5 sides (E 100, nu 0),
    ///   heights 1.10 / 1.78, width 0.5, mu 0.1, plane strain, small
    ///   strain: bisects once at t = 2.2 (the stiff block tilts onto a few
    ///   nodes of the soft strip; the node at its contact edge pulls in
    ///   contact and is inside the strip when open);
    /// - block 10 sides (E 314, nu 0.44) over strip 7 sides (E 18262, nu
    ///   0), heights 1.01 / 0.3, width 0.5, mu 0.194, plane strain, small
    ///   strain: the press failed at its first increment (so did
    ///   node-to-segment's, and 4-node presses of the kind: the inner
    ///   solves wandered, `scripts/press_sweep.py`). Since the ninth
    ///   session it converges, in 17 iterations (the issue's largest is
    ///   15): the outer iteration narrows the stick zone a node or two at
    ///   a time (docs/performance-log.md, ninth session).
    /// The family's other failures are fixed and have tests of their own
    /// above.
    #[test]
    #[ignore]
    fn a_block_dragged_over_any_non_matching_strip_slides_with_coulomb_friction(
        case in prop_oneof![drag("q4"), drag("q8")]
    ) {
        check_drag(&case)?;
    }
}
