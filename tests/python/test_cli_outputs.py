"""The command line end to end: `run` on a uniaxial tension test whose exact
solution is linear (so Q4 elements reproduce it to round-off), its VTK files
read back with meshio and its summary JSON; `check` on good and bad scenes;
a failed increment."""

import json
import xml.etree.ElementTree as ET

import meshio
import numpy as np
import pytest

# Plane strain block, bottom held in y (bottom-left corner also in x), top
# pulled up by D * t: uniaxial stress sigma_yy, lateral faces free.
E, NU = 1000.0, 0.25
X0, Y0, W, H = 0.5, -1.0, 2.0, 3.0
NX, NY = 3, 4
D = 0.01
TIMES = [0.5, 1.0]

SCENE = f"""\
title = "Uniaxial tension, plane strain"

[analysis]
kind = "plane_strain"
thickness = 1.0
kinematics = "{{kinematics}}"

[[material]]
name = "soft"
model = "linear_elastic"
E = {E}
nu = {{nu}}

[[body]]
name = "block"
material = "soft"
element = "q4"
mesh = {{{{ generator = "rectangle", origin = [{X0}, {Y0}], size = [{W}, {H}], divisions = [{NX}, {NY}] }}}}

[[function]]
name = "ramp"
points = [[0.0, 0.0], [1.0, 1.0]]

[[driver]]
name = "base"
set = "block.bottom"
uy = 0.0

[[driver]]
name = "pin"
set = "block.bottom_left"
ux = 0.0

[[driver]]
name = "pull"
set = "block.top"
uy = {{{{ function = "ramp", scale = {{pull}} }}}}

[steps]
dt = 0.5
t_end = 1.0
{{solver}}"""


def scene_text(kinematics="small_strain", nu=NU, pull=D, solver=""):
    return SCENE.format(kinematics=kinematics, nu=nu, pull=pull, solver=solver)


def exact(t):
    """Plane strain, sigma_xx = 0, eps_zz = 0, eps_yy = D t / H, from the Lame
    constants: sigma = lambda tr(eps) I + 2 mu eps."""
    lam = E * NU / ((1 + NU) * (1 - 2 * NU))
    mu = E / (2 * (1 + NU))
    eyy = D * t / H
    exx = -lam / (lam + 2 * mu) * eyy  # from sigma_xx = 0
    syy = lam * (exx + eyy) + 2 * mu * eyy
    szz = lam * (exx + eyy)
    return exx, eyy, syy, szz


def close(actual, expected, scale):
    np.testing.assert_allclose(actual, expected, rtol=1e-9, atol=1e-9 * scale)


@pytest.fixture
def solved(tmp_path, run_cli):
    scene = tmp_path / "tension.toml"
    scene.write_text(scene_text())
    out = run_cli("run", scene, "--summary", "out/summary.json", "--vtk", "out/vtk")
    assert out.returncode == 0, out.stderr
    return tmp_path / "out", out


def test_run_prints_a_line_per_increment(solved):
    _, out = solved
    lines = out.stdout.splitlines()
    steps = [l for l in lines if l.startswith("step ")]
    assert [l.split()[1] for l in steps] == ["1/2", "2/2"]
    for l, t in zip(steps, TIMES):
        assert f"t = {t:g}" in l
        for name in ("base:", "pin:", "pull:", "NEQC 0", "|r|/F"):
            assert name in l
    # Newton's iterations only with --verbose (tests/python/test_cli_run_modes.py).
    assert not any(l.lstrip().startswith("[logNewton]") for l in lines)
    assert lines[-1].startswith("done: 2 increments in ")


def test_vtk_files_hold_the_exact_solution(solved):
    out, _ = solved
    pvd = ET.parse(out / "vtk" / "tension.pvd").getroot()
    sets = pvd.findall("./Collection/DataSet")
    # No contact pair, no rigid target: the solid alone, from t = 0 on.
    assert [s.get("part") for s in sets] == ["0"] * 3
    assert [float(s.get("timestep")) for s in sets] == [0.0] + TIMES
    assert [s.get("file") for s in sets] == ["tension_0000.vtu", "tension_0001.vtu", "tension_0002.vtu"]

    for s, t in zip(sets, [0.0] + TIMES):
        mesh = meshio.read(out / "vtk" / s.get("file"))
        # An elastic scene has no plastic strain to show.
        assert "plastic_strain" not in mesh.cell_data
        assert mesh.points.shape == ((NX + 1) * (NY + 1), 3)
        assert len(mesh.cells) == 1 and mesh.cells[0].type == "quad"
        assert mesh.cells[0].data.shape == (NX * NY, 4)
        x, y = mesh.points[:, 0], mesh.points[:, 1]
        assert np.all(mesh.points[:, 2] == 0.0)
        assert np.isclose(x.min(), X0) and np.isclose(y.max(), Y0 + H)

        exx, eyy, syy, szz = exact(t)
        u = mesh.point_data["displacement"]
        assert u.shape == (len(x), 3)
        top = np.isclose(y, Y0 + H)
        assert top.sum() == NX + 1
        close(u[top, 1], D * t, D)
        close(u[:, 1], eyy * (y - Y0), D)
        close(u[:, 0], exx * (x - X0), D)
        assert np.all(u[:, 2] == 0.0)

        stress = mesh.cell_data["stress"][0]
        assert stress.shape == (NX * NY, 4)
        close(stress[:, 0], 0.0, syy)
        close(stress[:, 1], syy, syy)
        close(stress[:, 2], szz, syy)
        close(stress[:, 3], 0.0, syy)
        vm = np.sqrt(0.5 * ((syy - szz) ** 2 + szz**2 + syy**2))
        close(mesh.cell_data["von_mises"][0], vm, syy)


