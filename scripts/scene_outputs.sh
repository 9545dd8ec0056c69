#!/usr/bin/env bash
# Runs every shipped, verification and stress scene (and the winding
# machine's capstan) with a contact2d binary and writes one summary per
# scene into DIR, for scripts/compare_runs.py:
#   bash scripts/scene_outputs.sh DIR [BINARY]   (default target/release/contact2d)
# A scene that stops early (cgs4_inclined by design) still leaves its summary.
set -uo pipefail
cd "$(dirname "$0")/.."
dir="$1"
bin="${2:-target/release/contact2d}"
mkdir -p "$dir"
for scene in scenes/*.toml scenes/verification/*.toml scenes/stress/*.toml examples/winding_machine/capstan.toml examples/sweep/capstan_wrap.toml; do
    stem="$(basename "$(dirname "$scene")")_$(basename "$scene" .toml)"
    "$bin" run "$scene" --quiet --summary "$dir/$stem.json" >/dev/null 2>&1
    echo "$stem: exit $?"
done
