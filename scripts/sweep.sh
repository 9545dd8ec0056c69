#!/usr/bin/env bash
# The parameter-sweep example (examples/sweep, docs/sweep.md): exports the
# capstan with the wrap and back tension as parameters, runs the grid of
# friction coefficients x wrap angles as FMU runs on a local Dask cluster
# (two worker processes), prints T2/T1 at the onset of full slip against
# exp(mu theta), and writes out/sweep/{sweep_steps.csv,capstan_ratio.csv,
# capstan_ratio.png}. Extra arguments go to capstan_sweep.py (--workers N,
# --scheduler tcp://HOST:8786, --serial).
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh
cargo build --release --bin contact2d --lib
.venv/bin/python examples/sweep/capstan_sweep.py --binary target/release/contact2d --out out/sweep "$@"
