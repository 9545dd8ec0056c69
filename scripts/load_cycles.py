"""Memory that loading and unloading the FMU's library leaves behind (issue
35, item 2): per cycle, dlopen the FMU's library, instantiate, initialise,
set inputs, doStep, save and restore the state, a directional derivative
(when asked), terminate, free the instance and dlclose; the
resident size of this process after each cycle. Prints the growth per cycle
and how many copies of the library are still mapped.

    .venv/bin/python scripts/load_cycles.py FMU [--cycles N] [--set NAME=VALUE ...]
                         [--derivative OUTPUT,INPUT] [--copy] [--max-kib-per-cycle K]
                         [--way full|init|step|unterminated] [--fmpy]

FMU is a .fmu or an extracted folder. `--copy` loads the library from a new
path each cycle (as a sweep that extracts an FMU per case does): a library
that dlclose does not unload then stays mapped once per cycle. The calls go
through ctypes, not fmpy: fmpy's own objects grow by about 9 KiB a cycle,
which would hide a leak of that size; `--fmpy` makes the same cycles
through fmpy's FMU2Slave (whose freeInstance unloads the library).
`--way` sets how far a cycle goes before the free: `full` (the default:
everything above), `init` (initialise, terminate), `step` (initialise, a
step, terminate), `unterminated` (initialise, a step, no fmi2Terminate).
Exits 1 when the growth per cycle exceeds --max-kib-per-cycle (when given).
"""

import argparse
import ctypes
import os
import shutil
import sys
import tempfile
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import _ctypes

LOGGER = ctypes.CFUNCTYPE(
    None, ctypes.c_void_p, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_char_p
)
ALLOCATE = ctypes.CFUNCTYPE(ctypes.c_void_p, ctypes.c_size_t, ctypes.c_size_t)
FREE = ctypes.CFUNCTYPE(None, ctypes.c_void_p)
STEP_FINISHED = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_int)


class Callbacks(ctypes.Structure):
    _fields_ = [
        ("logger", LOGGER),
        ("allocateMemory", ALLOCATE),
        ("freeMemory", FREE),
        ("stepFinished", STEP_FINISHED),
        ("componentEnvironment", ctypes.c_void_p),
    ]


LIBC = ctypes.CDLL(None)
LIBC.calloc.restype = ctypes.c_void_p
LIBC.calloc.argtypes = [ctypes.c_size_t, ctypes.c_size_t]
LIBC.free.argtypes = [ctypes.c_void_p]
MESSAGES = []
CALLBACKS = Callbacks(
    LOGGER(lambda env, name, status, category, message: MESSAGES.append((status, message))),
    ALLOCATE(lambda n, size: LIBC.calloc(n, size)),
    FREE(lambda p: LIBC.free(p)),
    STEP_FINISHED(0),
    None,
)


def rss_kib() -> int:
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS"):
                return int(line.split()[1])
    raise RuntimeError("no VmRSS")


def mapped_copies(name: str) -> int:
    """How many distinct files called `name` this process has mapped."""
    with open("/proc/self/maps") as f:
        paths = {line.split(maxsplit=5)[-1].strip() for line in f if len(line.split()) > 5}
    return len({p for p in paths if p.removesuffix(" (deleted)").endswith("/" + name)})


class Unit:
    """The extracted FMU: its folder, GUID and variables by name."""

    def __init__(self, fmu: Path, folder: Path):
        if fmu.is_dir():
            shutil.copytree(fmu, folder)
        else:
            with zipfile.ZipFile(fmu) as z:
                z.extractall(folder)
        root = ET.parse(folder / "modelDescription.xml").getroot()
        self.folder = folder
        self.guid = root.get("guid").encode()
        self.identifier = root.find("CoSimulation").get("modelIdentifier")
        self.vr = {v.get("name"): int(v.get("valueReference")) for v in root.iter("ScalarVariable")}

    def library(self) -> Path:
        return self.folder / "binaries" / "linux64" / f"{self.identifier}.so"


def check(status: int, what: str):
    if status > 1:  # fmi2OK, fmi2Warning
        raise RuntimeError(f"{what} returned status {status}: {MESSAGES[-3:]}")


