"""The FMU (FMI 2.0 co-simulation, issue 4) driven step by step from fmpy's
FMU2Slave: its outputs equal the command line's summary of the same load
path, the Hertz pressure, the stick/slip pattern of a dragged block, rollback
(FMU state get/set/serialize), a discarded step and its retry, and rejected
inputs and parameters with their log messages.

The fixtures (`fmus`, `unpacked`, `cli_summary`, `open_fmu`, `Slave`) are in
conftest.py: every FMU is exported once per session with `contact2d export`.
"""

import math
import shutil

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import fmi2LastSuccessfulTime

from conftest import REPO, SCENES

DISCARD, ERROR = 2, 3

# Round-off agreement between the FMU and the CLI. Both run the same solver
# on the same mesh, but the FMU receives its prescribed displacements as
# numbers computed here (-0.07 * t) while the CLI evaluates its load
# function by interpolation, so the inputs may differ in the last bit; the
# Newton iterations stop at |r|/|r0| between 1e-15 and 1e-9, far below any
# physical difference. 1e-9 relative to the scale of each quantity (forces
# to the largest force, tractions to the largest traction, coordinates to
# the body's size) allows that and nothing more. Integer outputs (states,
# counts, iterations) must be equal.
RTOL = 1e-9


def _close(actual, expected, scale, what):
    np.testing.assert_allclose(
        np.asarray(actual, dtype=float),
        np.asarray(expected, dtype=float),
        rtol=RTOL,
        atol=RTOL * scale,
        err_msg=what,
    )


def assert_matches_summary(slave, step, force_scale, length_scale):
    """Every output of the FMU after a step equals the CLI summary's step."""
    t = step["time"]
    assert step["converged"] is True
    checked = {"solver.iterations", "solver.substeps", "solver.residual"}
    for driver, comps in step["drivers"].items():
        for comp, value in comps.items():
            scale = force_scale * length_scale if comp == "Mz" else force_scale
            _close(slave.real(f"{driver}.{comp}"), value, scale, f"t = {t}: {driver}.{comp}")
            checked.add(f"{driver}.{comp}")
    for pair, res in step["pairs"].items():
        for comp in ("Fx", "Fy", "Fn", "Ft"):
            _close(slave.real(f"{pair}.{comp}"), res[comp], force_scale, f"t = {t}: {pair}.{comp}")
        for comp in ("n_stick", "n_slip", "n_open"):
            assert slave.int(f"{pair}.{comp}") == res[comp], f"t = {t}: {pair}.{comp}"
        for comp in ("stick_length", "slip_length"):
            _close(slave.real(f"{pair}.{comp}"), res[comp], length_scale, f"t = {t}: {pair}.{comp}")
        nodes = res["nodes"]
        assert slave.nodes(pair, "state") == nodes["state"], f"t = {t}: {pair}.state"
        traction_scale = max(1.0, max(abs(v) for v in nodes["tn"]))
        for what in ("tn", "tt"):
            _close(slave.nodes(pair, what), nodes[what], traction_scale, f"t = {t}: {pair}.{what}")
        for what in ("x", "y"):
            _close(slave.nodes(pair, what), nodes[what], length_scale, f"t = {t}: {pair}.{what}")
        checked |= {
            f"{pair}.{c}"
            for c in ("Fx", "Fy", "Fn", "Ft", "n_stick", "n_slip", "n_open", "stick_length", "slip_length")
        }
        checked |= {f"{pair}.{w}[{k}]" for w in nodes for k in range(1, len(nodes[w]) + 1)}
    assert slave.int("solver.iterations") == step["iterations"], f"t = {t}"
    assert slave.int("solver.substeps") == step["substeps"], f"t = {t}"
    # The final residual is itself round-off (1e-15 here): it is only
    # asserted to be converged, below the scene's tolerance (1e-8), on both.
    assert slave.real("solver.residual") <= 1e-8
    assert step["residual"] <= 1e-8
    # Nothing left out: every output variable of the FMU was compared.
    outputs = {n for n, v in slave.vars.items() if v.causality == "output"}
    assert checked == outputs, outputs ^ checked


def write_scene(tmp_path, scene, name, edits):
    """The shipped scene with textual edits (each must apply exactly once)."""
    text = scene.read_text()
    for old, new in edits:
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    path = tmp_path / name
    path.write_text(text)
    return path


