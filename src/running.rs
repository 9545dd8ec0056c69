//! A running strip: material enters at its supply end and leaves at its
//! take-up end, for any distance, on a mesh of fixed size (docs/contact.md
//! section 12). The strip is Lagrangian and its elements are alike (a
//! straight, uniform reference). Once its supply end has run half an
//! element past its home on the path, the state is shifted one element
//! downstream: each node takes the displacement, history and contact
//! memory of the node one element upstream, the element leaving at the
//! take-up end is dropped and a new one enters at the supply end, its
//! positions extrapolated from the span there. Where the span is straight
//! and uniform (the free span a strip runs in from) that is exact: the
//! shifted state is the same equilibrium, relabelled.

use crate::assembly::Model;
use crate::problem::{Body, ContactPair, Problem, Target};
use crate::results::RunningResult;
use crate::state::{RunningMemory, State};
use crate::strip::StripPath;
use std::collections::HashMap;

/// Where a node's new state comes from in a shift.
#[derive(Clone, Copy, Debug)]
enum Source {
    /// The node one element upstream (against the shift).
    Copy(usize),
    /// At the entering end: twice its own position less that of the node
    /// one element further in (`Extrapolate(further)`).
    Extrapolate(usize),
}

/// A shift's map, one direction.
#[derive(Debug, Default)]
struct Shift {
    nodes: Vec<(usize, Source)>,
    /// (element, the element whose history it takes); elements entering
    /// keep their own.
    elements: Vec<(usize, usize)>,
    pairs: Vec<PairShift>,
}

/// A shift of a contact pair on the strip: per contactor chain position
/// its source position (None: a node that enters); the pair's memory
/// shifts with it (`PairMemory::shift`).
#[derive(Debug)]
struct PairShift {
    pair: usize,
    nodes: Vec<Option<usize>>,
}

/// One running strip: its path, columns and shift maps.
#[derive(Debug)]
pub struct Strip {
    pub body: usize,
    pub name: String,
    pub path: StripPath,
    /// The rigid target the strip's first contact pair presses it on (its
    /// turn carries the strip in the predictor, `carry`).
    pub drum: Option<usize>,
    /// Node columns at each end, cross-section by cross-section: the end
    /// column and the one an element further in.
    supply: [Vec<usize>; 2],
    takeup: [Vec<usize>; 2],
    /// Elements along the strip.
    columns: usize,
    /// Shift downstream (material running in) and upstream.
    down: Shift,
    up: Shift,
}

/// Nodes of a strip by half-column and cross-section position, elements
/// by column and row (`Strip::new`).
type Grid = HashMap<(i64, i64), usize>;

impl Shift {
    /// The shift by one element downstream (`dir` 1) or upstream (-1).
    fn new(problem: &Problem, b: &Body, grid: &Grid, cells: &Grid, dir: i64) -> Self {
        let mut s = Shift::default();
        for (&(m, y), &n) in grid {
            let src = match grid.get(&(m - 2 * dir, y)) {
                Some(&from) => Source::Copy(from),
                None => Source::Extrapolate(grid[&(m + 2 * dir, y)]),
            };
            s.nodes.push((n, src));
        }
        s.nodes.sort_unstable_by_key(|p| p.0);
        for (&(c, r), &e) in cells {
            if let Some(&from) = cells.get(&(c - dir, r)) {
                s.elements.push((e, from));
            }
        }
        s.elements.sort_unstable();
        let from: HashMap<usize, Source> = s.nodes.iter().copied().collect();
        for (i, pair) in problem.contacts.iter().enumerate() {
            if pair.contactor.iter().all(|n| b.nodes.contains(n)) {
                s.pairs.push(PairShift::new(i, pair, &from));
            }
        }
        s
    }
}

impl PairShift {
    /// Pair `i`'s chain positions mapped by the nodes' sources.
    fn new(i: usize, pair: &ContactPair, from: &HashMap<usize, Source>) -> Self {
        let at: HashMap<usize, usize> = (pair.contactor.iter().enumerate())
            .map(|(i, &n)| (n, i))
            .collect();
        let source = |n: usize| match from[&n] {
            Source::Copy(f) => at.get(&f).copied(),
            Source::Extrapolate(_) => None,
        };
        let nodes = pair.contactor.iter().map(|&n| source(n)).collect();
        PairShift { pair: i, nodes }
    }
}

