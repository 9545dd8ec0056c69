"""The wire-winding machine example (examples/winding_machine): its physics
on a short, compressed run in fmpy, and the whole example in libcosim from
its system structure file."""

import math
import statistics
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
ELEMENT = winding.WRAP / 128  # capstan.toml: 128 elements over the wrap
# The schedule compressed into 12.5 s at the line speed of 100 mm/s (a wrap
# length, 314 mm, every 3.1 s): the T2 set point 30 N, stepped to 36 N at
# 5.5 s; the first layer change at about 6.7 s (a 4 mm traverse: two
# winder revolutions); a stop from 10.5 s (standing still 11 to 11.5 s)
# and a restart at 11.5 s.
SCHEDULE = {
    "t_step": 5.5,
    "W_traverse": 4.0,
    "t_stop": 10.5,
    "t_restart": 11.5,
    "t_ramp": 0.5,
}
STOP = 12.5
WRAP_TIME = math.pi * winding.SCENE_RADIUS / 100.0  # a wrap length at line speed


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
    # Newton's work per step: that of steady running at line speed. The
    # stop and the restart, where the whole slip zone sticks again at
    # once, may take more, and a step is bisected where the node about to
    # touch the drum alternates between open and contact (docs/contact.md
    # section 12); neither loses a step.
    at_speed = [n for n, v in zip(short_run["solver.iterations"], short_run["v_line"]) if v == 100.0]
    assert statistics.median(at_speed) <= 5 and max(at_speed) <= 15


def test_steady_running_against_the_creep_theory(short_run):
    """A wrap length after the controller has brought T2 to its set point
    (30 N after the start, 36 N after the step: the step's transient has
    washed out by then) the capstan runs as the creep theory says
    (Johnson, Contact Mechanics, section 8.3): the strip sticks at the entry
    at T1 and slides over ln(T2 / T1) / mu at the exit. Bending the tape
    onto the drum makes the stick zone carry a little more than T1
    (docs/contact.md section 12: 0.2 % at T1 = 20 N/mm; measured 0.1-0.2 %
    here, at T1 = 10 N/mm; 1 % allowed, as in test_running_capstan); the
    slip arc is compared with the theory at the stick zone's tension and
    must lie within one element of it. The winder runs at the speed the capstan delivers (T2
    steady): the capstan's surface speed times the creep (1 + e2) / (1 + e1)
    and the mid-line's radius over the drum's (1e-3, the issue's bound)."""
    plateaus = [(30.0, SCHEDULE["t_ramp"], SCHEDULE["t_step"]), (36.0, SCHEDULE["t_step"], SCHEDULE["t_stop"])]
    for demand, start, end in plateaus:
        settled = next(i for i, t in enumerate(short_run["t"]) if t > start and abs(short_run["T2"][i] / demand - 1) < 0.01)
        t = short_run["t"][settled] + WRAP_TIME
        assert t < end, (demand, t)
        i = at(short_run, t)
        t1, t2 = winding.capstan_tensions(short_run, i, B)
        held = short_run["stick_tension"][i] * B
        assert abs(held / t1 - 1) < 0.01, (t, held, t1)
        theory = math.log(t2 / held) / winding.MU
        arc = short_run["slip_arc"][i]
        assert abs(arc - theory) <= ELEMENT, (t, math.degrees(arc), math.degrees(theory))
        assert abs(short_run["T2"][i] / demand - 1) < 0.01, (t, short_run["T2"][i])
        creep = winding.creep_theory(short_run, i)
        assert 1.003 < creep < 1.01, creep
        speeds = short_run["strip.speed_out"][i] / short_run["strip.speed_in"][i]
        assert abs(speeds / creep - 1) < 1e-3, (speeds, creep)
        winder = short_run["v_winder"][i] / short_run["v_capstan"][i]
        surface = creep * (1 + winding.THICKNESS / (2 * winding.SCENE_RADIUS))
        assert abs(winder / surface - 1) < 1e-3, (t, winder, surface)


def test_layer_change_raises_the_winding_radius(short_run):
    layers = short_run["layer"]
    assert layers[0] == 0 and layers[-1] >= 1
    first = layers.index(1)
    assert 6.0 < short_run["t"][first] < 7.5, short_run["t"][first]
    assert short_run["R_winder"][first] - short_run["R_winder"][first - 1] == pytest.approx(0.05)


def test_standstill_holds_inputs(short_run):
    """Standing still (11.0 .. 11.5 s, after the ramp down; the restart
    ramps from 11.5 s) the capstan's inputs are held: it returns at once,
    with no Newton iteration, and its outputs do not move; the strip does
    not run."""
    still = [i for i, t in enumerate(short_run["t"]) if 11.05 <= t <= 11.45]
    assert still
    assert all(short_run["solver.iterations"][i] == 0 for i in still)
    assert len({short_run["T2"][i] for i in still[1:]}) == 1
    assert len({short_run["strip.fed"][i] for i in still}) == 1
    assert all(short_run["v_line"][i] == 0.0 and short_run["strip.speed_out"][i] == 0.0 for i in still)
    # Running again after the restart.
    assert short_run["v_line"][-1] > 0 and short_run["solver.iterations"][-1] > 0


def test_libcosim_runs_the_example_like_fmpy(built):
    """libcosim, from the shipped OspSystemStructure.xml (default schedule,
    first 12 s: steady running at 30 N and the tension step), computes what
    the fmpy master computes: both are Jacobi masters, so the runs agree to
    round-off."""
    out, machine, capstan = built
    cosim, ok = winding.run_libcosim(out, STOP, STEP)
    assert ok
    assert len(cosim["t"]) == round(STOP / STEP)
    rec, _ = winding.run_fmpy(machine, capstan, STOP, STEP)
    assert rec["status"] == [0] * len(cosim["t"])
    scale = max(rec["T2"])
    assert max(abs(a - b) for a, b in zip(rec["T2"], cosim["T2"])) < 1e-9 * scale
    assert cosim["theta_capstan"] == pytest.approx(rec["theta_capstan"], rel=1e-9, abs=1e-12)


def test_capstan_fmu_validates(built):
    """fmpy's validation and fmutool's check find nothing in the shipped
    example's contact FMU."""
    _, _, capstan = built
    assert_fmu_validates(capstan)
