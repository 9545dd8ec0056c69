//! The global contact entries of `contact::update` against central finite
//! differences of the potentials of Eqs. (11) and (17) (docs/contact.md,
//! sections 4 and 5), written here from the document, on a small patch: a
//! 2x1 Q4 (or Q8) contactor block pressed into a 2x1 Q4 target block (or a
//! rigid polyline at the same place), some contactor nodes sticking at a
//! given material point (beta), some sliding, all with nonzero contact
//! forces.
//!
//! With `W = sum_k W_k(dU, dlambda)` over the constrained nodes, docs section
//! 2 item 5 and the assembly in `src/newton.rs` (rhs `-(F_int - R_ext) +
//! force`, rows entering as `[K + k, C^T; C, 0]`) require
//!
//! - `force` = `R_c` = `dW/dU` at 0, summed per global dof,
//! - `rows`: coefficients `C = -d2W/(dlambda dU)` (the multiplier block of
//!   `K_c`) and right-hand side `Delta_c = dW/dlambda` at 0, one row per
//!   multiplier, in the order of the contactor nodes and of the
//!   multipliers of each node (`[dlambda_x, dlambda_y]` sticking,
//!   `[dlambda_s]` sliding),
//! - `k` = `K_beta` = `-d2W/dU2` (the sliding gradient matrix).
//!
//! Every global dof is compared, so an entry on a wrong dof (A and B
//! swapped, a target dof filled against a rigid target) fails, and the test
//! itself checks that the expectations of a potential with A and B swapped,
//! or with beta replaced by 1 - beta, are rejected.

mod common;

use contact2d::contact::{self, ContactSystem, Flips, PairMemory, RigidSegments};
use contact2d::mesh::{ElementKind, Mesh};
use contact2d::problem::*;
use contact2d::results::NodeState;
use contact2d::results::NodeState::{Slip, Stick};
use std::collections::BTreeMap;

type V2 = [f64; 2];

fn sub(a: V2, b: V2) -> V2 {
    [a[0] - b[0], a[1] - b[1]]
}

fn dot(a: V2, b: V2) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// The patch: a problem with one contact pair, displacements that press the
/// contactor's bottom nodes into the target, and the node lists.
struct Patch {
    problem: Problem,
    u: Vec<f64>,
    /// Contactor bottom nodes (mesh numbering), in +x order.
    contactor: Vec<usize>,
    /// Target top nodes (mesh numbering), in decreasing x: A -> B of each
    /// segment has the target on its left.
    top: Vec<usize>,
    /// Current positions of the target top nodes (also the rigid polyline).
    top_x: Vec<V2>,
}

impl Patch {
    fn x(&self, n: usize) -> V2 {
        let p = self.problem.mesh.nodes[n];
        [p[0] + self.u[2 * n], p[1] + self.u[2 * n + 1]]
    }
}

