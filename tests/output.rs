//! The output writers: VTK XML content read back (cell types, offsets,
//! connectivity, values that round-trip) and the summary JSON shape.

use contact2d::mesh::{Element, ElementKind, Mesh};
use contact2d::output::{PvdEntry, Summary, von_mises, write_pvd, write_vtu};
use contact2d::results::{DriverResult, NodeState, PairNodes, PairResult, StepResult};
use std::path::PathBuf;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("contact2d-output-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// The XML part of a `.vtu` (before its appended binary data) and the
/// appended bytes (after the underscore, up to the newline before the
/// closing tag).
fn split_vtu(bytes: &[u8]) -> (String, &[u8]) {
    let tag = b"<AppendedData encoding=\"raw\">\n_";
    let at = bytes
        .windows(tag.len())
        .position(|w| w == tag)
        .expect("appended raw data");
    let end = bytes.len() - b"\n</AppendedData>\n</VTKFile>\n".len();
    assert_eq!(&bytes[end..], b"\n</AppendedData>\n</VTKFile>\n");
    let xml = String::from_utf8(bytes[..at].to_vec()).unwrap();
    (xml, &bytes[at + tag.len()..end])
}

/// An attribute of the XML element that starts at `element`.
fn attribute<'a>(element: &'a str, key: &str) -> Option<&'a str> {
    let element = &element[..element.find('>').unwrap()];
    let start = element.find(&format!(" {key}=\""))? + key.len() + 3;
    let end = start + element[start..].find('"').unwrap();
    Some(&element[start..end])
}

/// The type and decompressed bytes of the DataArray named `name`: its
/// header (UInt64 block count, block size, last block size, compressed
/// sizes) at its offset into the appended data, then zlib blocks.
fn data_array(vtu: &[u8], name: &str) -> (String, Vec<u8>) {
    use std::io::Read;
    let (xml, appended) = split_vtu(vtu);
    let at = xml
        .find(&format!("Name=\"{name}\""))
        .unwrap_or_else(|| panic!("no DataArray {name}"));
    let element = &xml[xml[..at].rfind('<').unwrap()..];
    assert_eq!(attribute(element, "format"), Some("appended"));
    let offset: usize = attribute(element, "offset").unwrap().parse().unwrap();
    let word = |i: usize| {
        let b = &appended[offset + 8 * i..offset + 8 * i + 8];
        u64::from_le_bytes(b.try_into().unwrap()) as usize
    };
    let (blocks, block, last) = (word(0), word(1), word(2));
    let mut start = offset + 8 * (3 + blocks);
    let mut raw = Vec::new();
    for k in 0..blocks {
        let size = word(3 + k);
        let mut inflated = Vec::new();
        flate2::read::ZlibDecoder::new(&appended[start..start + size])
            .read_to_end(&mut inflated)
            .unwrap();
        let expected = if k + 1 == blocks && last > 0 {
            last
        } else {
            block
        };
        assert_eq!(inflated.len(), expected, "block {k} of {name}");
        raw.extend_from_slice(&inflated);
        start += size;
    }
    (attribute(element, "type").unwrap().to_string(), raw)
}

fn numbers(vtu: &[u8], name: &str) -> Vec<f64> {
    let (kind, raw) = data_array(vtu, name);
    assert_eq!(kind, "Float64", "{name}");
    raw.chunks(8)
        .map(|b| f64::from_le_bytes(b.try_into().unwrap()))
        .collect()
}

fn integers(vtu: &[u8], name: &str) -> Vec<usize> {
    let (kind, raw) = data_array(vtu, name);
    match kind.as_str() {
        "Int64" => raw
            .chunks(8)
            .map(|b| i64::from_le_bytes(b.try_into().unwrap()) as usize)
            .collect(),
        "Int32" => raw
            .chunks(4)
            .map(|b| i32::from_le_bytes(b.try_into().unwrap()) as usize)
            .collect(),
        "UInt8" => raw.iter().map(|&b| b as usize).collect(),
        other => panic!("{name}: {other}"),
    }
}

