"""Parameter sweeps on Dask (examples/sweep, issue 15): the capstan grid run
on a local cluster of two worker processes gives the very rows of the same
runs made one after the other here, and the capstan ratio at the onset of
full slip is Euler-Eytelwein's exp(mu theta)."""

import csv
import math
import sys

import pytest

# conftest puts examples/sweep on sys.path.
import capstan_sweep
from conftest import assert_fmu_validates, export_fmu
from contact2d_sweep import grid, run_case, sweep, write_csv

CASES = capstan_sweep.cases(mus=[0.2, 0.4], wraps_deg=[90.0, 180.0])
# Full slip at mu = 0.4 over 180 deg comes after 4 mm of pull.
SCHEDULE = capstan_sweep.schedule(pull_mm=4.5)
OUTPUTS = capstan_sweep.OUTPUTS


@pytest.fixture(scope="module")
def capstan_fmu(contact2d, tmp_path_factory):
    return export_fmu(contact2d, capstan_sweep.SCENE, tmp_path_factory.mktemp("sweep") / "capstan_wrap.fmu")


@pytest.fixture(scope="module")
def serial(capstan_fmu):
    return sweep(capstan_fmu, CASES, SCHEDULE, OUTPUTS, client=None, record="all")


def test_the_sweep_fmu_validates(capstan_fmu):
    assert_fmu_validates(capstan_fmu)


def test_grid_is_the_cartesian_product_with_tied_names():
    cases = grid({("wrap.mu_s", "wrap.mu_d"): [0.1, 0.2], "wrap_deg": [90.0, 180.0, 270.0]})
    assert len(cases) == 6
    assert cases[0] == {"wrap.mu_s": 0.1, "wrap.mu_d": 0.1, "wrap_deg": 90.0}
    assert cases[5] == {"wrap.mu_s": 0.2, "wrap.mu_d": 0.2, "wrap_deg": 270.0}
    assert [c["wrap_deg"] for c in cases[:3]] == [90.0, 180.0, 270.0]  # the last axis varies fastest


def test_a_local_dask_cluster_gives_the_serial_rows(capstan_fmu, serial):
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with Client(cluster) as client:
            distributed = sweep(capstan_fmu, CASES, SCHEDULE, OUTPUTS, client=client, record="all")
            # Each worker process that ran cases extracted the FMU once.
            extracted = client.run(lambda: len(getattr(sys.modules.get("contact2d_sweep"), "_UNPACKED", ())))
    assert len(extracted) == 2 and sum(extracted.values()) >= 1 and max(extracted.values()) == 1, extracted
    assert len(serial) == len(CASES) * len(SCHEDULE)
    assert all(r["error"] is None for r in serial), [r["error"] for r in serial if r["error"]]
    # Bit for bit: the same library, the same inputs, one thread each.
    assert distributed == serial


def test_capstan_ratio_at_full_slip_is_exp_mu_theta(serial):
    table = {(r["mu"], r["wrap_deg"]): r for r in capstan_sweep.onset_of_full_slip(serial)}
    assert set(table) == {(0.2, 90.0), (0.2, 180.0), (0.4, 90.0), (0.4, 180.0)}
    r = table[(0.4, 180.0)]
    mu, theta = 0.4, math.pi
    assert r["exp_mu_theta"] == math.exp(mu * theta)
    # Euler-Eytelwein within 1 %; closer still (0.2 %) with the exponent the
    # strip's thickness lowers by t / (2R) (the tension acts at its mid-line).
    assert abs(r["T2_over_T1"] / math.exp(mu * theta) - 1) < 0.01, r
    t_over_2r = capstan_sweep.THICKNESS / (2 * capstan_sweep.RADIUS)
    assert abs(r["T2_over_T1"] / math.exp(mu * theta * (1 - t_over_2r)) - 1) < 0.002, r
    # Before full slip the tight side holds less: the onset is a step of the run.
    before = [s for s in serial if s["case"] == r["case"] and s["time"] < 1.0 + r["pull_mm"] / capstan_sweep.STEP_MM]
    assert before and all(s["wrap.n_stick"] > 0 or -s["pull.Ry"] <= capstan_sweep.T1 for s in before)


def test_a_case_that_fails_is_a_row_with_its_reason(capstan_fmu):
    # mu_d > mu_s is refused at fmi2ExitInitializationMode.
    rows = run_case(capstan_fmu, {"wrap.mu_s": 0.1, "wrap.mu_d": 0.2}, SCHEDULE[:2], ["pull.Ry"], index=7)
    assert len(rows) == 1
    assert rows[0]["case"] == 7 and rows[0]["time"] == 0.0
    assert "mu_d" in rows[0]["error"], rows[0]["error"]


def test_wrong_names_are_refused_before_any_run(capstan_fmu):
    with pytest.raises(ValueError, match="not a variable"):
        sweep(capstan_fmu, [{"wrap.mu": 0.1}], SCHEDULE, OUTPUTS)
    with pytest.raises(ValueError, match="has causality 'output', not parameter or input"):
        sweep(capstan_fmu, [{"pull.Ry": 1.0}], SCHEDULE, OUTPUTS)
    with pytest.raises(ValueError, match="set by the case and by the schedule"):
        sweep(capstan_fmu, [{"pull.uy": -1.0}], SCHEDULE, OUTPUTS)
    with pytest.raises(ValueError, match="must increase"):
        sweep(capstan_fmu, [{}], [(1.0, {}), (1.0, {})], OUTPUTS)


def test_csv_keeps_every_digit(serial, tmp_path):
    path = write_csv(serial, tmp_path / "rows.csv")
    with open(path) as f:
        back = list(csv.DictReader(f))
    assert len(back) == len(serial)
    assert [float(b["pull.Ry"]) for b in back] == [r["pull.Ry"] for r in serial]


def test_the_example_writes_its_table_and_plot(capstan_fmu, tmp_path, capsys):
    """capstan_sweep.py on a grid of two cases, serially: the table it
    prints, its CSV files and its plot."""
    code = capstan_sweep.main(["--serial", "--fmu", str(capstan_fmu), "--out", str(tmp_path), "--mu", "0.3", "--wrap", "60", "120"])
    out = capsys.readouterr().out
    assert code == 0, out
    assert "2 runs of capstan_wrap.fmu" in out, out
    with open(tmp_path / "capstan_ratio.csv") as f:
        table = list(csv.DictReader(f))
    assert [(float(r["mu"]), float(r["wrap_deg"])) for r in table] == [(0.3, 60.0), (0.3, 120.0)]
    for r in table:
        assert abs(float(r["rel_error"])) < 0.01, r
    assert (tmp_path / "sweep_steps.csv").stat().st_size > 0
    assert (tmp_path / "capstan_ratio.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