def cycle(unit: Unit, library: Path, k: int, inputs: dict, derivative, way: str):
    """One load, instance, use and unload through the C calls."""
    lib = ctypes.CDLL(str(library), mode=os.RTLD_NOW | os.RTLD_LOCAL)
    lib.fmi2Instantiate.restype = ctypes.c_void_p
    lib.fmi2Instantiate.argtypes = [
        ctypes.c_char_p,
        ctypes.c_int,
        ctypes.c_char_p,
        ctypes.c_char_p,
        ctypes.POINTER(Callbacks),
        ctypes.c_int,
        ctypes.c_int,
    ]
    resources = (unit.folder / "resources").as_uri().encode()
    c = lib.fmi2Instantiate(f"cycle{k}".encode(), 1, unit.guid, resources, ctypes.byref(CALLBACKS), 0, 0)
    if not c:
        raise RuntimeError(f"fmi2Instantiate failed: {MESSAGES[-3:]}")
    c = ctypes.c_void_p(c)
    lib.fmi2SetupExperiment.argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.c_double, ctypes.c_double, ctypes.c_int, ctypes.c_double]
    check(lib.fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), "fmi2SetupExperiment")
    check(lib.fmi2EnterInitializationMode(c), "fmi2EnterInitializationMode")
    check(lib.fmi2ExitInitializationMode(c), "fmi2ExitInitializationMode")
    if inputs:
        refs = (ctypes.c_uint * len(inputs))(*(unit.vr[n] for n in inputs))
        values = (ctypes.c_double * len(inputs))(*inputs.values())
        check(lib.fmi2SetReal(c, refs, ctypes.c_size_t(len(inputs)), values), "fmi2SetReal")
    lib.fmi2DoStep.argtypes = [ctypes.c_void_p, ctypes.c_double, ctypes.c_double, ctypes.c_int]
    if way != "init":
        check(lib.fmi2DoStep(c, 0.0, 1.0, 1), "fmi2DoStep")
    if way == "full":
        state = ctypes.c_void_p()
        check(lib.fmi2GetFMUstate(c, ctypes.byref(state)), "fmi2GetFMUstate")
        check(lib.fmi2SetFMUstate(c, state), "fmi2SetFMUstate")
        check(lib.fmi2FreeFMUstate(c, ctypes.byref(state)), "fmi2FreeFMUstate")
    if derivative and way == "full":
        unknown, known = (ctypes.c_uint * 1)(unit.vr[derivative[0]]), (ctypes.c_uint * 1)(unit.vr[derivative[1]])
        seed, out = (ctypes.c_double * 1)(1.0), (ctypes.c_double * 1)()
        one = ctypes.c_size_t(1)
        check(lib.fmi2GetDirectionalDerivative(c, unknown, one, known, one, seed, out), "fmi2GetDirectionalDerivative")
    if way != "unterminated":
        check(lib.fmi2Terminate(c), "fmi2Terminate")
    lib.fmi2FreeInstance(c)
    handle = lib._handle
    del lib
    _ctypes.dlclose(handle)


def fmpy_cycle(unit: Unit, k: int, inputs: dict, way: str):
    """One load, instance, use and unload through fmpy's FMU2Slave, whose
    freeInstance frees the instance and unloads the library."""
    from fmpy.fmi2 import FMU2Slave

    fmu = FMU2Slave(
        guid=unit.guid.decode(), unzipDirectory=str(unit.folder), modelIdentifier=unit.identifier, instanceName=f"cycle{k}"
    )
    fmu.instantiate(loggingOn=False)
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    if inputs:
        fmu.setReal([unit.vr[n] for n in inputs], list(inputs.values()))
    if way != "init":
        fmu.doStep(0.0, 1.0)
    if way != "unterminated":
        fmu.terminate()
    fmu.freeInstance()


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("fmu", type=Path)
    ap.add_argument("--cycles", type=int, default=300)
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE")
    ap.add_argument("--derivative", metavar="OUTPUT,INPUT", help="d OUTPUT / d INPUT after the step")
    ap.add_argument("--copy", action="store_true", help="load the library from a new path each cycle")
    ap.add_argument("--max-kib-per-cycle", type=float)
    ap.add_argument("--way", choices=["full", "init", "step", "unterminated"], default="full")
    ap.add_argument("--fmpy", action="store_true", help="the cycles through fmpy's FMU2Slave")
    args = ap.parse_args()
    inputs = {k: float(v) for k, v in (s.split("=", 1) for s in args.set)}
    warm = min(20, args.cycles // 4)
    with tempfile.TemporaryDirectory() as tmp:
        unit = Unit(args.fmu, Path(tmp) / "fmu")
        name = unit.library().name
        samples = []
        for k in range(args.cycles):
            library = unit.library()
            if args.copy:
                library = Path(tmp) / f"copy{k}" / name
                library.parent.mkdir()
                shutil.copy(unit.library(), library)
            if args.fmpy:
                fmpy_cycle(unit, k, inputs, args.way)
            else:
                cycle(unit, library, k, inputs, args.derivative and args.derivative.split(","), args.way)
            if args.copy:
                shutil.rmtree(library.parent)
            samples.append(rss_kib())
        left = mapped_copies(name)
    # After `warm` cycles the allocator and the interpreter have settled.
    # The allocator still holds freed memory now and then for a few cycles
    # (Hertz: +20 MiB over cycles 300..325 of 400, gone by 350), so the
    # growth is taken between the smallest sizes of a window after the
    # warm-up and of the last window: what every cycle leaves behind.
    w = max(5, args.cycles // 10)
    early, late = min(samples[warm - 1 : warm - 1 + w]), min(samples[-w:])
    per_cycle = (late - early) / (args.cycles - warm - w + 1)
    print(
        f"load_cycles: {args.cycles} cycles ({args.way}{', fmpy' if args.fmpy else ''}) of {args.fmu.name}"
        f"{' (a new copy each)' if args.copy else ''}: "
        f"RSS {samples[0]} KiB after the first, at least {early} over cycles {warm}..{warm + w - 1}, "
        f"at least {late} over the last {w}, {samples[-1]} after the last: "
        f"{per_cycle:.2f} KiB per cycle; library copies still mapped: {left}"
    )
    if args.max_kib_per_cycle is not None and per_cycle > args.max_kib_per_cycle:
        print(f"load_cycles: more than {args.max_kib_per_cycle} KiB per cycle", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