# ---------------------------------------------------------------------------
# 1. Hertz: FMU == CLI at every step; the pressure against Hertz's solution.

HERTZ_TIMES = [0.25, 0.5, 0.75, 1.0]
R, E, NU = 10.0, 200000.0, 0.3


def press_uy(t):
    """The scene's own load: press.uy = -0.07 * ramp(t)."""
    return -0.07 * t


def step_hertz(slave, times=HERTZ_TIMES, start=0.0):
    t = start
    for t_next in times:
        slave.set("press.uy", press_uy(t_next))
        slave.fmu.doStep(t, t_next - t)
        t = t_next


def test_hertz_steps_equal_the_cli_summary_and_hertz(open_fmu, cli_summary):
    summary = cli_summary(SCENES["hertz"])
    steps = summary["steps"]
    assert [s["time"] for s in steps] == HERTZ_TIMES
    p_half = steps[-1]["pairs"]["contact"]["Fn"]

    h = open_fmu("hertz").init()
    # At rest before the first step: no force, every contactor node open.
    m = len(h.nodes("contact", "x"))
    assert m == len(steps[0]["pairs"]["contact"]["nodes"]["x"])
    assert h.real("contact.Fn") == 0.0 and h.int("contact.n_open") == m

    t = 0.0
    for step in steps:
        h.set("press.uy", press_uy(step["time"]))
        h.fmu.doStep(t, step["time"] - t)
        t = step["time"]
        assert h.fmu.getRealStatus(fmi2LastSuccessfulTime) == t
        assert_matches_summary(h, step, force_scale=p_half, length_scale=R)
        # Frictionless: no tangential resultant (round-off of the force scale).
        assert abs(h.real("contact.Ft")) <= 1e-9 * p_half
        assert h.real("contact.Fn") > 0.0

    # Hertz at the last step. The quarter model carries P/2 (per unit
    # thickness); tractions are per undeformed area, nodes are numbered from
    # the symmetry axis outwards.
    P = 2.0 * h.real("contact.Fn")
    e_star = E / (1.0 - NU**2)
    a = math.sqrt(4.0 * P * R / (math.pi * e_star))
    p0 = 2.0 * P / (math.pi * a)
    x = np.array(h.nodes("contact", "x"))
    tn = np.array(h.nodes("contact", "tn"))
    state = np.array(h.nodes("contact", "state"))
    closed = state != 0
    assert np.all(np.diff(x) > 0), "nodes ordered along +x"
    last = np.flatnonzero(closed)[-1]
    assert np.all(closed[: last + 1]), "one contact zone from the axis"
    # The computed contact half-width brackets a: the last closed node lies
    # inside it, the first open one outside.
    assert x[last] <= a <= x[last + 1], (x[last], a, x[last + 1])
    assert np.all(tn[~closed] == 0.0)
    # Pressure: RMS error over the closed nodes with x < 0.8 a within 2 % of
    # p0 (0.47 % now). The nodes nearer the edge carry the square-root
    # error of the mesh where p falls like sqrt(a - x); the Rust tests
    # (tests/contact_hertz.rs) hold the finer checks.
    inner = closed & (x < 0.8 * a)
    assert inner.sum() >= 20
    err = tn[inner] - p0 * np.sqrt(1.0 - x[inner] ** 2 / a**2)
    rms = math.sqrt(np.mean(err**2))
    assert rms <= 0.02 * p0, f"RMS {rms / p0:.2%} of p0"


# ---------------------------------------------------------------------------
# 2. Sliding block: stick, slip at mu_d, reversal through stick.

MU_S, MU_D = 0.3, 0.2
NODES = 9
DU = 0.002  # drag increment: the CLI's own (scene t = 1.02, 1.04, ...)
N_DRAG = 10  # up to ux = 0.02, then back to 0 in as many steps


def sliding_path():
    """(time, ux, uy) per FMU step: the press in two steps as the scene does
    (t = 0.5, 1), then +DU per step up to 0.02, then -DU per step to 0.

    Not in one press step: after pressing to -0.01 in one increment, the
    first drag increment (even 3e-5 after six bisections) never converges,
    in the FMU and in the CLI alike (the stick/slip state of the first node
    flips every iteration). Reported as a solver defect; larger drag steps
    are a known open one too, so neither is tested here."""
    path = [(0.5, 0.0, -0.005), (1.0, 0.0, -0.01)]
    for k in range(1, 2 * N_DRAG + 1):
        ux = DU * k if k <= N_DRAG else DU * (2 * N_DRAG - k)
        path.append((1.0 + k, ux, -0.01))
    return path


