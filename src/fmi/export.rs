//! `contact2d export`: the FMU of a scene, a zip with
//! `modelDescription.xml`, `binaries/linux64/contact2d.so` and `resources/`
//! (the scene as `scene.toml`, and the mesh files it reads, at the same
//! relative paths); with `--fmi 3`, the FMI 3.0 FMU: its model description
//! and `binaries/x86_64-linux/contact2d.so` (the same library, which has
//! both interfaces). The library shipped by default is the portable build
//! (glibc 2.17, `scripts/build_fmu_library.sh`) when it is up to date.

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

/// Where `scripts/build_fmu_library.sh` leaves the portable library, below
/// cargo's target folder: `cargo zigbuild --profile fmu --target
/// x86_64-unknown-linux-gnu.2.17` (the glibc version is not part of the
/// folder's name).
pub const PORTABLE_DIR: [&str; 2] = ["x86_64-unknown-linux-gnu", "fmu"];

fn modified(p: &Path) -> Option<std::time::SystemTime> {
    std::fs::metadata(p).and_then(|m| m.modified()).ok()
}

fn library_name() -> String {
    format!("lib{MODEL_IDENTIFIER}.so")
}

/// The shared library next to a binary of this crate (`cargo build` puts it
/// beside the executable, `cargo test` under `deps/`): the newer of the two.
/// Linked against this machine's glibc.
pub fn find_library(exe: &Path) -> Option<PathBuf> {
    let dir = exe.parent()?;
    [
        dir.join(library_name()),
        dir.join("deps").join(library_name()),
    ]
    .into_iter()
    .filter_map(|p| Some((modified(&p)?, p)))
    .max()
    .map(|(_, p)| p)
}

/// The portable library of the target folder a binary of this crate was
/// built in (`target/release/contact2d` -> `target/x86_64-unknown-linux-gnu/fmu/`).
pub fn portable_library(exe: &Path) -> PathBuf {
    let target = exe.parent().and_then(Path::parent).unwrap_or(Path::new(""));
    target
        .join(PORTABLE_DIR[0])
        .join(PORTABLE_DIR[1])
        .join(library_name())
}

/// The library `export` ships when none is named, and whether it is the
/// portable one: the portable library unless the native one beside `exe`
/// is newer (both are builds of the same code, so the newer one has the
/// current code: a portable library left from an older revision is not
/// shipped).
pub fn default_library(exe: &Path) -> Option<(PathBuf, bool)> {
    let portable = portable_library(exe);
    let native = find_library(exe);
    match (modified(&portable), native) {
        (Some(tp), Some(n)) if modified(&n).is_some_and(|tn| tn > tp) => Some((n, false)),
        (Some(_), _) => Some((portable, true)),
        (None, n) => n.map(|n| (n, false)),
    }
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
    export_version(scene, out, library, FmiVersion::Fmi2, Packing::Fast)
}

/// How the library is compressed into the FMU. Both write standard
/// deflate, which every FMI importer reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Packing {
    /// zlib's best level, a second or two for any library.
    Fast,
    /// zopfli (one iteration): some 2.5 % smaller than zlib's best (47 kB
    /// of the Hertz scene's FMU), for some 16 s per 6 MB. Done once
    /// per library build: the compressed library is kept beside it
    /// (`<library>.zopfli.zip`) and copied into each FMU while its CRC-32
    /// and size are the library's.
    Thorough,
}

/// Which standard an exported FMU follows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FmiVersion {
    Fmi2,
    Fmi3,
}

