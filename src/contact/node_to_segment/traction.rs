//! Section 3 of Bathe & Chaudhary (1984) for one contactor surface: the nodal tractions
//! recovered from the out-of-balance forces (Eqs. 26, 27), the segment tractions and
//! resultants (Eqs. 28-31), the release/stick/slide decision of each segment (Sections
//! 3.2-3.4), the contact forces (Fig. 5, Eq. 32) and the node states (Table 1).
//! A pure kernel: no mesh, no solver.
//!
//! # Conventions
//!
//! - The contactor surface is a chain of nodes `k = 0..m-1` with the contactor body on
//!   the LEFT walking from `k` to `k+1`. Segment `j` joins nodes `j` and `j+1`; a closed
//!   chain also has segment `m-1` from node `m-1` to node `0`.
//! - `tau_j` is the unit tangent of segment `j` (from its first node to its second) and
//!   `nu_j = (-tau_y, tau_x)` its left normal, which points INTO the contactor body.
//!   `t_n = t . nu_j` is positive in compression (acting onto the body) and
//!   `t_t = t . tau_j` is positive from `k` toward `k+1` (Fig. 4c).
//! - `force[k]` is the force the contact exerts on contactor node `k`, in global
//!   components (the solver passes `F_int - R_ext`, minus the paper's `Delta R` of
//!   Eq. 25). Tractions are forces per unit area acting onto the contactor body.
//! - Axisymmetric analysis (x is the radius, y the axis): this solver's nodal forces are
//!   totals over the full circle, so every consistent weight of Eq. (27) and of
//!   Eqs. (30), (31), (32) carries a factor `2 pi`. The resultants `T_n`, `T_t`, `T_f` are
//!   then totals over the circle, and the tractions stay forces per unit area.
//!
//! # The consistent weights
//!
//! For segment `j` with nodes `a`, `b`, length `d`, and a traction varying linearly
//! between its nodal values, the load at node `a` is `M_aa t_a + M_ab t_b` with
//! (`N_a` the linear shape functions, `ds` the arc length)
//!
//! - planar: `M = h d / 6 [[2, 1], [1, 2]]` (Eq. 26),
//! - axisymmetric: `M = 2 pi d / 12 [[3 x_a + x_b, x_a + x_b], [x_a + x_b, x_a + 3 x_b]]`,
//!   which is `2 pi int N_a N_b x ds` with x linear on the segment (Eq. 27 times `2 pi`).
//!
//! The row sums `1^T M` give the resultants, `T = (1^T M) [t_a, t_b]`: `h d / 2 (t_a + t_b)`
//! (Eqs. 28, 29) and `2 pi d / 6 ((2 x_a + x_b) t_a + (x_a + 2 x_b) t_b)` (Eqs. 30, 31 times
//! `2 pi`). A uniform traction `tbar` has the loads `(1^T M)_a tbar`, `(1^T M)_b tbar`.
//!
//! # What the stick round trip reproduces
//!
//! Tractions are unknowns at active nodes only; at inactive nodes `t = 0`. The traction
//! on a segment joining an active node `k+1` to an inactive node `k` therefore falls
//! linearly to zero at `k`. When every segment sticks, the contact forces of
//! [`contact_forces`] are the consistent loads of the recovered field, and
//!
//! - at an active node they equal `force` to round-off (they are the rows that were
//!   solved),
//! - at an inactive node `k` next to an active node `l` they are `M_kl t_l` (planar
//!   `h d / 6 t_l`, axisymmetric `2 pi d (x_k + x_l) / 12 t_l`), summed over such
//!   neighbours: the recovered field "spills" a load onto the edge of the contact zone,
//! - at an inactive node whose neighbours are both inactive they are exactly zero.
//!
//! The pair resultants `Fx`, `Fy` sum all nodal forces, spill included, which keeps them
//! equal to the sum of the segment resultant vectors `T_n nu + T_t tau` (after the
//! friction modification), i.e. consistent with `Fn`, `Ft`. A caller that applies
//! contact forces only at nodes in contact should take `forces` at active nodes only
//! (and sum those if it wants the total the multipliers carry).

use std::f64::consts::TAU;

use crate::contact::report::Geometry;
use crate::problem::{FrictionRule, Recovery};
use crate::results::NodeState;

/// A pivot of the recovery system this small against its diagonal means the node has
/// (numerically) no contact area: the recovery is singular there.
const PIVOT_TOLERANCE: f64 = 1e-12;

/// State of a contactor segment after an iteration.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SegmentState {
    /// Not in contact, or released (Section 3.2).
    #[default]
    Open,
    /// Sticking: the recovered tractions are applied as they are (Fig. 5a).
    Stick,
    /// Sliding: the tangential traction is replaced by a uniform one of total `T_f`
    /// (Fig. 5b, Eq. 32).
    Slide,
}

/// Errors of the traction kernel, carrying the offending indices and values.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TractionError {
    /// An open chain needs two nodes, a closed one three.
    #[error(
        "a {} contactor chain needs at least {} nodes, got {nodes}",
        if *closed { "closed" } else { "open" },
        if *closed { 3 } else { 2 }
    )]
    TooFewNodes { nodes: usize, closed: bool },
    /// A node position is NaN or infinite.
    #[error("contactor node {node} has a non-finite position ({}, {})", x[0], x[1])]
    NonFinitePosition { node: usize, x: [f64; 2] },
    /// A node lies at a negative radius in axisymmetric analysis.
    #[error("contactor node {node} lies at the negative radius {radius} (axisymmetric)")]
    NegativeRadius { node: usize, radius: f64 },
    /// A segment joins two coincident nodes.
    #[error(
        "contactor segment {segment} from ({}, {}) to ({}, {}) has length {length}",
        xa[0], xa[1], xb[0], xb[1]
    )]
    DegenerateSegment {
        segment: usize,
        xa: [f64; 2],
        xb: [f64; 2],
        length: f64,
    },
    /// The planar thickness is not positive and finite.
    #[error("thickness {thickness} is not positive and finite")]
    InvalidThickness { thickness: f64 },
    /// A per-node or per-segment input has the wrong length.
    #[error("{what} has {found} entries, expected {expected}")]
    LengthMismatch {
        what: &'static str,
        expected: usize,
        found: usize,
    },
    /// The force at an active node is NaN or infinite.
    #[error("active contactor node {node} has a non-finite force ({}, {})", force[0], force[1])]
    NonFiniteForce { node: usize, force: [f64; 2] },
    /// A friction coefficient is negative or not finite.
    #[error("friction coefficients mu_s = {mu_s}, mu_d = {mu_d} must be finite and non-negative")]
    InvalidFriction { mu_s: f64, mu_d: f64 },
    /// An active node has no contact area (all its weights vanish, e.g. every adjoining
    /// segment lies on the axis of revolution).
    #[error(
        "traction recovery is singular at contactor node {node}: pivot {pivot} against \
         diagonal {diagonal} (no contact area there)"
    )]
    SingularRecovery {
        node: usize,
        pivot: f64,
        diagonal: f64,
    },
    /// A result overflowed.
    #[error("{quantity} (index {index}) is not finite (overflow)")]
    NonFinite {
        quantity: &'static str,
        index: usize,
    },
}

