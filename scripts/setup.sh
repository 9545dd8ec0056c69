#!/usr/bin/env bash
# Installs what the tests and scripts need, on a fresh Debian 12 machine (as
# root) with the Rust toolchain, or on one set up before: safe to run again.
#   - Debian packages listed in DEB_PACKAGES (apt-get update only when one is
#     missing);
#   - .venv at the repo root with Python 3.11 and requirements.txt (with
#     ziglang, the zig toolchain that links the portable FMU library);
#   - cargo-zigbuild (pinned below), from crates.io with `cargo install`.
set -euo pipefail
cd "$(dirname "$0")/.."

# ---------------------------------------------------------------------------
# Debian packages: libclang-dev for bindgen, which fmi-sys runs on the FMI
# headers at build time. (pyvista's VTK wheels read files without libGL or
# X11: the tests do not render, so no graphics package is needed.)
DEB_PACKAGES="libclang-dev"
# cargo-zigbuild builds the FMU's library against glibc 2.17
# (scripts/build_fmu_library.sh); zig itself comes from PyPI (ziglang, in
# requirements.txt).
CARGO_ZIGBUILD_VERSION="0.24.1"
# ---------------------------------------------------------------------------

PYTHON="${PYTHON:-python3}"

# A Python without venv/ensurepip (Debian's python3 before python3-venv is
# installed) cannot make .venv: use Debian's with its venv package.
if ! command -v "$PYTHON" >/dev/null 2>&1 || ! "$PYTHON" -c 'import venv, ensurepip' >/dev/null 2>&1; then
    DEB_PACKAGES="$DEB_PACKAGES python3 python3-venv"
    PYTHON=/usr/bin/python3
fi

install_debian_packages() {
    local missing=()
    local p
    for p in "$@"; do
        if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
            missing+=("$p")
        fi
    done
    if [ "${#missing[@]}" -eq 0 ]; then
        return 0
    fi
    echo "setup: installing Debian packages: ${missing[*]}"
    local sudo=""
    if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

# shellcheck disable=SC2086 # word splitting of the package list is intended
install_debian_packages $DEB_PACKAGES

for tool in cargo rustfmt cargo-clippy; do
    if ! command -v "$tool" >/dev/null 2>&1; then
        echo "setup: $tool not found: the Rust toolchain (rustup, with rustfmt and clippy) is required" >&2
        exit 1
    fi
done

# cargo-zigbuild, unless this version is installed. The portable library is
# built for x86_64-unknown-linux-gnu.2.17: the standard library of the
# ordinary x86_64-unknown-linux-gnu target, the host's own on this machine.
if [ "$(cargo-zigbuild --version 2>/dev/null || true)" != "cargo-zigbuild $CARGO_ZIGBUILD_VERSION" ]; then
    echo "setup: installing cargo-zigbuild $CARGO_ZIGBUILD_VERSION"
    cargo install --quiet --locked cargo-zigbuild --version "=$CARGO_ZIGBUILD_VERSION"
fi
if command -v rustup >/dev/null 2>&1 && ! rustup target list --installed | grep -qx x86_64-unknown-linux-gnu; then
    rustup target add x86_64-unknown-linux-gnu
fi

version="$("$PYTHON" -c 'import sys; print("%d.%d" % sys.version_info[:2])')"
if [ "$version" != "3.11" ]; then
    echo "setup: $PYTHON is Python $version, 3.11 expected" >&2
    exit 1
fi

# A .venv left broken (interrupted creation, another Python) is made anew.
if [ ! -x .venv/bin/python ] || ! .venv/bin/python -c 'import sys; assert sys.version_info[:2] == (3, 11)' >/dev/null 2>&1; then
    rm -rf .venv
    "$PYTHON" -m venv .venv
fi

# pip only when requirements.txt changed since the last successful install.
stamp=.venv/.requirements.sha256
want="$(sha256sum requirements.txt | cut -d' ' -f1)"
if [ "$(cat "$stamp" 2>/dev/null || true)" != "$want" ]; then
    .venv/bin/python -m pip install --quiet --disable-pip-version-check -r requirements.txt
    echo "$want" >"$stamp"
fi
echo "setup: ok (.venv: $(.venv/bin/python --version); $(cargo --version))"
