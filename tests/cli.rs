//! The command line's small promises (issue 35, item 10): `check` counts
//! one of a thing in the singular, and `export -o NAME` writes `NAME.fmu`.

use std::path::PathBuf;
use std::process::Command;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn contact2d(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_contact2d"))
        .args(args)
        .current_dir(repo())
        .output()
        .unwrap()
}

/// Hertz has a one-node set and a one-segment rigid target: `check` says
/// "1 node" and "1 segment", never "1 nodes" or "1 segments", and keeps the
/// plural for the others.
#[test]
fn check_counts_one_in_the_singular() {
    let out = contact2d(&["check", "scenes/hertz_plane_strain.toml"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("contact_point (1 node)"), "{text}");
    assert!(text.contains("2 points, 1 segment,"), "{text}");
    assert!(text.contains("against rigid flat (1 segment)"), "{text}");
    assert!(text.contains("arc (121 nodes, 60 edges)"), "{text}");
    for word in [
        "nodes",
        "edges",
        "elements",
        "points",
        "segments",
        "increments",
    ] {
        let one = format!(" 1 {word}");
        let starts = format!("(1 {word}");
        assert!(
            !text.contains(&one) && !text.contains(&starts),
            "'1 {word}' in:\n{text}"
        );
    }
}

/// `export -o NAME` without the `.fmu` extension writes `NAME.fmu` (and
/// says so); a name with it is kept as it is. (With the native library
/// named: the default, the portable one, may need a zig build first,
/// tested in tests/python/test_portable_library.py.)
#[test]
fn export_appends_the_fmu_extension() {
    let native =
        contact2d::fmi::export::find_library(std::path::Path::new(env!("CARGO_BIN_EXE_contact2d")))
            .expect("libcontact2d.so beside the binary");
    let dir = std::env::temp_dir().join(format!("contact2d-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (given, written) in [
        ("hertz", "hertz.fmu"),
        ("h.FMU", "h.FMU"),
        ("h.v2", "h.v2.fmu"),
    ] {
        let out = contact2d(&[
            "export",
            "scenes/hertz_plane_strain.toml",
            "-o",
            dir.join(given).to_str().unwrap(),
            "--library",
            native.to_str().unwrap(),
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(
            dir.join(written).is_file(),
            "{given}: {written} not written"
        );
        if given != written {
            assert!(!dir.join(given).exists(), "{given} written as given");
        }
        let said = String::from_utf8_lossy(&out.stdout);
        assert!(said.contains(written), "{said}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `check` names a mortar pair's formulation instead of node-to-segment's
/// friction rule and traction recovery, which it has not.
#[test]
fn check_names_a_mortar_pair() {
    let dir = std::env::temp_dir().join(format!("contact2d-cli-mortar-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("m.toml");
    let text = std::fs::read_to_string(repo().join("scenes/verification/flexible_target.toml"))
        .unwrap()
        .replace("mu_s = 0.0\n", "mu_s = 0.0\nformulation = \"mortar\"\n");
    std::fs::write(&scene, text).unwrap();
    let out = contact2d(&["check", scene.to_str().unwrap()]);
    std::fs::remove_dir_all(&dir).ok();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("mu_s = 0, mu_d = 0, formulation: mortar"),
        "{text}"
    );
    assert!(!text.contains("recovery:"), "{text}");
}