/// Coulomb friction of a pair: static and dynamic coefficients and the rule that picks
/// the coefficient of a sticking segment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Friction {
    pub mu_s: f64,
    pub mu_d: f64,
    pub rule: FrictionRule,
}

impl Friction {
    /// Checks that both coefficients are finite and non-negative.
    pub fn new(mu_s: f64, mu_d: f64, rule: FrictionRule) -> Result<Self, TractionError> {
        if !(mu_s.is_finite() && mu_d.is_finite() && mu_s >= 0.0 && mu_d >= 0.0) {
            return Err(TractionError::InvalidFriction { mu_s, mu_d });
        }
        Ok(Friction { mu_s, mu_d, rule })
    }

    /// `mu_s == mu_d == 0`: every segment in contact slides, from the start (the footnote
    /// of Section 3).
    pub fn is_frictionless(&self) -> bool {
        self.mu_s == 0.0 && self.mu_d == 0.0
    }

    /// Coefficient of a segment that was sticking (or is new to contact): `mu_s`, or `mu_d`
    /// once the segment has slid under [`FrictionRule::MuDAfterSlip`] (Section 3.3).
    pub fn sticking_mu(&self, ever_slid: bool) -> f64 {
        match self.rule {
            FrictionRule::MuDAfterSlip if ever_slid => self.mu_d,
            _ => self.mu_s,
        }
    }
}

/// One segment of a [`Chain`]: its nodes, geometry and consistent weights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChainSegment {
    /// First and second node (the body is on the left from the first to the second).
    pub nodes: [usize; 2],
    /// Length `d_j`.
    pub length: f64,
    /// Unit tangent `tau_j`, from the first node to the second.
    pub tangent: [f64; 2],
    /// Left normal `nu_j = (-tau_y, tau_x)`, pointing into the contactor body.
    pub normal: [f64; 2],
    /// Consistent weights `M`: a traction linear between `t_a` and `t_b` loads the first
    /// node with `M[0][0] t_a + M[0][1] t_b` and the second with `M[1][0] t_a + M[1][1] t_b`
    /// (see the module documentation; `2 pi` included in axisymmetry).
    pub weights: [[f64; 2]; 2],
}

impl ChainSegment {
    /// Row sums of the weights: the loads of a unit uniform traction, and the factors of
    /// the nodal tractions in the resultant (Eqs. 28-31).
    pub fn row_sums(&self) -> [f64; 2] {
        let w = &self.weights;
        [w[0][0] + w[0][1], w[1][0] + w[1][1]]
    }

    /// Resultant of a traction component linear between `t[0]` and `t[1]` (Eqs. 28-31).
    pub fn resultant(&self, t: [f64; 2]) -> f64 {
        let r = self.row_sums();
        r[0] * t[0] + r[1] * t[1]
    }

    /// Consistent nodal loads of a traction component linear between `t[0]` and `t[1]`.
    pub fn loads(&self, t: [f64; 2]) -> [f64; 2] {
        let w = &self.weights;
        [
            w[0][0] * t[0] + w[0][1] * t[1],
            w[1][0] * t[0] + w[1][1] * t[1],
        ]
    }
}

/// A contactor surface at its current positions: validated nodes and segments.
#[derive(Clone, Debug, PartialEq)]
pub struct Chain {
    geometry: Geometry,
    closed: bool,
    x: Vec<[f64; 2]>,
    segments: Vec<ChainSegment>,
}

impl Chain {
    /// The chain through `x` (closed: with the segment from the last node to the first).
    /// Rejects too few nodes, non-finite positions, negative radii in axisymmetry,
    /// zero-length segments and a non-positive thickness.
    pub fn new(geometry: Geometry, closed: bool, x: &[[f64; 2]]) -> Result<Self, TractionError> {
        let m = x.len();
        if m < if closed { 3 } else { 2 } {
            return Err(TractionError::TooFewNodes { nodes: m, closed });
        }
        if let Geometry::Planar { thickness } = geometry
            && (!thickness.is_finite() || thickness <= 0.0)
        {
            return Err(TractionError::InvalidThickness { thickness });
        }
        for (node, p) in x.iter().enumerate() {
            if !(p[0].is_finite() && p[1].is_finite()) {
                return Err(TractionError::NonFinitePosition { node, x: *p });
            }
            if geometry == Geometry::Axisymmetric && p[0] < 0.0 {
                return Err(TractionError::NegativeRadius { node, radius: p[0] });
            }
        }
        let count = if closed { m } else { m - 1 };
        let mut segments = Vec::with_capacity(count);
        for j in 0..count {
            let (a, b) = (j, (j + 1) % m);
            let (xa, xb) = (x[a], x[b]);
            let (dx, dy) = (xb[0] - xa[0], xb[1] - xa[1]);
            let length = dx.hypot(dy);
            if !(length.is_finite() && length > 0.0) {
                return Err(TractionError::DegenerateSegment {
                    segment: j,
                    xa,
                    xb,
                    length,
                });
            }
            let tangent = [dx / length, dy / length];
            let weights = match geometry {
                Geometry::Planar { thickness } => {
                    let c = thickness * length / 6.0;
                    [[2.0 * c, c], [c, 2.0 * c]]
                }
                Geometry::Axisymmetric => {
                    let c = TAU * length / 12.0;
                    let (ra, rb) = (xa[0], xb[0]);
                    [
                        [c * (3.0 * ra + rb), c * (ra + rb)],
                        [c * (ra + rb), c * (ra + 3.0 * rb)],
                    ]
                }
            };
            segments.push(ChainSegment {
                nodes: [a, b],
                length,
                tangent,
                normal: [-tangent[1], tangent[0]],
                weights,
            });
        }
        Ok(Chain {
            geometry,
            closed,
            x: x.to_vec(),
            segments,
        })
    }