fn mean(problem: &Problem, u: &[f64], nodes: &[usize]) -> [f64; 2] {
    let mut m = [0.0; 2];
    for &n in nodes {
        for (c, v) in m.iter_mut().enumerate() {
            *v += problem.mesh.nodes[n][c] + u[2 * n + c];
        }
    }
    let k = nodes.len().max(1) as f64;
    [m[0] / k, m[1] / k]
}

fn along(a: [f64; 2], b: [f64; 2], t: [f64; 2]) -> f64 {
    (b[0] - a[0]) * t[0] + (b[1] - a[1]) * t[1]
}

impl Strip {
    /// The running strip of body `body` (`problem.bodies[body].running`).
    pub fn new(problem: &Problem, body: usize) -> Self {
        let b = &problem.bodies[body];
        let path = b.strip.clone().expect("a running body is a strip");
        let h = path.element;
        // Nodes by half-column (x in steps of h / 2) and cross-section
        // position; elements by column and row.
        let key = |p: [f64; 2]| {
            (
                (2.0 * p[0] / h).round() as i64,
                (p[1] / path.thickness * 1e6).round() as i64,
            )
        };
        let grid: Grid = b
            .nodes
            .clone()
            .map(|n| (key(problem.mesh.nodes[n]), n))
            .collect();
        let last = grid.keys().map(|k| k.0).max().unwrap_or(0);
        let centroid = |e: usize| {
            let el = &problem.mesh.elements[e];
            let mut c = [0.0; 2];
            for &n in &el.nodes[..4] {
                c[0] += 0.25 * problem.mesh.nodes[n][0];
                c[1] += 0.25 * problem.mesh.nodes[n][1];
            }
            (
                (c[0] / h).floor() as i64,
                (c[1] / path.thickness * 1e6).round() as i64,
            )
        };
        let cells: Grid = b.elements.clone().map(|e| (centroid(e), e)).collect();
        let column = |m: i64| {
            let mut c: Vec<(i64, usize)> = (grid.iter())
                .filter(|(k, _)| k.0 == m)
                .map(|(k, &n)| (k.1, n))
                .collect();
            c.sort_unstable();
            c.into_iter().map(|(_, n)| n).collect::<Vec<_>>()
        };
        let shift = |dir| Shift::new(problem, b, &grid, &cells, dir);
        let (down, up) = (shift(1), shift(-1));
        let drum = (problem.contacts.iter())
            .filter(|c| c.body == body)
            .find_map(|c| match c.target {
                Target::Rigid(r) => Some(r),
                Target::Body { .. } => None,
            });
        Strip {
            body,
            name: b.name.clone(),
            drum,
            supply: [column(0), column(2)],
            takeup: [column(last), column(last - 2)],
            columns: (last / 2) as usize,
            path,
            down,
            up,
        }
    }

    /// Moves the strip's nodes in `u` as the drum's turn by `turn` carries
    /// them (`StripPath::carry`): the configuration of steady running,
    /// which stands still in the drum's frame, a turn further on. Newton's
    /// predictor starts from there, so the wrap's rotation is not first
    /// taken along its tangents.
    pub fn carry(&self, problem: &Problem, u: &mut [f64], turn: f64) {
        let ds = self.path.run_by_turn(turn);
        for n in problem.bodies[self.body].nodes.clone() {
            let x = problem.mesh.nodes[n];
            let q = [x[0] + u[2 * n], x[1] + u[2 * n + 1]];
            let c = self.path.carry(q, ds);
            u[2 * n] = c[0] - x[0];
            u[2 * n + 1] = c[1] - x[1];
        }
    }

    /// How far the supply end's mid-line has run past its home along the
    /// span in, and the length of its first element there.
    fn supply_travel(&self, problem: &Problem, u: &[f64]) -> (f64, f64) {
        let t = self.path.tangent_in();
        let home = self.path.place([0.0, 0.0]);
        let end = mean(problem, u, &self.supply[0]);
        let next = mean(problem, u, &self.supply[1]);
        (along(home, end, t), along(end, next, t))
    }

