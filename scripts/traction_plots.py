"""Traction plots of a contact pair: tn and tt over the contactor's current
x at a few times, with the scene's units, Hertz's pressure where the scene is
a Hertz problem, and no panel of round-off.

`plan()` makes every decision (panels, labels, analytic curves, what is
dropped and why) from plain data; `draw()` only draws a plan. Used by
scripts/run_scene.sh (from the summary of `contact2d run`) and
scripts/fmu_demo.py (from the FMU's outputs); tests/python/test_traction_plots.py
tests the decisions.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

# A panel whose values are all below NOISE times the largest traction of the
# plot is not data: the solver resolves forces to its force tolerance (1e-8
# of the force scale by default) and a frictionless pair's tt is round-off
# (1e-15 of tn in the Hertz scene).
NOISE = 1e-8

# Stress unit of force / length^2 (the scene's [units]; docs/scenes.md).
STRESS = {("N", "mm"): "MPa", ("N", "m"): "Pa", ("kN", "m"): "kPa", ("kN", "mm"): "GPa"}


@dataclass
class Units:
    length: str = "m"
    force: str = "N"

    @property
    def stress(self) -> str:
        return STRESS.get((self.force, self.length), f"{self.force}/{self.length}²")


def load_scene(path) -> dict:
    with open(path, "rb") as f:
        return tomllib.load(f)


def scene_units(scene: dict) -> Units:
    """The scene's [units] table, with its documented defaults (m, N)."""
    u = scene.get("units", {})
    return Units(length=u.get("length", "m"), force=u.get("force", "N"))


@dataclass
class Hertz:
    """Hertz's frictionless contact of a cylinder (plane strain) or sphere
    (axisymmetric) of radius R on a rigid flat: p(x) = p0 sqrt(1 - x²/a²)
    about the center's x, from the load P = factor * Fn."""

    kind: str  # "plane_strain" or "axisymmetric"
    radius: float
    e_star: float  # E / (1 - nu²)
    center_x: float
    # P (per unit length in plane strain; the total in axisymmetry) per
    # pair Fn: 2 / thickness for the quarter cylinder, 1 / thickness for
    # the half; 1 for the quarter meridian section of a sphere.
    factor: float

    def contact(self, fn: float) -> tuple[float, float]:
        """Half-width (radius) a and peak pressure p0 under the pair force fn."""
        p = self.factor * fn
        if p <= 0:
            return 0.0, 0.0
        if self.kind == "plane_strain":
            a = math.sqrt(4 * p * self.radius / (math.pi * self.e_star))
            return a, 2 * p / (math.pi * a)
        a = (3 * p * self.radius / (4 * self.e_star)) ** (1 / 3)
        return a, 3 * p / (2 * math.pi * a * a)

    def pressure(self, fn: float, xs) -> list[float]:
        a, p0 = self.contact(fn)
        if a == 0:
            return [0.0 for _ in xs]
        return [p0 * math.sqrt(max(0.0, 1 - ((x - self.center_x) / a) ** 2)) for x in xs]


def _named(entries, name):
    return next((e for e in entries if e.get("name") == name), None)


def _number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def hertz_reference(scene: dict, pair: str) -> Hertz | None:
    """Hertz's solution for `pair` when the scene is a Hertz problem: a
    frictionless pair between the arc of a `disk` body of linear elastic
    material and a straight rigid target, plane strain or axisymmetric,
    small strain, every number written out (no parameter expression)."""
    analysis = scene.get("analysis", {})
    kind = analysis.get("kind")
    if kind not in ("plane_strain", "axisymmetric") or analysis.get("kinematics", "small_strain") != "small_strain":
        return None
    contact = _named(scene.get("contact", []), pair)
    if contact is None or contact.get("mu_s", 0.0) != 0.0:
        return None
    body_name, _, set_name = str(contact.get("contactor", "")).partition(".")
    body = _named(scene.get("body", []), body_name)
    rigid = _named(scene.get("rigid", []), contact.get("target"))
    if body is None or rigid is None or set_name != "arc":
        return None
    mesh = body.get("mesh", {})
    if mesh.get("generator") != "disk":
        return None
    half = mesh.get("half", False)
    material = _named(scene.get("material", []), body.get("material"))
    if material is None or material.get("model") != "linear_elastic":
        return None
    e, nu, radius, center = material.get("E"), material.get("nu"), mesh.get("radius"), mesh.get("center")
    thickness = analysis.get("thickness", 1.0)
    if not all(_number(v) for v in (e, nu, radius, thickness)) or not all(_number(c) for c in center or [None]):
        return None
    points = rigid.get("points", [])
    if len(points) < 2 or any(not _number(c) for p in points for c in p):
        return None
    (x0, y0), (x1, y1) = points[0], points[-1]
    straight = all(abs((x1 - x0) * (p[1] - y0) - (y1 - y0) * (p[0] - x0)) <= 1e-12 * math.hypot(x1 - x0, y1 - y0) ** 2 for p in points)
    if not straight or "theta" in rigid:
        return None
    if kind == "axisymmetric":
        if half:
            return None
        factor = 1.0
    else:
        factor = (1.0 if half else 2.0) / thickness
    return Hertz(kind=kind, radius=radius, e_star=e / (1 - nu * nu), center_x=center[0], factor=factor)