/// A 2x1 `kind` contactor block on [0, 2] x [0, 1] over a 2x1 Q4 target
/// block on [-0.4, 2.2] x [-1, 0], both displaced so that the target's top
/// segments are tilted and every contactor bottom node has penetrated the
/// target by 0.01 to 0.03. Against a rigid target the polyline takes the
/// target's current top edge, and the target block stays in the mesh (its
/// dofs must receive nothing).
fn patch(kind: ElementKind, rigid: bool) -> Patch {
    let c = common::grid(kind, [0.0, 0.0], [2.0, 1.0], 2, 1, |x, y| [x, y]);
    let t = common::grid(ElementKind::Q4, [-0.4, -1.0], [2.6, 1.0], 2, 1, |x, y| {
        [x, y]
    });
    let (nc, nec) = (c.nodes.len(), c.elements.len());
    let mut bottom = c.node_sets["bottom"].clone();
    bottom.sort_by(|&a, &b| c.nodes[a][0].total_cmp(&c.nodes[b][0]));
    let mut top: Vec<usize> = t.node_sets["top"].iter().map(|&n| n + nc).collect();
    let mut elements = c.elements.clone();
    for e in &t.elements {
        let mut e = e.clone();
        for n in &mut e.nodes {
            *n += nc;
        }
        elements.push(e);
    }
    let mut nodes = c.nodes.clone();
    nodes.extend(t.nodes.iter().copied());
    let (nn, ne) = (nodes.len(), elements.len());
    top.sort_by(|&a, &b| nodes[b][0].total_cmp(&nodes[a][0]));
    let mesh = Mesh {
        nodes,
        elements,
        node_sets: BTreeMap::new(),
        edge_sets: BTreeMap::new(),
        element_sets: BTreeMap::new(),
    };
    let mut problem = common::problem(
        mesh,
        AnalysisKind::PlaneStrain { thickness: 1.0 },
        Kinematics::SmallStrain,
        1000.0,
        0.3,
    );
    problem.bodies = vec![
        Body {
            name: "contactor".into(),
            material: 0,
            elements: 0..nec,
            nodes: 0..nc,
            strip: None,
            running: false,
        },
        Body {
            name: "target".into(),
            material: 0,
            elements: nec..ne,
            nodes: nc..nn,
            strip: None,
            running: false,
        },
    ];
    // A generic displacement field, then the contactor's bottom nodes put
    // below the (tilted) target surface.
    let mut u: Vec<f64> = (0..2 * nn)
        .map(|d| 0.02 * (0.7 * d as f64 + 0.4).sin())
        .collect();
    let pos = |u: &[f64], n: usize| {
        let p = problem.mesh.nodes[n];
        [p[0] + u[2 * n], p[1] + u[2 * n + 1]]
    };
    let top_x: Vec<V2> = top.iter().map(|&n| pos(&u, n)).collect();
    for (k, &n) in bottom.iter().enumerate() {
        let x = pos(&u, n)[0];
        let s = top_x
            .windows(2)
            .find(|w| w[1][0] <= x && x <= w[0][0])
            .expect("contactor node over the target");
        let surface = s[0][1] + (s[1][1] - s[0][1]) * (x - s[0][0]) / (s[1][0] - s[0][0]);
        let penetration = 0.01 + 0.02 * k as f64 / (bottom.len() - 1) as f64;
        u[2 * n + 1] = surface - penetration - problem.mesh.nodes[n][1];
    }
    let target = if rigid {
        problem.rigids.push(Rigid {
            name: "flat".into(),
            points: top_x.clone(),
            reference: [0.0, 0.0],
            ux: Scaled::constant(0.0),
            uy: Scaled::constant(0.0),
            theta: Scaled::constant(0.0),
        });
        Target::Rigid(0)
    } else {
        Target::Body {
            body: 1,
            segments: top.windows(2).map(|w| [w[0], w[1]]).collect(),
            smooth: None,
        }
    };
    problem.contacts.push(ContactPair {
        name: "patch".into(),
        body: 0,
        contactor: bottom.clone(),
        closed: false,
        target,
        mu_s: 0.3,
        mu_d: 0.2,
        rule: FrictionRule::MuDAfterSlip,
        recovery: Recovery::Consistent,
        decisions: contact2d::problem::Decisions::Paper,
        formulation: Default::default(),
    });
    Patch {
        problem,
        u,
        contactor: bottom,
        top,
        top_x,
    }
}

/// One constrained contactor node, as the potential sees it.
#[derive(Clone, Debug)]
struct Constrained {
    node: usize,
    state: NodeState,
    /// Target segment end nodes A, B (None: rigid, no dofs).
    dofs_ab: Option<[usize; 2]>,
    beta: f64,
    lambda: V2,
    /// Current positions of k, A and B.
    xk: V2,
    xa: V2,
    xb: V2,
}

impl Constrained {
    fn multipliers(&self) -> usize {
        if self.state == NodeState::Stick { 2 } else { 1 }
    }
}

