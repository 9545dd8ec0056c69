#!/usr/bin/env python3
"""Compares two sets of run summaries (`contact2d run --summary`) scene by
scene, as issue 32 asks of a change that must not move results: the same
increments, iterations, bisections and node states, and every force and
length within REL (default 1e-9) of the scene's largest value.

    python3 scripts/compare_runs.py OLD_DIR NEW_DIR [--rel 1e-9]

Each DIR holds one `<scene>.json` per scene (scripts/scene_outputs.sh makes
them). Prints one line per scene (its largest relative change) and exits 1
if any scene differs beyond REL or in a count or state."""
import json
import math
import sys
from pathlib import Path

COUNTS = {"iterations", "substeps", "converged", "n_open", "n_stick", "n_slip", "neqc", "state"}
SKIP = {"wall_s", "build", "scene", "title"}


def walk(a, b, path, out):
    """Appends (path, old, new, kind) for each leaf; kind 'count' must match."""
    if isinstance(a, dict) and isinstance(b, dict):
        if set(a) != set(b):
            out.append((path, sorted(a), sorted(b), "keys"))
            return
        for k in a:
            if k not in SKIP:
                walk(a[k], b[k], f"{path}.{k}", out)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            out.append((path, len(a), len(b), "length"))
            return
        for i, (x, y) in enumerate(zip(a, b)):
            walk(x, y, f"{path}[{i}]", out)
    else:
        key = path.rsplit(".", 1)[-1].split("[")[0]
        kind = "count" if key in COUNTS or not isinstance(a, (int, float)) or isinstance(a, bool) else "value"
        out.append((path, a, b, kind))


def largest(leaves):
    m = 0.0
    for _, a, _, kind in leaves:
        if kind == "value" and a is not None and math.isfinite(a):
            m = max(m, abs(a))
    return m


def compare(old, new, rel):
    leaves = []
    walk(old, new, "", leaves)
    scale = largest(leaves) or 1.0
    worst, bad = 0.0, []
    for path, a, b, kind in leaves:
        if kind == "value":
            if a is None or b is None or not (math.isfinite(a) and math.isfinite(b)):
                if not (a == b or (a is not None and b is not None and math.isnan(a) and math.isnan(b))):
                    bad.append((path, a, b))
                continue
            d = abs(a - b) / scale
            worst = max(worst, d)
            if d > rel:
                bad.append((path, a, b))
        elif a != b:
            bad.append((path, a, b))
    return worst, scale, bad


def main():
    args = sys.argv[1:]
    rel = 1e-9
    if "--rel" in args:
        i = args.index("--rel")
        rel = float(args[i + 1])
        del args[i : i + 2]
    old_dir, new_dir = map(Path, args)
    failed = 0
    for old_file in sorted(old_dir.glob("*.json")):
        new_file = new_dir / old_file.name
        if not new_file.exists():
            print(f"{old_file.stem}: missing in {new_dir}")
            failed += 1
            continue
        worst, scale, bad = compare(json.load(open(old_file)), json.load(open(new_file)), rel)
        status = "ok" if not bad else f"DIFFERS ({len(bad)} entries)"
        print(f"{old_file.stem:40s} largest change {worst:.2e} of {scale:.4g}  {status}")
        for path, a, b in bad[:5]:
            print(f"    {path}: {a} -> {b}")
        failed += bool(bad)
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
