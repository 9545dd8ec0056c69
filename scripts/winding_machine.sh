#!/usr/bin/env bash
# The main job: the wire-winding machine example (examples/winding_machine).
# Builds the contact FMU of the tape running over the capstan (`contact2d
# export`) and the machine's system model as an FMU (pythonfmu), runs them
# coupled step by step in fmpy and then in libcosim from
# OspSystemStructure.xml, prints the tensions, the stick and slip arcs and
# the creep against the steady theory, the cost per capstan doStep (median,
# max) and the coupled run time against simulated time, and writes
# out/winding_machine/winding_machine.png. Extra arguments go to winding.py (--stop, --step).
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh
cargo build --release --bin contact2d --lib
.venv/bin/python examples/winding_machine/winding.py --binary target/release/contact2d \
    --out out/winding_machine "$@"
