"""The decisions of the traction plots (scripts/traction_plots.py, used by
scripts/run_scene.sh and scripts/fmu_demo.py): units from the scene, Hertz's
pressure where the scene is a Hertz problem (and not elsewhere), and a
panel of round-off dropped with its reason."""

import copy
import math
import sys

import pytest

from conftest import REPO

sys.path.insert(0, str(REPO / "scripts"))
import traction_plots as tp  # noqa: E402

HERTZ = REPO / "scenes" / "hertz_plane_strain.toml"
HERTZ_AXI = REPO / "scenes" / "hertz_axisymmetric.toml"
BLOCK = REPO / "scenes" / "verification" / "sliding_block.toml"


def test_units_from_the_scene():
    assert tp.scene_units(tp.load_scene(HERTZ)) == tp.Units("mm", "N")
    assert tp.scene_units(tp.load_scene(HERTZ)).stress == "MPa"
    # No [units]: the documented defaults, m and N.
    assert tp.scene_units(tp.load_scene(BLOCK)).stress == "Pa"
    assert tp.Units("m", "kN").stress == "kPa"
    assert tp.Units("mm", "kN").stress == "GPa"


def test_hertz_cylinder_from_the_scene():
    h = tp.hertz_reference(tp.load_scene(HERTZ), "contact")
    assert h is not None and h.kind == "plane_strain"
    assert (h.radius, h.center_x) == (10.0, 0.0)
    assert h.e_star == pytest.approx(200000.0 / (1 - 0.3**2))
    # A quarter cylinder: the pair carries half the load.
    assert h.factor == 2.0
    # The scene's own comment: P = 6582 gives a = 0.6175, p0 = 6786.
    a, p0 = h.contact(6582.0 / 2)
    assert a == pytest.approx(0.6175, abs=5e-4) and p0 == pytest.approx(6786, abs=1)
    assert h.pressure(6582.0 / 2, [0.0, a / 2, a, 2 * a]) == pytest.approx([p0, p0 * math.sqrt(0.75), 0.0, 0.0])


def test_hertz_sphere_from_the_scene():
    h = tp.hertz_reference(tp.load_scene(HERTZ_AXI), "contact")
    assert h is not None and h.kind == "axisymmetric" and h.factor == 1.0
    # The scene's comment: P = 23625 gives a = 2.005, p0 = 2806.
    a, p0 = h.contact(23625.0)
    assert a == pytest.approx(2.005, abs=5e-4) and p0 == pytest.approx(2806, abs=1)


def changed(scene, edit):
    s = copy.deepcopy(scene)
    edit(s)
    return s


@pytest.mark.parametrize(
    "edit",
    [
        lambda s: s["contact"][0].update(mu_s=0.2),  # friction
        lambda s: s["material"][0].update(model="von_mises"),
        lambda s: s["analysis"].update(kinematics="total_lagrangian"),
        lambda s: s["analysis"].update(kind="plane_stress"),
        lambda s: s["rigid"][0].update(points=[[12.0, 0.0], [5.0, 0.0], [-2.0, 1.0]]),  # not flat
        lambda s: s["rigid"][0].update(theta=0.1),
        lambda s: s["body"][0]["mesh"].update(generator="rectangle"),
        lambda s: s["material"][0].update(E="= stiffness"),  # a parameter expression
    ],
)
def test_no_hertz_curve_off_hertz_problems(edit):
    scene = tp.load_scene(HERTZ)
    assert tp.hertz_reference(scene, "contact") is not None
    assert tp.hertz_reference(changed(scene, edit), "contact") is None


def test_no_hertz_curve_for_the_sliding_block():
    assert tp.hertz_reference(tp.load_scene(BLOCK), "base") is None


def hertz_snapshots(h, loads, tt):
    """Contactor nodes 0.05 apart from the center, open beyond a, with
    Hertz's tn and the given tt."""
    out = []
    for fn in loads:
        a, _ = h.contact(fn)
        x = [0.05 * k for k in range(30)]
        tn = h.pressure(fn, x)
        state = [2 if v > 0 else 0 for v in tn]
        out.append(tp.Snapshot(f"Fn = {fn:g}", x, tn, [tt(v) for v in tn], state, fn))
    return out