    pub fn is_closed(&self) -> bool {
        self.closed
    }

    /// Number of nodes `m`.
    pub fn nodes(&self) -> usize {
        self.x.len()
    }

    /// Segments `0..m-1` (open) or `0..m` (closed).
    #[cfg(test)]
    pub fn segments(&self) -> &[ChainSegment] {
        &self.segments
    }

    /// The segments adjoining node `k`: `[the one ending at k, the one starting at k]`,
    /// `None` at the ends of an open chain (or for `k` out of range).
    pub fn adjoining(&self, k: usize) -> [Option<usize>; 2] {
        let m = self.x.len();
        if k >= m {
            return [None, None];
        }
        let before = if k > 0 {
            Some(k - 1)
        } else if self.closed {
            Some(m - 1)
        } else {
            None
        };
        let after = if k + 1 < m || self.closed {
            Some(k)
        } else {
            None
        };
        [before, after]
    }

    /// Diagonal weight of node `k`: the sum over its adjoining segments of `M_kk`
    /// (the `(d_{j-1} + d_j) / 3` entry of Eq. 26), whether or not the neighbours are
    /// active.
    fn diagonal(&self, k: usize) -> f64 {
        let [before, after] = self.adjoining(k);
        before.map_or(0.0, |s| self.segments[s].weights[1][1])
            + after.map_or(0.0, |s| self.segments[s].weights[0][0])
    }

    /// Tributary weight of node `k`: the sum of the row sums of its adjoining segments
    /// (the consistent loads of a unit uniform traction at `k`).
    fn tributary(&self, k: usize) -> f64 {
        let [before, after] = self.adjoining(k);
        before.map_or(0.0, |s| self.segments[s].row_sums()[1])
            + after.map_or(0.0, |s| self.segments[s].row_sums()[0])
    }
}

fn check_len(what: &'static str, expected: usize, found: usize) -> Result<(), TractionError> {
    if expected == found {
        Ok(())
    } else {
        Err(TractionError::LengthMismatch {
            what,
            expected,
            found,
        })
    }
}

/// Step 1: the nodal tractions `t^k` (global components, force per unit area) from the
/// contact forces at the active nodes; zero at inactive nodes.
///
/// - [`Recovery::Consistent`]: Eq. (26) (planar) or Eq. (27) times `2 pi` (axisymmetric),
///   `force_k = sum_l A_kl t_l` over the active nodes `k`, with `t = 0` at inactive nodes
///   (a segment to an inactive neighbour still adds its `M_kk` to the diagonal). The
///   system is tridiagonal within each maximal run of consecutive active nodes and the
///   runs are independent; each is solved by the Thomas algorithm, a fully active closed
///   chain (cyclic tridiagonal) by Sherman-Morrison. O(m) in all cases.
/// - [`Recovery::Lumped`]: `t_k = force_k / w_k` with the tributary weight `w_k` the
///   row sum of the consistent weights of the adjoining segments: `h (d_{j-1} + d_j) / 2`
///   planar and `2 pi [d_{j-1} (x_{k-1} + 2 x_k) + d_j (2 x_k + x_{k+1})] / 6`
///   axisymmetric (which equals `2 pi x_k (d_{j-1} + d_j) / 2` on an evenly spaced radial
///   chain, and stays positive at a node on the axis). It recovers a uniform traction
///   exactly at every node whose adjoining segments carry it (ends included).
///
/// Only the active entries of `force` are read (and must be finite).
pub fn recover_tractions(
    chain: &Chain,
    recovery: Recovery,
    active: &[bool],
    force: &[[f64; 2]],
) -> Result<Vec<[f64; 2]>, TractionError> {
    let m = chain.nodes();
    check_len("active", m, active.len())?;
    check_len("force", m, force.len())?;
    for k in 0..m {
        let f = force[k];
        if active[k] && !(f[0].is_finite() && f[1].is_finite()) {
            return Err(TractionError::NonFiniteForce { node: k, force: f });
        }
    }
    let mut t = vec![[0.0; 2]; m];
    match recovery {
        Recovery::Lumped => {
            for k in (0..m).filter(|&k| active[k]) {
                let w = chain.tributary(k);
                if !w.is_finite() || w <= 0.0 {
                    return Err(TractionError::SingularRecovery {
                        node: k,
                        pivot: w,
                        diagonal: w,
                    });
                }
                t[k] = [force[k][0] / w, force[k][1] / w];
            }
        }
        Recovery::Consistent => {
            if chain.is_closed() && active.iter().all(|&a| a) {
                solve_cyclic(chain, force, &mut t)?;
            } else {
                for run in active_runs(chain, active) {
                    solve_run(chain, &run, force, &mut t)?;
                }
            }
        }
    }
    for (k, tk) in t.iter().enumerate() {
        if !(tk[0].is_finite() && tk[1].is_finite()) {
            return Err(TractionError::NonFinite {
                quantity: "traction at node",
                index: k,
            });
        }
    }
    Ok(t)
}

