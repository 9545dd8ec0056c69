//! Scenes and meshes that claim more than they hold or than the machine
//! can make (issue 13, defects 1 and 8): an error naming the key and the
//! value, at once, never an allocation that aborts the process or a read
//! that never returns.

use contact2d::scene::{self, SceneErrorKind};
use std::path::Path;
use std::time::Instant;

const FILE: &str = "scenes/limits.toml";

fn scene_with(mesh: &str, solver: &str) -> String {
    format!(
        r#"[analysis]
kind = "plane_strain"

[[material]]
name = "steel"
model = "linear_elastic"
E = 1000.0
nu = 0.3

[[body]]
name = "block"
material = "steel"
mesh = {mesh}

[[driver]]
name = "base"
set = "block.bottom"
ux = 0.0
uy = 0.0

[steps]
times = [1.0]
{solver}
"#
    )
}

fn rectangle(divisions: &str) -> String {
    format!(
        "{{ generator = \"rectangle\", origin = [0.0, 0.0], size = [1.0, 1.0], divisions = {divisions} }}"
    )
}

#[test]
fn a_generator_asked_for_too_many_elements_is_refused_before_it_allocates() {
    for (divisions, count) in [
        ("[100000, 100000]", "10000000000 elements"),
        ("[8, 100000000]", "800000000 elements"),
        ("[3000, 3000]", "9000000 elements"),
        ("[9223372036854775807, 4]", "more than 2^64 elements"),
    ] {
        let started = Instant::now();
        let e = scene::parse(&scene_with(&rectangle(divisions), ""), Path::new(FILE)).unwrap_err();
        // Before any allocation: well under the seconds a generator of this
        // size would take (a timing bound 1000 times looser than measured).
        assert!(started.elapsed().as_secs_f64() < 1.0, "{divisions}");
        assert_eq!(e.kind, SceneErrorKind::InvalidValue, "{e}");
        assert_eq!(e.key, "body[0].mesh.divisions", "{e}");
        assert_eq!(e.line, 13, "{e}");
        assert!(e.message.contains(count), "{e}");
        assert!(e.message.contains("[solver] max_elements = 1000000"), "{e}");
    }
    // Other generators too.
    let disk =
        "{ generator = \"disk\", center = [0.0, 0.0], radius = 1.0, divisions = 10000000000 }";
    let e = scene::parse(&scene_with(disk, ""), Path::new(FILE)).unwrap_err();
    assert!(
        e.message.contains("elements: more than the scene may have"),
        "{e}"
    );
    let ring = "{ generator = \"ring\", center = [0.0, 0.0], r_inner = 1.0, r_outer = 2.0, angles = [0.0, 90.0], divisions = [4000, 4000] }";
    let e = scene::parse(&scene_with(ring, ""), Path::new(FILE)).unwrap_err();
    assert!(e.message.contains("16000000 elements"), "{e}");
}

#[test]
fn a_scene_may_raise_or_lower_the_limit() {
    let solver = |n: usize| format!("\n[solver]\nmax_elements = {n}\n");
    // 12 elements: over a limit of 10, within one of 12.
    let e = scene::parse(
        &scene_with(&rectangle("[4, 3]"), &solver(10)),
        Path::new(FILE),
    )
    .unwrap_err();
    assert!(
        e.message.contains("12 elements") && e.message.contains("max_elements = 10"),
        "{e}"
    );
    let p = scene::parse(
        &scene_with(&rectangle("[4, 3]"), &solver(12)),
        Path::new(FILE),
    )
    .unwrap();
    assert_eq!(p.mesh.elements.len(), 12);
    let e = scene::parse(
        &scene_with(&rectangle("[4, 3]"), &solver(0)),
        Path::new(FILE),
    )
    .unwrap_err();
    assert_eq!(e.key, "solver.max_elements", "{e}");
}

#[test]
fn a_gmsh_header_that_claims_more_than_the_file_holds_is_refused() {
    let dir = std::env::temp_dir().join(format!("contact2d-limits-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let msh = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 999999999999 1 999999999999\n2 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n$EndNodes\n";
    std::fs::write(dir.join("huge.msh"), msh).unwrap();
    let text = scene_with("{ file = \"huge.msh\" }", "");
    let started = Instant::now();
    let e = scene::parse(&text, &dir.join("s.toml")).unwrap_err();
    assert!(started.elapsed().as_secs_f64() < 1.0);
    assert_eq!(e.kind, SceneErrorKind::Mesh, "{e}");
    assert!(
        e.message
            .contains("the number of nodes is 999999999999, more than a file of"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A FIFO where the scene or its mesh should be: refused at once (a read
/// would wait for a writer forever).
#[test]
fn a_fifo_is_not_read() {
    let dir = std::env::temp_dir().join(format!("contact2d-fifo-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let fifo = dir.join("scene.toml");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(made.success());
    let e = scene::load(&fifo).unwrap_err();
    assert_eq!(e.kind, SceneErrorKind::Io, "{e}");
    assert!(e.message.contains("not a regular file"), "{e}");
    // The mesh file as a FIFO.
    let mesh = dir.join("mesh.msh");
    assert!(
        std::process::Command::new("mkfifo")
            .arg(&mesh)
            .status()
            .unwrap()
            .success()
    );
    let e = scene::parse(
        &scene_with("{ file = \"mesh.msh\" }", ""),
        &dir.join("s.toml"),
    )
    .unwrap_err();
    assert!(e.message.contains("not a regular file"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Found by tests/fuzz_scene.rs: counts that follow from the geometry or
/// from a count key outside the mesh table. A plate with a hole whose width
/// is 1e300 needed 1e300 elements in its strips (a capacity-overflow
/// panic); a rigid arc of 9e18 segments panicked, one of 1e8 took 15 GB
/// and minutes.
#[test]
fn counts_from_geometry_and_rigid_arcs_are_bounded() {
    let plate = "{ generator = \"plate_with_hole\", hole_radius = 0.5, width = 1e300, y_range = [-3.0, 3.0], divisions = [10, 24] }";
    let started = Instant::now();
    let e = scene::parse(&scene_with(plate, ""), Path::new(FILE)).unwrap_err();
    assert!(started.elapsed().as_secs_f64() < 1.0);
    assert_eq!(e.kind, SceneErrorKind::Mesh, "{e}");
    assert!(e.message.contains("would need 1.818e300 elements"), "{e}");
    for (segments, ok) in [
        ("9223372036854775807", false),
        ("100000000", false),
        ("5120", true),
    ] {
        let text = scene_with(&rectangle("[4, 2]"), "").replace(
            "[steps]",
            &format!(
                "[[rigid]]\nname = \"drum\"\narc = {{ center = [2.0, -10.0], radius = 10.0, angles = [0.0, 180.0], segments = {segments} }}\n\n[steps]"
            ),
        );
        let started = Instant::now();
        let parsed = scene::parse(&text, Path::new(FILE));
        assert!(started.elapsed().as_secs_f64() < 1.0, "{segments}");
        match parsed {
            Ok(_) => assert!(ok, "{segments} accepted"),
            Err(e) => {
                assert!(!ok, "{segments}: {e}");
                assert_eq!(e.key, "rigid[0].arc.segments", "{e}");
                assert!(e.message.contains("at most 1000000 segments"), "{e}");
            }
        }
    }
}