@pytest.fixture(scope="module")
def sliding_cli(cli_summary, tmp_path_factory):
    """The CLI on the same path: the shipped scene with its drag function
    and times replaced (drag up to 0.02 over t = 1..11, back by t = 21)."""
    shipped = SCENES["sliding_block"]
    times = next(l for l in shipped.read_text().splitlines() if l.startswith("times = "))
    scene = write_scene(
        tmp_path_factory.mktemp("sliding"),
        shipped,
        "sliding_path.toml",
        [
            ("points = [[0.0, 0.0], [1.0, 1.0]]", "points = [[0.0, 0.0], [1.0, 1.0], [21.0, 1.0]]"),
            (
                "points = [[0.0, 0.0], [1.0, 0.0], [3.0, 1.0], [4.0, 0.5]]",
                "points = [[0.0, 0.0], [1.0, 0.0], [11.0, 1.0], [21.0, 0.0]]",
            ),
            ('ux = { function = "drag", scale = 0.2 }', 'ux = { function = "drag", scale = 0.02 }'),
            (times, "times = [" + ", ".join(str(t) for t, _, _ in sliding_path()) + "]"),
        ],
    )
    return cli_summary(scene)


def test_sliding_block_sticks_slips_and_reverses(open_fmu, sliding_cli):
    steps = sliding_cli["steps"]
    path = sliding_path()
    assert [s["time"] for s in steps] == [t for t, _, _ in path]

    b = open_fmu("sliding_block").init()
    assert b.real("base.mu_s") == MU_S and b.real("base.mu_d") == MU_D
    rows = []
    t = 0.0
    for (t_next, ux, uy), step in zip(path, steps):
        b.set("top.ux", ux)
        b.set("top.uy", uy)
        b.fmu.doStep(t, t_next - t)
        t = t_next
        fn, ft = b.real("base.Fn"), b.real("base.Ft")
        # Same as the CLI on the same path (forces scale: Fn ~ 24).
        assert_matches_summary(b, step, force_scale=25.0, length_scale=2.0)
        # At every converged state: all nodes in contact, the block in
        # equilibrium (the plane takes what the top applies) and Coulomb's
        # bound on the resultant.
        assert b.int("base.n_open") == 0
        assert b.int("base.n_stick") + b.int("base.n_slip") == NODES
        assert fn > 0.0
        assert abs(b.real("plane.Rx") - b.real("top.Rx")) <= 1e-9 * fn
        assert abs(b.real("plane.Ry") - b.real("top.Ry")) <= 1e-9 * fn
        assert abs(ft) <= MU_S * fn * (1 + 1e-9), f"t = {t}"
        rows.append(
            dict(
                ux=ux,
                fn=fn,
                ft=ft,
                stick=b.int("base.n_stick"),
                slip=b.int("base.n_slip"),
                tt=np.array(b.nodes("base", "tt")),
                state=b.nodes("base", "state"),
            )
        )

    # Pressed (t = 1): no tangential resultant, a symmetric pattern, the
    # middle sticks. (The edge nodes slip outwards: the Poisson expansion
    # under a top held in x; every node sticks only for nu = 0, see below.)
    pressed = rows[1]
    assert abs(pressed["ft"]) <= 1e-9 * pressed["fn"]
    assert pressed["state"] == pressed["state"][::-1]
    assert pressed["state"][NODES // 2] == 1
    _close(pressed["tt"], -pressed["tt"][::-1], pressed["fn"], "tt antisymmetric")

    drag = rows[2 : 2 + N_DRAG]
    back = rows[2 + N_DRAG :]
    # Dragged in +x: friction on the block points to -x, so Ft < 0 (Ft is
    # measured along the contactor, +x), growing in size while the stick
    # zone shrinks, then every node slips at Ft = -mu_d Fn (0.1 %, the
    # issue's bound).
    assert all(r["ft"] < 0 for r in drag)
    assert all(a["ft"] > q["ft"] for a, q in zip(drag, drag[1:]) if a["slip"] < NODES)
    assert all(a["stick"] >= q["stick"] for a, q in zip(drag, drag[1:]))
    first = next(i for i, r in enumerate(drag) if r["slip"] == NODES)
    assert drag[first]["ux"] <= 0.012, "breaks away by ux = 0.012 (0.01 in the CLI)"
    assert first >= 1 and drag[0]["stick"] > 0, "partial stick before sliding"
    for r in drag[first:]:
        assert r["slip"] == NODES
        assert abs(r["ft"] / r["fn"] + MU_D) < 1e-3, r
        assert np.all(r["tt"] < 0), "every node's traction opposes the drag"

    # Reversed: the tangential force rises through zero while every node
    # sticks (elastic unloading), then the block slides back at +mu_d Fn.
    fts = [drag[-1]["ft"]] + [r["ft"] for r in back]
    assert all(a < q for a, q in zip(fts, fts[1:]) if abs(q) < MU_D * back[0]["fn"] * (1 - 1e-3))
    assert back[0]["stick"] == NODES, "reversal starts by sticking"
    cross = next(i for i, r in enumerate(back) if r["ft"] > 0)
    assert cross >= 1 and back[cross - 1]["ft"] < 0
    # The sign change happens while the block sticks: every node before
    # it; after it every node but the block's corners (the nodal decisions
    # hold each node to its own capacity, and a corner node, where the
    # block's edge concentrates the shear, reverses first: the CLI shows
    # the trailing corner sliding from Ft = +0.14 mu_d Fn on).
    assert back[cross - 1]["stick"] == NODES, "every node sticks before the sign change"
    interior = back[cross]["state"][1:-1]
    assert all(st == 1 for st in interior), back[cross]["state"]
    assert back[-1]["slip"] == NODES
    assert abs(back[-1]["ft"] / back[-1]["fn"] - MU_D) < 1e-3
    assert np.all(back[-1]["tt"] > 0), "every node's traction has changed sign"


def test_sliding_block_without_poisson_sticks_everywhere(open_fmu):
    """nu = 0 (a parameter of the FMU): pressing is uniaxial strain, so
    every contactor node sticks with tn = E * 0.01 / H = 10 exactly (Q4
    elements reproduce the uniform state) and no tangential traction; then
    the drag breaks it away to Ft = -mu_d Fn."""
    b = open_fmu("sliding_block").init(**{"rubberish.nu": 0.0})
    b.set("top.uy", -0.01)
    b.fmu.doStep(0.0, 1.0)
    assert b.int("base.n_stick") == NODES and b.ints(["base.n_slip", "base.n_open"]) == [0, 0]
    assert b.nodes("base", "state") == [1] * NODES
    _close(b.nodes("base", "tn"), [10.0] * NODES, 10.0, "tn = E eps")
    _close(b.nodes("base", "tt"), [0.0] * NODES, 10.0, "tt = 0")
    _close(b.real("base.Fn"), 20.0, 20.0, "Fn = 10 * width 2")
    t = 1.0
    for k in range(1, 8):
        b.set("top.ux", DU * k)
        b.fmu.doStep(t, 1.0)
        t += 1.0
    assert b.int("base.n_slip") == NODES
    assert abs(b.real("base.Ft") / b.real("base.Fn") + MU_D) < 1e-3


# ---------------------------------------------------------------------------
# 3. Rollback, serialization, Discard and retry.


def test_state_rollback_and_serialization_repeat_a_step_exactly(open_fmu):
    h = open_fmu("hertz").init()
    step_hertz(h, HERTZ_TIMES[:2])
    at_half = h.outputs()
    state = h.fmu.getFMUstate()
    step_hertz(h, HERTZ_TIMES[2:3], start=0.5)
    first = h.outputs()
    assert first != at_half

    # Set the state back: the outputs are those at t = 0.5 again, and the
    # same step gives the same outputs, bit for bit.
    h.fmu.setFMUstate(state)
    assert h.outputs() == at_half
    assert h.fmu.getRealStatus(fmi2LastSuccessfulTime) == 0.5
    step_hertz(h, HERTZ_TIMES[2:3], start=0.5)
    assert h.outputs() == first

    # Serialized and deserialized into the same instance: the same again.
    data = h.fmu.serializeFMUstate(state)
    assert isinstance(data, bytes) and len(data) > 0
    restored = h.fmu.deSerializeFMUstate(data)
    h.fmu.setFMUstate(restored)
    assert h.outputs() == at_half
    step_hertz(h, HERTZ_TIMES[2:3], start=0.5)
    assert h.outputs() == first
    # And it goes on: the last step as the CLI's (checked in test 1) works.
    step_hertz(h, HERTZ_TIMES[3:], start=0.75)
    h.fmu.freeFMUstate(state)
    h.fmu.freeFMUstate(restored)


@pytest.fixture(scope="module")
def tl_quarters(cli_summary, tmp_path_factory):
    """The CLI's run of tl_shear in four increments (the retry's path)."""
    scene = write_scene(
        tmp_path_factory.mktemp("tl"),
        SCENES["tl_shear"],
        "tl_quarters.toml",
        [("times = [1.0]", "times = [0.25, 0.5, 0.75, 1.0]")],
    )
    return cli_summary(scene)


def test_discarded_step_keeps_the_state_and_smaller_steps_succeed(open_fmu, tl_quarters):
    s = open_fmu("tl_shear").init()
    # The scene allows 6 Newton iterations and no bisection; one jump to
    # (0.5, -0.3) needs 7.
    assert s.int("solver.max_iterations") == 6 and s.int("solver.max_substeps") == 0
    before = s.outputs()
    s.set("top.ux", 0.5)
    s.set("top.uy", -0.3)
    with pytest.raises(FMICallException) as failed:
        s.fmu.doStep(0.0, 1.0)
    assert failed.value.status == DISCARD
    assert any(m[0] == ERROR and "discarded" in m[2] for m in s.messages), s.text()
    assert s.fmu.getRealStatus(fmi2LastSuccessfulTime) == 0.0
    after = s.outputs()
    # Outputs stay those of the last converged time (t = 0: at rest); only
    # the work counters describe the failed attempt.
    for name, v in before.items():
        if not name.startswith("solver."):
            assert after[name] == v, name

    # Retry from the same state (no rollback needed) in four steps.
    t = 0.0
    for step in tl_quarters["steps"]:
        f = step["time"]
        s.set("top.ux", 0.5 * f)
        s.set("top.uy", -0.3 * f)
        s.fmu.doStep(t, f - t)
        t = f
        assert s.fmu.getRealStatus(fmi2LastSuccessfulTime) == t
        assert s.int("solver.iterations") <= 6
        # Same as the CLI's four increments from the untouched state.
        assert_matches_summary(s, step, force_scale=abs(tl_quarters["steps"][-1]["drivers"]["top"]["Ry"]), length_scale=1.0)


def test_held_and_tiny_inputs_converge(open_fmu):
    """A co-simulation master steps on with the inputs it holds (issue 11):
    a doStep whose inputs did not change returns OK without a Newton
    iteration (the converged state is in equilibrium against the problem's
    forces, not against a first residual at round-off), and leaves every
    output as it was; a change of 1e-9 of the drag step converges too, and
    so does a step of h = 1e-9."""
    import time

    b = open_fmu("sliding_block").init()
    b.set("top.uy", -0.01)
    b.fmu.doStep(0.0, 1.0)
    t = 1.0
    for k in range(1, 16):
        b.set("top.ux", DU * k)
        b.fmu.doStep(t, 1.0)
        t += 1.0
    assert b.int("base.n_slip") == NODES
    before = b.outputs()
    started = time.perf_counter()
    for _ in range(10):
        b.fmu.doStep(t, 1.0)
        t += 1.0
    held = (time.perf_counter() - started) / 10
    print(f"held doStep: {held * 1e6:.0f} us")
    assert b.int("solver.iterations") == 0
    after = b.outputs()
    for name, v in before.items():
        if ".slip[" in name:
            # The slip over the last step: a held step slides nowhere (to
            # round-off of the positions, 1e-12 of the drag step DU).
            assert abs(v - DU) < 1e-12 * DU or abs(v + DU) < 1e-12 * DU, (name, v)
            assert abs(after[name]) < 1e-12 * DU, (name, after[name])
        elif not name.startswith("solver."):
            assert after[name] == v, name
    # A change of 1e-9 of the drag step, then a step of h = 1e-9.
    for ux, h in ((DU * (15 + 1e-9), 1.0), (DU * (15 + 2e-9), 1e-9)):
        b.set("top.ux", ux)
        b.fmu.doStep(t, h)
        t += h
        assert b.int("solver.substeps") == 0
        assert b.int("solver.iterations") <= 2
        assert b.int("base.n_slip") == NODES


# ---------------------------------------------------------------------------
# 4. Bad input: an error with a message naming it, and the process goes on.


def _rejected(slave, call, status=ERROR):
    n = len(slave.messages)
    with pytest.raises(FMICallException) as failed:
        call()
    assert failed.value.status == status
    new = slave.messages[n:]
    assert new, "a log message explains the error"
    assert all(m[0] >= status for m in new), new
    return "\n".join(m[2] for m in new)


@pytest.mark.parametrize("bad, shown", [(math.nan, "NaN"), (math.inf, "inf"), (-math.inf, "-inf")])
def test_non_finite_input_is_rejected_by_name(open_fmu, cli_summary, bad, shown):
    h = open_fmu("hertz").init()
    text = _rejected(h, lambda: h.set("press.uy", bad))
    assert f"press.uy = {shown} rejected: not a finite number" in text, text
    # The input keeps its last good value; the instance still steps, as the
    # CLI does.
    h.set("press.uy", press_uy(0.25))
    h.fmu.doStep(0.0, 0.25)
    step = cli_summary(SCENES["hertz"])["steps"][0]
    _close(h.real("contact.Fn"), step["pairs"]["contact"]["Fn"], 1e3, "Fn")


@pytest.mark.parametrize(
    "name, value, expect",
    [
        ("steel.nu", 0.5, "steel.nu = 0.5 rejected: Poisson's ratio must satisfy -1 < nu < 0.5 in plane strain"),
        ("steel.E", 0.0, "steel.E = 0.0 rejected"),
        ("steel.E", -1.0, "steel.E = -1.0 rejected: Young's modulus"),
        ("contact.mu_s", -0.1, "contact.mu_s = -0.1 rejected"),
    ],
)
def test_out_of_range_parameter_is_rejected_by_name(open_fmu, cli_summary, name, value, expect):
    h = open_fmu("hertz")
    h.fmu.setupExperiment(startTime=0.0)
    h.fmu.enterInitializationMode()
    text = _rejected(h, lambda: h.set(name, value))
    assert expect in text, text
    # Not applied: initialization ends and the first step is the scene's.
    h.fmu.exitInitializationMode()
    step_hertz(h, HERTZ_TIMES[:1])
    step = cli_summary(SCENES["hertz"])["steps"][0]
    _close(h.real("contact.Fn"), step["pairs"]["contact"]["Fn"], 1e3, "Fn")


def test_mu_d_above_mu_s_is_rejected_at_the_end_of_initialization(open_fmu):
    h = open_fmu("hertz")
    h.fmu.setupExperiment(startTime=0.0)
    h.fmu.enterInitializationMode()
    assert h.real("contact.mu_s") == 0.0
    h.set("contact.mu_d", 0.2)  # alone it is in range
    text = _rejected(h, h.fmu.exitInitializationMode)
    assert "contact.mu_d = 0.2: mu_d must not exceed mu_s = 0.0" in text, text
    # Corrected, initialization ends and the instance steps.
    h.set("contact.mu_d", 0.0)
    h.fmu.exitInitializationMode()
    step_hertz(h, HERTZ_TIMES[:1])
    assert h.real("contact.Fn") > 0.0


def test_missing_scene_makes_instantiate_fail_with_a_message(open_fmu, unpacked, tmp_path):
    from conftest import _MESSAGES, Slave

    broken = tmp_path / "no_scene"
    shutil.copytree(unpacked["hertz"], broken)
    (broken / "resources" / "scene.toml").unlink()
    before = set(_MESSAGES)
    with pytest.raises(Exception, match="Failed to instantiate model"):
        Slave(broken, "no_scene")
    (name,) = set(_MESSAGES) - before
    text = "\n".join(m[2] for m in _MESSAGES[name])
    assert _MESSAGES[name] and all(m[0] >= ERROR for m in _MESSAGES[name]), _MESSAGES[name]
    assert str(broken / "resources" / "scene.toml") in text, text
    assert "cannot read the scene file" in text, text
    # The process goes on: the intact FMU still instantiates and steps.
    h = open_fmu("hertz").init()
    step_hertz(h, HERTZ_TIMES[:1])
    assert h.real("contact.Fn") > 0.0
