//! Modelling mistakes that used to pass in silence (issue 13): a contact
//! pair whose contactor and target face away from each other (a rigid
//! polyline walked the wrong way, a contactor set on the far face of its
//! body) is refused with the fix; an initial overlap is reported with its
//! size.

mod common;

use contact2d::scene::SceneErrorKind;

const BLOCK: &str = "verification/sliding_block.toml";
const PLANE: &str = "points = [[10.0, 0.0], [-10.0, 0.0]]";

fn parse(
    edits: &[(&str, &str)],
) -> Result<contact2d::problem::Problem, contact2d::scene::SceneError> {
    let (text, path) = common::scene_text(BLOCK, edits);
    contact2d::scene::parse(&text, &path)
}

#[test]
fn a_rigid_walked_the_wrong_way_is_refused_with_the_fix() {
    let e = parse(&[(PLANE, "points = [[-10.0, 0.0], [10.0, 0.0]]")]).unwrap_err();
    assert_eq!(e.kind, SceneErrorKind::InvalidValue, "{e}");
    assert_eq!(e.key, "contact[0]", "{e}");
    assert!(
        e.message
            .contains("face away from each other at every contactor node"),
        "{e}"
    );
    assert!(e.message.contains("reverse the target's points"), "{e}");
}

#[test]
fn a_contactor_on_the_far_face_is_refused() {
    let e = parse(&[("contactor = \"block.bottom\"", "contactor = \"block.top\"")]).unwrap_err();
    assert!(e.message.contains("face away from each other"), "{e}");
    assert!(
        e.message
            .contains("name the contactor set on the face of its body"),
        "{e}"
    );
}

#[test]
fn an_initial_overlap_is_reported_with_its_size() {
    // The plane raised by 0.01 into the block: every bottom node inside.
    let p = parse(&[(PLANE, "points = [[10.0, 0.01], [-10.0, 0.01]]")]).unwrap();
    assert_eq!(p.warnings.len(), 1, "{:?}", p.warnings);
    let w = &p.warnings[0];
    assert!(
        w.contains(
            "pair 'base': 9 of 9 contactor nodes start inside the target, by up to 1.000e-2"
        ),
        "{w}"
    );
    // A touch-start overlap far below the displacements is not a mistake,
    // nor is a gap.
    for y in ["1e-9", "-0.01"] {
        let p = parse(&[(PLANE, &format!("points = [[10.0, {y}], [-10.0, {y}]]"))]).unwrap();
        assert!(p.warnings.is_empty(), "{y}: {:?}", p.warnings);
    }
    // The shipped scenes have none, but the interference fit, which means it.
    let fit = common::shipped_scene("stress/shrink_fit.toml", &[]);
    assert!(
        fit.warnings[0].contains("by up to 5.000e-2"),
        "{:?}",
        fit.warnings
    );
    for scene in [
        "hertz_plane_strain.toml",
        "wire_winding.toml",
        "verification/cattaneo_mindlin.toml",
    ] {
        assert!(
            common::shipped_scene(scene, &[]).warnings.is_empty(),
            "{scene}"
        );
    }
}
