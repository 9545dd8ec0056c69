"""Independent FMI clients on the exported FMU: fmpy's validation and
simulate_fmu, fmu-manipulation-toolbox's compliance check, and the Open
Simulation Platform's libcosim (libcosimpy) stepping it."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.validation import validate_fmu

from conftest import REPO, SCENES, assert_fmu_validates, export_fmu

# As in test_fmu.py: FMU and CLI agree to round-off (the inputs may differ in
# the last bit, Newton stops at |r|/|r0| <= 1e-9), relative to the force.
RTOL = 1e-9
HERTZ_TIMES = [0.25, 0.5, 0.75, 1.0]


def hertz_fn(cli_summary):
    return [s["pairs"]["contact"]["Fn"] for s in cli_summary(SCENES["hertz"])["steps"]]


@pytest.mark.parametrize("name", ["hertz", "sliding_block"])
def test_fmpy_validate_finds_no_problem(fmus, name):
    assert validate_fmu(str(fmus[name])) == []
    # The same through the command line client.
    done = subprocess.run(
        [sys.executable, "-m", "fmpy.cli", "validate", str(fmus[name])],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    assert "No problems found." in done.stdout, done.stdout


def test_simulate_fmu_with_an_input_table(fmus, cli_summary):
    fn = hertz_fn(cli_summary)
    h = 0.25
    # fmpy applies the input at the start of each communication step, the
    # FMU takes it as the prescribed value at the end (SPEC section 4: "its
    # value at the end of the step"), so the table holds at time t the
    # scene's load at t + h: press.uy = -0.07 * min(t + h, 1).
    times = np.arange(0.0, 1.0 + h / 2, h)
    table = np.array(
        [(t, -0.07 * min(t + h, 1.0)) for t in times],
        dtype=[("time", np.float64), ("press.uy", np.float64)],
    )
    kwargs = dict(
        start_time=0.0,
        stop_time=1.0,
        output_interval=h,
        input=table,
        output=["contact.Fn", "contact.n_slip", "press.uy"],
    )
    # Start values at the scene's own values: the CLI's results.
    result = simulate_fmu(
        str(fmus["hertz"]),
        start_values={"steel.E": 200000.0, "steel.nu": 0.3, "solver.max_iterations": 25},
        **kwargs,
    )
    assert list(result["time"]) == [0.0] + HERTZ_TIMES
    np.testing.assert_allclose(result["contact.Fn"], [0.0] + fn, rtol=RTOL, atol=RTOL * fn[-1])
    steps = cli_summary(SCENES["hertz"])["steps"]
    assert list(result["contact.n_slip"][1:]) == [s["pairs"]["contact"]["n_slip"] for s in steps]

    # A start value that changes the answer: with every boundary condition a
    # prescribed displacement (small strain, frictionless), the displacement
    # field does not depend on E, so doubling E doubles every force.
    doubled = simulate_fmu(str(fmus["hertz"]), start_values={"steel.E": 400000.0}, **kwargs)
    np.testing.assert_allclose(doubled["contact.Fn"][1:], 2.0 * np.array(fn), rtol=RTOL)


def test_fmutool_check_says_compliant(fmus):
    fmutool = Path(sys.executable).with_name("fmutool")
    assert fmutool.is_file(), f"{fmutool}: run scripts/setup.sh"
    done = subprocess.run(
        [str(fmutool), "-input", str(fmus["hertz"]), "-check"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    out = done.stdout + done.stderr
    # On a faulty FMU it prints "ERROR | ..." lines, "This FMU does not
    # validate with FMI standard." and exits with the number of errors.
    assert done.returncode == 0, out
    assert "This FMU seems to be compliant with FMI-2.0." in out, out
    assert "No semantic error against the FMI-2 standard." in out, out
    assert "ERROR" not in out, out


def test_libcosim_loads_sets_the_input_and_steps(fmus, cli_summary):
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimManipulator import CosimManipulator
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    fn = hertz_fn(cli_summary)
    log_output_level(CosimLogLevel.WARNING)
    # libcosim counts time in nanoseconds: one step of 0.25 (the scene's).
    execution = CosimExecution.from_step_size(step_size=250_000_000)
    slave = CosimLocalSlave(fmu_path=str(fmus["hertz"]), instance_name="hertz")
    index = execution.add_local_slave(local_slave=slave)
    assert execution.num_slaves() == 1
    refs = {v.name.decode(): v.reference for v in execution.slave_variables(index)}
    assert {"press.uy", "contact.Fn", "contact.n_slip"} <= set(refs)
    override = CosimManipulator.create_override()
    assert execution.add_manipulator(manipulator=override)
    observer = CosimObserver.create_last_value()
    assert execution.add_observer(observer=observer)

    previous = 0.0
    for k, t in enumerate(HERTZ_TIMES):
        # The input for the step that ends at t (the FMU's convention).
        assert override.slave_real_values(index, [refs["press.uy"]], [-0.07 * t])
        assert execution.step()
        assert execution.status().current_time == round(t * 1e9)
        got, uy = observer.last_real_values(index, [refs["contact.Fn"], refs["press.uy"]])
        assert uy == -0.07 * t
        assert got > previous, "pressing harder, more force"
        assert abs(got - fn[k]) <= RTOL * fn[-1], (t, got, fn[k])
        previous = got


SHIPPED = sorted((REPO / "scenes").glob("*.toml")) + sorted((REPO / "scenes" / "verification").glob("*.toml"))


@pytest.mark.parametrize("fmi", [2, 3])
@pytest.mark.parametrize("scene", SHIPPED, ids=[p.stem for p in SHIPPED])
def test_every_shipped_fmu_validates(contact2d, tmp_path, scene, fmi):
    """fmpy's validation and fmutool's check find no problem in the FMI 2.0
    and the FMI 3.0 FMU of any shipped scene (the machine example's capstan:
    test_winding_machine, and below)."""
    fmu = export_fmu(contact2d, scene, tmp_path / f"{scene.stem}.fmu", fmi=fmi)
    assert_fmu_validates(fmu, fmi=fmi)


def test_capstan_fmi3_validates(contact2d, tmp_path):
    """The machine example's capstan as FMI 3.0: a running strip with scene
    parameters, the drum's angle and two forces as inputs, tunable
    friction, per-node arrays with the angles along the wrap."""
    scene = REPO / "examples" / "winding_machine" / "capstan.toml"
    assert_fmu_validates(export_fmu(contact2d, scene, tmp_path / "capstan3.fmu", fmi=3), fmi=3)
