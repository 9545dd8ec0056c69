//! The crate's modules depend one way (issue 32). Every top-level module of
//! `src/` has a layer below; a module may use only modules of lower layers
//! (`crate::x` paths read as text, test modules left out), and the files of
//! a folder module at any depth (a room: `contact`, `contact::mortar`, ...)
//! may not use each other in a cycle. A new module must be given its layer here; a `use` that points
//! up, or sideways within a layer, fails with the file that makes it.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Bottom to top: the problem's data (with a strip's path, pure geometry),
/// the element and material laws above it, assembly, then contact and the
/// linear solver side by side, the solver's state, the running strips'
/// shifts of it, Newton and the readers and writers around it, the FMU.
const LAYERS: &[&[&str]] = &[
    &["mesh", "constraint", "strip"],
    &["element", "problem"],
    &["material", "results"],
    &["kinematics"],
    &["assembly"],
    &["contact", "linsolve"],
    &["state"],
    &["running"],
    &["newton", "output", "scene"],
    &["fmi"],
];

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            if path.file_name().is_some_and(|n| n != "tests") {
                rust_files(&path, out);
            }
        } else if path.extension().is_some_and(|e| e == "rs")
            && path.file_name().is_some_and(|n| n != "tests.rs")
        {
            out.push(path);
        }
    }
}

/// The text without `//` comments and without `#[cfg(test)] mod x { .. }`
/// (or `#[cfg(test)] mod x;`).
fn code(text: &str) -> String {
    const TEST: &str = "#[cfg(test)]";
    let mut out = String::new();
    let mut rest = text;
    while let Some(at) = rest.find(TEST) {
        out.push_str(&rest[..at]);
        let after = rest[at + TEST.len()..].trim_start();
        let open = after.find(['{', ';']).unwrap_or(after.len());
        if !after.starts_with("mod ") || open == after.len() {
            out.push_str(TEST);
            rest = &rest[at + TEST.len()..];
            continue;
        }
        let mut end = open + 1;
        if after.as_bytes()[open] == b'{' {
            let mut depth = 0;
            for (i, c) in after[open..].char_indices() {
                depth += match c {
                    '{' => 1,
                    '}' => -1,
                    _ => 0,
                };
                if depth == 0 {
                    end = open + i + 1;
                    break;
                }
            }
        }
        rest = &after[end..];
    }
    out.push_str(rest);
    out.lines()
        .map(|l| l.find("//").map_or(l, |i| &l[..i]))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The identifiers that follow each `prefix` in `text`: `crate::a::b` gives
/// `[a, b]` for prefix `crate::`.
fn paths<'a>(text: &'a str, prefix: &str) -> Vec<Vec<&'a str>> {
    let mut out = Vec::new();
    for (i, _) in text.match_indices(prefix) {
        if text[..i].ends_with(|c: char| c.is_alphanumeric() || c == '_') {
            continue;
        }
        let mut parts = Vec::new();
        let mut rest = &text[i + prefix.len()..];
        loop {
            let end = rest
                .find(|c: char| !(c.is_alphanumeric() || c == '_'))
                .unwrap_or(rest.len());
            if end == 0 {
                break;
            }
            parts.push(&rest[..end]);
            match rest[end..].strip_prefix("::") {
                Some(r) => rest = r,
                None => break,
            }
        }
        out.push(parts);
    }
    out
}

type Graph = BTreeMap<String, BTreeSet<String>>;

/// A module's path from `src/` (`contact/node_to_segment/nodal.rs` gives
/// `[contact, node_to_segment, nodal]`, a `mod.rs` its folder's).
fn module_path(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).unwrap().with_extension("");
    let mut parts: Vec<String> = rel.iter().map(|p| p.to_string_lossy().into()).collect();
    if parts.last().is_some_and(|p| p == "mod") {
        parts.pop();
    }
    parts
}

/// `path` (after `crate::`, or after `super::` when `supers` > 0) as a path
/// from the crate's root, read in the module `at` (a `mod.rs` file's module
/// is its folder, whose `super` is the folder above).
fn resolve(at: &[String], supers: usize, path: &[&str]) -> Option<Vec<String>> {
    let base = at.len().checked_sub(supers)?;
    let mut out = at[..base].to_vec();
    out.extend(path.iter().map(|p| p.to_string()));
    Some(out)
}

