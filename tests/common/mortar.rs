//! Scenes of two bodies meeting on non-matching meshes, for the mortar
//! tests and the mortar benchmark.

use contact2d::newton::Solver;
use contact2d::problem::Problem;
use contact2d::results::{NodeState, StepResult};

/// The text of an axisymmetric shrink fit: a hub (r from `a`, 0 for a
/// solid one, to b + delta = 75.05) inside a rim (r from b = 75 to c =
/// 100), 40 high, both held axially at top and bottom (plane strain in z,
/// so Lame's plane strain solution holds), the radial overlap delta = 0.05
/// the only load; the interface meshed with 5 hub sides against 7 rim
/// sides.
pub fn shrink_fit(element: &str, a: f64, radial: usize) -> String {
    format!(
        r#"title = "shrink fit"
[analysis]
kind = "axisymmetric"
kinematics = "small_strain"
[[material]]
name = "steel"
model = "linear_elastic"
E = 200000.0
nu = 0.3
[[material]]
name = "aluminium"
model = "linear_elastic"
E = 70000.0
nu = 0.33
[[body]]
name = "hub"
material = "steel"
element = "{element}"
mesh = {{ generator = "rectangle", origin = [{a:?}, 0.0], size = [{:?}, 40.0], divisions = [{radial}, 5] }}
[[body]]
name = "rim"
material = "aluminium"
element = "{element}"
mesh = {{ generator = "rectangle", origin = [75.0, 0.0], size = [25.0, 40.0], divisions = [{radial}, 7] }}
[[driver]]
name = "hub_bottom"
set = "hub.bottom"
uy = 0.0
[[driver]]
name = "hub_top"
set = "hub.top"
uy = 0.0
[[driver]]
name = "rim_bottom"
set = "rim.bottom"
uy = 0.0
[[driver]]
name = "rim_top"
set = "rim.top"
uy = 0.0
[[contact]]
name = "fit"
contactor = "hub.right"
target = "rim.left"
[steps]
dt = 1.0
t_end = 1.0
"#,
        75.05 - a
    )
}

/// Lame's interface pressure on the hub (per its reference area, radius
/// b + delta) for a hub from `a`: the hub's outer radius and the rim's
/// bore carry the same force per radian F, and the bore's growth plus the
/// hub's shrinkage close the overlap (plane strain: E' = E / (1 - nu^2),
/// nu' = nu / (1 - nu)).
pub fn lame_pressure(a: f64) -> f64 {
    let (b, c, delta) = (75.0, 100.0, 0.05);
    let plane = |e: f64, nu: f64| (e / (1.0 - nu * nu), nu / (1.0 - nu));
    let ((e_hub, nu_hub), (e_rim, nu_rim)) = (plane(200000.0, 0.3), plane(70000.0, 0.33));
    let bi = b + delta;
    let rim = ((c * c + b * b) / (c * c - b * b) + nu_rim) / e_rim;
    let hub = ((bi * bi + a * a) / (bi * bi - a * a) - nu_hub) / e_hub;
    delta / (rim + hub) / bi
}

/// Two equal elastic cylinders (R = 10, steel) pressed together, plane
/// strain, quarter models: the upper one a graded `disk` (its arc the
/// contactor), the lower one a `ring` with a small bore (r 0.5 .. 10, its
/// outer arc the target, held at its horizontal diameter), so that the
/// two arcs' nodes do not match. `elements`: "q4" or "q8";
/// `divisions`: the disk's, and the ring's [radial, around].
pub fn two_cylinders(element: &str, formulation: &str, disk: usize, ring: [usize; 2]) -> String {
    format!(
        r#"title = "two cylinders"
[analysis]
kind = "plane_strain"
kinematics = "small_strain"
[[material]]
name = "steel"
model = "linear_elastic"
E = 200000.0
nu = 0.3
[[body]]
name = "upper"
material = "steel"
element = "{element}"
mesh = {{ generator = "disk", center = [0.0, 10.0], radius = 10.0, divisions = {disk}, ratio = 40.0 }}
[[body]]
name = "lower"
material = "steel"
element = "{element}"
mesh = {{ generator = "ring", center = [0.0, -10.0], r_inner = 0.5, r_outer = 10.0, angles = [0.0, 90.0], divisions = [{}, {}], ratio = 0.2 }}
[[function]]
name = "ramp"
points = [[0.0, 0.0], [1.0, 1.0]]
[[driver]]
name = "upper_axis"
set = "upper.axis"
ux = 0.0
[[driver]]
name = "lower_axis"
set = "lower.end"
ux = 0.0
[[driver]]
name = "lower_base"
set = "lower.start"
uy = 0.0
[[driver]]
name = "press"
set = "upper.top"
uy = {{ function = "ramp", scale = -0.1 }}
[[contact]]
name = "contact"
contactor = "upper.arc"
target = "lower.outer"
formulation = "{formulation}"
[steps]
dt = 0.5
t_end = 1.0
"#,
        ring[0], ring[1]
    )
}

