#!/usr/bin/env python3
"""Write the block mesh of scenes/verification/cattaneo_mindlin.toml.

A Gmsh 4.1 ASCII file of 4-node quadrilaterals on a tensor grid over
[-W/2, W/2] x [-D, 0], with physical groups "block" (the elements), "top"
and "bottom" (edges). Within the disk generator's core block (the first
m_arc elements on either side of the contact point) the top nodes sit at
the x of the cylinder's arc nodes, so that in the contact zone every
contactor node lands on a target node: node-to-segment contact between
matching meshes. Outside the core, and downward, the spacing grows
geometrically.

The arc nodes are those of `disk` in src/mesh/generators.rs: along the arc
from the contact point, at the arc lengths R * t_k of the geometric grading
t_k = (q^k - 1) / (q^n - 1), q = ratio^(1 / (n - 1)), for k up to
m_arc = along_top - along_top / 2, along_top = 2 round((pi / 4) / ln q)
(clamped to 2..n). tests/contact_cattaneo.rs checks the match.

Usage: python3 scripts/cattaneo_block_mesh.py [--q8] [--divisions N] > FILE.msh

  (no options)     scenes/verification/meshes/cattaneo_block.msh
  --divisions 120  tests/data/cattaneo_block_120.msh, for the cylinder with
                   divisions = 120 (the refined run of tests/contact_cattaneo.rs)
  --q8             8-node quadrilaterals, the top's mid-side nodes matching
                   those of a q8 cylinder
"""

import argparse
import math
import sys

# The cylinder's disk generator (must match the scene's [[body]] "cylinder";
# --divisions overrides DIVISIONS).
RADIUS = 20.0
DIVISIONS = 80
RATIO = 20.0
# The block.
WIDTH = 40.0
DEPTH = 20.0
GROWTH = 1.15


def graded(n, ratio):
    log_q = math.log(ratio) / (n - 1)
    total = math.expm1(n * log_q)
    return [math.expm1(k * log_q) / total for k in range(n + 1)]


def fine(t):
    """The positions with their midpoints inserted (8-node lattices)."""
    out = []
    for a, b in zip(t, t[1:]):
        out += [a, 0.5 * (a + b)]
    return out + [t[-1]]


def core_arc_x(q8, divisions):
    """x of the arc nodes of the core, from the contact point outward; with
    q8, mid-side nodes included (at the middle of each arc, in arc length)."""
    log_q = math.log(RATIO) / (divisions - 1)
    along_top = min(max(2 * round((math.pi / 4) / log_q), 2), divisions)
    m_arc = along_top - along_top // 2
    t = graded(divisions, RATIO)[: m_arc + 1]
    return [RADIUS * math.sin(s) for s in (fine(t) if q8 else t)]


def grow(start, first, end):
    """Points from `start` toward `end` (> start), the spacing growing from
    `first` by GROWTH; the last interval is stretched to end exactly."""
    pts = [start]
    h = first
    while pts[-1] + h * (1.0 + GROWTH) < end:
        pts.append(pts[-1] + h)
        h *= GROWTH
    pts.append(end)
    return pts


def main():
    parser = argparse.ArgumentParser(description="Write the Cattaneo-Mindlin block mesh.")
    parser.add_argument("--q8", action="store_true", help="8-node quadrilaterals")
    parser.add_argument("--divisions", type=int, default=DIVISIONS, help="the disk's divisions")
    args = parser.parse_args()
    q8 = args.q8
    core = core_arc_x(False, args.divisions)
    right = core + grow(core[-1], (core[-1] - core[-2]) * GROWTH, 0.5 * WIDTH)[1:]
    xs = [-x for x in reversed(right[1:])] + right
    # Downward: the core spacings first (square elements under the contact
    # zone), then growing.
    depth = core + grow(core[-1], (core[-1] - core[-2]) * GROWTH, DEPTH)[1:]
    ys = [-y for y in reversed(depth)]
    if q8:
        # Mid-side nodes: on the arc's in the core, at the middle elsewhere.
        core8 = core_arc_x(True, args.divisions)
        m = len(core) - 1
        right8 = core8 + fine(right[m:])[1:]
        xs = [-x for x in reversed(right8[1:])] + right8
        ys = fine(ys)
    nx, ny = len(xs), len(ys)
    step = 2 if q8 else 1

    def tag(i, j):
        return j * nx + i + 1

    def used(i, j):
        return not (q8 and i % 2 == 1 and j % 2 == 1)

    quads = []
    for j in range(0, ny - 1, step):
        for i in range(0, nx - 1, step):
            e = [tag(i, j), tag(i + step, j), tag(i + step, j + step), tag(i, j + step)]
            if q8:
                e += [tag(i + 1, j), tag(i + 2, j + 1), tag(i + 1, j + 2), tag(i, j + 1)]
            quads.append(tuple(e))
    top, bottom = [], []
    for i in range(0, nx - 1, step):
        mid = [tag(i + 1, ny - 1)] if q8 else []
        top.append((tag(i + step, ny - 1), tag(i, ny - 1), *mid))
        mid = [tag(i + 1, 0)] if q8 else []
        bottom.append((tag(i, 0), tag(i + step, 0), *mid))

    out = sys.stdout
    w = out.write
    w("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n")
    w('$PhysicalNames\n3\n1 1 "top"\n1 2 "bottom"\n2 3 "block"\n$EndPhysicalNames\n')
    x0, x1, y0 = xs[0], xs[-1], ys[0]
    w("$Entities\n0 2 1 0\n")
    w(f"1 {x0} 0 0 {x1} 0 0 1 1 0\n")
    w(f"2 {x0} {y0} 0 {x1} {y0} 0 1 2 0\n")
    w(f"1 {x0} {y0} 0 {x1} 0 0 1 3 2 1 2\n")
    w("$EndEntities\n")
    nodes = [(i, j) for j in range(ny) for i in range(nx) if used(i, j)]
    n = len(nodes)
    w(f"$Nodes\n1 {n} 1 {nx * ny}\n2 1 0 {n}\n")
    for i, j in nodes:
        w(f"{tag(i, j)}\n")
    for i, j in nodes:
        w(f"{xs[i]!r} {ys[j]!r} 0\n")
    w("$EndNodes\n")
    ne = len(top) + len(bottom) + len(quads)
    w(f"$Elements\n3 {ne} 1 {ne}\n")
    e = 1
    line, quad = (8, 16) if q8 else (1, 3)
    for dim, entity, kind, items in ((1, 1, line, top), (1, 2, line, bottom), (2, 1, quad, quads)):
        w(f"{dim} {entity} {kind} {len(items)}\n")
        for item in items:
            w(f"{e} {' '.join(str(v) for v in item)}\n")
            e += 1
    w("$EndElements\n")


if __name__ == "__main__":
    main()
