#!/usr/bin/env bash
# Solves a shipped scene with the command line and prints its results:
#   bash scripts/run_scene.sh [SCENE]     (default: Hertz, cylinder on a flat)
# Writes out/<stem>/summary.json, out/<stem>/vtk/<stem>.pvd (open the .pvd in
# ParaView; "Warp By Vector" on displacement shows the deformation) and, for
# a scene with contact, out/<stem>/tractions.png (normal and tangential
# tractions over the contactor at each increment, in the scene's units, with
# Hertz's pressure on a Hertz scene and no panel of round-off: see
# scripts/traction_plots.py).
set -euo pipefail
cd "$(dirname "$0")/.."

scene="${1:-scenes/hertz_plane_strain.toml}"
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

.venv/bin/python - "$out/summary.json" "$scene" <<'PY'
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
pairs = list(steps[0]["pairs"]) if steps else []
for p in pairs:
    print()
    print(f"contact pair {p}:")
    print(f"{'time':>8} {'Fx':>13} {'Fy':>13} {'Fn':>13} {'Ft':>13} {'stick':>5} {'slip':>5} {'open':>5}")
    for st in steps:
        r = st["pairs"][p]
        print(f"{st['time']:8.4g} {num(r['Fx'])} {num(r['Fy'])} {num(r['Fn'])} {num(r['Ft'])} "
              f"{r['n_stick'] if r['n_stick'] is not None else '-':>5} "
              f"{r['n_slip'] if r['n_slip'] is not None else '-':>5} "
              f"{r['n_open'] if r['n_open'] is not None else '-':>5}")
if pairs:
    import os

    sys.path.insert(0, "scripts")
    import traction_plots as tp

    scene = tp.load_scene(sys.argv[2])
    units = tp.scene_units(scene)
    plans = [tp.plan(p, tp.summary_snapshots(s, p), units, tp.hertz_reference(scene, p)) for p in pairs]
    png = tp.draw(plans, os.path.join(os.path.dirname(sys.argv[1]), "tractions.png"))
    print()
    for p, pl in zip(pairs, plans):
        for c in (c for panel in pl.panels for c in panel.curves if c.analytic_of):
            print(f"{p}: {c.label}")
        for d in pl.dropped:
            print(f"{p}: {d}")
    print(f"plot: {png}")
PY
echo
echo "summary: $out/summary.json"
echo "ParaView: $out/vtk/$stem.pvd"
exit "$status"
