#!/usr/bin/env bash
# The main job: builds the FMU of a shipped scene and simulates it in fmpy,
# step by step, as a system model would: an input displacement ramp, then a
# reversal. Prints the contact resultants and stick/slip/open counts per
# step and writes out/fmu_demo/tractions.png (tractions over the contact
# surface at a few steps).
#   bash scripts/demo.sh      Hertz: press.uy 0 -> -0.07 in 8 steps, back to
#                             -0.02 in 5
# scripts/fmu_demo.py drives any FMU the same way (see its --help).
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh
cargo build --release --bin contact2d --lib
out=out/fmu_demo
mkdir -p "$out"
case "${1:-hertz}" in
hertz)
    target/release/contact2d export scenes/hertz_plane_strain.toml -o "$out/hertz_plane_strain.fmu"
    .venv/bin/python scripts/fmu_demo.py "$out/hertz_plane_strain.fmu" --input press.uy \
        --path 0:0 1:-0.07 1.625:-0.02 --steps 8 5 --pair contact --out "$out"
    ;;
*)
    echo "usage: bash scripts/demo.sh [hertz]" >&2
    exit 2
    ;;
esac
