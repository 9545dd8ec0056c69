"""The wire-winding machine example (examples/winding_machine): its physics
on a short, compressed run in fmpy, and the whole example in libcosim from
its system structure file."""

import math
import sys
import zipfile
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "examples" / "winding_machine"))

import winding  # noqa: E402
from conftest import PORTABLE_LIBRARY, assert_fmu_validates  # noqa: E402

STEP = 0.025
B = 2.0  # machine.py's strip width
# The schedule compressed into 12 s: tension step 30 -> 36 N at 2.5 s, a
# demand of 50 N (above T1 exp(mu theta) = 43.9 N) from 5 to 6 s, the first
# layer change at about 8 s (a 10 mm traverse: five winder revolutions), a
# stop from 9.5 s (standing still 10 to 10.5 s) and a restart at 10.5 s.
SCHEDULE = {
    "t_step": 2.5,
    "t_slip": 5.0,
    "t_slip_end": 6.0,
    "W_traverse": 10.0,
    "t_stop": 9.5,
    "t_restart": 10.5,
    "t_ramp": 0.5,
}
STOP = 12.0


@pytest.fixture(scope="module")
def built(contact2d, tmp_path_factory):
    out = tmp_path_factory.mktemp("winding_machine")
    machine, capstan = winding.build(contact2d, out)
    # The capstan FMU carries the portable library (glibc 2.17).
    with zipfile.ZipFile(capstan) as z:
        assert z.read("binaries/linux64/contact2d.so") == PORTABLE_LIBRARY.read_bytes()
    return out, machine, capstan


@pytest.fixture(scope="module")
def short_run(built):
    _, machine, capstan = built
    return winding.run_fmpy(machine, capstan, STOP, STEP, parameters=SCHEDULE)[0]


def at(rec, t):
    """Index of the communication point at time t."""
    return min(range(len(rec["t"])), key=lambda i: abs(rec["t"][i] - t))


def test_no_discard_and_every_step_taken(short_run):
    assert short_run["status"] == [0] * round(STOP / STEP)
    assert len(short_run["T2"]) == round(STOP / STEP)
    # Newton's work per step stays small (the robust iteration's bar).
    assert max(short_run["solver.iterations"]) <= 15
    assert sum(short_run["solver.substeps"]) == 0


def test_capstan_ratio_in_full_slip(short_run):
    """While the demand is beyond the capstan's hold, the whole wrap slides
    and T2/T1 = exp(mu theta). Tolerance 1 %: the stress suite's capstan
    (the same strip and drum, scenes/stress/capstan_half_wrap.toml) sums
    what the model leaves out of the membrane formula (thickness, bending of
    4-node elements, the polygonal drum) to 7.2e-3."""
    ratios = winding.full_slip_ratios(short_run, B)
    assert len(ratios) >= 5, "the demand of 50 N must make the wrap slide"
    closed = math.exp(winding.MU * winding.WRAP)
    for t, r in ratios:
        assert 5.0 < t <= 6.1, t
        assert abs(r / closed - 1) < 0.01, (t, r, closed)
    # Below the hold, some of the wrap sticks.
    before = at(short_run, 4.9)
    assert short_run["wrap.n_stick"][before] > 0


def test_tension_tracked_by_the_controller(short_run):
    """The controller brings T2 to its set point after the tension step,
    after the slide, after the layer change and after the restart; within 1 %
    (the controller's integral removes offsets, the strip's stick/slip
    steps are 1/64 of the wrap)."""
    for t in (4.95, 9.45, 12.0):
        i = at(short_run, t)
        assert abs(short_run["T2"][i] / short_run["T2_demand"][i] - 1) < 0.01, (t, short_run["T2"][i])
    # The step itself was taken (T2 rose from 30 to 36 N).
    assert abs(short_run["T2"][at(short_run, 2.45)] / 30.0 - 1) < 0.02


def test_layer_change_raises_the_winding_radius(short_run):
    layers = short_run["layer"]
    assert layers[0] == 0 and layers[-1] >= 1
    first = layers.index(1)
    assert 7.5 < short_run["t"][first] < 8.5
    assert short_run["R_winder"][first] - short_run["R_winder"][first - 1] == pytest.approx(1.0)
    # The radius jump disturbs the tension, which the controller brings back.
    blip = max(abs(short_run["T2"][i] - 36.0) for i in range(first, first + 20))
    assert blip > 0.1


def test_standstill_holds_inputs(short_run):
    """Standing still (10.0 .. 10.5 s, after the ramp down; the restart ramps from 10.5 s) the capstan's
    inputs are held: it returns at once, with no Newton iteration, and its
    outputs do not move."""
    still = [i for i, t in enumerate(short_run["t"]) if 10.05 <= t <= 10.45]
    assert still
    assert all(short_run["solver.iterations"][i] == 0 for i in still)
    assert len({short_run["T2"][i] for i in still[1:]}) == 1
    assert all(short_run["v_line"][i] == 0.0 for i in still)
    # Running again after the restart.
    assert short_run["v_line"][-1] > 0 and short_run["solver.iterations"][-1] > 0


def test_libcosim_runs_the_example_like_fmpy(built):
    """libcosim, from the shipped OspSystemStructure.xml (default schedule,
    first 12 s: the tension step, the slide, the first layer change),
    computes what the fmpy master computes: both are Jacobi
    masters, so the runs agree to round-off."""
    out, machine, capstan = built
    cosim, ok = winding.run_libcosim(out, STOP, STEP)
    assert ok
    assert len(cosim["t"]) == round(STOP / STEP)
    rec, _ = winding.run_fmpy(machine, capstan, STOP, STEP)
    assert rec["status"] == [0] * len(cosim["t"])
    scale = max(rec["T2"])
    assert max(abs(a - b) for a, b in zip(rec["T2"], cosim["T2"])) < 1e-9 * scale
    assert cosim["u_pull"] == pytest.approx(rec["u_pull"], rel=1e-9, abs=1e-12)


def test_capstan_fmu_validates(built):
    """fmpy's validation and fmutool's check find nothing in the shipped
    example's contact FMU."""
    _, _, capstan = built
    assert_fmu_validates(capstan)
