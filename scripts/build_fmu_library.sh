#!/usr/bin/env bash
# Builds the shared library that `contact2d export` puts in the FMUs,
# portable to Linux distributions with glibc 2.17 or later (RHEL/CentOS 7,
# Debian 8, Ubuntu 14.04 on): cargo-zigbuild links it with zig (PyPI's
# `ziglang`, in .venv) against glibc 2.17's symbol versions, in the `fmu`
# profile (release code, no debug info, stripped). It leaves
#   target/x86_64-unknown-linux-gnu/fmu/libcontact2d.so
# (below $CARGO_TARGET_DIR when set), which export ships by default, and
# builds with this script first when it is missing or older than the
# native library (docs/fmu.md, "A portable library").
# tests/python/test_portable_library.py checks its symbol versions.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh >/dev/null
target="$(realpath -m "${CARGO_TARGET_DIR:-target}")"
start=$SECONDS
# cargo-zigbuild runs zig as `python -m ziglang`, with the venv's Python.
# It runs from scripts/, not the repo root: zig names its C include folders
# relative to the working folder when they lie below it (.venv/...), and
# cargo-zigbuild hands them on to bindgen in fmi-sys's build script, which
# runs in another folder.
(cd scripts && CARGO_TARGET_DIR="$target" CARGO_ZIGBUILD_PYTHON_PATH="$PWD/../.venv/bin/python" \
    cargo zigbuild --manifest-path ../Cargo.toml --profile fmu --lib \
    --target x86_64-unknown-linux-gnu.2.17)
lib="$target/x86_64-unknown-linux-gnu/fmu/libcontact2d.so"
# Up to date with the sources now, even when cargo had nothing to rebuild:
# export ships the newer of this and the native library (src/fmi/export.rs).
touch "$lib"
echo "build_fmu_library: $lib, $(stat -c %s "$lib") bytes, $((SECONDS - start)) s"
