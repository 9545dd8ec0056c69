"""Parameter sweeps of a contact2d FMU, serial or on a Dask cluster.

    from contact2d_sweep import grid, sweep, write_csv

    cases = grid({("wrap.mu_s", "wrap.mu_d"): [0.1, 0.2], "wrap_deg": [90.0, 180.0]})
    schedule = [(0.1 * k, {"pull.uy": -0.5 * k}) for k in range(1, 13)]
    rows = sweep("capstan.fmu", cases, schedule, ["pull.Ry", "wrap.n_stick"], client=None)
    write_csv(rows, "sweep.csv")

A case is one run of the FMU: a dict of variable name -> value. Its
parameters (a scene's `[parameters]`, material constants, `<pair>.mu_s`,
`<pair>.mu_d`, solver settings) are set in initialisation mode; its inputs
are held at that value for the whole run. The schedule is the master's
table, shared by every case: rows (t, {input: value}), t increasing from
the start time 0; at each row the inputs are set to the values they reach
at t (the FMU's convention: docs/fmu.md, "Input timing") and the FMU steps
to t. A run records the outputs asked for after every step ("all") or after
the last ("last").

With `client=None` the cases run one after the other in this process;
with a `distributed.Client` each case is one task: every worker extracts
the FMU itself once (an FMU instance cannot be pickled, its path can) and
runs its cases with fmpy's FMU2Slave. Both give the same rows, in the order
of `cases`. On a cluster beyond this machine, the FMU's path must be
readable on every worker (a shared file system) and this module importable
there (`client.upload_file("contact2d_sweep.py")`).
"""

from __future__ import annotations

import csv
import itertools
import math
import os
import tempfile
import threading
import uuid
from pathlib import Path

__all__ = ["fmpy_callbacks", "grid", "run_case", "sweep", "write_csv"]


def grid(axes: dict) -> list[dict]:
    """The cartesian product of `axes`: {name: values} -> one case (dict)
    per combination, the last axis varying fastest. A key that is a tuple
    of names gives all of them the same value (`("wrap.mu_s", "wrap.mu_d")`:
    one friction coefficient)."""
    keys = list(axes)
    cases = []
    for values in itertools.product(*(axes[k] for k in keys)):
        case = {}
        for key, value in zip(keys, values):
            for name in key if isinstance(key, tuple) else (key,):
                case[name] = value
        cases.append(case)
    return cases


# --- In each process that runs cases: the extracted FMUs and the logger. ---

_UNPACKED: dict = {}
_LOCK = threading.Lock()


def _unpacked(fmu: str):
    """(model description, folder) of `fmu`, extracted once per process and
    version of the file."""
    from fmpy import extract, read_model_description

    stat = os.stat(fmu)
    key = (os.path.realpath(fmu), stat.st_mtime_ns, stat.st_size)
    with _LOCK:
        if key not in _UNPACKED:
            folder = tempfile.TemporaryDirectory(prefix="contact2d-sweep-")
            extract(fmu, folder.name)
            # The TemporaryDirectory object is kept: the folder lives as long
            # as the process.
            _UNPACKED[key] = (read_model_description(folder.name), folder)
        md, folder = _UNPACKED[key]
    return md, folder.name


def fmpy_callbacks(logger):
    """fmpy's fmi2CallbackFunctions with `logger(env, instance_name, status,
    category, message)` as the FMU's logger, through fmpy's native proxy
    (addLoggerProxy), which formats the printf-style message. The proxy
    keeps one Python target per process: route the messages by instance
    name, and keep the returned struct alive as long as an instance uses it."""
    import ctypes

    from fmpy import calloc, free
    from fmpy.fmi2 import (
        fmi2CallbackAllocateMemoryTYPE,
        fmi2CallbackFreeMemoryTYPE,
        fmi2CallbackFunctions,
        fmi2CallbackLoggerTYPE,
    )
    from fmpy.logging import addLoggerProxy

    cb = fmi2CallbackFunctions()
    cb.logger = fmi2CallbackLoggerTYPE(logger)
    cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
    cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
    addLoggerProxy(ctypes.byref(cb))
    return cb


# The warnings and errors of each run of this process, by instance name.
_MESSAGES: dict = {}
_CALLBACKS = None


def _log(env, instance_name, status, category, message):
    name = instance_name.decode() if instance_name else ""
    if name in _MESSAGES and status >= 1:  # warnings, discards, errors
        _MESSAGES[name].append((message or b"").decode(errors="replace"))


def _callbacks():
    global _CALLBACKS
    with _LOCK:
        if _CALLBACKS is None:
            _CALLBACKS = fmpy_callbacks(_log)
    return _CALLBACKS


def _check(md, case: dict, schedule, outputs) -> dict:
    """The model variables by name, after checking that every name is one
    of the FMU's with the role it is given here."""
    variables = {v.name: v for v in md.modelVariables}

    def need(name, causalities, role):
        v = variables.get(name)
        if v is None:
            raise ValueError(f"{name!r} ({role}) is not a variable of the FMU {md.modelName!r}")
        if causalities and v.causality not in causalities:
            raise ValueError(f"{name!r} ({role}) has causality {v.causality!r}, not {' or '.join(causalities)}")

    for name in case:
        need(name, ("parameter", "input"), "case")
    previous = None
    for t, inputs in schedule:
        if previous is not None and not t > previous:
            raise ValueError(f"schedule times must increase: {t} after {previous}")
        previous = t
        for name in inputs:
            need(name, ("input",), "schedule")
            if name in case:
                raise ValueError(f"{name!r} is set by the case and by the schedule")
    if previous is None or previous <= 0.0:
        raise ValueError("the schedule needs at least one row at t > 0")
    for name in outputs:
        need(name, (), "output")
    return variables