/// Maximal runs of consecutive active nodes, in chain order; in a closed chain (not
/// fully active) a run may wrap from node m-1 to node 0.
fn active_runs(chain: &Chain, active: &[bool]) -> Vec<Vec<usize>> {
    let m = chain.nodes();
    let mut runs = Vec::new();
    let mut current = Vec::new();
    // Start after an inactive node so that a wrapping run is found whole.
    let start = if chain.is_closed() {
        match active.iter().position(|&a| !a) {
            Some(s) => s + 1,
            None => 0,
        }
    } else {
        0
    };
    for i in 0..m {
        let k = (start + i) % m;
        if active[k] {
            current.push(k);
        } else if !current.is_empty() {
            runs.push(std::mem::take(&mut current));
        }
    }
    if !current.is_empty() {
        runs.push(current);
    }
    runs
}

/// The tridiagonal system of one run: diagonal, and the coupling between `run[i]` and
/// `run[i+1]` (the segment starting at `run[i]`).
fn run_system(chain: &Chain, run: &[usize]) -> (Vec<f64>, Vec<f64>) {
    let diag = run.iter().map(|&k| chain.diagonal(k)).collect();
    let off = run
        .windows(2)
        .map(|w| chain.adjoining(w[0])[1].map_or(0.0, |s| chain.segments[s].weights[0][1]))
        .collect();
    (diag, off)
}

fn solve_run(
    chain: &Chain,
    run: &[usize],
    force: &[[f64; 2]],
    t: &mut [[f64; 2]],
) -> Result<(), TractionError> {
    let (diag, off) = run_system(chain, run);
    let mut rhs: Vec<[f64; 2]> = run.iter().map(|&k| force[k]).collect();
    thomas(&diag, &off, &mut rhs, run)?;
    for (i, &k) in run.iter().enumerate() {
        t[k] = rhs[i];
    }
    Ok(())
}

/// Thomas algorithm for a symmetric positive definite tridiagonal system (diagonal
/// `diag`, off-diagonal `off[i]` between rows i and i+1) with `R` right-hand sides,
/// overwritten by the solution. No pivoting is needed for SPD matrices; a pivot that is
/// not positive against its diagonal reports `SingularRecovery` at `nodes[i]`.
fn thomas<const R: usize>(
    diag: &[f64],
    off: &[f64],
    rhs: &mut [[f64; R]],
    nodes: &[usize],
) -> Result<(), TractionError> {
    let n = diag.len();
    let mut c = vec![0.0; n];
    for i in 0..n {
        let (lower, prev_c) = if i > 0 {
            (off[i - 1], c[i - 1])
        } else {
            (0.0, 0.0)
        };
        let pivot = diag[i] - lower * prev_c;
        if !pivot.is_finite() || pivot <= PIVOT_TOLERANCE * diag[i].abs() {
            return Err(TractionError::SingularRecovery {
                node: nodes[i],
                pivot,
                diagonal: diag[i],
            });
        }
        c[i] = if i + 1 < n { off[i] / pivot } else { 0.0 };
        for r in 0..R {
            let prev = if i > 0 { rhs[i - 1][r] } else { 0.0 };
            rhs[i][r] = (rhs[i][r] - lower * prev) / pivot;
        }
    }
    for i in (0..n.saturating_sub(1)).rev() {
        for r in 0..R {
            rhs[i][r] -= c[i] * rhs[i + 1][r];
        }
    }
    Ok(())
}

/// A fully active closed chain: cyclic tridiagonal, corner coupling between nodes m-1 and
/// 0. Sherman-Morrison with `gamma = -A_00`: `A = A' - w w^T / A_00`, `w = (A_00, 0, ..,
/// -c)`, where `A'` (tridiagonal, `A'_00 = 2 A_00`, `A'_{m-1,m-1} = A_{m-1,m-1} +
/// c^2 / A_00`) is SPD, and the denominator `det A / det A'` is positive.
fn solve_cyclic(
    chain: &Chain,
    force: &[[f64; 2]],
    t: &mut [[f64; 2]],
) -> Result<(), TractionError> {
    let m = chain.nodes();
    let nodes: Vec<usize> = (0..m).collect();
    let (mut diag, off) = run_system(chain, &nodes);
    let corner = chain.segments[m - 1].weights[0][1];
    let b0 = diag[0];
    if !b0.is_finite() || b0 <= 0.0 {
        return Err(TractionError::SingularRecovery {
            node: 0,
            pivot: b0,
            diagonal: b0,
        });
    }
    let gamma = -b0;
    diag[0] -= gamma;
    diag[m - 1] -= corner * corner / gamma;
    // Columns: the two force components, then u = (gamma, 0, .., corner).
    let mut rhs: Vec<[f64; 3]> = force.iter().map(|f| [f[0], f[1], 0.0]).collect();
    rhs[0][2] = gamma;
    rhs[m - 1][2] = corner;
    thomas(&diag, &off, &mut rhs, &nodes)?;
    let ratio = corner / gamma;
    let vz = rhs[0][2] + ratio * rhs[m - 1][2];
    let den = 1.0 + vz;
    if !den.is_finite() || den <= PIVOT_TOLERANCE {
        return Err(TractionError::SingularRecovery {
            node: m - 1,
            pivot: den,
            diagonal: 1.0,
        });
    }
    for r in 0..2 {
        let vy = rhs[0][r] + ratio * rhs[m - 1][r];
        let s = vy / den;
        for k in 0..m {
            t[k][r] = rhs[k][r] - s * rhs[k][2];
        }
    }
    Ok(())
}

/// Normal and tangential tractions of one segment at its two nodes, and its resultants
/// (Step 2).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SegmentTractions {
    /// Whether at least one of the segment's nodes is active.
    pub in_contact: bool,
    /// `t_n` at the first and second node, in the segment's frame (positive in
    /// compression).
    pub tn: [f64; 2],
    /// `t_t` at the first and second node (positive from the first node to the second).
    pub tt: [f64; 2],
    /// `T_n`, Eq. (28) planar, Eq. (30) times `2 pi` axisymmetric.
    pub tn_total: f64,
    /// `T_t`, Eq. (29) planar, Eq. (31) times `2 pi` axisymmetric.
    pub tt_total: f64,
}

fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// Step 2: the nodal tractions `t` (global) turned into each segment's frame, at both of
/// its nodes (discontinuous at the nodes, Fig. 4), with the resultants `T_n`, `T_t`.
pub fn segment_tractions(
    chain: &Chain,
    active: &[bool],
    traction: &[[f64; 2]],
) -> Result<Vec<SegmentTractions>, TractionError> {
    check_len("active", chain.nodes(), active.len())?;
    check_len("traction", chain.nodes(), traction.len())?;
    Ok(chain
        .segments
        .iter()
        .map(|s| {
            let [a, b] = s.nodes;
            let tn = [dot(traction[a], s.normal), dot(traction[b], s.normal)];
            let tt = [dot(traction[a], s.tangent), dot(traction[b], s.tangent)];
            SegmentTractions {
                in_contact: active[a] || active[b],
                tn,
                tt,
                tn_total: s.resultant(tn),
                tt_total: s.resultant(tt),
            }
        })
        .collect())
}

/// New state of one segment and its frictional capacity (Step 3).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SegmentDecision {
    pub state: SegmentState,
    /// `T_f`: for a sticking segment the capacity it was checked against, for a sliding
    /// one `mu_d T_n` (zero when frictionless), zero when open.
    pub tf: f64,
    /// Whether the segment has ever slid, this decision included.
    pub ever_slid: bool,
    /// Sliding: the sign of the friction resultant it applies along its tangent
    /// (`sign(T_t)`, or the direction it kept, see [`evaluate`]); zero otherwise.
    pub sign: f64,
}

/// Step 3 for one segment (Sections 3.2-3.4):
///
/// - no active node: Open; `T_n < 0`: Open (tension release);
/// - frictionless: Slide with `T_f = 0`;
/// - previously Stick or Open (a new contact starts sticking): capacity
///   `T_f = mu T_n`, `mu` from [`Friction::sticking_mu`]; `|T_t| <= T_f` sticks, otherwise
///   Slide with `T_f = mu_d T_n`;
/// - previously Slide: Slide with `T_f = mu_d T_n`. A sliding segment does not return to
///   sticking on force grounds (Section 3.4's test): after an iteration its `T_t` is the
///   friction it applied itself (its nodes are free along the target) plus what its
///   neighbours' changes spill onto its nodes, so the test would compare `mu_d T_n` of
///   two iterations, or a transient. With large increments (a drag of 0.05 on
///   scenes/verification/sliding_block.toml) it sent segments back to sticking at points
///   they had slid to, and the converged states alternated between increments. The caller
///   decides the return to sticking kinematically instead: when its nodes' slip from
///   their anchors runs along its friction, it sticks.
///
/// `ever_slid` becomes true when the segment slides now.
pub fn decide_segment(
    friction: &Friction,
    previous: SegmentState,
    ever_slid: bool,
    seg: &SegmentTractions,
) -> SegmentDecision {
    let open = SegmentDecision {
        state: SegmentState::Open,
        tf: 0.0,
        ever_slid,
        sign: 0.0,
    };
    if !seg.in_contact || seg.tn_total < 0.0 {
        return open;
    }
    let tn = seg.tn_total;
    let tt = seg.tt_total.abs();
    let slide = SegmentDecision {
        state: SegmentState::Slide,
        tf: friction.mu_d * tn,
        ever_slid: true,
        sign: signum0(seg.tt_total),
    };
    if friction.is_frictionless() {
        return SegmentDecision { tf: 0.0, ..slide };
    }
    match previous {
        SegmentState::Stick | SegmentState::Open => {
            let capacity = friction.sticking_mu(ever_slid) * tn;
            if tt <= capacity {
                SegmentDecision {
                    state: SegmentState::Stick,
                    tf: capacity,
                    ever_slid,
                    sign: 0.0,
                }
            } else {
                slide
            }
        }
        SegmentState::Slide => slide,
    }
}

/// Step 3 for every segment; see [`decide_segment`].
pub fn decide_segments(
    friction: &Friction,
    previous: &[SegmentState],
    ever_slid: &[bool],
    tractions: &[SegmentTractions],
) -> Result<Vec<SegmentDecision>, TractionError> {
    check_len("previous segment states", tractions.len(), previous.len())?;
    check_len("ever_slid", tractions.len(), ever_slid.len())?;
    Ok(tractions
        .iter()
        .enumerate()
        .map(|(j, s)| decide_segment(friction, previous[j], ever_slid[j], s))
        .collect())
}

