//! `contact2d export`: the FMU of a scene, a zip with
//! `modelDescription.xml`, `binaries/linux64/contact2d.so` and `resources/`
//! (the scene as `scene.toml`, and the mesh files it reads, at the same
//! relative paths); with `--fmi 3`, the FMI 3.0 FMU: its model description
//! and `binaries/x86_64-linux/contact2d.so` (the same library, which has
//! both interfaces).

use super::SCENE_FILE;
use super::description::{MODEL_IDENTIFIER, model_description};
use std::io::Write;
use std::path::{Component, Path, PathBuf};

/// What was written.
#[derive(Debug)]
pub struct Exported {
    pub variables: usize,
    pub bytes: u64,
}

/// The shared library next to a binary of this crate (`cargo build` puts it
/// beside the executable, `cargo test` under `deps/`): the newer of the two.
pub fn find_library(exe: &Path) -> Option<PathBuf> {
    let dir = exe.parent()?;
    let name = format!("lib{MODEL_IDENTIFIER}.so");
    [dir.join(&name), dir.join("deps").join(&name)]
        .into_iter()
        .filter_map(|p| {
            let t = std::fs::metadata(&p).and_then(|m| m.modified()).ok()?;
            Some((t, p))
        })
        .max()
        .map(|(_, p)| p)
}

/// Why an FMU was not written: the scene (or a mesh file it reads) is wrong
/// or unreadable, or the library could not be read or the FMU written.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    #[error("{0}")]
    Scene(String),
    #[error("{0}")]
    Output(String),
}

/// Writes the FMI 2.0 FMU of `scene` to `out`, with the shared library
/// `library`.
pub fn export(scene: &Path, out: &Path, library: &Path) -> Result<Exported, ExportError> {
    export_version(scene, out, library, FmiVersion::Fmi2)
}

/// Which standard an exported FMU follows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FmiVersion {
    Fmi2,
    Fmi3,
}

/// Writes the FMU of `scene` to `out` for FMI `version`, with the shared
/// library `library`.
pub fn export_version(
    scene: &Path,
    out: &Path,
    library: &Path,
    version: FmiVersion,
) -> Result<Exported, ExportError> {
    use ExportError::{Output, Scene};
    let problem = crate::scene::load(scene).map_err(|e| Scene(e.to_string()))?;
    let (xml, platform) = match version {
        FmiVersion::Fmi2 => (model_description(&problem), "linux64"),
        FmiVersion::Fmi3 => (super::fmi3::model_description3(&problem), "x86_64-linux"),
    };
    let scene_text =
        std::fs::read(scene).map_err(|e| Scene(format!("{}: {e}", scene.display())))?;
    let lib = std::fs::read(library).map_err(|e| {
        Output(format!(
            "cannot read the shared library {}: {e} (build it with `cargo build --release`, or pass --library)",
            library.display()
        ))
    })?;
    let dir = scene.parent().unwrap_or(Path::new(""));
    let mut files = vec![(format!("resources/{SCENE_FILE}"), scene_text)];
    for rel in crate::scene::mesh_files(scene).map_err(|e| Scene(e.to_string()))? {
        let inside = rel
            .components()
            .all(|c| matches!(c, Component::Normal(_) | Component::CurDir));
        if !inside {
            return Err(Scene(format!(
                "{}: the mesh file {} is not below the scene's folder; the FMU keeps the scene's relative paths, so move the mesh beside the scene",
                scene.display(),
                rel.display()
            )));
        }
        let bytes = std::fs::read(dir.join(&rel))
            .map_err(|e| Scene(format!("{}: {e}", dir.join(&rel).display())))?;
        let name = rel
            .components()
            .filter_map(|c| match c {
                Component::Normal(s) => Some(s.to_string_lossy().into_owned()),
                _ => None,
            })
            .collect::<Vec<_>>()
            .join("/");
        files.push((format!("resources/{name}"), bytes));
    }
    files.push(("modelDescription.xml".into(), xml.into_bytes()));
    files.push((format!("binaries/{platform}/{MODEL_IDENTIFIER}.so"), lib));

    if let Some(parent) = out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent)
            .map_err(|e| Output(format!("{}: {e}", parent.display())))?;
    }
    let file = std::fs::File::create(out).map_err(|e| Output(format!("{}: {e}", out.display())))?;
    let mut zip = zip::ZipWriter::new(file);
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .unix_permissions(0o644);
    let fail = |e: &dyn std::fmt::Display| Output(format!("{}: {e}", out.display()));
    for (name, bytes) in &files {
        zip.start_file(name.as_str(), options)
            .map_err(|e| fail(&e))?;
        zip.write_all(bytes).map_err(|e| fail(&e))?;
    }
    zip.finish().map_err(|e| fail(&e))?;
    let bytes = std::fs::metadata(out).map_err(|e| fail(&e))?.len();
    Ok(Exported {
        variables: super::variables::variables(&problem).len(),
        bytes,
    })
}
