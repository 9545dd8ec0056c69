//! The scene reader under fuzzing (issue 13): shipped scenes with random
//! edits (bytes replaced, lines dropped or repeated, numbers made huge,
//! negative or zero) are read without a panic; each is either a problem or
//! a SceneError that names a line of the file. Bounded for CI (a few
//! hundred cases); `PROPTEST_CASES=100000 cargo test --release --test
//! fuzz_scene` runs a long campaign.

use proptest::prelude::*;
use std::path::PathBuf;

fn shipped() -> Vec<(PathBuf, String)> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut out = Vec::new();
    for dir in [root.clone(), root.join("verification"), root.join("stress")] {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "toml") {
                let text = std::fs::read_to_string(&path).unwrap();
                out.push((path, text));
            }
        }
    }
    out.sort();
    out
}

/// One edit of a scene's text.
#[derive(Clone, Debug)]
enum Edit {
    /// Replace the byte at this fraction of the text.
    Byte(f64, u8),
    /// Drop the line at this fraction of the lines.
    DropLine(f64),
    /// Repeat the line at this fraction.
    RepeatLine(f64),
    /// Replace the n-th number of the text (wrapping) by a chosen one.
    Number(usize, &'static str),
}

const NUMBERS: [&str; 10] = [
    "0",
    "-1",
    "1e300",
    "-1e-300",
    "9223372036854775807",
    "100000",
    "0.5",
    "1e-12",
    "-0.0",
    "3",
];

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        (0.0..1.0f64, any::<u8>()).prop_map(|(f, b)| Edit::Byte(f, b)),
        (0.0..1.0f64).prop_map(Edit::DropLine),
        (0.0..1.0f64).prop_map(Edit::RepeatLine),
        (0..400usize, 0..NUMBERS.len()).prop_map(|(n, k)| Edit::Number(n, NUMBERS[k])),
    ]
}

fn apply(text: &str, e: &Edit) -> String {
    match e {
        Edit::Byte(f, b) => {
            let mut bytes = text.as_bytes().to_vec();
            let i = ((*f * bytes.len() as f64) as usize).min(bytes.len() - 1);
            bytes[i] = *b;
            String::from_utf8_lossy(&bytes).into_owned()
        }
        Edit::DropLine(f) | Edit::RepeatLine(f) => {
            let mut lines: Vec<&str> = text.lines().collect();
            let i = ((*f * lines.len() as f64) as usize).min(lines.len() - 1);
            if matches!(e, Edit::DropLine(_)) {
                lines.remove(i);
            } else {
                lines.insert(i, lines[i]);
            }
            lines.join("\n")
        }
        Edit::Number(n, new) => {
            // Numbers outside comments: runs of digits after '=', '[', ',' or ' '.
            let spans: Vec<(usize, usize)> = number_spans(text);
            if spans.is_empty() {
                return text.to_string();
            }
            let (a, b) = spans[n % spans.len()];
            format!("{}{new}{}", &text[..a], &text[b..])
        }
    }
}

fn number_spans(text: &str) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        let code = line.split('#').next().unwrap_or("");
        let bytes = code.as_bytes();
        let mut i = 0;
        while i < bytes.len() {
            let starts = (bytes[i].is_ascii_digit() || bytes[i] == b'-')
                && (i == 0 || b"=[, ".contains(&bytes[i - 1]));
            if starts {
                let mut j = i + 1;
                while j < bytes.len()
                    && (bytes[j].is_ascii_digit() || b".eE+-_".contains(&bytes[j]))
                {
                    j += 1;
                }
                spans.push((offset + i, offset + j));
                i = j;
            } else {
                i += 1;
            }
        }
        offset += line.len();
    }
    spans
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn edited_scenes_read_to_a_problem_or_a_located_error(
        which in 0..64usize,
        edits in proptest::collection::vec(edit(), 1..4),
    ) {
        let scenes = shipped();
        let (path, text) = &scenes[which % scenes.len()];
        let mut edited = text.clone();
        for e in &edits {
            edited = apply(&edited, e);
        }
        let lines = edited.lines().count().max(1);
        let outcome = std::panic::catch_unwind(|| contact2d::scene::parse(&edited, path));
        prop_assert!(outcome.is_ok(), "{} with {edits:?}: the reader panicked", path.display());
        if let Err(e) = outcome.unwrap() {
            prop_assert!(e.line >= 1 && e.line <= lines + 1, "{e} (line out of the file's {lines})");
            prop_assert!(!e.message.is_empty());
        }
    }
}