def _set(fmu, v, value):
    if v.type == "Integer":
        fmu.setInteger([v.valueReference], [int(value)])
    elif v.type == "Boolean":
        fmu.setBoolean([v.valueReference], [bool(value)])
    elif v.type == "String":
        fmu.setString([v.valueReference], [str(value)])
    else:
        fmu.setReal([v.valueReference], [float(value)])


def _get(fmu, v):
    if v.type == "Integer":
        return fmu.getInteger([v.valueReference])[0]
    if v.type == "Boolean":
        return fmu.getBoolean([v.valueReference])[0]
    if v.type == "String":
        return fmu.getString([v.valueReference])[0].decode()
    return fmu.getReal([v.valueReference])[0]


def run_case(fmu, case: dict, schedule, outputs, record: str = "last", index: int = 0) -> list[dict]:
    """Runs one case of the FMU at path `fmu` through `schedule` (see the
    module's text) and returns its rows: the case's values, `case` (its
    index), `time`, each output, and `error` (None, or why the run stopped:
    the step that failed and the FMU's messages; the row then holds the
    outputs at the last time reached)."""
    from fmpy.fmi1 import FMICallException
    from fmpy.fmi2 import FMU2Slave

    if record not in ("last", "all"):
        raise ValueError(f"record must be 'last' or 'all', not {record!r}")
    md, folder = _unpacked(str(fmu))
    variables = _check(md, case, schedule, outputs)
    name = f"case{index}-{uuid.uuid4().hex[:8]}"
    messages = _MESSAGES.setdefault(name, [])
    slave = FMU2Slave(
        guid=md.guid,
        unzipDirectory=folder,
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName=name,
    )
    rows = []

    def row(t, error=None):
        r = dict(case)
        r["case"] = index
        r["time"] = t
        for out in outputs:
            try:
                r[out] = _get(slave, variables[out])
            except FMICallException:
                if error is None:
                    raise
                r[out] = math.nan  # an instance that failed may refuse it
        r["error"] = error
        return r

    try:
        slave.instantiate(callbacks=_callbacks())
        t = 0.0
        try:
            slave.setupExperiment(startTime=t, stopTime=schedule[-1][0])
            slave.enterInitializationMode()
            for n, value in case.items():
                if variables[n].causality == "parameter":
                    _set(slave, variables[n], value)
            slave.exitInitializationMode()
            for t_next, inputs in schedule:
                for n, value in case.items():
                    if variables[n].causality == "input":
                        _set(slave, variables[n], value)
                for n, value in inputs.items():
                    _set(slave, variables[n], value)
                slave.doStep(currentCommunicationPoint=t, communicationStepSize=t_next - t)
                t = t_next
                if record == "all":
                    rows.append(row(t))
        except FMICallException as e:  # a call that returned Discard or Error
            text = "; ".join(messages) or str(e)
            failed = row(t, f"at t = {t}: {e} {text}")
            # The failed row replaces the one of the last time reached.
            return [r for r in rows if r["time"] != t] + [failed]
        if record == "last":
            rows.append(row(t))
        slave.terminate()
        return rows
    finally:
        slave.freeInstance()
        _MESSAGES.pop(name, None)


def sweep(fmu, cases, schedule, outputs, client=None, record: str = "last") -> list[dict]:
    """Runs every case of `cases` (a list of dicts, e.g. from `grid`) of the
    FMU at path `fmu` through `schedule`, and returns the rows of all the
    runs in the order of `cases` (see `run_case`). `client`: None runs them
    here one after the other; a `distributed.Client` runs one task per case
    on its cluster (a `LocalCluster`, or any Dask cluster whose workers can
    read `fmu`)."""
    fmu = str(Path(fmu).resolve())
    schedule = [(float(t), dict(inputs)) for t, inputs in schedule]
    outputs = list(outputs)
    cases = [dict(c) for c in cases]
    # Wrong names are found here, before any task is sent.
    from fmpy import read_model_description

    md = read_model_description(fmu)
    for case in cases:
        _check(md, case, schedule, outputs)
    kwargs = dict(schedule=schedule, outputs=outputs, record=record)
    if client is None:
        per_case = [run_case(fmu, case, index=i, **kwargs) for i, case in enumerate(cases)]
    else:
        futures = [client.submit(run_case, fmu, case, index=i, pure=False, **kwargs) for i, case in enumerate(cases)]
        per_case = client.gather(futures)
    return [r for rows in per_case for r in rows]


def write_csv(rows: list[dict], path) -> Path:
    """Writes `rows` as a CSV table (one column per key, in first-seen
    order; floats with all their digits) and returns the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    columns = list(dict.fromkeys(k for r in rows for k in r))
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=columns)
        w.writeheader()
        for r in rows:
            w.writerow({k: (repr(v) if isinstance(v, float) and math.isfinite(v) else v) for k, v in r.items()})
    return path
