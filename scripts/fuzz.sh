#!/usr/bin/env bash
# A long fuzz campaign (issue 13); CI runs short bounded ones inside
# scripts/test.sh. Random edits of the shipped scenes through the scene
# reader (proptest), then random FMI call sequences on an FMU (hypothesis),
# each with a new random seed; then load/unload cycles of the sliding
# block's FMU (scripts/load_cycles.py: the RSS growth per cycle, from the
# same path and from a new copy each cycle):
#   bash scripts/fuzz.sh [SCENE_CASES] [FMI_SEQUENCES] [CYCLES]   (default 20000, 500, 300)
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh
cargo build --release --bin contact2d --lib
echo "== scene reader: ${1:-20000} edited scenes"
PROPTEST_CASES="${1:-20000}" cargo test --release --test fuzz_scene
echo "== FMI call sequences: ${2:-500} sequences of up to 40 calls"
FUZZ_EXAMPLES="${2:-500}" FUZZ_STEPS=40 FUZZ_RANDOM=1 CONTACT2D_BIN="$PWD/target/release/contact2d" \
    .venv/bin/pytest tests/python/test_fmu_fuzz.py -q
echo "== load/unload cycles: ${3:-300} of the sliding block's FMU"
fmu_dir="$(mktemp -d)"
trap 'rm -rf "$fmu_dir"' EXIT
target/release/contact2d export scenes/verification/sliding_block.toml -o "$fmu_dir/sliding_block.fmu"
for copy in "" --copy; do
    .venv/bin/python scripts/load_cycles.py "$fmu_dir/sliding_block.fmu" --cycles "${3:-300}" ${copy:+"$copy"} \
        --set top.uy=-0.01 --derivative top.Ry,top.uy --max-kib-per-cycle 10
done
