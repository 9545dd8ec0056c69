//! The contact conditions of a converged state linearised exactly, with the
//! contact states held (sticking nodes tied, sliding nodes with their
//! friction `mu_d p_n` against their slip, open nodes free): what the
//! sensitivities of the state (the FMU's directional derivatives) solve
//! with. Newton's own rows drop terms the paper drops (the turn of the
//! target normal, and Eq. 24's symmetric sliding gradient for the exact
//! `b a^T`, docs/contact.md section 7); here every term is kept, so the
//! solution is the derivative of the converged state.
//!
//! Per node in contact, with `G = [I, -(1-beta) I, -beta I]` over the node
//! and the target segment's ends A, B (none for a rigid target), the
//! contact force on the dofs is `G^T lambda` and the condition holds the
//! node on the target:
//! - held (sticking, or a frictionless node at a reflex corner): `lambda`
//!   is two multipliers, beta is fixed, `x_k - x_C = 0`;
//! - sliding: `lambda = -P (n_s + phi n_r)` with `P` the multiplier (the
//!   normal force) and `phi = s mu_d`, beta follows the projection, and
//!   `n_s . (x_k - x_A) = 0`.
//!
//! A rigid target's pose `[ux, uy, theta]` moves its material point at `x`
//! with `d x = (d ux, d uy) + d theta e_z x (x - reference)`.

use super::ContactSystem;
use crate::assembly::PRESCRIBED;
use crate::problem::Problem;
use nalgebra::Vector2;

/// One linearised contact condition: `sum dofs . du + sum poses . dpose =
/// 0`, and the contact force its multiplier brings, `column` per dof.
#[derive(Clone, Debug, Default)]
pub struct Row {
    pub dofs: Vec<(usize, f64)>,
    /// (rigid target, pose component, coefficient).
    pub poses: Vec<(usize, usize, f64)>,
    pub column: Vec<(usize, f64)>,
}

/// How the target segment a node touches turns: the rate `omega` of its
/// tangent (`d n_r = omega n_s`, `d n_s = -omega n_r`).
#[derive(Clone, Copy, Debug)]
pub enum Turn {
    /// `omega = n_s . (du_B - du_A) / length`.
    Segment { a: usize, b: usize, length: f64 },
    /// `omega = d theta` of the rigid target.
    Rigid { rigid: usize },
    /// The frame of a mortar contactor's node (`report::node_frame`), along
    /// the bisector of its sides' chords, turns by their turns' mean:
    /// `omega = sum w . (du_b - du_a)` over the chords (a, b) with `w` the
    /// chord's left normal over its length and their count.
    Chords {
        chords: [Option<(usize, usize, Vector2<f64>)>; 2],
    },
}

/// A contactor node in contact, as the pair results count it.
#[derive(Clone, Debug)]
pub struct NodeForce {
    pub pair: usize,
    /// Mesh node.
    pub node: usize,
    /// Its contact force (the out-of-balance force at its free
    /// components; with `multipliers`, its rows' forces at every
    /// component), the target's normal and tangent where it touches, and
    /// the contact point.
    pub force: Vector2<f64>,
    pub normal: Vector2<f64>,
    pub tangent: Vector2<f64>,
    pub point: Vector2<f64>,
    pub turn: Turn,
    /// Held at a material point of the target (else it slides along it).
    pub held: bool,
    /// A rigid target's moved reference point (the moment's origin).
    pub reference: [f64; 2],
    /// The pair reads the node's force from its multipliers (mortar), a
    /// prescribed component's too; else from the out-of-balance force,
    /// which counts a prescribed component as zero (node-to-segment).
    pub multipliers: bool,
}

/// The linearised contact part of a converged state.
#[derive(Clone, Debug, Default)]
pub struct Linearised {
    /// `d(G^T lambda)/du` at fixed multipliers over all dofs: (row dof,
    /// column dof, value). Only a sliding node on a flexible target has one.
    pub k: Vec<(usize, usize, f64)>,
    /// `d(G^T lambda)/d pose` at fixed multipliers: (dof, rigid, pose
    /// component, value). Only a sliding node on a turning rigid target.
    pub pose: Vec<(usize, usize, usize, f64)>,
    pub rows: Vec<Row>,
    pub nodes: Vec<NodeForce>,
}
/// Derivatives of a material point of a rigid target at `x` with respect to
/// its pose [ux, uy, theta] (`reference`: the moved reference point).
pub(crate) fn material_velocity(x: Vector2<f64>, reference: [f64; 2]) -> [Vector2<f64>; 3] {
    [
        Vector2::new(1.0, 0.0),
        Vector2::new(0.0, 1.0),
        Vector2::new(-(x.y - reference[1]), x.x - reference[0]),
    ]
}
/// A converged state, as its linearisation reads it: the out-of-balance
/// forces `r` (contact excluded), the equation map `eq` and
/// the rigid targets' poses.
pub struct At<'a> {
    pub problem: &'a Problem,
    pub poses: &'a [[f64; 3]],
    pub r: &'a [f64],
    pub eq: &'a [u32],
}