/// The top-level edges (module -> module, with a file that makes each) and,
/// per folder module at any depth (a room: `contact`,
/// `contact::node_to_segment`, ...), the edges between its direct children:
/// a file of child `a` (or of a module inside it) that names `room::b::..`
/// makes the edge `a -> b` when `b` is a module.
fn graph(src: &Path) -> (BTreeMap<(String, String), String>, BTreeMap<String, Graph>) {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let modules: BTreeSet<Vec<String>> = files
        .iter()
        .map(|f| module_path(src, f))
        .flat_map(|p| (1..=p.len()).map(move |n| p[..n].to_vec()))
        .collect();
    let mut top = BTreeMap::new();
    let mut rooms: BTreeMap<String, Graph> = BTreeMap::new();
    for file in files {
        let parts = module_path(src, &file);
        if parts.is_empty() || ["lib", "main", "bin"].contains(&parts[0].as_str()) {
            continue;
        }
        let text = code(&std::fs::read_to_string(&file).unwrap());
        // A `mod.rs` is its folder's module; `super` of a file `x.rs` is
        // the folder it is in.
        let is_mod = file.file_name().is_some_and(|n| n == "mod.rs");
        let here: Vec<String> = if is_mod {
            parts.clone()
        } else {
            parts[..parts.len() - 1].to_vec()
        };
        let mut used: Vec<Vec<String>> = Vec::new();
        for path in paths(&text, "crate::") {
            used.extend(resolve(&[], 0, &path));
        }
        for path in paths(&text, "super::") {
            let supers = 1 + path.iter().take_while(|p| **p == "super").count();
            let rest = &path[supers - 1..];
            // `super` of a `mod.rs` module is one folder up from `here`.
            let up = if is_mod { supers } else { supers - 1 };
            used.extend(resolve(&here, up, rest));
        }
        for q in used {
            let Some(first) = q.first() else { continue };
            if *first != parts[0] {
                let name = file.strip_prefix(src).unwrap().with_extension("");
                top.entry((parts[0].clone(), first.clone()))
                    .or_insert(name.display().to_string());
                continue;
            }
            let common = parts.iter().zip(&q).take_while(|(a, b)| a == b).count();
            if common == parts.len() || common == q.len() {
                continue; // a module of its own, or an item of a room it is in
            }
            if !modules.contains(&q[..=common]) {
                continue; // an item of the room's own file, not a module
            }
            let room = rooms.entry(parts[..common].join("::")).or_default();
            room.entry(parts[common].clone())
                .or_default()
                .insert(q[common].clone());
        }
    }
    (top, rooms)
}

/// A cycle of `g`, if it has one.
fn cycle(g: &Graph) -> Option<Vec<String>> {
    fn visit(
        g: &Graph,
        v: &str,
        stack: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(at) = stack.iter().position(|s| s == v) {
            return Some(stack[at..].to_vec());
        }
        if done.contains(v) {
            return None;
        }
        stack.push(v.into());
        for w in g.get(v).into_iter().flatten() {
            if let Some(c) = visit(g, w, stack, done) {
                return Some(c);
            }
        }
        stack.pop();
        done.insert(v.into());
        None
    }
    let mut done = BTreeSet::new();
    g.keys()
        .find_map(|v| visit(g, v, &mut Vec::new(), &mut done))
}

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

#[test]
fn modules_use_only_lower_layers() {
    let layer = |m: &str| LAYERS.iter().position(|l| l.contains(&m));
    let (top, _) = graph(&src());
    let lib = std::fs::read_to_string(src().join("lib.rs")).unwrap();
    let mut wrong = Vec::new();
    for ((from, to), file) in &top {
        let declared = |m: &str| lib.contains(&format!("pub mod {m};"));
        let Some(lf) = layer(from) else {
            wrong.push(format!(
                "module {from} has no layer in tests/module_graph.rs"
            ));
            continue;
        };
        if !declared(to) {
            continue; // an item of lib.rs (`crate::build_id`), not a module
        }
        match layer(to) {
            None => wrong.push(format!("module {to} has no layer in tests/module_graph.rs")),
            Some(lt) if lt >= lf => wrong.push(format!(
                "src/{file}.rs: {from} (layer {lf}) uses {to} (layer {lt})"
            )),
            _ => {}
        }
    }
    assert!(
        wrong.is_empty(),
        "modules that depend the wrong way:\n{}",
        wrong.join("\n")
    );
}

