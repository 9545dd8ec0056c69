#!/usr/bin/env bash
# Solves a shipped scene with the command line and prints its results:
#   bash scripts/demo.sh [SCENE]     (default: the Lame thick cylinder)
# Writes out/<stem>/summary.json and out/<stem>/vtk/<stem>.pvd (open the
# .pvd in ParaView; "Warp By Vector" on displacement shows the deformation).
set -euo pipefail
cd "$(dirname "$0")/.."

scene="${1:-scenes/verification/lame_cylinder.toml}"
stem="$(basename "$scene" .toml)"
out="out/$stem"

bash scripts/setup.sh
cargo build --release --bin contact2d
mkdir -p "$out"
rm -f "$out/summary.json"
status=0
target/release/contact2d run "$scene" --summary "$out/summary.json" --vtk "$out/vtk" || status=$?
# A failed increment still leaves the summary (exit code 1); a bad scene not.
[ -f "$out/summary.json" ] || exit "$status"

.venv/bin/python - "$out/summary.json" <<'PY'
import json, sys

s = json.load(open(sys.argv[1]))
steps = s["steps"]
drivers = list(steps[0]["drivers"]) if steps else []
print()
print(f"{s['title']}: {s['dofs']} unknowns, solved in {s['wall_s']:.3f} s")
head = f"{'time':>8} {'ok':>3} {'iter':>4} {'residual':>10} {'NEQC':>4}"
head += "".join(f" {d + '.Rx':>13} {d + '.Ry':>13}" for d in drivers)
print(head)
num = lambda v: f"{v:13.5e}" if v is not None else f"{'-':>13}"
for st in steps:
    res = f"{st['residual']:10.2e}" if st["residual"] is not None else f"{'-':>10}"
    row = f"{st['time']:8.4g} {'yes' if st['converged'] else 'NO':>3} {st['iterations']:4d} {res} {st['neqc']:4d}"
    row += "".join(f" {num(st['drivers'][d]['Rx'])} {num(st['drivers'][d]['Ry'])}" for d in drivers)
    print(row)
PY
echo
echo "summary: $out/summary.json"
echo "ParaView: $out/vtk/$stem.pvd"
exit "$status"