fn signum0(v: f64) -> f64 {
    if v > 0.0 {
        1.0
    } else if v < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// The signed tangential resultant a segment applies after the friction modification:
/// `T_t` sticking, `sign(T_t) T_f` sliding, zero open.
pub fn applied_tangential(seg: &SegmentTractions, decision: &SegmentDecision) -> f64 {
    match decision.state {
        SegmentState::Open => 0.0,
        SegmentState::Stick => seg.tt_total,
        SegmentState::Slide => decision.sign * decision.tf,
    }
}

/// The tangential traction at the two nodes of a segment that its contact forces use
/// (Fig. 5): the recovered linear one sticking; the uniform `tbar = sign(T_t) T_f / A`
/// sliding, with `A` the segment area (`h d` planar, `pi d (x_a + x_b)` axisymmetric,
/// i.e. Eq. 32 with `T_f` for `T_t`, times `2 pi`); zero open.
pub fn applied_tangential_traction(
    segment: &ChainSegment,
    seg: &SegmentTractions,
    decision: &SegmentDecision,
) -> [f64; 2] {
    match decision.state {
        SegmentState::Open => [0.0; 2],
        SegmentState::Stick => seg.tt,
        SegmentState::Slide => {
            let r = segment.row_sums();
            let area = r[0] + r[1];
            let tbar = if area > 0.0 {
                applied_tangential(seg, decision) / area
            } else {
                0.0
            };
            [tbar; 2]
        }
    }
}

/// Step 3, continued: the sticking segments next to sliding ones are checked again on
/// the force that the sliding segments leave them.
///
/// Table 1 makes a node stick when one of its segments sticks, so a sticking node shared
/// with a sliding segment takes, through its two multipliers, whatever its out-of-balance
/// force is. The sliding segment applies only its friction `T_f` (Fig. 5b) at that node;
/// the rest of the node's force is carried by the sticking side. The resultants of
/// Eqs. (28)-(31), however, split that node's force between both segments through the
/// recovered linear tractions, so the sticking segment is checked on part of what it
/// carries, and the part recovered onto the sliding segment beyond its `T_f` is carried
/// by nobody's capacity: the pair can hold more than `mu Fn` (0.54 % on CGS-4).
///
/// Here each maximal run of sticking segments that touches a sliding one is checked on
/// the force left at its nodes once the sliding segments' loads (unaltered normal
/// tractions and uniform friction, Fig. 5) are taken off: the tractions are recovered
/// over the run alone (the same Eq. 26/27 system, or lumped), and its segments are
/// decided as in Section 3.3 on those resultants. A segment that now fails slides, which
/// can expose its neighbour: repeated until nothing changes (only sticking turns into
/// sliding, so at most once per segment). The resultants of every segment then add up to
/// the pair's total, and a converged state has `|Ft| <= mu Fn` on a straight target.
/// The runs' tractions decide only; the contact forces stay those of Fig. 5 (a sticking
/// node's multipliers take the difference).
#[allow(clippy::too_many_arguments)]
fn recheck_sticking_runs(
    chain: &Chain,
    recovery: Recovery,
    friction: &Friction,
    active: &[bool],
    force: &[[f64; 2]],
    previous: &[SegmentState],
    ever_slid: &[bool],
    tractions: &[SegmentTractions],
    decisions: &mut [SegmentDecision],
) -> Result<(), TractionError> {
    let nseg = chain.segments.len();
    if friction.is_frictionless() {
        return Ok(());
    }
    // A segment that was not sliding is decided on the remainder once a sliding
    // neighbour takes its share; its own check on the full recovery (Section 3.3) stands
    // only where no sliding segment touches its run. Start from the continuing slides.
    let plain = decisions.to_vec();
    for (j, d) in decisions.iter_mut().enumerate() {
        if previous[j] != SegmentState::Slide && d.state == SegmentState::Slide {
            *d = SegmentDecision {
                state: SegmentState::Stick,
                tf: friction.sticking_mu(ever_slid[j]) * tractions[j].tn_total,
                ever_slid: ever_slid[j],
                sign: 0.0,
            };
        }
    }
    loop {
        // Where the runs are enumerated from: an open chain from its first segment, a
        // closed one from a segment that does not stick (all sticking: one run, which
        // touches no sliding segment).
        let start = match (0..nseg).find(|&j| decisions[j].state != SegmentState::Stick) {
            _ if !chain.closed => nseg - 1,
            Some(j) => j,
            None => {
                let failed: Vec<usize> = (0..nseg)
                    .filter(|&j| plain[j].state != SegmentState::Stick)
                    .collect();
                if failed.is_empty() {
                    return Ok(());
                }
                for j in failed {
                    decisions[j] = plain[j];
                }
                continue;
            }
        };
        let slide_load = slide_loads(chain, tractions, decisions);
        // Maximal runs of sticking segments, in chain order from a segment that does
        // not stick (so that a run of a closed chain does not wrap around it).
        let mut changed = false;
        let mut run: Vec<usize> = Vec::new();
        for i in 1..=nseg {
            let j = (start + i) % nseg;
            if decisions[j].state == SegmentState::Stick {
                run.push(j);
                if i < nseg {
                    continue;
                }
            }
            if run.is_empty() {
                continue;
            }
            let first = chain.segments[run[0]].nodes[0];
            let last = chain.segments[*run.last().unwrap()].nodes[1];
            let touches_slide = chain
                .adjoining(first)
                .into_iter()
                .chain(chain.adjoining(last))
                .flatten()
                .any(|s| decisions[s].state == SegmentState::Slide);
            if !touches_slide {
                for &j in &run {
                    if plain[j].state != SegmentState::Stick {
                        decisions[j] = plain[j];
                        changed = true;
                    }
                }
            } else {
                let inputs = RunInputs {
                    active,
                    force,
                    slide_load: &slide_load,
                    previous,
                    ever_slid,
                    tractions,
                };
                changed |= recheck_run(chain, recovery, friction, &run, &inputs, decisions)?;
            }
            run.clear();
        }
        if !changed {
            return Ok(());
        }
    }
}

/// The loads of the sliding segments (unaltered normal tractions and their
/// friction, Fig. 5), per node.
fn slide_loads(
    chain: &Chain,
    tractions: &[SegmentTractions],
    decisions: &[SegmentDecision],
) -> Vec<[f64; 2]> {
    let mut slide_load = vec![[0.0; 2]; chain.nodes()];
    for (j, s) in chain.segments.iter().enumerate() {
        if decisions[j].state != SegmentState::Slide {
            continue;
        }
        let normal = s.loads(tractions[j].tn);
        let tangential = s.loads(applied_tangential_traction(s, &tractions[j], &decisions[j]));
        for (end, &k) in s.nodes.iter().enumerate() {
            for c in 0..2 {
                slide_load[k][c] += normal[end] * s.normal[c] + tangential[end] * s.tangent[c];
            }
        }
    }
    slide_load
}

/// What a run of sticking segments is checked on: the nodes' contact and
/// forces, the sliding segments' loads on them, and each segment's
/// previous state, history and recovered resultants.
struct RunInputs<'a> {
    active: &'a [bool],
    force: &'a [[f64; 2]],
    slide_load: &'a [[f64; 2]],
    previous: &'a [SegmentState],
    ever_slid: &'a [bool],
    tractions: &'a [SegmentTractions],
}

