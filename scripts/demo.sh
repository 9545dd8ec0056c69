#!/usr/bin/env bash
# The main job: builds the FMUs of two shipped scenes and simulates them in
# fmpy step by step, as a system model would: an input displacement ramp,
# then a reversal. Prints the contact resultants and stick/slip/open counts
# per step and writes a plot of the tractions over the contact surface at a
# few steps:
#   - Hertz (cylinder on a rigid flat): press.uy 0 -> -0.07 in 8 steps, back
#     to -0.02 in 5; out/fmu_demo/hertz/tractions.png
#   - the sliding block (mu_s 0.3, mu_d 0.2): pressed (top.uy = -0.01), dragged
#     by top.ux to +0.05 in 5 steps, back to -0.05 in 10: stick, slip at
#     mu_d, a sticking step at the reversal, slip the other way;
#     out/fmu_demo/block/tractions.png
# scripts/fmu_demo.py drives any FMU the same way (see its --help).
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh
cargo build --release --bin contact2d --lib
out=out/fmu_demo
mkdir -p "$out"

echo
echo "== Hertz, cylinder on a rigid flat"
target/release/contact2d export scenes/hertz_plane_strain.toml -o "$out/hertz_plane_strain.fmu"
.venv/bin/python scripts/fmu_demo.py "$out/hertz_plane_strain.fmu" --input press.uy \
    --path 0:0 1:-0.07 1.625:-0.02 --steps 8 5 --pair contact --out "$out/hertz"

echo
echo "== Block dragged on a rigid plane"
target/release/contact2d export scenes/verification/sliding_block.toml -o "$out/sliding_block.fmu"
.venv/bin/python scripts/fmu_demo.py "$out/sliding_block.fmu" --set top.uy=-0.01 \
    --input top.ux --path 0:0 1:0 2:0.05 3:-0.05 --steps 1 5 10 --pair base --out "$out/block"