/// Writes the FMU of `scene` to `out` for FMI `version`, with the shared
/// library `library` compressed as `packing` says.
pub fn export_version(
    scene: &Path,
    out: &Path,
    library: &Path,
    version: FmiVersion,
    packing: Packing,
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
    let lib_name = format!("binaries/{platform}/{MODEL_IDENTIFIER}.so");
    let mut packed = match packing {
        Packing::Fast => None,
        Packing::Thorough => Some(thoroughly_packed(library, &lib)?),
    };
    if packed.is_none() {
        files.push((lib_name.clone(), lib));
    }

    if let Some(parent) = out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent)
            .map_err(|e| Output(format!("{}: {e}", parent.display())))?;
    }
    let file = std::fs::File::create(out).map_err(|e| Output(format!("{}: {e}", out.display())))?;
    let mut zip = zip::ZipWriter::new(file);
    // zlib's best level: the library is most of the FMU, and level 9 packs
    // it some 13 kB (0.7 %) tighter than the default 6, at export time only
    // (issue 15: the Hertz FMU under 2 MB).
    let options = entry_options(9);
    let fail = |e: &dyn std::fmt::Display| Output(format!("{}: {e}", out.display()));
    for (name, bytes) in &files {
        zip.start_file(name.as_str(), options)
            .map_err(|e| fail(&e))?;
        zip.write_all(bytes).map_err(|e| fail(&e))?;
    }
    if let Some(archive) = packed.as_mut() {
        let entry = archive.by_index_raw(0).map_err(|e| fail(&e))?;
        zip.raw_copy_file_rename(entry, lib_name)
            .map_err(|e| fail(&e))?;
    }
    zip.finish().map_err(|e| fail(&e))?;
    let bytes = std::fs::metadata(out).map_err(|e| fail(&e))?.len();
    Ok(Exported {
        variables: super::variables::variables(&problem).len(),
        bytes,
    })
}

/// The zip entry options of a file in the FMU: deflated at `level` (10 and
/// above: zopfli's iterations plus 9).
fn entry_options(level: i64) -> zip::write::SimpleFileOptions {
    zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .compression_level(Some(level))
        .unix_permissions(0o644)
}

type Packed = zip::ZipArchive<std::io::Cursor<Vec<u8>>>;

