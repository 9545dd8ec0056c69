"""The snapped wire of the paper's Section 4.3 (scenes/wire_winding.toml) as
a figure: the axial stress just below the contact surface and through the
layer against the friction shear-lag estimate, and the interface tractions
with the stick and slip zones, after each of the two snap steps.

    figure(binary, out_dir, work_dir) -> list of printable result lines

runs the scene with the command line (summary and VTK output), reads the
element stresses from the .vtu files and writes out_dir/wire_winding.png.
"""

import xml.etree.ElementTree as ET
import sys
from pathlib import Path

# The sibling modules, also when this file runs on its own.
if str(Path(__file__).resolve().parents[1]) not in sys.path:
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from paper import cli  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
SCENE = REPO / "scenes" / "wire_winding.toml"
# The scene's intact wound state, layer thickness and friction coefficient.
SIGMA0, P, H, MU = 750.0, 300.0, 1.0, 0.1
STICK, SLIP = 1, 2


def read_vtu(path):
    """Element centres (reference) and element-average stresses [xx, yy, zz, xy]."""
    arrays = {}
    for a in ET.parse(path).getroot().iter("DataArray"):
        arrays[a.get("Name")] = [float(v) for v in a.text.split()]
    pts = arrays["Points"]
    conn = [int(v) for v in arrays["connectivity"]]
    offsets = [int(v) for v in arrays["offsets"]]
    s = arrays["stress"]
    centres, stresses, start = [], [], 0
    for e, end in enumerate(offsets):
        nodes = conn[start:end]
        start = end
        centres.append(
            (
                sum(pts[3 * n] for n in nodes) / len(nodes),
                sum(pts[3 * n + 1] for n in nodes) / len(nodes),
            )
        )
        stresses.append(s[4 * e : 4 * e + 4])
    return centres, stresses


def columns(centres, stresses):
    """Per column of elements along x: x, thickness-mean sigma_xx, and the
    stress [xx, yy, zz, xy] of the element on the interface (just below the
    contact surface)."""
    cols = {}
    for (x, y), s in zip(centres, stresses):
        cols.setdefault(round(x, 9), []).append((y, s))
    out = []
    for x in sorted(cols):
        v = sorted(cols[x], key=lambda c: c[0])
        out.append((x, sum(c[1][0] for c in v) / len(v), v[0][1]))
    return out


def shear_lag(x, released):
    """sigma_xx rises by mu p / h per unit length from what the break left."""
    return SIGMA0 - released + min(MU * P * x / H, released)


def figure(binary, out_dir, work_dir):
    work_dir = Path(work_dir)
    out_dir = Path(out_dir)
    vtk = work_dir / "wire_winding_vtk"
    summary, wall = cli.run(binary, SCENE, work_dir / "wire_winding.json", "--vtk", vtk)
    steps = summary["steps"]

    fig, (ax_s, ax_b, ax_t) = plt.subplots(3, 1, figsize=(8, 10), sharex=True)
    lines = [
        f"wire winding: {len(steps)} increments, {summary['dofs']} unknowns, "
        f"run {wall:.2f} s (solve {summary['wall_s']:.3f} s)"
    ]
    colours = {2.0: "tab:orange", 3.0: "tab:blue"}
    for i, released in ((1, SIGMA0 / 2), (2, SIGMA0)):
        step = steps[i]
        t = step["time"]
        c = colours[t]
        cols = columns(*read_vtu(vtk / f"wire_winding_{i + 1:04d}.vtu"))
        xs = [x for x, _, _ in cols]
        ax_s.plot(xs, [m for _, m, _ in cols], "o", ms=3, color=c, label=f"t = {t:g}: thickness mean")
        ax_s.plot(xs, [b[0] for _, _, b in cols], "-", lw=1, color=c, label=f"t = {t:g}: just below the contact surface")
        ax_b.plot(xs, [b[1] for _, _, b in cols], "-", color=c, label=f"t = {t:g}: sigma_yy")
        ax_b.plot(xs, [b[3] for _, _, b in cols], "--", color=c, label=f"t = {t:g}: tau_xy")
        ax_s.plot(xs, [shear_lag(x, released) for x in xs], "k--", lw=0.8)

        nodes = step["pairs"]["interface"]["nodes"]
        order = sorted(range(len(nodes["x"])), key=lambda k: nodes["x"][k])
        x = [nodes["x"][k] for k in order]
        tn = [nodes["tn"][k] for k in order]
        tt = [nodes["tt"][k] for k in order]
        state = [nodes["state"][k] for k in order]
        ax_t.plot(x, [-v for v in tt], "-", color=c, label=f"t = {t:g}: -t_t")
        ax_t.plot(x, [MU * v for v in tn], ":", color=c, label=f"t = {t:g}: mu t_n")
        slip = [xx for xx, s in zip(x, state) if s == SLIP]
        stick = [xx for xx, s in zip(x, state) if s == STICK]
        level = 36.0 if t == 3.0 else 34.0
        ax_t.plot(slip, [level] * len(slip), "|", color=c, ms=8)
        ax_t.plot(stick, [level] * len(stick), ".", color=c, ms=3)
        end = max(slip) if slip else 0.0
        recovery = released * H / (MU * P)
        inner = [(xx, m) for xx, m, _ in cols if 2 * H < xx < recovery - 2 * H]
        n = len(inner)
        mx = sum(p[0] for p in inner) / n
        my = sum(p[1] for p in inner) / n
        slope = sum((p[0] - mx) * (p[1] - my) for p in inner) / sum((p[0] - mx) ** 2 for p in inner)
        reached = (SIGMA0 - (my - slope * mx)) / slope
        worst = max(
            abs(m - shear_lag(xx, released))
            for xx, m, _ in cols
            if xx >= 2 * H and abs(xx - recovery) >= 2 * H
        )
        lines.append(
            f"  t = {t:g}: slip zone 0 .. {end:.2f} mm ({len(slip)} slip, {len(stick)} stick nodes); "
            f"recovery length {reached:.2f} mm (shear lag {recovery:.2f}); "
            f"build-up {slope:.3f} MPa/mm (mu p / h = {MU * P / H:g}); "
            f"|mean sigma_xx - shear lag| <= {worst:.2f} MPa; {step['iterations']} iterations"
        )
    ax_s.plot([], [], "k--", lw=0.8, label="shear lag: d(sigma_xx h)/dx = mu p")
    ax_s.set_ylabel("sigma_xx (MPa)")
    ax_s.set_title("Snapped wire: axial stress in the layer (h = 1 mm, mu = 0.1, p = 300 MPa)")
    ax_s.legend(fontsize=7, loc="lower right")
    ax_s.grid(alpha=0.3)
    ax_b.set_ylabel("stress (MPa)")
    ax_b.set_title("Just below the contact surface (the interface row of elements, centres at y = h/4)")
    ax_b.legend(fontsize=7, loc="center right", ncol=2)
    ax_b.grid(alpha=0.3)
    ax_t.set_xlabel("x, distance from the break (mm)")
    ax_t.set_ylabel("interface traction (MPa)")
    ax_t.set_title("Interface: tangential traction and mu t_n; zones at the top: | slip, . stick")
    ax_t.set_ylim(0, 40)
    ax_t.legend(fontsize=7, loc="center right")
    ax_t.grid(alpha=0.3)
    fig.tight_layout()
    out_dir.mkdir(parents=True, exist_ok=True)
    png = out_dir / "wire_winding.png"
    fig.savefig(png, dpi=110)
    plt.close(fig)
    lines.append(f"  figure: {png}")
    return lines


if __name__ == "__main__":
    cli.standalone(figure, __doc__.splitlines()[0])