/// The linearisation of the contact conditions `system` holds at the
/// converged state `at`, pair by pair by its formulation.
pub fn linearise(at: &At, system: &ContactSystem) -> Result<Linearised, String> {
    let mut out = Linearised::default();
    for (p, pair) in at.problem.contacts.iter().enumerate() {
        let kept = system.kept.get(p).ok_or_else(|| {
            format!(
                "contact pair '{}': no decisions at this state (internal)",
                pair.name
            )
        })?;
        super::formulation(pair).linearise(at, (p, pair), kept, &mut out)?;
    }
    Ok(out)
}

impl Linearised {
    /// `out += d(G^T lambda)`: the change of the contact forces on every dof
    /// for displacement changes `du` (all dofs), multiplier changes
    /// `multipliers` (one per row) and pose changes `dpose`.
    pub fn force_change(
        &self,
        du: &[f64],
        multipliers: &[f64],
        dpose: &[[f64; 3]],
        out: &mut [f64],
    ) {
        for &(i, j, v) in &self.k {
            out[i] += v * du[j];
        }
        for &(i, rigid, c, v) in &self.pose {
            out[i] += v * dpose[rigid][c];
        }
        for (row, &m) in self.rows.iter().zip(multipliers) {
            for &(i, v) in &row.column {
                out[i] += v * m;
            }
        }
    }

    /// Changes of each pair's resultants [Fx, Fy, Fn, Ft] (`pairs` of
    /// them) and of each rigid target's reaction [Rx, Ry, Mz] (`rigids`),
    /// for displacement changes `du`, out-of-balance force changes `dr`
    /// (all dofs; `eq` marks the prescribed ones, whose force counts as
    /// zero), contact force changes `dfc` (all dofs: a node read from its
    /// multipliers, `NodeForce::multipliers`) and pose changes `dpose`.
    pub fn resultant_changes(
        &self,
        [pairs, rigids]: [usize; 2],
        du: &[f64],
        [dr, dfc]: [&[f64]; 2],
        eq: &[u32],
        dpose: &[[f64; 3]],
    ) -> (Vec<[f64; 4]>, Vec<[f64; 3]>) {
        let mut pair = vec![[0.0; 4]; pairs];
        let mut rigid = vec![[0.0; 3]; rigids];
        let at = |v: &[f64], m: usize| Vector2::new(v[2 * m], v[2 * m + 1]);
        for node in &self.nodes {
            let component = |d: usize| match (node.multipliers, eq[d] == PRESCRIBED) {
                (true, _) => dfc[d],
                (false, true) => 0.0,
                (false, false) => dr[d],
            };
            let df = Vector2::new(component(2 * node.node), component(2 * node.node + 1));
            let omega = match node.turn {
                Turn::Segment { a, b, length } => {
                    node.normal.dot(&(at(du, b) - at(du, a))) / length
                }
                Turn::Rigid { rigid } => dpose[rigid][2],
                Turn::Chords { chords } => (chords.iter().flatten())
                    .map(|&(a, b, w)| w.dot(&(at(du, b) - at(du, a))))
                    .sum(),
            };
            let (f, n_s, n_r) = (node.force, node.normal, node.tangent);
            let out = &mut pair[node.pair];
            out[0] += df.x;
            out[1] += df.y;
            // Fn = -sum f . n_s, Ft = -sum f . n_r, with the frame turning.
            out[2] -= df.dot(&n_s) - omega * f.dot(&n_r);
            out[3] -= df.dot(&n_r) + omega * f.dot(&n_s);
            let Turn::Rigid { rigid: ri } = node.turn else {
                continue;
            };
            // The target's reaction: -f at the contact point, the moment
            // about the moved reference point.
            let v = material_velocity(node.point, node.reference);
            let carried: Vector2<f64> = (0..3).map(|c| v[c] * dpose[ri][c]).sum();
            let dx = if node.held {
                carried
            } else {
                n_s * n_s.dot(&carried) + n_r * n_r.dot(&at(du, node.node))
            };
            let arm = node.point - Vector2::new(node.reference[0], node.reference[1]);
            let darm = dx - Vector2::new(dpose[ri][0], dpose[ri][1]);
            let out = &mut rigid[ri];
            out[0] -= df.x;
            out[1] -= df.y;
            out[2] -= darm.x * f.y - darm.y * f.x + arm.x * df.y - arm.y * df.x;
        }
        (pair, rigid)
    }
}