/// `W = sum_k W_k`: Eq. (11) for a sticking node, Eq. (17) for a sliding one
/// (docs/contact.md sections 4 and 5), at displacement increments `du` (all
/// mesh dofs) and multiplier increments `dl` (all multipliers in order).
fn potential(nodes: &[Constrained], du: &[f64], dl: &[f64]) -> f64 {
    let mut w = 0.0;
    let mut m = 0;
    for c in nodes {
        let at = |n: usize| [du[2 * n], du[2 * n + 1]];
        let duk = at(c.node);
        let (dua, dub) = c
            .dofs_ab
            .map_or(([0.0; 2], [0.0; 2]), |[a, b]| (at(a), at(b)));
        let b = c.beta;
        // Segment geometry (Eqs. 3-6) and the overlap Delta_k = x_k - x_C.
        let ab = sub(c.xb, c.xa);
        let length = dot(ab, ab).sqrt();
        let tangent = [ab[0] / length, ab[1] / length];
        let overlap: V2 = std::array::from_fn(|i| c.xk[i] - c.xa[i] - b * ab[i]);
        // g = G dU + Delta_k: the overlap after the iteration, C held at the
        // material point beta.
        let g: V2 = std::array::from_fn(|i| duk[i] - (1.0 - b) * dua[i] - b * dub[i] + overlap[i]);
        match c.state {
            NodeState::Stick => {
                // Eq. (11): (lambda + dlambda)^T g.
                let lam = [c.lambda[0] + dl[m], c.lambda[1] + dl[m + 1]];
                w += dot(lam, g);
            }
            NodeState::Slip => {
                // Eq. (17): the force distributed with beta + dbeta (Eq. 12),
                // dbeta from Eq. (14); lambda(i) = lambda - dlambda_s n_s
                // (Eqs. 15, 16), the product dlambda_s dbeta dropped.
                let nbar = [tangent[0] / length, tangent[1] / length];
                let normal = [-tangent[1], tangent[0]];
                let dbeta = dot(nbar, g);
                let moved: V2 = std::array::from_fn(|i| {
                    duk[i] - (1.0 - b - dbeta) * dua[i] - (b + dbeta) * dub[i] + overlap[i]
                });
                w += dot(c.lambda, moved) - dl[m] * dot(normal, g);
            }
            NodeState::Open => unreachable!(),
        }
        m += c.multipliers();
    }
    w
}

/// The code's entries as dense global arrays.
struct Assembled {
    force: Vec<f64>,
    rows: Vec<Vec<f64>>,
    rhs: Vec<f64>,
    k: Vec<Vec<f64>>,
}

fn assembled(c: &ContactSystem, ndof: usize) -> Assembled {
    let mut force = vec![0.0; ndof];
    for &(d, f) in &c.force {
        force[d] += f;
    }
    let mut k = vec![vec![0.0; ndof]; ndof];
    for &(a, b, v) in &c.k {
        k[a][b] += v;
    }
    let mut rows = Vec::new();
    let mut rhs = Vec::new();
    for r in &c.rows {
        let mut row = vec![0.0; ndof];
        for &(d, v) in &r.dofs {
            row[d] += v;
        }
        rows.push(row);
        rhs.push(r.rhs);
    }
    Assembled {
        force,
        rows,
        rhs,
        k,
    }
}

/// Step of the first derivatives, relative to the displacement scale (the
/// block size, 1) and to the largest contact force. The potentials are
/// quadratic in (dU, dlambda), so central differences have no truncation
/// error; the round-off of a first derivative is ~ eps |W| / h ~ 1e-16 x
/// |lambda . Delta| / 1e-6 ~ 1e-10 of the derivatives here, far below the
/// 1e-6 tolerance.
const H1: f64 = 1e-6;
/// Step of the second derivatives (four-point formula): still exact for a
/// quadratic, but its round-off is ~ eps |W| / h^2, which is 1e-5 of the
/// entries at h = 1e-6 and 1e-9 at h = 1e-4.
const H2: f64 = 1e-4;
/// Agreement, relative to the largest entry of each compared quantity:
/// everything above is exact to ~1e-9, so 1e-6 leaves a margin of 1e3
/// while a wrong dof, sign or weight (entries of order one of that size)
/// fails by orders of magnitude.
const TOL: f64 = 1e-6;