def test_plan_of_a_frictionless_hertz_run():
    scene = tp.load_scene(HERTZ)
    h = tp.hertz_reference(scene, "contact")
    snaps = hertz_snapshots(h, [1000.0, 3000.0], tt=lambda v: 1e-11 * (1 if v > 3000 else -1))
    p = tp.plan("contact", snaps, tp.scene_units(scene), h)
    # The round-off panel is dropped, and says why.
    assert [panel.key for panel in p.panels] == ["tn"]
    assert len(p.dropped) == 1 and p.dropped[0].startswith("tt not plotted") and "round-off" in p.dropped[0]
    tn = p.panels[0]
    assert tn.ylabel == "tn (MPa)" and p.xlabel == "x, current (mm)"
    data = [c for c in tn.curves if c.analytic_of is None]
    analytic = [c for c in tn.curves if c.analytic_of is not None]
    assert [c.label for c in data] == ["Fn = 1000", "Fn = 3000"]
    assert [c.analytic_of for c in analytic] == ["Fn = 1000", "Fn = 3000"]
    for snap, curve in zip(snaps, analytic):
        a, p0 = h.contact(snap.fn)
        assert f"a = {a:.4g} mm" in curve.label and f"p0 = {p0:.4g} MPa" in curve.label
        # Over the plotted window, from the center (p0) out past a (0).
        assert curve.y[0] == pytest.approx(p0) and curve.y[-1] == 0.0
        for x, y in zip(curve.x, curve.y):
            assert y == pytest.approx(p0 * math.sqrt(max(0.0, 1 - x * x / (a * a))), abs=1e-9 * p0)


def test_plan_keeps_a_friction_panel():
    scene = tp.load_scene(HERTZ)
    h = tp.hertz_reference(scene, "contact")
    snaps = hertz_snapshots(h, [2000.0], tt=lambda v: -0.2 * v)
    p = tp.plan("contact", snaps, tp.scene_units(scene), h)
    assert [panel.key for panel in p.panels] == ["tn", "tt"] and p.dropped == []
    # Hertz's curve belongs with tn only.
    assert all(c.analytic_of is None for c in p.panels[1].curves)
    # Without a Hertz reference, data only.
    p = tp.plan("contact", snaps, tp.scene_units(scene), None)
    assert all(c.analytic_of is None for panel in p.panels for c in panel.curves)


def test_plan_of_an_open_pair_draws_nothing_and_drops_nothing():
    snap = tp.Snapshot("t = 0", [0.0, 1.0], [0.0, 0.0], [0.0, 0.0], [0, 0], 0.0)
    p = tp.plan("base", [snap], tp.Units(), None)
    assert p.dropped == [] and all(panel.curves == [] for panel in p.panels)


def test_solved_hertz_scene_against_its_curve(cli_summary, tmp_path):
    """End to end: the command line's Hertz run against the analytic curve
    the plot draws for it, and the plot is written. The plot's x is the
    nodes' current x, which the surface's lateral displacement has moved
    outward from the reference x of Hertz's linear theory (tests/contact_hertz.rs
    finds 0.42 % of p0 over reference x): 1.3 % RMS over the contact zone."""
    scene = tp.load_scene(HERTZ)
    summary = cli_summary(HERTZ)
    h = tp.hertz_reference(scene, "contact")
    p = tp.plan("contact", tp.summary_snapshots(summary, "contact"), tp.scene_units(scene), h)
    assert [panel.key for panel in p.panels] == ["tn"] and len(p.dropped) == 1
    last = summary["steps"][-1]["pairs"]["contact"]
    a, p0 = h.contact(last["Fn"])
    nodes = last["nodes"]
    inside = [(x, tn) for x, tn in zip(nodes["x"], nodes["tn"]) if x < a]
    assert len(inside) > 10
    errors = [tn - h.pressure(last["Fn"], [x])[0] for x, tn in inside]
    assert math.sqrt(sum(e * e for e in errors) / len(errors)) < 0.02 * p0
    assert abs(errors[0]) < 0.005 * p0  # the peak, at the center
    png = tp.draw([p], tmp_path / "tractions.png")
    assert png.stat().st_size > 10_000
