"""Each of the paper's sample problems (issue 5, docs/paper-problems.md)
exported as an FMU and stepped in fmpy along the scene's own load history
(`contact2d inputs`): every output equals the command line's summary of the
same scene at every increment.

The increments are the scene's own (`[steps]`), so the FMU solves exactly
what the CLI solves; the inputs are the values at the end of each step
(end-of-step semantics, docs/fmu.md).
"""

import csv
import subprocess

import numpy as np
import pytest
from fmpy import extract
from fmpy.fmi2 import fmi2LastSuccessfulTime

from conftest import REPO, Slave, export_fmu
from test_fmu import assert_matches_summary

# The paper's problems as shipped, by section of the paper.
PAPER = {
    "hertz_plane_strain": REPO / "scenes" / "hertz_plane_strain.toml",
    "hertz_axisymmetric": REPO / "scenes" / "hertz_axisymmetric.toml",
    "rubber_sheet": REPO / "scenes" / "rubber_sheet.toml",
    "wire_winding": REPO / "scenes" / "wire_winding.toml",
    "buried_pipe": REPO / "scenes" / "buried_pipe.toml",
}


def input_table(contact2d, scene, tmp_path):
    """`contact2d inputs SCENE`: [(time, {input name: value})], t = 0 first."""
    path = tmp_path / "inputs.csv"
    done = subprocess.run(
        [str(contact2d), "inputs", str(scene), "-o", str(path)], capture_output=True, text=True, timeout=60
    )
    assert done.returncode == 0, done.stderr
    with path.open() as f:
        rows = list(csv.DictReader(f))
    return [(float(r.pop("time")), {k: float(v) for k, v in r.items()}) for r in rows]


@pytest.mark.parametrize("name", sorted(PAPER))
def test_paper_problem_steps_in_fmpy_as_the_cli(name, contact2d, cli_summary, tmp_path):
    scene = PAPER[name]
    fmu = export_fmu(contact2d, scene, tmp_path / f"{name}.fmu")
    summary = cli_summary(scene)
    steps = summary["steps"]
    assert steps and all(s["converged"] for s in steps), f"{name}: the CLI run must converge"
    table = input_table(contact2d, scene, tmp_path)
    assert [t for t, _ in table] == [0.0] + [s["time"] for s in steps]

    slave = Slave(extract(str(fmu), str(tmp_path / "unpacked")), name)
    try:
        slave.init()
        # Start values are the scene's inputs at t = 0.
        for var, value in table[0][1].items():
            assert slave.real(var) == value, var
        t = 0.0
        for (t1, inputs), step in zip(table[1:], steps):
            for var, value in inputs.items():
                slave.set(var, value)
            slave.fmu.doStep(t, t1 - t)
            assert slave.fmu.getRealStatus(fmi2LastSuccessfulTime) == t1
            forces = [abs(v) for d in step["drivers"].values() for v in d.values()]
            forces += [abs(p[c]) for p in step["pairs"].values() for c in ("Fx", "Fy", "Fn", "Ft")]
            lengths = [abs(v) for p in step["pairs"].values() for w in ("x", "y") for v in p["nodes"][w]]
            assert_matches_summary(slave, step, force_scale=max(forces), length_scale=max(lengths))
            t = t1
    finally:
        slave.free()


def test_input_derivatives_follow_the_scene_in_fmpy(contact2d, cli_summary, tmp_path):
    """fmi2SetRealInputDerivatives from fmpy's FMU2Slave: at each
    communication point the master sets each input's value at that time
    (the table of `contact2d inputs`, not shifted) and its slope to the next
    row; the FMU extrapolates over the step and reaches the CLI's increment.
    The sliding block's history has uneven steps and kinks (its drag turns
    at t = 1 and 3), and friction. fmpy's simulate_fmu(...,
    set_input_derivatives=True) cannot drive it: fmpy 0.3.32 keeps nine
    derivative slots per input type and raises ValueError for any other
    number of inputs (this scene has five)."""
    scene = REPO / "scenes" / "verification" / "sliding_block.toml"
    fmu = export_fmu(contact2d, scene, tmp_path / "sliding_block.fmu")
    steps = cli_summary(scene)["steps"]
    table = input_table(contact2d, scene, tmp_path)
    assert [t for t, _ in table] == [0.0] + [s["time"] for s in steps]

    slave = Slave(extract(str(fmu), str(tmp_path / "unpacked")), "derivatives")
    try:
        slave.init()
        names = list(table[0][1])
        vrs = [slave.vr(n) for n in names]
        for (t0, now), (t1, then), step in zip(table, table[1:], steps):
            slave.fmu.setReal(vrs, [now[n] for n in names])
            slopes = [(then[n] - now[n]) / (t1 - t0) for n in names]
            slave.fmu.setRealInputDerivatives(vrs, [1] * len(vrs), slopes)
            slave.fmu.doStep(t0, t1 - t0)
            forces = [abs(v) for d in step["drivers"].values() for v in d.values()]
            forces += [abs(p[c]) for p in step["pairs"].values() for c in ("Fx", "Fy", "Fn", "Ft")]
            assert_matches_summary(slave, step, force_scale=max(forces), length_scale=2.0)
            # The inputs hold the values they reached.
            for n in names:
                assert abs(slave.real(n) - then[n]) <= 1e-15 * max(1.0, abs(then[n])), n
    finally:
        slave.free()


def test_fmpy_simulate_fmu_cannot_yet_drive_input_derivatives(contact2d, tmp_path):
    """Issue 12 asks for fmpy's own simulate_fmu(..., set_input_derivatives=True)
    to reproduce the CLI from the `contact2d inputs` table. fmpy 0.3.32 (the
    newest release, and its main branch as of 2026-07) cannot, for reasons in
    fmpy's simulation.py, not in the FMU:
    - `Input.__init__` allocates `(value_type * 9)()` derivative slots
      whatever the number of inputs, so `derivatives[:] = d` raises
      ValueError unless a type has exactly nine inputs (the sliding block
      has five);
    - at a table row t_k, `Input.interpolate` returns the slope of the
      segment before t_k (forward only at a repeated time, an event);
    - at the first row it returns slope 0, so the first step holds the
      start values.
    The test above drives the same table through fmpy's FMU2Slave instead
    and matches the CLI at every increment. This one keeps watch: when a
    new fmpy accepts the call, it fails, and should become the
    simulate_fmu comparison the issue asks for."""
    import fmpy

    scene = REPO / "scenes" / "verification" / "sliding_block.toml"
    fmu = export_fmu(contact2d, scene, tmp_path / "sliding_block.fmu")
    table = input_table(contact2d, scene, tmp_path)
    names = list(table[0][1])
    assert len(names) != 9
    signals = np.array(
        [(t, *(row[n] for n in names)) for t, row in table],
        dtype=[("time", np.float64)] + [(n, np.float64) for n in names],
    )
    with pytest.raises(ValueError, match="same size"):
        fmpy.simulate_fmu(
            str(fmu), stop_time=table[-1][0], input=signals, set_input_derivatives=True, output_interval=table[-1][0]
        )