    /// Shifts `state` by whole elements until the supply end lies within
    /// half an element of its home; returns the number of shifts (negative:
    /// upstream).
    pub fn recycle(&self, problem: &Problem, model: &Model, state: &mut State, k: usize) -> i64 {
        let mut count = 0;
        // A step moves the strip by far less than its length; the bound
        // only stops a state run off its path from looping.
        for _ in 0..self.columns {
            let (d, l) = self.supply_travel(problem, &state.u);
            let dir = if d > 0.5 * l {
                1
            } else if d < -0.5 * l {
                -1
            } else {
                break;
            };
            let shift = if dir > 0 { &self.down } else { &self.up };
            self.apply(shift, problem, model, state);
            count += dir;
        }
        if let Some(m) = state.running.get_mut(k) {
            m.shifts += count;
        }
        count
    }

    fn apply(&self, s: &Shift, problem: &Problem, model: &Model, state: &mut State) {
        let shift_u = |u: &mut Vec<f64>| {
            let old = u.clone();
            let x = |n: usize, c: usize| problem.mesh.nodes[n][c] + old[2 * n + c];
            for &(n, src) in &s.nodes {
                for c in 0..2 {
                    let new = match src {
                        Source::Copy(f) => x(f, c),
                        Source::Extrapolate(g) => 2.0 * x(n, c) - x(g, c),
                    };
                    u[2 * n + c] = new - problem.mesh.nodes[n][c];
                }
            }
        };
        shift_u(&mut state.u);
        if !state.step_start_u.is_empty() {
            shift_u(&mut state.step_start_u);
        }
        let shift_history = |hist: &mut Vec<f64>| {
            if hist.is_empty() {
                return;
            }
            let old = hist.clone();
            for &(e, from) in &s.elements {
                let (to, from) = (model.history_range(e), model.history_range(from));
                hist[to].copy_from_slice(&old[from]);
            }
        };
        shift_history(&mut state.history);
        shift_history(&mut state.step_start_history);
        for PairShift { pair, nodes } in &s.pairs {
            state.contact[*pair].shift(nodes);
        }
    }

    /// The strip's figures in `state`, with the speeds it holds.
    pub fn result(&self, problem: &Problem, state: &State, k: usize) -> RunningResult {
        let memory = state.running.get(k).cloned().unwrap_or_default();
        self.figures(problem, &state.u, &memory)
    }

    fn figures(&self, problem: &Problem, u: &[f64], memory: &RunningMemory) -> RunningResult {
        let h = self.path.element;
        let (d, l_in) = self.supply_travel(problem, u);
        let t_out = self.path.tangent_out();
        let end = mean(problem, u, &self.takeup[0]);
        let before = mean(problem, u, &self.takeup[1]);
        let l_out = along(before, end, t_out);
        RunningResult {
            fed: memory.shifts as f64 * h + d * h / l_in,
            speed_in: memory.speed[0],
            speed_out: memory.speed[1],
            strain_in: l_in / h - 1.0,
            strain_out: l_out / h - 1.0,
        }
    }

    /// The material speeds at the two ends over a step from `start` to
    /// `end` (no shift between them), `dt` long.
    pub fn speeds(&self, problem: &Problem, start: &[f64], end: &[f64], dt: f64) -> [f64; 2] {
        let v = |nodes: &[usize], t: [f64; 2]| {
            along(mean(problem, start, nodes), mean(problem, end, nodes), t) / dt
        };
        [
            v(&self.supply[0], self.path.tangent_in()),
            v(&self.takeup[0], self.path.tangent_out()),
        ]
    }
}

/// Each running strip's figures at rest (laid along its path, nothing fed
/// yet), by body name: what a step reports before the first.
pub fn at_rest(problem: &Problem) -> Vec<(String, RunningResult)> {
    let u = problem.initial_u();
    (0..problem.bodies.len())
        .filter(|&b| problem.bodies[b].running)
        .map(|b| {
            let strip = Strip::new(problem, b);
            let r = strip.figures(problem, &u, &RunningMemory::default());
            (strip.name, r)
        })
        .collect()
}
