//! The contact stress suite (issue 11) on every scene variant, the meshes
//! refined twice included: one table row per variant.
//!
//!     cargo bench --bench stress              # every case
//!     cargo bench --bench stress -- capstan   # the cases whose name contains "capstan"
//!
//! Columns: case, mesh, unknowns, converged increments, Newton iterations
//! per increment (median, largest), the most linear solves in one increment
//! (its Newton iterations plus the inner solves while the linearised
//! problem's contact states change), the most numeric factorizations in one
//! increment (an inner solve borders its iteration's factorization), bisections (summed), failed increments
//! (1@t: the run stopped at the increment to t), wall time of the solve,
//! and each closed-form check: computed / reference (relative error, or
//! absolute for angles and lengths, and the tolerance tests/stress.rs
//! asserts; FAIL beyond it). Below each row, the number of findings the
//! test would report and the first of them. Nothing is asserted here.

#[path = "../tests/common/mod.rs"]
mod common;

use common::stress::Outcome;
use common::stress::families::{self, Case};
use std::path::PathBuf;

fn report(out: &Outcome) {
    println!("{}", out.row());
    let findings = out.findings();
    if let Some(first) = findings.first() {
        let first: String = first.chars().take(200).collect();
        println!("    {} finding(s); first: {first}", findings.len());
    }
}

/// The Cattaneo-Mindlin block mesh with 8-node elements, written by
/// scripts/cattaneo_block_mesh.py --q8 under target/ (not shipped: 0.8 MB).
fn cattaneo_q8_block() -> Option<PathBuf> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let dir = root.join("target").join("stress");
    std::fs::create_dir_all(&dir).ok()?;
    let path = dir.join("cattaneo_block_q8.msh");
    if !path.exists() {
        let out = std::process::Command::new("python3")
            .arg(root.join("scripts/cattaneo_block_mesh.py"))
            .arg("--q8")
            .output()
            .ok()?;
        if !out.status.success() {
            return None;
        }
        std::fs::write(&path, out.stdout).ok()?;
    }
    Some(path)
}

fn main() {
    // `cargo bench` passes --bench; any other argument filters the cases.
    let filter: Option<String> = std::env::args().skip(1).find(|a| !a.starts_with("--"));
    let wanted = |name: &str| filter.as_ref().is_none_or(|f| name.contains(f.as_str()));
    println!("{}", Outcome::header());
    for Case {
        name,
        run,
        variants,
    } in families::cases()
    {
        if !wanted(name) {
            continue;
        }
        for &v in variants {
            report(&run(v));
        }
    }
    if wanted("cattaneo_q8") {
        match cattaneo_q8_block() {
            Some(path) => report(&families::cattaneo(false, Some(path.to_str().unwrap()))),
            None => {
                println!("cattaneo q8: python3 scripts/cattaneo_block_mesh.py --q8 did not run")
            }
        }
    }
}
