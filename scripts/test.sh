#!/usr/bin/env bash
# Every test, as CI runs it (.ci/run): formatting, clippy, the Rust tests in
# release (the heavy ones need it), then the Python tests against the
# release binary, whose `export` ships the portable library built last
# (glibc 2.17, scripts/build_fmu_library.sh). Stops at the first failure
# with a non-zero exit code.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh

echo "== cargo fmt --check"
cargo fmt --check
echo "== cargo clippy --all-targets -- -D warnings"
cargo clippy --all-targets -- -D warnings
echo "== cargo test --release"
cargo test --release
echo "== cargo build --release"
cargo build --release --bin contact2d --lib
echo "== scripts/build_fmu_library.sh (the FMUs' library, glibc 2.17)"
bash scripts/build_fmu_library.sh
echo "== pytest tests/python"
CONTACT2D_BIN="$PWD/target/release/contact2d" .venv/bin/pytest tests/python -q