/// One run of sticking segments next to a sliding one, decided on the
/// force its nodes are left with (see `recheck_sticking_runs`): whether a
/// segment of it now slides or opens.
fn recheck_run(
    chain: &Chain,
    recovery: Recovery,
    friction: &Friction,
    run: &[usize],
    inputs: &RunInputs,
    decisions: &mut [SegmentDecision],
) -> Result<bool, TractionError> {
    let first = chain.segments[run[0]].nodes[0];
    let nodes: Vec<usize> = std::iter::once(first)
        .chain(run.iter().map(|&s| chain.segments[s].nodes[1]))
        .collect();
    let x: Vec<[f64; 2]> = nodes.iter().map(|&k| chain.x[k]).collect();
    let on: Vec<bool> = nodes.iter().map(|&k| inputs.active[k]).collect();
    let left: Vec<[f64; 2]> = nodes
        .iter()
        .map(|&k| {
            let (f, l) = (inputs.force[k], inputs.slide_load[k]);
            [f[0] - l[0], f[1] - l[1]]
        })
        .collect();
    let sub = Chain::new(chain.geometry, false, &x)?;
    let t = recover_tractions(&sub, recovery, &on, &left)?;
    let st = segment_tractions(&sub, &on, &t)?;
    let mut changed = false;
    for (r, &j) in run.iter().enumerate() {
        let d = decide_segment(friction, inputs.previous[j], inputs.ever_slid[j], &st[r]);
        if d.state != SegmentState::Stick {
            // Slides (or releases) on what it carries: the applied friction
            // is mu_d of its own T_n, in the direction of the force it was
            // left with.
            decisions[j] = SegmentDecision {
                state: d.state,
                tf: if d.state == SegmentState::Slide {
                    friction.mu_d * inputs.tractions[j].tn_total
                } else {
                    0.0
                },
                ever_slid: d.ever_slid,
                sign: d.sign,
            };
            changed = true;
        }
    }
    Ok(changed)
}

/// Step 4: the contact forces (global components, per node): the consistent nodal loads
/// of the unaltered linear normal traction and of the tangential traction of
/// [`applied_tangential_traction`] of every segment that is not open (Fig. 5, Eq. 32).
/// Inactive nodes next to an active one receive the loads of the segment between them
/// (see the module documentation).
pub fn contact_forces(
    chain: &Chain,
    tractions: &[SegmentTractions],
    decisions: &[SegmentDecision],
) -> Result<Vec<[f64; 2]>, TractionError> {
    check_len("segment tractions", chain.segments.len(), tractions.len())?;
    check_len("segment decisions", chain.segments.len(), decisions.len())?;
    let mut f = vec![[0.0; 2]; chain.nodes()];
    for (j, s) in chain.segments.iter().enumerate() {
        let (seg, dec) = (&tractions[j], &decisions[j]);
        if dec.state == SegmentState::Open {
            continue;
        }
        // A uniform tangential traction (sliding) loads the nodes by the row sums.
        let normal = s.loads(seg.tn);
        let tangential = s.loads(applied_tangential_traction(s, seg, dec));
        for (end, &k) in s.nodes.iter().enumerate() {
            for c in 0..2 {
                f[k][c] += normal[end] * s.normal[c] + tangential[end] * s.tangent[c];
            }
        }
    }
    Ok(f)
}

/// Step 5 (Table 1): an active node with at least one adjoining Stick segment sticks;
/// else with at least one Slide segment it slips; else it is Open. Inactive nodes are
/// reported Open: whether they come into contact is decided kinematically by the caller
/// (penetration), not by the recovery, even when an adjoining segment sticks or slides
/// through its other node.
pub fn node_states(
    chain: &Chain,
    active: &[bool],
    states: &[SegmentState],
) -> Result<Vec<NodeState>, TractionError> {
    check_len("active", chain.nodes(), active.len())?;
    check_len("segment states", chain.segments.len(), states.len())?;
    Ok((0..chain.nodes())
        .map(|k| {
            if !active[k] {
                return NodeState::Open;
            }
            let adj = chain.adjoining(k);
            let has = |st: SegmentState| adj.iter().flatten().any(|&s| states[s] == st);
            if has(SegmentState::Stick) {
                NodeState::Stick
            } else if has(SegmentState::Slide) {
                NodeState::Slip
            } else {
                NodeState::Open
            }
        })
        .collect())
}

/// Per node, for output: `t_n` and `t_t` averaged over the node's values in the frames of
/// its adjoining non-open segments (zero when both are open). The values are the
/// recovered ones (an Open segment's are zero).
pub fn node_tractions(
    chain: &Chain,
    segments: &[SegmentEval],
) -> Result<(Vec<f64>, Vec<f64>), TractionError> {
    check_len("segments", chain.segments.len(), segments.len())?;
    let m = chain.nodes();
    let (mut tn, mut tt) = (vec![0.0; m], vec![0.0; m]);
    for k in 0..m {
        let [before, after] = chain.adjoining(k);
        let mut count = 0.0;
        for (s, end) in [(before, 1), (after, 0)] {
            if let Some(s) = s.filter(|&s| segments[s].state != SegmentState::Open) {
                tn[k] += segments[s].tn[end];
                tt[k] += segments[s].tt[end];
                count += 1.0;
            }
        }
        if count > 0.0 {
            tn[k] /= count;
            tt[k] /= count;
        }
    }
    Ok((tn, tt))
}

/// Everything Section 3 gives for one segment.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SegmentEval {
    /// `t_n` at the first and second node (zero when Open).
    pub tn: [f64; 2],
    /// `t_t` at the first and second node, as recovered (zero when Open).
    pub tt: [f64; 2],
    /// `T_n` as recovered (kept when released: it is why the segment released).
    pub tn_total: f64,
    /// `T_t` as recovered, before the friction modification.
    pub tt_total: f64,
    /// `T_f`, see [`SegmentDecision::tf`].
    pub tf: f64,
    pub state: SegmentState,
    pub ever_slid: bool,
    /// See [`SegmentDecision::sign`].
    pub sign: f64,
}

