"""The VTK series of `contact2d run --vtk`, read back with meshio and
pyvista (the .pvd too) and checked against the JSON summary of the same run:
a small plastic block pressed onto a rigid plane that then slides under it
(sticking and sliding nodes, a moving rigid target, plastic strain)."""

import json
import xml.etree.ElementTree as ET

import meshio
import numpy as np
import pytest
import pyvista as pv

TIMES = [0.5, 1.0, 1.02, 1.5, 3.0]
DRAG = 0.05  # the plane's ux at t = 3
NX, NY = 4, 2

SCENE = f"""\
title = "Plastic block pressed on a rigid plane that then slides under it"

[analysis]
kind = "plane_strain"
kinematics = "mno"

[[material]]
name = "soft"
model = "von_mises"
E = 1000.0
nu = 0.3
sigma_y = 4.0
H = 100.0

[[body]]
name = "block"
material = "soft"
element = "q4"
mesh = {{ generator = "rectangle", origin = [0.0, 0.0], size = [2.0, 1.0], divisions = [{NX}, {NY}] }}

[[rigid]]
name = "plane"
points = [[10.0, 0.0], [-10.0, 0.0]]
ux = {{ function = "drag", scale = {DRAG} }}

[[function]]
name = "press"
points = [[0.0, 0.0], [1.0, 1.0], [3.0, 1.0]]

[[function]]
name = "drag"
points = [[0.0, 0.0], [1.0, 0.0], [3.0, 1.0]]

[[driver]]
name = "top"
set = "block.top"
ux = 0.0
uy = {{ function = "press", scale = -0.01 }}

[[contact]]
name = "base"
contactor = "block.bottom"
target = "plane"
mu_s = 0.3
mu_d = 0.3

[steps]
times = {TIMES}
"""


def drag(t):
    return DRAG * min(max(t - 1.0, 0.0) / 2.0, 1.0)


