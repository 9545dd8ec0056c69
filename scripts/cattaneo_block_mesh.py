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

Usage: python3 scripts/cattaneo_block_mesh.py > scenes/verification/meshes/cattaneo_block.msh
"""

import math
import sys

# The cylinder's disk generator (must match the scene's [[body]] "cylinder").
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


def core_arc_x():
    """x of the arc nodes of the core, from the contact point outward."""
    log_q = math.log(RATIO) / (DIVISIONS - 1)
    along_top = min(max(2 * round((math.pi / 4) / log_q), 2), DIVISIONS)
    m_arc = along_top - along_top // 2
    t = graded(DIVISIONS, RATIO)
    return [RADIUS * math.sin(s) for s in t[: m_arc + 1]]


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
    core = core_arc_x()
    right = core + grow(core[-1], (core[-1] - core[-2]) * GROWTH, 0.5 * WIDTH)[1:]
    xs = [-x for x in reversed(right[1:])] + right
    # Downward: the core spacings first (square elements under the contact
    # zone), then growing.
    depth = core + grow(core[-1], (core[-1] - core[-2]) * GROWTH, DEPTH)[1:]
    ys = [-y for y in reversed(depth)]
    nx, ny = len(xs), len(ys)

    def tag(i, j):
        return j * nx + i + 1

    quads = []
    for j in range(ny - 1):
        for i in range(nx - 1):
            quads.append((tag(i, j), tag(i + 1, j), tag(i + 1, j + 1), tag(i, j + 1)))
    top = [(tag(i + 1, ny - 1), tag(i, ny - 1)) for i in range(nx - 1)]
    bottom = [(tag(i, 0), tag(i + 1, 0)) for i in range(nx - 1)]

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
    n = nx * ny
    w(f"$Nodes\n1 {n} 1 {n}\n2 1 0 {n}\n")
    for k in range(n):
        w(f"{k + 1}\n")
    for j in range(ny):
        for i in range(nx):
            w(f"{xs[i]!r} {ys[j]!r} 0\n")
    w("$EndNodes\n")
    ne = len(top) + len(bottom) + len(quads)
    w(f"$Elements\n3 {ne} 1 {ne}\n")
    e = 1
    for dim, entity, kind, items in ((1, 1, 1, top), (1, 2, 1, bottom), (2, 1, 3, quads)):
        w(f"{dim} {entity} {kind} {len(items)}\n")
        for item in items:
            w(f"{e} {' '.join(str(v) for v in item)}\n")
            e += 1
    w("$EndElements\n")


if __name__ == "__main__":
    main()