fn two_q4() -> Mesh {
    Mesh {
        nodes: vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [2.0, 0.0],
            [0.0, 1.0],
            [1.0, 1.0],
            [2.0, 1.0],
        ],
        elements: vec![
            Element {
                kind: ElementKind::Q4,
                nodes: vec![0, 1, 4, 3],
            },
            Element {
                kind: ElementKind::Q4,
                nodes: vec![1, 2, 5, 4],
            },
        ],
        ..Mesh::default()
    }
}

#[test]
fn vtu_of_two_q4_elements() {
    let mesh = two_q4();
    // Values that print with many digits, or tiny and huge exponents.
    let u = [
        0.1 + 0.2,
        -1.0 / 3.0,
        1e-300,
        -2.5e300,
        std::f64::consts::PI,
        0.0,
        -0.0,
        f64::MIN_POSITIVE,
        1.0 / 7.0,
        123456789.12345679,
        -5e-324,
        2.0_f64.sqrt(),
    ];
    let stress = [[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 2.0]];
    let path = scratch("two_q4.vtu");
    write_vtu(&path, &mesh, &u, &stress, None).unwrap();
    let xml = std::fs::read(&path).unwrap();
    let (head, _) = split_vtu(&xml);

    assert!(head.starts_with("<?xml"));
    assert!(head.contains(r#"<VTKFile type="UnstructuredGrid""#));
    assert!(head.contains(r#"compressor="vtkZLibDataCompressor""#));
    assert!(head.contains(r#"<Piece NumberOfPoints="6" NumberOfCells="2">"#));
    assert!(!head.contains("plastic_strain"));
    assert_eq!(integers(&xml, "types"), vec![9, 9]);
    assert_eq!(integers(&xml, "offsets"), vec![4, 8]);
    assert_eq!(integers(&xml, "connectivity"), vec![0, 1, 4, 3, 1, 2, 5, 4]);

    let points = numbers(&xml, "Points");
    assert_eq!(points.len(), 3 * 6);
    for (n, p) in mesh.nodes.iter().enumerate() {
        assert_eq!(&points[3 * n..3 * n + 3], &[p[0], p[1], 0.0]);
    }

    let d = numbers(&xml, "displacement");
    assert_eq!(d.len(), 3 * 6);
    for n in 0..6 {
        // Bit for bit, sign of zero included.
        assert_eq!(d[3 * n].to_bits(), u[2 * n].to_bits(), "ux of node {n}");
        assert_eq!(
            d[3 * n + 1].to_bits(),
            u[2 * n + 1].to_bits(),
            "uy of node {n}"
        );
        assert_eq!(d[3 * n + 2], 0.0);
    }

    assert_eq!(
        numbers(&xml, "stress"),
        vec![1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 2.0]
    );
    let vm = numbers(&xml, "von_mises");
    assert_eq!(vm.len(), 2);
    assert!((vm[0] - 1.0).abs() < 1e-15);
    assert!((vm[1] - 2.0 * 3.0_f64.sqrt()).abs() < 1e-14);
}

#[test]
fn vtu_of_one_q8_element() {
    // Corners counter-clockwise, then the mid-sides of faces 0..3: VTK's
    // own order for VTK_QUADRATIC_QUAD.
    let mesh = Mesh {
        nodes: vec![
            [0.0, 0.0],
            [2.0, 0.0],
            [2.0, 2.0],
            [0.0, 2.0],
            [1.0, 0.0],
            [2.0, 1.0],
            [1.0, 2.0],
            [0.0, 1.0],
        ],
        elements: vec![Element {
            kind: ElementKind::Q8,
            nodes: vec![0, 1, 2, 3, 4, 5, 6, 7],
        }],
        ..Mesh::default()
    };
    let u: Vec<f64> = (0..16).map(|i| 1e-3 * i as f64 / 3.0).collect();
    let s = [10.0, -4.0, 1.5, 2.25];
    let path = scratch("one_q8.vtu");
    write_vtu(&path, &mesh, &u, &[s], Some(&[0.125])).unwrap();
    let xml = std::fs::read(&path).unwrap();

    assert!(
        split_vtu(&xml)
            .0
            .contains(r#"<Piece NumberOfPoints="8" NumberOfCells="1">"#)
    );
    assert_eq!(numbers(&xml, "plastic_strain"), vec![0.125]);
    assert_eq!(integers(&xml, "types"), vec![23]);
    assert_eq!(integers(&xml, "offsets"), vec![8]);
    assert_eq!(integers(&xml, "connectivity"), (0..8).collect::<Vec<_>>());
    let d = numbers(&xml, "displacement");
    let back: Vec<f64> = d.chunks(3).flat_map(|c| [c[0], c[1]]).collect();
    assert_eq!(back, u);
    assert_eq!(numbers(&xml, "stress"), s.to_vec());
    let [xx, yy, zz, xy] = s;
    let expected =
        (((xx - yy).powi(2) + (yy - zz).powi(2) + (zz - xx).powi(2)) / 2.0 + 3.0 * xy * xy).sqrt();
    assert_eq!(numbers(&xml, "von_mises"), vec![von_mises(&s)]);
    assert!((von_mises(&s) - expected).abs() <= 1e-14 * expected);
}

#[test]
fn vtu_refuses_arrays_of_the_wrong_length() {
    let mesh = two_q4();
    let path = scratch("wrong.vtu");
    let err = write_vtu(&path, &mesh, &[0.0; 11], &[[0.0; 4]; 2], None).unwrap_err();
    assert_eq!(err.kind(), std::io::ErrorKind::InvalidInput);
    let err = write_vtu(&path, &mesh, &[0.0; 12], &[[0.0; 4]; 1], None).unwrap_err();
    assert_eq!(err.kind(), std::io::ErrorKind::InvalidInput);
    let err = write_vtu(&path, &mesh, &[0.0; 12], &[[0.0; 4]; 2], Some(&[0.0])).unwrap_err();
    assert_eq!(err.kind(), std::io::ErrorKind::InvalidInput);
}

#[test]
fn pvd_lists_the_series_in_order() {
    let path = scratch("series.pvd");
    let entry = |time: f64, part: usize, name: &str, file: &str| PvdEntry {
        time,
        part,
        name: name.into(),
        file: file.into(),
    };
    let entries = vec![
        entry(0.5, 0, "solid", "run_0001.vtu"),
        entry(1.0, 0, "solid", "run_0002.vtu"),
        entry(0.1 + 0.2, 1, "contact.c<1>", "a&b\"<c>.vtu"),
    ];
    write_pvd(&path, &entries).unwrap();
    let xml = std::fs::read_to_string(&path).unwrap();
    assert!(xml.contains(r#"<VTKFile type="Collection""#));
    let sets: Vec<&str> = xml.lines().filter(|l| l.contains("<DataSet")).collect();
    assert_eq!(sets.len(), 3);
    let attr = |line: &str, key: &str| -> String {
        let start = line.find(&format!("{key}=\"")).unwrap() + key.len() + 2;
        let end = start + line[start..].find('"').unwrap();
        line[start..end].to_string()
    };
    assert_eq!(attr(sets[0], "file"), "run_0001.vtu");
    assert_eq!(attr(sets[1], "file"), "run_0002.vtu");
    assert_eq!(attr(sets[2], "file"), "a&amp;b&quot;&lt;c&gt;.vtu");
    assert_eq!(attr(sets[2], "name"), "contact.c&lt;1&gt;");
    assert_eq!(attr(sets[2], "part"), "1");
    assert_eq!(attr(sets[0], "part"), "0");
    let times: Vec<f64> = sets
        .iter()
        .map(|l| attr(l, "timestep").parse().unwrap())
        .collect();
    assert_eq!(times, vec![0.5, 1.0, 0.1 + 0.2]);
}

fn converged_step() -> StepResult {
    let r = |rx, ry| DriverResult {
        rx,
        ry,
        mz: None,
        ..Default::default()
    };
    StepResult {
        time: 0.5,
        converged: true,
        iterations: 3,
        substeps: 1,
        solves: 3,
        factorizations: 3,
        fallbacks: 0,
        residual: 1.5e-11,
        neqc: 0,
        // Not in alphabetical order: the file keeps this order.
        drivers: vec![
            ("zeta".into(), r(0.0, -25.0)),
            ("alpha".into(), r(1.0, 2.0)),
            ("mid".into(), r(-3.5, 0.125)),
        ],
        pairs: vec![],
        ties: vec![],
        running: vec![],
    }
}

#[test]
fn summary_has_the_spec_shape() {
    let mut summary = Summary::new("scenes/x.toml", "X", 1234);
    summary.wall_s = 0.25;
    summary.steps.push(converged_step());
    let text = summary.to_json();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();

    assert_eq!(v["scene"], "scenes/x.toml");
    assert_eq!(v["dofs"], 1234);
    assert_eq!(v["wall_s"], 0.25);
    assert_eq!(v["title"], "X");
    assert!(
        v["build"]
            .as_str()
            .unwrap()
            .starts_with(env!("CARGO_PKG_VERSION"))
    );
    let steps = v["steps"].as_array().unwrap();
    assert_eq!(steps.len(), 1);
    let s = &steps[0];
    let mut keys: Vec<&str> = s.as_object().unwrap().keys().map(|k| k.as_str()).collect();
    keys.sort_unstable();
    assert_eq!(
        keys,
        [
            "converged",
            "drivers",
            "iterations",
            "neqc",
            "pairs",
            "residual",
            "substeps",
            "time"
        ]
    );
    assert_eq!(s["time"], 0.5);
    assert_eq!(s["converged"], true);
    assert_eq!(s["iterations"], 3);
    assert_eq!(s["substeps"], 1);
    assert_eq!(s["residual"], 1.5e-11);
    assert_eq!(s["neqc"], 0);
    assert_eq!(s["pairs"], serde_json::json!({}));
    assert_eq!(
        s["drivers"],
        serde_json::json!({
            "zeta": { "Rx": 0.0, "Ry": -25.0 },
            "alpha": { "Rx": 1.0, "Ry": 2.0 },
            "mid": { "Rx": -3.5, "Ry": 0.125 },
        })
    );
    // Scene order, not alphabetical.
    let at = |k: &str| text.find(&format!("\"{k}\"")).unwrap();
    assert!(at("zeta") < at("alpha") && at("alpha") < at("mid"));
}

#[test]
fn summary_has_the_ties_of_a_scene_with_ties() {
    let mut step = converged_step();
    step.ties = vec![(
        "interface".into(),
        contact2d::constraint::TieResult {
            force: [0.5, -3.0],
            normal: vec![1.0, 2.0],
            nodal: vec![[0.5, -1.0], [0.0, -2.0]],
            tangential: vec![0.5, 0.0],
            position: vec![[0.0, 1.0], [1.0, 1.0]],
        },
    )];
    let mut summary = Summary::new("s.toml", "S", 10);
    summary.steps.push(step);
    let v: serde_json::Value = serde_json::from_str(&summary.to_json()).unwrap();
    assert_eq!(
        v["steps"][0]["ties"],
        serde_json::json!({
            "interface": {
                "Fx": 0.5, "Fy": -3.0,
                "nodes": { "x": [0.0, 1.0], "y": [1.0, 1.0], "fn": [1.0, 2.0], "ft": [0.5, 0.0] }
            }
        })
    );
}

#[test]
fn summary_records_a_failed_step_last() {
    let mut summary = Summary::new("s.toml", "S", 10);
    summary.steps.push(converged_step());
    let names = ["zeta", "alpha", "mid"].map(String::from);
    summary.steps.push(Summary::failed_step(
        1.0,
        31,
        6,
        names.iter().cloned(),
        ["die".to_string()],
        ["upper".to_string(), "lower".to_string()],
    ));
    let path = scratch("summary.json");
    summary.write(&path).unwrap();
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let steps = v["steps"].as_array().unwrap();
    assert_eq!(steps.len(), 2);
    assert_eq!(steps[0]["converged"], true);
    let f = &steps[1];
    assert_eq!(f["time"], 1.0);
    assert_eq!(f["converged"], false);
    assert_eq!(f["iterations"], 31);
    assert_eq!(f["substeps"], 6);
    // Unknown values are null, never a number that could be mistaken.
    assert!(f["residual"].is_null());
    assert!(f["drivers"]["zeta"]["Ry"].is_null());
    assert!(f["drivers"]["zeta"].get("Mz").is_none());
    // Rigid targets follow the drivers, their moment unknown too.
    assert_eq!(
        f["drivers"]["die"],
        serde_json::json!({ "Rx": null, "Ry": null, "Mz": null })
    );
    assert_eq!(f["drivers"].as_object().unwrap().len(), 4);
    // Same keys as a solved pair: unknown numbers null, no nodes.
    let unknown = serde_json::json!({
        "Fx": null, "Fy": null, "Fn": null, "Ft": null,
        "n_stick": null, "n_slip": null, "n_open": null,
        "stick_length": null, "slip_length": null,
        "nodes": { "x": [], "y": [], "tn": [], "tt": [], "state": [], "gap": [], "slip": [] },
    });
    assert_eq!(
        f["pairs"],
        serde_json::json!({ "upper": unknown, "lower": unknown })
    );
    let text = std::fs::read_to_string(&path).unwrap();
    let at = |k: &str| text.rfind(&format!("\"{k}\"")).unwrap();
    assert!(at("mid") < at("die") && at("upper") < at("lower"));
}

/// A step with a rigid target (its moment) and one contact pair of two
/// nodes, one sticking and one sliding: the whole file, byte for byte.
#[test]
fn summary_of_a_step_with_a_pair_and_a_rigid_target() {
    let mut summary = Summary::new("scenes/punch.toml", "Punch", 42);
    summary.wall_s = 0.5;
    summary.build = "test".into();
    summary.steps.push(StepResult {
        time: 1.0,
        converged: true,
        iterations: 4,
        substeps: 0,
        solves: 4,
        factorizations: 4,
        fallbacks: 0,
        residual: 2.5e-10,
        neqc: 3,
        drivers: vec![
            (
                "base".into(),
                DriverResult {
                    rx: 0.0,
                    ry: 1200.0,
                    mz: None,
                    ..Default::default()
                },
            ),
            (
                "punch".into(),
                DriverResult {
                    rx: 30.0,
                    ry: -1200.0,
                    mz: Some(-37.5),
                    ..Default::default()
                },
            ),
        ],
        pairs: vec![(
            "punch_on_block".into(),
            PairResult {
                fx: -30.0,
                fy: 1200.0,
                fn_: 1200.0,
                ft: 30.0,
                n_stick: 1,
                n_slip: 1,
                n_open: 0,
                stick_length: 0.6,
                slip_length: 0.65,
                nodes: PairNodes {
                    x: vec![0.25, 1.5],
                    y: vec![2.0, 1.9375],
                    tn: vec![600.0, 0.125],
                    tt: vec![-0.0, 1e-3],
                    state: vec![NodeState::Stick, NodeState::Slip],
                    gap: vec![0.0, -2.5e-10],
                    slip: vec![0.0, 0.375],
                    angle: Vec::new(),
                    pn: Vec::new(),
                    pt: Vec::new(),
                },
            },
        )],
        ties: vec![],
        running: vec![],
    });
    let expected = r#"{
  "scene": "scenes/punch.toml",
  "dofs": 42,
  "wall_s": 0.5,
  "steps": [
    {
      "time": 1.0,
      "converged": true,
      "iterations": 4,
      "substeps": 0,
      "residual": 2.5e-10,
      "neqc": 3,
      "drivers": {
        "base": {
          "Rx": 0.0,
          "Ry": 1200.0
        },
        "punch": {
          "Rx": 30.0,
          "Ry": -1200.0,
          "Mz": -37.5
        }
      },
      "pairs": {
        "punch_on_block": {
          "Fx": -30.0,
          "Fy": 1200.0,
          "Fn": 1200.0,
          "Ft": 30.0,
          "n_stick": 1,
          "n_slip": 1,
          "n_open": 0,
          "stick_length": 0.6,
          "slip_length": 0.65,
          "nodes": {
            "x": [
              0.25,
              1.5
            ],
            "y": [
              2.0,
              1.9375
            ],
            "tn": [
              600.0,
              0.125
            ],
            "tt": [
              -0.0,
              0.001
            ],
            "state": [
              1,
              2
            ],
            "gap": [
              0.0,
              -2.5e-10
            ],
            "slip": [
              0.0,
              0.375
            ]
          }
        }
      }
    }
  ],
  "title": "Punch",
  "build": "test"
}"#;
    assert_eq!(summary.to_json(), expected);
    // The file is the same text with a final newline.
    let path = scratch("pair.json");
    summary.write(&path).unwrap();
    assert_eq!(
        std::fs::read_to_string(&path).unwrap(),
        format!("{expected}\n")
    );
}