/// Against Hertz for two cylinders (R* = R / 2, E* = E / (2 (1 - nu^2)),
/// P twice the quarter's force): per node within 0.8 a, the deviation
/// from p0 sqrt(1 - x^2 / a^2) over p0; its largest, and the largest
/// change between neighbouring nodes (the swing); the last node in
/// contact and the first open one beyond it, with a.
pub struct HertzFit {
    pub deviation: f64,
    pub swing: f64,
    pub edge: [f64; 2],
    pub a: f64,
    pub iterations: Vec<usize>,
    /// Wall time of the increments, s.
    pub seconds: f64,
    /// Where the run's time went, with the counts (`Phases::summary`).
    pub split: String,
}

/// A problem run through its times: the solver after it, the Newton
/// iterations of each increment, the last step and the wall time, s.
pub struct Ran {
    pub solver: Solver,
    pub iterations: Vec<usize>,
    pub last: StepResult,
    pub seconds: f64,
}

pub fn run(problem: Problem) -> Ran {
    let times = problem.times.clone();
    let start = std::time::Instant::now();
    let mut solver = Solver::new(problem).unwrap();
    let mut iterations = Vec::new();
    let mut last = None;
    for t in times {
        let step = solver.advance(t, &mut |_, _| {}).unwrap();
        iterations.push(step.iterations);
        last = Some(step);
    }
    Ran {
        seconds: start.elapsed().as_secs_f64(),
        solver,
        iterations,
        last: last.expect("a problem with times"),
    }
}

pub fn hertz_fit(text: &str) -> HertzFit {
    let problem = contact2d::scene::parse(text, std::path::Path::new("cylinders.toml"))
        .unwrap_or_else(|e| panic!("{e}"));
    let Ran {
        solver,
        iterations,
        last: step,
        seconds,
    } = run(problem);
    let press = step.drivers.iter().find(|d| d.0 == "press").unwrap().1.ry;
    let load = 2.0 * press.abs();
    let e_star = 200000.0 / (2.0 * (1.0 - 0.09));
    let a = (4.0 * load * 5.0 / (std::f64::consts::PI * e_star)).sqrt();
    let p0 = 2.0 * load / (std::f64::consts::PI * a);
    let nodes = &step.pairs[0].1.nodes;
    let mut order: Vec<usize> = (0..nodes.x.len()).collect();
    order.sort_by(|&i, &j| nodes.x[i].total_cmp(&nodes.x[j]));
    let inside: Vec<f64> = (order.iter())
        .filter(|&&k| nodes.x[k] < 0.8 * a)
        .map(|&k| (nodes.tn[k] - p0 * (1.0 - (nodes.x[k] / a).powi(2)).sqrt()) / p0)
        .collect();
    let closed = |k: usize| nodes.state[k] != NodeState::Open;
    let last_closed = order.iter().rposition(|&k| closed(k)).unwrap();
    HertzFit {
        deviation: inside.iter().fold(0.0, |m, d| m.max(d.abs())),
        swing: inside
            .windows(2)
            .fold(0.0, |m, w| m.max((w[1] - w[0]).abs())),
        edge: [
            nodes.x[order[last_closed]],
            order
                .get(last_closed + 1)
                .map_or(f64::INFINITY, |&k| nodes.x[k]),
        ],
        a,
        iterations,
        seconds,
        split: solver.phases().summary(),
    }
}