@pytest.fixture(scope="module")
def run(contact2d, tmp_path_factory):
    import subprocess

    base = tmp_path_factory.mktemp("vtk_series")
    scene = base / "block.toml"
    scene.write_text(SCENE)
    done = subprocess.run(
        [str(contact2d), "run", str(scene), "--summary", "s.json", "--vtk", "vtk", "--quiet"],
        cwd=base,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    summary = json.loads((base / "s.json").read_text())
    assert [s["time"] for s in summary["steps"]] == TIMES
    return base / "vtk", summary


def frames(vtk):
    """The .pvd's data sets: time -> {name: file}, part order checked."""
    root = ET.parse(vtk / "block.pvd").getroot()
    out = {}
    for d in root.findall("./Collection/DataSet"):
        out.setdefault(float(d.get("timestep")), []).append((int(d.get("part")), d.get("name"), d.get("file")))
    for t, sets in out.items():
        assert [(p, n) for p, n, _ in sets] == [(0, "solid"), (1, "contact.base"), (2, "rigid.plane")], t
    return {t: {n: f for _, n, f in sets} for t, sets in out.items()}


def test_pvd_names_every_block_from_t_0(run):
    vtk, _ = run
    series = frames(vtk)
    assert list(series) == [0.0] + TIMES
    assert series[0.0] == {
        "solid": "block_0000.vtu",
        "contact.base": "block_contact_base_0000.vtu",
        "rigid.plane": "block_rigid_plane_0000.vtu",
    }
    for files in series.values():
        for f in files.values():
            head = (vtk / f).read_bytes()[:2000]
            # Compressed binary, not ASCII numbers.
            assert b'compressor="vtkZLibDataCompressor"' in head and b'format="ascii"' not in head

    # pyvista's own PVD reader: one multiblock per time, in part order.
    reader = pv.get_reader(str(vtk / "block.pvd"))
    assert reader.time_values == [0.0] + TIMES
    reader.set_active_time_value(1.5)
    blocks = reader.read()
    assert blocks.n_blocks == 3
    solid, contact, rigid = blocks
    assert solid.n_cells == NX * NY and solid.n_points == (NX + 1) * (NY + 1)
    assert contact.n_points == NX + 1 and contact.n_cells == NX
    assert rigid.n_points == 2 and rigid.n_cells == 1
    assert "plastic_strain" in solid.cell_data and "tn" in contact.point_data


def test_meshio_reads_every_file_as_vtk_does(run):
    """meshio 5.3 moves each array of raw appended data to a new offset one
    at a time and finds the next by its old offset, so an array whose new
    offset equals a later one's old offset was read in its place (a frame's
    `tn` came back as its `slip`); the writer orders the appended data so
    that this cannot happen. Every array of every file, meshio against
    VTK's own reader, bit for bit."""
    vtk, _ = run
    for files in frames(vtk).values():
        for f in files.values():
            a, b = meshio.read(vtk / f), pv.read(vtk / f)
            np.testing.assert_array_equal(a.points, b.points, err_msg=f)
            assert set(a.point_data) == set(b.point_data), f
            for key, values in a.point_data.items():
                np.testing.assert_array_equal(values, b.point_data[key], err_msg=f"{f}: {key}")
            for key, values in a.cell_data.items():
                np.testing.assert_array_equal(values[0], b.cell_data[key], err_msg=f"{f}: {key}")


def test_frame_at_t_0_is_at_rest(run):
    vtk, _ = run
    files = frames(vtk)[0.0]
    solid = meshio.read(vtk / files["solid"])
    assert np.all(solid.point_data["displacement"] == 0.0)
    assert np.all(solid.cell_data["plastic_strain"][0] == 0.0)
    contact = meshio.read(vtk / files["contact.base"])
    assert np.all(contact.point_data["displacement"] == 0.0)
    assert np.all(contact.point_data["state"] == 0)
    assert np.all(contact.point_data["tn"] == 0.0) and np.all(contact.point_data["tt"] == 0.0)
    # The bottom rests on the plane: gap 0.
    np.testing.assert_allclose(contact.point_data["gap"], 0.0, atol=1e-12)
    rigid = meshio.read(vtk / files["rigid.plane"])
    assert np.all(rigid.point_data["displacement"] == 0.0)


def test_contact_surface_holds_the_summary_values(run):
    vtk, summary = run
    series = frames(vtk)
    states = set()
    for step in summary["steps"]:
        t = step["time"]
        nodes = step["pairs"]["base"]["nodes"]
        path = vtk / series[t]["contact.base"]
        with_meshio = meshio.read(path)
        with_pyvista = pv.read(path)
        for m in (with_meshio.point_data, with_pyvista.point_data):
            # Binary Float64: the summary's numbers bit for bit.
            for key in ("tn", "tt", "slip", "gap"):
                np.testing.assert_array_equal(m[key], nodes[key], err_msg=f"{key} at t = {t}")
            np.testing.assert_array_equal(m["state"], nodes["state"])
        current = with_meshio.points[:, :2] + with_meshio.point_data["displacement"][:, :2]
        np.testing.assert_allclose(current[:, 0], nodes["x"], rtol=0, atol=1e-14)
        np.testing.assert_allclose(current[:, 1], nodes["y"], rtol=0, atol=1e-14)
        # The contactor's segments join consecutive nodes.
        assert with_meshio.cells[0].type == "line"
        np.testing.assert_array_equal(with_meshio.cells[0].data, [[k, k + 1] for k in range(NX)])
        states |= set(nodes["state"])
    # The run shows both sticking and sliding nodes.
    assert {1, 2} <= states


def test_rigid_target_where_it_stands(run):
    vtk, summary = run
    series = frames(vtk)
    for t in [0.0] + TIMES:
        rigid = meshio.read(vtk / series[t]["rigid.plane"])
        np.testing.assert_array_equal(rigid.points[:, :2], [[10.0, 0.0], [-10.0, 0.0]])
        d = rigid.point_data["displacement"]
        np.testing.assert_allclose(d[:, 0], drag(t), rtol=0, atol=1e-15)
        np.testing.assert_array_equal(d[:, 1], 0.0)


def test_plastic_strain_where_the_block_yields(run):
    vtk, summary = run
    series = frames(vtk)
    last = meshio.read(vtk / series[TIMES[-1]]["solid"])
    ep = last.cell_data["plastic_strain"][0]
    assert ep.shape == (NX * NY,)
    # Pressed 1 % with sigma_y / E = 0.4 %: every element yields.
    assert np.all(ep > 1e-4) and np.all(ep < 0.05)
    # The plastic strain never decreases along the series.
    previous = np.zeros(NX * NY)
    for t in TIMES:
        ep = meshio.read(vtk / series[t]["solid"]).cell_data["plastic_strain"][0]
        assert np.all(ep >= previous - 1e-15), t
        previous = ep
    # The solid's displacement at the contactor nodes is the contact
    # surface's.
    contact = meshio.read(vtk / series[TIMES[-1]]["contact.base"])
    nodes = contact.point_data["node"]
    np.testing.assert_array_equal(last.point_data["displacement"][nodes], contact.point_data["displacement"])