/// `bytes`, the contents of `library`, deflated by zopfli as the only entry
/// of an in-memory zip: read from the cache beside the library when its
/// entry has the library's CRC-32 and size, else compressed and the cache
/// written (through a temporary file renamed into place, so that a
/// concurrent export never reads half of it; a cache that cannot be written
/// only costs the next export the time again).
fn thoroughly_packed(library: &Path, bytes: &[u8]) -> Result<Packed, ExportError> {
    let mut crc = flate2::Crc::new();
    crc.update(bytes);
    let file_name = library.file_name().unwrap_or_default().to_string_lossy();
    let cache = library.with_file_name(format!("{file_name}.zopfli.zip"));
    let matches = |archive: &mut Packed| {
        archive.len() == 1
            && archive
                .by_index_raw(0)
                .is_ok_and(|e| e.crc32() == crc.sum() && e.size() == bytes.len() as u64)
    };
    if let Ok(cached) = std::fs::read(&cache)
        && let Ok(mut archive) = zip::ZipArchive::new(std::io::Cursor::new(cached))
        && matches(&mut archive)
    {
        return Ok(archive);
    }
    let fail = |e: &dyn std::fmt::Display| {
        ExportError::Output(format!("compressing {}: {e}", library.display()))
    };
    let mut zip = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    zip.start_file("library", entry_options(10))
        .map_err(|e| fail(&e))?;
    zip.write_all(bytes).map_err(|e| fail(&e))?;
    let packed = zip.finish().map_err(|e| fail(&e))?.into_inner();
    let temporary = cache.with_extension(format!("{}.tmp", std::process::id()));
    if std::fs::write(&temporary, &packed).is_ok() && std::fs::rename(&temporary, &cache).is_err() {
        let _ = std::fs::remove_file(&temporary);
    }
    zip::ZipArchive::new(std::io::Cursor::new(packed)).map_err(|e| fail(&e))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::{Duration, SystemTime};

    /// A cargo target folder with the native library (beside the binary) and
    /// the portable one, each modified at the given second (None: absent).
    fn target(name: &str, native: Option<u64>, portable: Option<u64>) -> (PathBuf, PathBuf) {
        let root = std::env::temp_dir().join(format!("contact2d-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        let exe = root.join("release").join("contact2d");
        let files = [
            (exe.parent().unwrap().join(library_name()), native),
            (portable_library(&exe), portable),
        ];
        for (path, second) in files {
            if let Some(s) = second {
                std::fs::create_dir_all(path.parent().unwrap()).unwrap();
                let file = std::fs::File::create(&path).unwrap();
                file.set_modified(SystemTime::UNIX_EPOCH + Duration::from_secs(s))
                    .unwrap();
            }
        }
        (root, exe)
    }

    #[test]
    fn export_ships_the_portable_library_unless_the_native_one_is_newer() {
        let cases = [
            ("both-portable-newer", Some(100), Some(200), Some(true)),
            ("both-same-time", Some(100), Some(100), Some(true)),
            ("both-native-newer", Some(200), Some(100), Some(false)),
            ("native-only", Some(100), None, Some(false)),
            ("portable-only", None, Some(100), Some(true)),
            ("neither", None, None, None),
        ];
        for (name, native, portable, want) in cases {
            let (root, exe) = target(name, native, portable);
            let got = default_library(&exe);
            assert_eq!(got.as_ref().map(|(_, p)| *p), want, "{name}");
            if let Some((path, is_portable)) = got {
                let expected = if is_portable {
                    root.join("x86_64-unknown-linux-gnu/fmu/libcontact2d.so")
                } else {
                    root.join("release/libcontact2d.so")
                };
                assert_eq!(path, expected, "{name}");
            }
            let _ = std::fs::remove_dir_all(&root);
        }
    }

    /// The entry's bytes, inflated.
    fn inflated(archive: &mut Packed) -> Vec<u8> {
        let mut out = Vec::new();
        std::io::Read::read_to_end(&mut archive.by_index(0).unwrap(), &mut out).unwrap();
        out
    }

    /// Thorough packing inflates to the library, is smaller than zlib's
    /// best, is read back from its cache while the library is unchanged, and
    /// is redone when the library changes (same size, other bytes).
    #[test]
    fn thorough_packing_is_smaller_and_cached_per_library() {
        let root = std::env::temp_dir().join(format!("contact2d-packing-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        std::fs::create_dir_all(&root).unwrap();
        let library = root.join("libx.so");
        let cache = root.join("libx.so.zopfli.zip");
        // Machine code with its tables: the start of this test's binary.
        let exe = std::fs::read(std::env::current_exe().unwrap()).unwrap();
        let bytes = exe[..exe.len().min(300_000)].to_vec();
        std::fs::write(&library, &bytes).unwrap();

        let mut packed = thoroughly_packed(&library, &bytes).unwrap();
        assert_eq!(inflated(&mut packed), bytes);
        let thorough = packed.by_index_raw(0).unwrap().compressed_size();
        let mut fast = flate2::write::DeflateEncoder::new(Vec::new(), flate2::Compression::best());
        fast.write_all(&bytes).unwrap();
        let fast = fast.finish().unwrap().len() as u64;
        assert!(thorough < fast, "zopfli {thorough} bytes, zlib {fast}");

        // Cached: a marker put into the cache's comment survives the next call.
        let cached = std::fs::read(&cache).unwrap();
        let mut marked = zip::ZipWriter::new_append(std::io::Cursor::new(cached)).unwrap();
        marked.set_comment("marker").unwrap();
        std::fs::write(&cache, marked.finish().unwrap().into_inner()).unwrap();
        let again = thoroughly_packed(&library, &bytes).unwrap();
        assert_eq!(again.comment(), b"marker");

        // Changed library: packed again, and the cache replaced.
        let mut other = bytes.clone();
        other[1000] ^= 0xff;
        std::fs::write(&library, &other).unwrap();
        let mut redone = thoroughly_packed(&library, &other).unwrap();
        assert_eq!(inflated(&mut redone), other);
        assert_eq!(redone.comment(), b"");
        let mut from_cache =
            zip::ZipArchive::new(std::io::Cursor::new(std::fs::read(&cache).unwrap())).unwrap();
        assert_eq!(inflated(&mut from_cache), other);
        let _ = std::fs::remove_dir_all(&root);
    }
}
