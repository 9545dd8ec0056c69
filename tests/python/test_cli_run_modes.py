"""`contact2d run` at its three verbosities and with --log, and the exit
codes the README documents: 0 done; 1 an increment did not converge or an
output could not be written; 2 a bad scene or command line."""

import pytest
from test_cli_outputs import H, scene_text


@pytest.fixture
def scene(tmp_path):
    path = tmp_path / "tension.toml"
    path.write_text(scene_text())
    return path


@pytest.fixture
def failing(tmp_path):
    """One Newton iteration for a 50 % stretch, no bisection: the first
    increment fails."""
    path = tmp_path / "stretch.toml"
    solver = "\n[solver]\nmax_iterations = 1\nmax_bisections = 0\n"
    path.write_text(scene_text(kinematics="total_lagrangian", pull=0.5 * H, solver=solver))
    return path


def newton_lines(text):
    return [l for l in text.splitlines() if l.lstrip().startswith("[logNewton]")]


def test_default_prints_a_line_per_increment_and_no_newton(run_cli, scene):
    out = run_cli("run", scene)
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    assert lines[0].startswith("contact2d ") and "tension.toml" in lines[0]
    assert [l.split()[1] for l in lines if l.startswith("step ")] == ["1/2", "2/2"]
    assert newton_lines(out.stdout) == []
    assert lines[-1].startswith("done: 2 increments in ")
    assert out.stderr == ""


def test_verbose_adds_the_newton_iterations(run_cli, scene):
    out = run_cli("run", scene, "--verbose")
    assert out.returncode == 0, out.stderr
    newton = newton_lines(out.stdout)
    assert len(newton) >= 2 and all("|r|/F" in l for l in newton)
    # Each increment's Newton lines come before its summary line.
    lines = out.stdout.splitlines()
    first_step = next(i for i, l in enumerate(lines) if l.startswith("step 1/2"))
    assert lines[first_step - 1].lstrip().startswith("[logNewton]")
    assert lines[-1].startswith("done: 2 increments in ")


def test_quiet_prints_the_final_line_only(run_cli, scene):
    out = run_cli("run", scene, "--quiet", "--summary", "s.json")
    assert out.returncode == 0, out.stderr
    assert out.stdout.splitlines() == [out.stdout.strip()]
    assert out.stdout.startswith("done: 2 increments in ")
    assert out.stderr == ""


def test_quiet_failure_prints_the_error_only(run_cli, failing):
    out = run_cli("run", failing, "-q")
    assert out.returncode == 1
    assert out.stdout == ""
    assert out.stderr.startswith("error: ") and "panicked" not in out.stderr


def test_log_file_has_every_line_whatever_the_verbosity(tmp_path, run_cli, scene):
    verbose = run_cli("run", scene, "--verbose")
    out = run_cli("run", scene, "--quiet", "--log", "logs/run.log")
    assert out.returncode == 0, out.stderr
    log = (tmp_path / "logs" / "run.log").read_text()
    assert len(newton_lines(log)) == len(newton_lines(verbose.stdout)) > 0
    assert [l.split()[1] for l in log.splitlines() if l.startswith("step ")] == ["1/2", "2/2"]
    assert log.splitlines()[-1].startswith("done: 2 increments in ")


def test_log_of_a_failed_run_says_why(tmp_path, run_cli, failing):
    out = run_cli("run", failing, "--log", "run.log")
    assert out.returncode == 1
    log = (tmp_path / "run.log").read_text()
    assert "[logStatusError]" in log and "error: " in log


@pytest.mark.parametrize(
    "args",
    [
        ["--summary", "blocker/s.json"],  # a file where a folder must be
        ["--vtk", "blocker"],
        ["--log", "blocker/run.log"],
        ["--log", "."],  # a folder where a file must be
    ],
)
def test_unwritable_output_exits_1(tmp_path, run_cli, scene, args):
    (tmp_path / "blocker").write_text("a file, not a folder")
    out = run_cli("run", scene, *args)
    assert out.returncode == 1, out.stdout
    assert out.stderr.startswith("error: cannot") and "panicked" not in out.stderr


@pytest.mark.parametrize(
    "args",
    [
        ["run", "{scene}", "--quiet", "--verbose"],  # exclusive
        ["run", "{scene}", "--no-such-option"],
        ["run"],  # no scene
        ["run", "{scene}", "--set", "E"],  # NAME=VALUE expected
        ["solve", "{scene}"],  # no such command
    ],
)
def test_bad_command_line_exits_2(run_cli, scene, args):
    out = run_cli(*[a.format(scene=scene) for a in args])
    assert out.returncode == 2, out.stdout
    assert out.stderr and "panicked" not in out.stderr


def test_help_and_version_exit_0(run_cli):
    for args in (["--help"], ["run", "--help"], ["--version"]):
        out = run_cli(*args)
        assert out.returncode == 0 and out.stdout, args
    assert "--quiet" in run_cli("run", "--help").stdout


def test_export_exit_codes(tmp_path, run_cli, scene):
    (tmp_path / "blocker").write_text("a file, not a folder")
    # The FMU cannot be written: an output error.
    out = run_cli("export", scene, "-o", "blocker/x.fmu")
    assert out.returncode == 1 and out.stderr.startswith("error: ") and "blocker" in out.stderr, out.stderr
    # A bad scene.
    bad = tmp_path / "bad.toml"
    bad.write_text(scene_text(nu=0.7))
    out = run_cli("export", bad, "-o", "x.fmu")
    assert out.returncode == 2 and f"{bad}:" in out.stderr
    # The inputs table cannot be written.
    out = run_cli("inputs", scene, "-o", "blocker/inputs.csv")
    assert out.returncode == 1 and out.stderr.startswith("error: ") and "blocker" in out.stderr