/// The expected entries, from central differences of `potential`.
fn expected(nodes: &[Constrained], ndof: usize) -> Assembled {
    let nl: usize = nodes.iter().map(|c| c.multipliers()).sum();
    let lscale = nodes
        .iter()
        .flat_map(|c| c.lambda)
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let w = |du: &[f64], dl: &[f64]| potential(nodes, du, dl);
    let zu = vec![0.0; ndof];
    let zl = vec![0.0; nl];
    let unit = |n: usize, i: usize, h: f64| {
        let mut v = vec![0.0; n];
        v[i] = h;
        v
    };
    let plus = |a: &[f64], b: &[f64], s: f64| -> Vec<f64> {
        a.iter().zip(b).map(|(x, y)| x + s * y).collect()
    };
    let (hu, hl) = (H1, H1 * lscale);
    let force: Vec<f64> = (0..ndof)
        .map(|d| {
            let e = unit(ndof, d, hu);
            (w(&e, &zl) - w(&plus(&zu, &e, -1.0), &zl)) / (2.0 * hu)
        })
        .collect();
    let rhs: Vec<f64> = (0..nl)
        .map(|i| {
            let e = unit(nl, i, hl);
            (w(&zu, &e) - w(&zu, &plus(&zl, &e, -1.0))) / (2.0 * hl)
        })
        .collect();
    let (hu, hl) = (H2, H2 * lscale);
    let rows: Vec<Vec<f64>> = (0..nl)
        .map(|i| {
            let el = unit(nl, i, hl);
            let ml = plus(&zl, &el, -1.0);
            (0..ndof)
                .map(|d| {
                    let eu = unit(ndof, d, hu);
                    let mu = plus(&zu, &eu, -1.0);
                    let d2 =
                        (w(&eu, &el) - w(&eu, &ml) - w(&mu, &el) + w(&mu, &ml)) / (4.0 * hu * hl);
                    -d2
                })
                .collect()
        })
        .collect();
    let k: Vec<Vec<f64>> = (0..ndof)
        .map(|a| {
            (0..ndof)
                .map(|b| {
                    let ea = unit(ndof, a, hu);
                    let eb = unit(ndof, b, hu);
                    let f = |sa: f64, sb: f64| {
                        let du: Vec<f64> = (0..ndof).map(|q| sa * ea[q] + sb * eb[q]).collect();
                        w(&du, &zl)
                    };
                    let d2 = (f(1.0, 1.0) - f(1.0, -1.0) - f(-1.0, 1.0) + f(-1.0, -1.0))
                        / (4.0 * hu * hu);
                    -d2
                })
                .collect()
        })
        .collect();
    Assembled {
        force,
        rows,
        rhs,
        k,
    }
}

/// Max |a - b| over max |b|, or over `floor` when b vanishes.
fn rel_err(a: &[f64], b: &[f64], floor: f64) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = b.iter().fold(floor, |m, v| m.max(v.abs()));
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / scale
}

/// Compare every entry: the relative errors of `force`, the rows' rhs,
/// their coefficients and `k`, as a summary (Err when one exceeds TOL).
fn compare(code: &Assembled, fd: &Assembled, force_scale: f64) -> Result<String, String> {
    if code.rows.len() != fd.rows.len() {
        return Err(format!(
            "{} rows, expected {}",
            code.rows.len(),
            fd.rows.len()
        ));
    }
    // K_beta is of the size lambda / d; against a rigid target it vanishes
    // and is compared against the size of lambda.
    let errors = [
        ("force", rel_err(&code.force, &fd.force, 0.0)),
        ("rhs", rel_err(&code.rhs, &fd.rhs, 0.0)),
        ("rows", rel_err(&code.rows.concat(), &fd.rows.concat(), 0.0)),
        ("k", rel_err(&code.k.concat(), &fd.k.concat(), force_scale)),
    ];
    let summary = errors
        .iter()
        .map(|(q, e)| format!("{q} {e:.2e}"))
        .collect::<Vec<_>>()
        .join(", ");
    if errors.iter().all(|(_, e)| *e <= TOL) {
        Ok(summary)
    } else {
        Err(summary)
    }
}

