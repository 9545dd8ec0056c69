"""Shared fixtures: the contact2d binary and a way to run it."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
# examples/sweep/contact2d_sweep.py: fmpy's logger callbacks, and sweeps.
sys.path.insert(0, str(REPO / "examples" / "sweep"))


@pytest.fixture(scope="session")
def contact2d() -> Path:
    """The release binary (CONTACT2D_BIN overrides), built by scripts/test.sh."""
    path = Path(os.environ.get("CONTACT2D_BIN", REPO / "target" / "release" / "contact2d"))
    if not path.is_file():
        pytest.fail(f"{path} not found: build it with `cargo build --release`")
    return path


@pytest.fixture
def run_cli(contact2d, tmp_path):
    """Runs contact2d with the given arguments in tmp_path."""

    def run(*args) -> subprocess.CompletedProcess:
        return subprocess.run(
            [str(contact2d), *map(str, args)],
            cwd=tmp_path,
            capture_output=True,
            text=True,
            timeout=300,
        )

    return run


# --- The FMU (issue 4): exported once per session, opened through fmpy. ---

import json

SCENES = {
    "hertz": REPO / "scenes" / "hertz_plane_strain.toml",
    "sliding_block": REPO / "scenes" / "verification" / "sliding_block.toml",
    "tl_shear": REPO / "tests" / "data" / "scenes" / "tl_shear.toml",
}


# Where scripts/build_fmu_library.sh leaves the portable library (glibc
# 2.17), which `contact2d export` ships by default when it is up to date.
PORTABLE_LIBRARY = REPO / "target" / "x86_64-unknown-linux-gnu" / "fmu" / "libcontact2d.so"


def export_fmu(contact2d, scene, fmu, fmi=2) -> Path:
    """`contact2d export SCENE -o FMU --fmi FMI`, checked to ship the
    portable library: every FMU the tests load runs the binary that users
    get."""
    done = subprocess.run(
        [str(contact2d), "export", str(scene), "-o", str(fmu), "--fmi", str(fmi)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    assert "variables" in done.stdout, done.stdout
    assert f"(library {PORTABLE_LIBRARY})" in done.stdout, (
        f"{done.stdout}{done.stderr}export did not ship the portable library: "
        "build it with `bash scripts/build_fmu_library.sh` (scripts/test.sh does)"
    )
    return Path(fmu)


@pytest.fixture(scope="session")
def fmus(contact2d, tmp_path_factory) -> dict:
    """`contact2d export` of each scene of SCENES, once: name -> .fmu path."""
    out = tmp_path_factory.mktemp("fmus")
    return {name: export_fmu(contact2d, scene, out / f"{name}.fmu") for name, scene in SCENES.items()}


@pytest.fixture(scope="session")
def unpacked(fmus, tmp_path_factory) -> dict:
    """Each exported FMU extracted once (instances share the folder, as a
    master shares the loaded library between instances)."""
    from fmpy import extract

    base = tmp_path_factory.mktemp("unpacked")
    return {name: Path(extract(str(path), str(base / name))) for name, path in fmus.items()}


@pytest.fixture(scope="session")
def cli_summary(contact2d, tmp_path_factory):
    """`contact2d run SCENE --summary` -> the summary dict (cached per scene)."""
    cache = {}
    base = tmp_path_factory.mktemp("summaries")

    def summary(scene: Path) -> dict:
        key = str(scene)
        if key not in cache:
            path = base / f"{len(cache)}_{Path(scene).stem}.json"
            done = subprocess.run(
                [str(contact2d), "run", str(scene), "--summary", str(path)],
                capture_output=True,
                text=True,
                timeout=300,
            )
            assert done.returncode == 0, done.stderr
            cache[key] = json.loads(path.read_text())
        return cache[key]

    return summary


# One logger for every instance: fmpy's native proxy (addLoggerProxy), which
# formats the FMU's printf-style message, keeps a single Python target per
# process, so messages are routed by instance name.
_MESSAGES: dict = {}


def _route_log(env, instance_name, status, category, message):
    name = instance_name.decode() if instance_name else ""
    entry = (status, (category or b"").decode(), (message or b"").decode(errors="replace"))
    if name in _MESSAGES:
        _MESSAGES[name].append(entry)
    else:
        print(f"[{name} {status} {entry[1]}] {entry[2]}")


_CALLBACKS = None


def _callbacks():
    global _CALLBACKS
    if _CALLBACKS is None:
        from contact2d_sweep import fmpy_callbacks

        _CALLBACKS = fmpy_callbacks(_route_log)
    return _CALLBACKS


class Slave:
    """An fmpy FMU2Slave of an extracted FMU, with its log messages in
    `.messages` as (status, category, message), and value access by name."""

    _count = 0

    def __init__(self, unzipdir: Path, name: str = "fmu"):
        from fmpy import read_model_description
        from fmpy.fmi2 import FMU2Slave

        Slave._count += 1
        self.name = f"{name}-{Slave._count}"
        self.md = read_model_description(str(unzipdir))
        self.vars = {v.name: v for v in self.md.modelVariables}
        self.messages = _MESSAGES.setdefault(self.name, [])
        self.fmu = FMU2Slave(
            guid=self.md.guid,
            unzipDirectory=str(unzipdir),
            modelIdentifier=self.md.coSimulation.modelIdentifier,
            instanceName=self.name,
        )
        try:
            self.fmu.instantiate(callbacks=_callbacks())
        except Exception:
            self.fmu.freeLibrary()
            raise

    def vr(self, name):
        return self.vars[name].valueReference

    def init(self, **params):
        self.fmu.setupExperiment(startTime=0.0)
        self.fmu.enterInitializationMode()
        for k, v in params.items():
            self.set(k, v)
        self.fmu.exitInitializationMode()
        return self

    def set(self, name, value):
        if self.vars[name].type == "Integer":
            self.fmu.setInteger([self.vr(name)], [int(value)])
        else:
            self.fmu.setReal([self.vr(name)], [float(value)])

    def real(self, name) -> float:
        return self.fmu.getReal([self.vr(name)])[0]

    def int(self, name) -> int:
        return self.fmu.getInteger([self.vr(name)])[0]

    def reals(self, names) -> list:
        return self.fmu.getReal([self.vr(n) for n in names])

    def ints(self, names) -> list:
        return self.fmu.getInteger([self.vr(n) for n in names])

    def nodes(self, pair: str, what: str) -> list:
        m = sum(1 for n in self.vars if n.startswith(f"{pair}.{what}["))
        names = [f"{pair}.{what}[{k}]" for k in range(1, m + 1)]
        return self.ints(names) if what == "state" else self.reals(names)

    def outputs(self) -> dict:
        """Every output variable, by name (Integer ones as int)."""
        out = {}
        for name, v in self.vars.items():
            if v.causality == "output":
                out[name] = self.int(name) if v.type == "Integer" else self.real(name)
        return out

    def text(self) -> str:
        return "\n".join(m[2] for m in self.messages)

    def free(self):
        if self.fmu is not None:
            self.fmu.freeInstance()
            self.fmu = None


@pytest.fixture
def open_fmu(unpacked):
    """open_fmu("hertz") -> a new instantiated Slave; freed after the test."""
    made = []

    def open_(name: str, unzipdir: Path | None = None) -> Slave:
        s = Slave(unzipdir or unpacked[name], name)
        made.append(s)
        return s

    yield open_
    for s in reversed(made):
        s.free()


def assert_fmu_validates(fmu, fmi=2):
    """fmpy's validation and fmutool's compliance check (against FMI `fmi`:
    2 or 3) find no problem."""
    import sys

    from fmpy.validation import validate_fmu

    assert validate_fmu(str(fmu)) == []
    fmutool = Path(sys.executable).with_name("fmutool")
    done = subprocess.run([str(fmutool), "-input", str(fmu), "-check"], capture_output=True, text=True, timeout=120)
    out = done.stdout + done.stderr
    assert done.returncode == 0, out
    assert f"No semantic error against the FMI-{fmi} standard." in out, out
    assert "ERROR" not in out, out
