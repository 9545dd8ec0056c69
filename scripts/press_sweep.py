#!/usr/bin/env python3
"""A frictional press of a block onto a stiffer strip over a grid of
Poisson ratios, friction coefficients and strip meshes, under both
formulations: which presses converge. The scene is the drag family's of
tests/mortar_patch_family.rs (block on a strip three times as long, the
block's top held along the strip and pressed down by a thousandth of
the stack's height, sides free), run for its press only (t = 0.5 and 1), through the CLI.

    python3 scripts/press_sweep.py [BINARY] [--element q4|q8] [--block N]

BINARY defaults to target/release/contact2d. Prints, per formulation and
Poisson ratio, `ok` or `FAIL` for each (mu, strip sides) and the count of
failures; exits 0 (it measures, it does not judge)."""
import argparse
import itertools
import subprocess
import tempfile
from pathlib import Path

NUS = [0.3, 0.4, 0.44, 0.48]
MUS = [0.15, 0.194, 0.3]
STRIP_SIDES = [5, 7, 10]


def scene(element, block_sides, strip_sides, nu, mu, formulation):
    """The press: block 0.5 x 1.01 (E 314, nu), strip 1.5 x 0.3 (E 18262,
    nu 0), two elements through each, plane strain, small strain."""
    hb, hs, w = 1.01, 0.3, 0.5
    return f'''title = "press sweep"
[analysis]
kind = "plane_strain"
kinematics = "small_strain"
[[material]]
name = "block"
model = "linear_elastic"
E = 314.0
nu = {nu}
[[material]]
name = "strip"
model = "linear_elastic"
E = 18262.0
nu = 0.0
[[body]]
name = "strip"
material = "strip"
element = "{element}"
mesh = {{ generator = "rectangle", origin = [0.0, {-hs}], size = [{3 * w}, {hs}], divisions = [{strip_sides}, 2] }}
[[body]]
name = "block"
material = "block"
element = "{element}"
mesh = {{ generator = "rectangle", origin = [{0.5 * w}, 0.0], size = [{w}, {hb}], divisions = [{block_sides}, 2] }}
[[function]]
name = "press"
points = [[0.0, 0.0], [1.0, 1.0]]
[[driver]]
name = "base"
set = "strip.bottom"
ux = 0.0
uy = 0.0
[[driver]]
name = "top"
set = "block.top"
ux = 0.0
uy = {{ function = "press", scale = {-1e-3 * (hb + hs)} }}
[[contact]]
name = "interface"
contactor = "block.bottom"
target = "strip.top"
mu_s = {mu}
mu_d = {mu}
formulation = "{formulation}"
[steps]
times = [0.5, 1.0]
'''


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("binary", nargs="?", default="target/release/contact2d")
    ap.add_argument("--element", default="q8", choices=["q4", "q8"])
    ap.add_argument("--block", type=int, default=10, help="block sides along the interface")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "press.toml"
        for formulation in ["mortar", "node_to_segment"]:
            failures = 0
            print(f"{formulation} ({args.element}, block {args.block} sides)")
            for nu in NUS:
                cells = []
                for mu, sides in itertools.product(MUS, STRIP_SIDES):
                    path.write_text(scene(args.element, args.block, sides, nu, mu, formulation))
                    run = subprocess.run([args.binary, "run", "-q", str(path)], capture_output=True, text=True)
                    ok = run.returncode == 0
                    failures += not ok
                    cells.append(f"mu {mu}/strip {sides}: {'ok' if ok else 'FAIL'}")
                print(f"  nu {nu}: " + ", ".join(cells))
            print(f"  failures: {failures} of {len(NUS) * len(MUS) * len(STRIP_SIDES)}")


if __name__ == "__main__":
    main()
