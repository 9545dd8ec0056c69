//! A contactor node that alternates between open and closed within one
//! increment is detected and reported by name, not looped on.

mod common;

use contact2d::contact::{self, Flips, PairMemory, RigidSegments};
use contact2d::mesh::ElementKind;
use contact2d::problem::*;
use contact2d::results::NodeState;

#[test]
fn a_node_flipping_open_and_closed_is_reported() {
    // A 1x1 Q4 block whose bottom has sunk 0.01 into a rigid flat y = 0.
    let mesh = common::grid(ElementKind::Q4, [0.0, 0.0], [1.0, 1.0], 1, 1, |x, y| [x, y]);
    let mut p = common::problem(
        mesh,
        AnalysisKind::PlaneStrain { thickness: 1.0 },
        Kinematics::SmallStrain,
        1000.0,
        0.3,
    );
    let bottom = common::bottom_on_flat(&mut p, 0.0);
    let ndof = 2 * p.mesh.nodes.len();
    let mut u = vec![0.0; ndof];
    for &n in &bottom {
        u[2 * n + 1] = -0.01;
    }
    // The out-of-balance force (what the contact must supply) pulls the
    // bottom nodes down: the contact would have to hold them in tension.
    let mut r = vec![0.0; ndof];
    for &n in &bottom {
        r[2 * n + 1] = -5.0;
    }
    let eq: Vec<u32> = (0..ndof as u32).collect();
    let mut memory = vec![PairMemory::new(&p.contacts[0])];
    let mut flips = Flips::default();
    let mut log = Vec::new();
    let mut states = Vec::new();
    let poses = contact::scene_poses(&p, 0.0);
    let start = contact::Start {
        u: &u,
        poses: &poses,
        settling: false,
        touching: false,
        cache: &contact::StartCache::default(),
    };
    let error = loop {
        match contact::update(
            &p,
            &RigidSegments::default(),
            &poses,
            &u,
            &r,
            &eq,
            &start,
            &mut memory,
            &mut flips,
            &mut |m: &str| log.push(m.to_string()),
            None,
        ) {
            Ok(_) => states.push(memory[0].state(0)),
            Err(e) => break e,
        }
        assert!(states.len() < 20, "never reported: {states:?}");
    };
    // Closed (penetrating), released (tension), closed again, ...: six
    // changes are allowed, the seventh is reported.
    assert_eq!(
        states,
        [NodeState::Slip, NodeState::Open].repeat(3),
        "{log:?}"
    );
    assert!(
        error.contains("pair 'base' node 0")
            && error.contains("alternates between open and contact"),
        "{error}"
    );
}