/// The result of [`evaluate`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Evaluation {
    /// Nodal tractions `t^k`, global components (zero at inactive nodes).
    pub traction: Vec<[f64; 2]>,
    /// Per segment.
    pub segments: Vec<SegmentEval>,
    /// Contact forces on the contactor nodes, global components (Step 4).
    pub forces: Vec<[f64; 2]>,
    /// Table 1 (inactive nodes Open).
    pub node_states: Vec<NodeState>,
    /// Per node `t_n`, `t_t` for output ([`node_tractions`]).
    pub node_tn: Vec<f64>,
    pub node_tt: Vec<f64>,
    /// Sum of `forces`.
    pub fx: f64,
    pub fy: f64,
    /// Sum of `T_n` over the non-open segments.
    pub fn_: f64,
    /// Sum over the non-open segments of `T_t` (sticking) and `sign(T_t) T_f` (sliding).
    pub ft: f64,
}

/// Steps 1-5 for one contactor surface in one iteration.
///
/// `x`: current node positions; `active`: node in contact after the previous iteration;
/// `force`: force of the contact on each node (only active entries read); `previous`,
/// `ever_slid`: per segment, after the previous iteration; `directions`: per segment, the
/// sign of the friction it applied if it was sliding (zero if unknown). Frictionless when
/// `mu_s == mu_d == 0`.
///
/// A segment that was sliding and still slides keeps the direction of its friction
/// (Section 5 of the paper: the friction acts in the direction of the tangential force
/// before sliding). Its recovered `T_t` is, after an iteration, the friction it applied
/// itself plus what its neighbours' changes spilled onto its nodes; with large increments
/// the latter can flip its sign for an iteration, and friction that follows it would push
/// the node along its slip. A reversal is caught kinematically by the caller (the
/// segment whose nodes' slip runs along its friction sticks, its nodes at their anchors,
/// and the next sticking-to-sliding decision takes the new sign).
pub fn evaluate(
    geometry: Geometry,
    recovery: Recovery,
    mu_s: f64,
    mu_d: f64,
    rule: FrictionRule,
    closed: bool,
    x: &[[f64; 2]],
    active: &[bool],
    force: &[[f64; 2]],
    previous: &[SegmentState],
    ever_slid: &[bool],
    directions: &[f64],
) -> Result<Evaluation, TractionError> {
    let friction = Friction::new(mu_s, mu_d, rule)?;
    let chain = Chain::new(geometry, closed, x)?;
    let traction = recover_tractions(&chain, recovery, active, force)?;
    let tractions = segment_tractions(&chain, active, &traction)?;
    let mut decisions = decide_segments(&friction, previous, ever_slid, &tractions)?;
    check_len("directions", tractions.len(), directions.len())?;
    for (j, d) in decisions.iter_mut().enumerate() {
        if previous[j] == SegmentState::Slide
            && d.state == SegmentState::Slide
            && directions[j] != 0.0
        {
            d.sign = directions[j].signum();
        }
    }
    recheck_sticking_runs(
        &chain,
        recovery,
        &friction,
        active,
        force,
        previous,
        ever_slid,
        &tractions,
        &mut decisions,
    )?;
    let forces = contact_forces(&chain, &tractions, &decisions)?;
    let states: Vec<SegmentState> = decisions.iter().map(|d| d.state).collect();
    let node_states = node_states(&chain, active, &states)?;

    let segments = segment_evals(&tractions, &decisions);
    let (node_tn, node_tt) = node_tractions(&chain, &segments)?;
    let [fx, fy, fn_, ft] = resultants(&forces, &tractions, &decisions);
    check_finite(&forces, &segments, [&node_tn, &node_tt], [fx, fy, fn_, ft])?;
    Ok(Evaluation {
        traction,
        segments,
        forces,
        node_states,
        node_tn,
        node_tt,
        fx,
        fy,
        fn_,
        ft,
    })
}

/// Each segment's evaluation: its tractions (zero when open), resultants
/// and decision.
fn segment_evals(
    tractions: &[SegmentTractions],
    decisions: &[SegmentDecision],
) -> Vec<SegmentEval> {
    (tractions.iter().zip(decisions))
        .map(|(s, d)| {
            let (tn, tt) = if d.state == SegmentState::Open {
                ([0.0; 2], [0.0; 2])
            } else {
                (s.tn, s.tt)
            };
            SegmentEval {
                tn,
                tt,
                tn_total: s.tn_total,
                tt_total: s.tt_total,
                tf: d.tf,
                state: d.state,
                ever_slid: d.ever_slid,
                sign: d.sign,
            }
        })
        .collect()
}

/// The pair's resultants `[fx, fy, fn, ft]`: the sums of the contact
/// forces, and of the closed segments' normal and applied tangential
/// resultants.
fn resultants(
    forces: &[[f64; 2]],
    tractions: &[SegmentTractions],
    decisions: &[SegmentDecision],
) -> [f64; 4] {
    let (mut fx, mut fy) = (0.0, 0.0);
    for f in forces {
        fx += f[0];
        fy += f[1];
    }
    let (mut fn_, mut ft) = (0.0, 0.0);
    for (s, d) in tractions.iter().zip(decisions) {
        if d.state != SegmentState::Open {
            fn_ += s.tn_total;
            ft += applied_tangential(s, d);
        }
    }
    [fx, fy, fn_, ft]
}

/// An error naming the first non-finite contact force, segment
/// resultant, node traction or pair resultant.
fn check_finite(
    forces: &[[f64; 2]],
    segments: &[SegmentEval],
    [node_tn, node_tt]: [&[f64]; 2],
    pair: [f64; 4],
) -> Result<(), TractionError> {
    let non_finite = |quantity, index| Err(TractionError::NonFinite { quantity, index });
    if let Some(k) = forces
        .iter()
        .position(|f| !(f[0].is_finite() && f[1].is_finite()))
    {
        return non_finite("contact force at node", k);
    }
    if let Some(j) = segments
        .iter()
        .position(|s| !(s.tn_total.is_finite() && s.tt_total.is_finite() && s.tf.is_finite()))
    {
        return non_finite("resultant of segment", j);
    }
    if let Some(k) =
        (0..node_tn.len()).find(|&k| !(node_tn[k].is_finite() && node_tt[k].is_finite()))
    {
        return non_finite("node traction at node", k);
    }
    if !pair.iter().all(|v| v.is_finite()) {
        return non_finite("pair resultant", 0);
    }
    Ok(())
}

#[cfg(test)]
mod tests;