#[test]
fn no_room_has_a_cycle() {
    let (_, rooms) = graph(&src());
    let cycles: Vec<String> = (rooms.iter())
        .filter_map(|(room, g)| cycle(g).map(|c| format!("{room}: {}", c.join(" -> "))))
        .collect();
    assert!(
        cycles.is_empty(),
        "import cycles inside rooms:\n{}",
        cycles.join("\n")
    );
}

/// The checks see what they are meant to: an upward use and a cycle are
/// found in text made for it.
#[test]
fn the_checks_find_what_they_look_for() {
    let text = code(
        "use crate::contact::search::{self, x};\n// crate::fmi in a comment\n\
         #[cfg(test)]\nmod tests {\n    use crate::newton;\n}\nfn f() { super::memory::g(); }",
    );
    assert_eq!(paths(&text, "crate::"), vec![vec!["contact", "search"]]);
    assert_eq!(paths(&text, "super::"), vec![vec!["memory", "g"]]);
    let mut g = Graph::new();
    g.entry("a".into()).or_default().insert("b".into());
    assert_eq!(cycle(&g), None);
    g.entry("b".into()).or_default().insert("a".into());
    assert_eq!(cycle(&g), Some(vec!["a".to_string(), "b".to_string()]));
    // `super::` read at depth: from a file, its folder; from a `mod.rs`,
    // the folder above.
    let at: Vec<String> = ["contact", "node_to_segment"].map(String::from).to_vec();
    let nodal = resolve(&at, 0, &["linearise", "f"]).unwrap();
    assert_eq!(nodal, ["contact", "node_to_segment", "linearise", "f"]);
    let up = resolve(&at, 1, &["search"]).unwrap();
    assert_eq!(up, ["contact", "search"]);
}

/// A cycle between two files of a folder two levels down is found (the
/// one `contact/node_to_segment` had: `linearise` used `nodal`'s type and
/// `nodal` called `linearise`).
#[test]
fn a_cycle_at_depth_is_found() {
    let dir = std::env::temp_dir().join(format!("module_graph_{}", std::process::id()));
    let room = dir.join("contact/node_to_segment");
    std::fs::create_dir_all(&room).unwrap();
    std::fs::write(dir.join("contact/mod.rs"), "mod node_to_segment;").unwrap();
    std::fs::write(room.join("mod.rs"), "mod linearise;\nmod nodal;").unwrap();
    std::fs::write(room.join("linearise.rs"), "use super::nodal::Decision;").unwrap();
    let nodal = "use crate::contact::node_to_segment::linearise;";
    std::fs::write(room.join("nodal.rs"), nodal).unwrap();
    let (_, rooms) = graph(&dir);
    std::fs::remove_dir_all(&dir).unwrap();
    let g = &rooms["contact::node_to_segment"];
    assert_eq!(
        cycle(g),
        Some(vec!["linearise".to_string(), "nodal".to_string()])
    );
    assert!(!rooms.contains_key("contact"), "{rooms:?}");
}

/// The outer rooms (the FMU, the writers, the command line) talk to the
/// solver (`newton`) and read `results`: none names `contact` or `running`.
#[test]
fn the_outer_rooms_talk_to_the_solver() {
    let mut files = Vec::new();
    for room in ["fmi", "output", "bin"] {
        rust_files(&src().join(room), &mut files);
    }
    let mut wrong = Vec::new();
    for file in files {
        let text = code(&std::fs::read_to_string(&file).unwrap());
        for prefix in ["crate::", "contact2d::"] {
            for path in paths(&text, prefix) {
                if let Some(&first) = path.first()
                    && ["contact", "running"].contains(&first)
                {
                    let rel = file.strip_prefix(src()).unwrap().display().to_string();
                    wrong.push(format!("src/{rel}: {prefix}{}", path.join("::")));
                }
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "outer rooms reaching past the solver:\n{}",
        wrong.join("\n")
    );
}