/// What the FD expectations are computed from (the mutations must fail).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Mutation {
    SwapAB,
    OneMinusBeta,
}

fn mutate(nodes: &[Constrained], m: Mutation) -> Vec<Constrained> {
    nodes
        .iter()
        .map(|c| {
            let mut c = c.clone();
            match m {
                Mutation::SwapAB => c.dofs_ab = c.dofs_ab.map(|[a, b]| [b, a]),
                Mutation::OneMinusBeta => c.beta = 1.0 - c.beta,
            }
            c
        })
        .collect()
}

/// The patch with the given contactor segment states wanted (Stick or Slip),
/// the out-of-balance forces `r` at the contactor nodes, and, per node, the
/// beta of a sticking node relative to its projection (so that it carries a
/// tangential overlap). Runs `contact::update` and checks it against the
/// potential.
fn check(kind: ElementKind, rigid: bool, wanted: &[NodeState], r_nodes: &[V2], shift: &[f64]) {
    let p = patch(kind, rigid);
    let m = p.contactor.len();
    assert_eq!(wanted.len(), m - 1);
    assert_eq!(r_nodes.len(), m);
    let ndof = p.u.len();
    let pair = &p.problem.contacts[0];
    // Where each contactor node projects: segment and beta.
    let segs: Vec<[V2; 2]> = p.top_x.windows(2).map(|w| [w[0], w[1]]).collect();
    let project = |x: V2| -> (usize, f64) {
        segs.iter()
            .enumerate()
            .map(|(j, [xa, xb])| {
                let ab = sub(*xb, *xa);
                (j, dot(sub(x, *xa), ab) / dot(ab, ab))
            })
            .find(|(_, b)| (0.0..=1.0).contains(b))
            .expect("projection on the target")
    };
    // Node states from the segment states (Table 1): a node sticks when an
    // adjoining segment sticks, else slides.
    let node_state = |k: usize| {
        let adj = [k.checked_sub(1), (k < m - 1).then_some(k)];
        if adj.iter().flatten().any(|&s| wanted[s] == NodeState::Stick) {
            NodeState::Stick
        } else {
            NodeState::Slip
        }
    };
    // Memory after iteration (i-1): every node sticking at its material
    // point, every segment sticking (a segment then slides when its T_t
    // exceeds mu_s T_n: the forces below are chosen so).
    let mut memory = PairMemory::new(pair);
    let PairMemory::NodeToSegment(nodes) = &mut memory else {
        panic!("a node-to-segment pair");
    };
    let mut beta_stick = vec![0.0; m];
    for k in 0..m {
        let (j, b) = project(p.x(p.contactor[k]));
        beta_stick[k] = b + shift[k];
        let node = &mut nodes.nodes[k];
        node.state = NodeState::Stick;
        node.segment = j;
        node.beta = beta_stick[k];
    }
    for s in nodes.segments.iter_mut() {
        s.state = NodeState::Stick;
        s.ever_slid = false;
    }
    let mut r = vec![0.0; ndof];
    for (k, &n) in p.contactor.iter().enumerate() {
        r[2 * n] = r_nodes[k][0];
        r[2 * n + 1] = r_nodes[k][1];
    }
    // No prescribed dof: every dof its own equation.
    let eq: Vec<u32> = (0..ndof as u32).collect();
    let mut mem = vec![memory];
    let mut log = Vec::new();
    let poses = contact::scene_poses(&p.problem, 1.0);
    let start = contact::Start {
        u: &p.u,
        poses: &poses,
        settling: false,
        touching: false,
        cache: &contact::StartCache::default(),
    };
    let sys = contact::update(
        &p.problem,
        &RigidSegments::default(),
        &poses,
        &p.u,
        &r,
        &eq,
        &start,
        &mut mem,
        &mut Flips::default(),
        &mut |s: &str| log.push(s.to_string()),
        None,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let code = assembled(&sys, ndof);

    // The scenario holds: segment and node states as wanted.
    let PairMemory::NodeToSegment(after) = &mem[0] else {
        panic!("a node-to-segment pair");
    };
    let seg_states: Vec<NodeState> = after.segments.iter().map(|s| s.state).collect();
    assert_eq!(seg_states, wanted, "segment states; log {log:?}");
    let states: Vec<NodeState> = (0..m).map(node_state).collect();
    assert!(states.contains(&NodeState::Stick) && states.contains(&NodeState::Slip));
    for k in 0..m {
        assert_eq!(mem[0].state(k), states[k], "node {k}; log {log:?}");
    }

    // The potential's data, from the patch (not from the code), except
    // lambda: taken from `force` (its entries at the node's own dofs), and
    // checked to be r where every adjoining segment sticks. Next to a
    // sliding segment the friction part is the uniform traction's (Fig. 5).
    let mut nodes = Vec::new();
    let mut first_row = 0;
    let mut stick_drift = 0.0f64;
    for k in 0..m {
        let n = p.contactor[k];
        let xk = p.x(n);
        let (j, proj) = project(xk);
        let beta = if states[k] == NodeState::Stick {
            beta_stick[k]
        } else {
            proj
        };
        assert!(
            (beta - 0.5).abs() > 0.02,
            "node {k}: beta {beta} too close to 1/2 for the 1 - beta check"
        );
        assert_eq!(mem[0].contact(k).1, j, "node {k}");
        assert!((mem[0].contact(k).2 - beta).abs() <= 1e-12, "node {k}");
        let [xa, xb] = segs[j];
        let ab = sub(xb, xa);
        let length = dot(ab, ab).sqrt();
        let xc = [xa[0] + beta * ab[0], xa[1] + beta * ab[1]];
        let tangential_overlap = dot(sub(xk, xc), ab) / length;
        // The contact force the code used: R_c = G^T lambda, whose entries at
        // the contactor node's own dofs are lambda.
        let lambda = [code.force[2 * n], code.force[2 * n + 1]];
        let adjoining_stick = [k.checked_sub(1), (k < m - 1).then_some(k)]
            .iter()
            .flatten()
            .all(|&s| wanted[s] == NodeState::Stick);
        if adjoining_stick {
            // Consistent recovery with every node in contact reproduces the
            // out-of-balance force at a node whose segments all stick.
            let e = dot(sub(lambda, r_nodes[k]), sub(lambda, r_nodes[k])).sqrt();
            assert!(
                e <= 1e-12 * dot(r_nodes[k], r_nodes[k]).sqrt(),
                "node {k}: lambda {lambda:?} != r {:?}",
                r_nodes[k]
            );
        }
        let normal = [-ab[1] / length, ab[0] / length];
        assert!(dot(lambda, normal) < 0.0, "node {k}: compressive lambda");
        let c = Constrained {
            node: n,
            state: states[k],
            dofs_ab: (!rigid).then(|| [p.top[j], p.top[j + 1]]),
            beta,
            lambda,
            xk,
            xa,
            xb,
        };
        // Groups: the node's rows, in contactor order.
        let rows = first_row..first_row + c.multipliers();
        first_row = rows.end;
        assert!(
            sys.groups.iter().any(|g| g.0 == n && g.1 == rows),
            "node {k} (mesh {n}) rows {rows:?}: groups {:?}",
            sys.groups
        );
        if c.state == NodeState::Stick {
            stick_drift = stick_drift.max(tangential_overlap.abs());
        } else {
            assert!(tangential_overlap.abs() < 1e-12, "sliding: the projection");
        }
        nodes.push(c);
    }
    assert_eq!(sys.groups.len(), m);
    assert_eq!(sys.neqc(), first_row);
    // The sticking nodes carry a tangential overlap, so the rhs checks beta.
    assert!(stick_drift > 1e-3, "tangential overlap {stick_drift}");

    let lscale = nodes
        .iter()
        .flat_map(|c| c.lambda)
        .fold(0.0f64, |a, v| a.max(v.abs()));
    let fd = expected(&nodes, ndof);
    match compare(&code, &fd, lscale) {
        Ok(summary) => eprintln!("{kind:?} rigid {rigid}: relative errors {summary}"),
        Err(e) => panic!("{kind:?} rigid {rigid}: relative errors {e}"),
    }
    // Against a rigid target nothing lands on the target block's dofs and
    // there is no sliding gradient matrix.
    if rigid {
        for &n in &p.top {
            assert_eq!(code.force[2 * n], 0.0);
            assert_eq!(code.force[2 * n + 1], 0.0);
        }
        assert!(sys.k.is_empty());
        for row in &sys.rows {
            assert!(
                row.dofs
                    .iter()
                    .all(|&(d, _)| d / 2 < p.problem.bodies[0].nodes.end)
            );
        }
    } else {
        assert!(
            !sys.k.is_empty(),
            "a sliding node against a flexible target"
        );
    }
    // The comparison would see a wrong dof or a wrong weight.
    let mutations: &[Mutation] = if rigid {
        &[Mutation::OneMinusBeta]
    } else {
        &[Mutation::SwapAB, Mutation::OneMinusBeta]
    };
    for &mutation in mutations {
        let wrong = expected(&mutate(&nodes, mutation), ndof);
        match compare(&code, &wrong, lscale) {
            Ok(summary) => panic!("{mutation:?} not detected: {summary}"),
            Err(e) => eprintln!("  {mutation:?} rejected: {e}"),
        }
    }
}

/// Q4 contactor (nodes at x = 0, 1, 2): segment 0 sticks, segment 1 slides
/// (|T_t| > mu_s T_n), so nodes 0, 1 stick (node 1 next to the sliding
/// segment) and node 2 slides.
const Q4_FORCES: [V2; 3] = [[20.0, 300.0], [40.0, 500.0], [160.0, 280.0]];
const Q4_SHIFT: [f64; 3] = [0.06, -0.04, 0.0];

/// Q8 contactor (nodes at x = 0, 0.5, 1, 1.5, 2): segments 0, 1 stick,
/// segments 2, 3 slide: nodes 0-2 stick, nodes 3, 4 slide.
const Q8_FORCES: [V2; 5] = [
    [10.0, 200.0],
    [20.0, 400.0],
    [80.0, 380.0],
    [250.0, 400.0],
    [130.0, 220.0],
];
const Q8_SHIFT: [f64; 5] = [0.05, -0.07, 0.04, 0.0, 0.0];

#[test]
fn q4_patch_flexible_target_sticking_and_sliding() {
    check(
        ElementKind::Q4,
        false,
        &[Stick, Slip],
        &Q4_FORCES,
        &Q4_SHIFT,
    );
}

#[test]
fn q4_patch_rigid_target_sticking_and_sliding() {
    check(ElementKind::Q4, true, &[Stick, Slip], &Q4_FORCES, &Q4_SHIFT);
}

#[test]
fn q8_patch_flexible_target_sticking_and_sliding() {
    check(
        ElementKind::Q8,
        false,
        &[Stick, Stick, Slip, Slip],
        &Q8_FORCES,
        &Q8_SHIFT,
    );
}

#[test]
fn q8_patch_rigid_target_sticking_and_sliding() {
    check(
        ElementKind::Q8,
        true,
        &[Stick, Stick, Slip, Slip],
        &Q8_FORCES,
        &Q8_SHIFT,
    );
}
