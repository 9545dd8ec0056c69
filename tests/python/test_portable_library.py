"""The library the FMUs ship (issue 15): built by scripts/build_fmu_library.sh
against glibc 2.17, stripped, what `contact2d export` puts in every FMU by
default, and small enough that the Hertz scene's FMU stays under 2 MB.
The FMU tests of fmpy, libcosim and fmutool load this library: conftest's
export_fmu checks that every FMU they export ships it."""

import re
import subprocess
import zipfile
from pathlib import Path

from elftools.elf.elffile import ELFFile

from conftest import PORTABLE_LIBRARY, REPO

# The oldest glibc the FMU must load with (RHEL/CentOS 7).
BASELINE = (2, 17)
# Issue 15: "the FMU zip of the Hertz scene is under 2 MB".
HERTZ_FMU_LIMIT = 2_000_000


def version_needs(path: Path) -> dict:
    """The ELF file's symbol-version needs (.gnu.version_r): library name ->
    the set of version names its symbols are bound to (GLIBC_2.14, ...)."""
    with open(path, "rb") as f:
        elf = ELFFile(f)
        section = elf.get_section_by_name(".gnu.version_r")
        assert section is not None, f"{path}: no .gnu.version_r section"
        return {need.name: {aux.name for aux in auxes} for need, auxes in section.iter_versions()}


def glibc_versions(needs: dict) -> set:
    """Every GLIBC_x.y[.z] version needed, as tuples of ints."""
    found = set()
    for names in needs.values():
        for name in names:
            m = re.fullmatch(r"GLIBC_(\d+(?:\.\d+)+)", name)
            if m:
                found.add(tuple(int(x) for x in m.group(1).split(".")))
    return found


def test_portable_library_needs_nothing_newer_than_glibc_2_17():
    assert PORTABLE_LIBRARY.is_file(), f"{PORTABLE_LIBRARY}: run `bash scripts/build_fmu_library.sh`"
    needs = version_needs(PORTABLE_LIBRARY)
    assert "libc.so.6" in needs, needs
    versions = glibc_versions(needs)
    assert (2, 2, 5) in versions, versions  # x86_64's first glibc: the parse found the needs
    newer = sorted(v for v in versions if v[:2] > BASELINE)
    assert newer == [], f"needs glibc {newer} (baseline {BASELINE}): {needs}"
    # Nothing else a bare old system may lack: no private glibc symbols,
    # no libgcc_s or libstdc++ (zig links its unwinder in).
    assert not any("PRIVATE" in n for names in needs.values() for n in names), needs
    assert set(needs) <= {"libc.so.6", "libm.so.6", "libpthread.so.0", "libdl.so.2", "ld-linux-x86-64.so.2"}, needs


def test_the_version_check_sees_a_native_build_newer_than_the_baseline():
    """The same check on the library `cargo build --release` links against
    this machine's glibc (2.36) finds versions past 2.17: it would catch a
    portable build that was not."""
    native = REPO / "target" / "release" / "libcontact2d.so"
    assert native.is_file(), f"{native}: run `cargo build --release --lib`"
    newer = [v for v in glibc_versions(version_needs(native)) if v[:2] > BASELINE]
    assert newer, "the native library should need a glibc newer than 2.17 on this machine"


def test_portable_library_is_stripped():
    with open(PORTABLE_LIBRARY, "rb") as f:
        elf = ELFFile(f)
        names = {s.name for s in elf.iter_sections()}
    assert ".symtab" not in names and not any(n.startswith(".debug") for n in names), sorted(names)


def test_the_hertz_fmu_ships_it_and_is_under_2_mb(fmus):
    fmu = fmus["hertz"]  # exported by conftest.export_fmu: the default library
    with zipfile.ZipFile(fmu) as z:
        assert z.read("binaries/linux64/contact2d.so") == PORTABLE_LIBRARY.read_bytes()
    size = fmu.stat().st_size
    print(f"hertz_plane_strain FMU: {size} bytes (library {PORTABLE_LIBRARY.stat().st_size} bytes)")
    assert size < HERTZ_FMU_LIMIT, f"{fmu}: {size} bytes"


def test_an_export_after_a_native_build_ships_the_portable_library(contact2d, tmp_path):
    """Issue 35, item 7: after `cargo build --release` of a change (the
    native library newer than the portable one, as the README's first
    command leaves it), `contact2d export` builds the portable library
    first (scripts/build_fmu_library.sh; a no-op for cargo here, the code
    unchanged) and ships it: the capstan FMU of the winding machine is
    under 2 MB, its library stripped and needing at most glibc 2.17. Before,
    export shipped the native library (8.8 MB FMU, glibc 2.35) with a
    warning."""
    native = REPO / "target" / "release" / "libcontact2d.so"
    assert native.is_file(), f"{native}: run `cargo build --release --lib`"
    native.touch()
    scene = REPO / "examples" / "winding_machine" / "capstan.toml"
    fmu = tmp_path / "capstan.fmu"
    done = subprocess.run(
        [str(contact2d), "export", str(scene), "-o", str(fmu)],
        capture_output=True,
        text=True,
        timeout=1200,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    assert "building the portable library" in done.stderr, done.stderr
    assert f"(library {PORTABLE_LIBRARY})" in done.stdout, done.stdout + done.stderr
    assert PORTABLE_LIBRARY.stat().st_mtime >= native.stat().st_mtime
    shipped = tmp_path / "contact2d.so"
    with zipfile.ZipFile(fmu) as z:
        shipped.write_bytes(z.read("binaries/linux64/contact2d.so"))
    versions = glibc_versions(version_needs(shipped))
    print(f"capstan FMU: {fmu.stat().st_size} bytes; library needs glibc up to {max(versions)}")
    assert fmu.stat().st_size < HERTZ_FMU_LIMIT, fmu.stat().st_size
    assert max(v[:2] for v in versions) <= BASELINE, sorted(versions)
    with open(shipped, "rb") as f:
        assert ELFFile(f).get_section_by_name(".symtab") is None, "not stripped"
    # Up to date now: the next export builds nothing.
    again = subprocess.run(
        [str(contact2d), "export", str(scene), "-o", str(fmu)], capture_output=True, text=True, timeout=300
    )
    assert again.returncode == 0 and "building" not in again.stderr, again.stderr