@dataclass
class Snapshot:
    """The pair at one time: contactor nodes' current x, tn, tt, state,
    and the pair's Fn."""

    label: str
    x: list
    tn: list
    tt: list
    state: list
    fn: float


@dataclass
class Curve:
    label: str
    x: list
    y: list
    # An analytic curve names the snapshot (its label) it belongs to.
    analytic_of: str | None = None


@dataclass
class Panel:
    key: str  # "tn" or "tt"
    title: str
    ylabel: str
    curves: list = field(default_factory=list)


@dataclass
class Plan:
    xlabel: str
    panels: list
    # Why a panel is not drawn (shown under the figure's title).
    dropped: list = field(default_factory=list)


def _window(s: Snapshot):
    """The contact zone and one node either side; None when all is open."""
    closed = [k for k, st in enumerate(s.state) if st != 0]
    if not closed:
        return None
    return max(min(closed) - 1, 0), min(max(closed) + 2, len(s.x))


def plan(pair: str, snapshots: list, units: Units, hertz: Hertz | None = None) -> Plan:
    """Panels tn and tt with a curve per snapshot in contact, Hertz's
    pressure beside each tn curve when there is a Hertz reference, and any
    panel whose values are all round-off (below NOISE of the largest
    traction plotted) dropped with the reason."""
    shown = [(s, w) for s in snapshots if (w := _window(s)) is not None]
    stress = units.stress
    panels = {
        "tn": Panel("tn", f"{pair}: normal traction tn (compression > 0)", f"tn ({stress})"),
        "tt": Panel("tt", f"{pair}: tangential traction tt", f"tt ({stress})"),
    }
    for s, (lo, hi) in shown:
        xs = s.x[lo:hi]
        panels["tn"].curves.append(Curve(s.label, xs, s.tn[lo:hi]))
        panels["tt"].curves.append(Curve(s.label, xs, s.tt[lo:hi]))
        if hertz is not None:
            a, p0 = hertz.contact(s.fn)
            n = 200
            grid = [xs[0] + (xs[-1] - xs[0]) * i / (n - 1) for i in range(n)]
            label = f"Hertz, {s.label}: a = {a:.4g} {units.length}, p0 = {p0:.4g} {stress}"
            panels["tn"].curves.append(Curve(label, grid, hertz.pressure(s.fn, grid), analytic_of=s.label))
    largest = {
        k: max((abs(v) for c in p.curves if c.analytic_of is None for v in c.y), default=0.0)
        for k, p in panels.items()
    }
    scale = max(largest.values())
    kept, dropped = [], []
    for k, p in panels.items():
        if shown and largest[k] <= NOISE * scale:
            dropped.append(
                f"{k} not plotted: every |{k}| <= {largest[k]:.1e} {stress}, below {NOISE:g} of the largest traction ({scale:.3g} {stress}): round-off, not data"
            )
        else:
            kept.append(p)
    return Plan(xlabel=f"x, current ({units.length})", panels=kept, dropped=dropped)


def draw(plans: list, png) -> Path:
    """Draws plans into png, one row of panels each."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    cols = max([len(p.panels) for p in plans] + [1])
    fig, axes = plt.subplots(len(plans), cols, figsize=(5.5 * cols, 4.4 * len(plans)), squeeze=False)
    import textwrap

    notes = [line for p in plans for d in p.dropped for line in textwrap.wrap(d, 100)]
    for row, p in zip(axes, plans):
        for ax in row[len(p.panels) :]:
            ax.set_visible(False)
        for ax, panel in zip(row, p.panels):
            colors = {}
            for c in panel.curves:
                if c.analytic_of is not None:
                    # Hertz's curve in its snapshot's color, dashed.
                    ax.plot(c.x, c.y, "--", color=colors.get(c.analytic_of), lw=1, label=c.label)
                else:
                    (line,) = ax.plot(c.x, c.y, ".-", label=c.label)
                    colors[c.label] = line.get_color()
            ax.set_title(panel.title, fontsize=10)
            ax.set_xlabel(p.xlabel)
            ax.set_ylabel(panel.ylabel)
            ax.grid(True)
            if panel.curves:
                ax.legend(fontsize=6)
    if notes:
        fig.text(0.5, 0.005, "\n".join(notes), ha="center", va="bottom", fontsize=7)
        fig.tight_layout(rect=(0, min(0.035 * len(notes) / len(plans), 0.3), 1, 1))
    else:
        fig.tight_layout()
    png = Path(png)
    png.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(png, dpi=110)
    plt.close(fig)
    return png


def summary_snapshots(summary: dict, pair: str) -> list:
    """One snapshot per converged step of a `contact2d run` summary."""
    out = []
    for st in summary["steps"]:
        if not st["converged"]:
            continue
        r = st["pairs"][pair]
        n = r["nodes"]
        out.append(Snapshot(f"t = {st['time']:g}", n["x"], n["tn"], n["tt"], n["state"], r["Fn"]))
    return out