def test_summary_has_the_reactions(solved):
    out, _ = solved
    summary = json.loads((out / "summary.json").read_text())
    assert summary["scene"].endswith("tension.toml")
    assert summary["dofs"] > 0 and summary["wall_s"] >= 0.0
    steps = summary["steps"]
    assert [s["time"] for s in steps] == TIMES
    for s, t in zip(steps, TIMES):
        assert s["converged"] is True
        assert s["iterations"] >= 1 and s["substeps"] == 0
        assert s["residual"] <= 1e-8
        assert s["neqc"] == 0 and s["pairs"] == {}
        assert list(s["drivers"]) == ["base", "pin", "pull"]
        _, _, syy, _ = exact(t)
        force = syy * W  # thickness 1
        close(s["drivers"]["pull"]["Ry"], force, force)
        close(s["drivers"]["base"]["Ry"], -force, force)
        close(s["drivers"]["pull"]["Rx"], 0.0, force)
        close(s["drivers"]["pin"]["Rx"], 0.0, force)


def test_check_describes_a_scene(tmp_path, run_cli):
    scene = tmp_path / "tension.toml"
    scene.write_text(scene_text())
    out = run_cli("check", scene)
    assert out.returncode == 0, out.stderr
    text = out.stdout
    assert "plane strain" in text and "small strain" in text
    assert f"block: {NX * NY} elements ({NX * NY} Q4), {(NX + 1) * (NY + 1)} nodes" in text
    assert f"top ({NX + 1} nodes, {NX} edges)" in text
    assert "soft: linear_elastic, E = 1000, nu = 0.25" in text
    assert f"pull: {NX + 1} nodes, ux = free, uy = 0.01 * ramp(t)" in text
    assert "2 increments, t = 0.5 .. 1" in text


@pytest.mark.parametrize("command", ["check", "run"])
def test_bad_scene_exits_2_with_file_and_line(tmp_path, run_cli, command):
    scene = tmp_path / "bad.toml"
    text = scene_text(nu=0.7)
    scene.write_text(text)
    line = next(i for i, l in enumerate(text.splitlines(), 1) if l.startswith("nu = "))
    out = run_cli(command, scene)
    assert out.returncode == 2
    assert f"{scene}:{line}:" in out.stderr
    assert "nu" in out.stderr and "0.7" in out.stderr
    assert "panicked" not in out.stderr


def test_missing_scene_exits_2(tmp_path, run_cli):
    out = run_cli("check", tmp_path / "nowhere.toml")
    assert out.returncode == 2
    assert "nowhere.toml" in out.stderr and "panicked" not in out.stderr


def test_failed_increment_is_in_the_summary(tmp_path, run_cli):
    # A 50 % stretch, total Lagrangian, one Newton iteration and no
    # bisection allowed: the first increment cannot converge.
    scene = tmp_path / "stretch.toml"
    scene.write_text(
        scene_text(
            kinematics="total_lagrangian",
            pull=0.5 * H,
            solver="\n[solver]\nmax_iterations = 1\nmax_bisections = 0\n",
        )
    )
    out = run_cli("run", scene, "--summary", "s.json", "--vtk", "vtk")
    assert out.returncode == 1
    assert "error:" in out.stderr and "panicked" not in out.stderr
    steps = json.loads((tmp_path / "s.json").read_text())["steps"]
    assert len(steps) == 1
    assert steps[0]["time"] == 0.5 and steps[0]["converged"] is False
    assert list(steps[0]["drivers"]) == ["base", "pin", "pull"]
    assert steps[0]["pairs"] == {}
    # The series holds the frame at rest only.
    pvd = ET.parse(tmp_path / "vtk" / "stretch.pvd").getroot()
    assert [s.get("file") for s in pvd.findall("./Collection/DataSet")] == ["stretch_0000.vtu"]
