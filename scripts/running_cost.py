"""The running capstan's cost over a long run (issue 34): its FMU
(scenes/running_capstan.toml) driven in fmpy for N steps at T2 = 1.8 T1, the
drum turning one element of the wrap per step; prints the median doStep
wall time of the first and the last 1,000 steps, their ratio, and the
process's resident memory after the first and the last 1,000 steps.

    .venv/bin/python scripts/running_cost.py --binary target/release/contact2d --steps 10000

A step costs the same after any distance run (the mesh, the pattern and the
contact pair never change; docs/contact.md section 12): the ratio stays
near 1 and the memory flat.
"""

import argparse
import math
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
T1, T2 = 20.0, 36.0
ELEMENT = math.pi / 128


def rss_mib() -> float:
    """The current resident set size, from /proc (Linux)."""
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024.0
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--binary", default=str(REPO / "target" / "release" / "contact2d"))
    ap.add_argument("--steps", type=int, default=10000)
    args = ap.parse_args()
    window = min(1000, args.steps // 2)

    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave

    tmp = Path(tempfile.mkdtemp())
    fmu = tmp / "running_capstan.fmu"
    scene = REPO / "scenes" / "running_capstan.toml"
    subprocess.run([args.binary, "export", str(scene), "-o", str(fmu)], check=True, capture_output=True)
    unzipdir = extract(str(fmu), str(tmp / "unpacked"))
    md = read_model_description(unzipdir)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    slave = FMU2Slave(
        guid=md.guid,
        unzipDirectory=unzipdir,
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="cost",
    )
    slave.instantiate()
    slave.setupExperiment(startTime=0.0)
    slave.enterInitializationMode()
    slave.setReal([vr["T2"]], [T2])
    slave.exitInitializationMode()

    t, theta, dt = 0.0, 0.0, 0.25
    walls, iterations, memory = [], [], {}
    for k in range(4 + args.steps):
        pull = T1 + (T2 - T1) * min(k + 1, 4) / 4
        if k >= 4:
            theta += ELEMENT
        slave.setReal([vr["back.Fy"], vr["pull.Fy"], vr["drum.theta"]], [-T1, -pull, theta])
        start = time.perf_counter()
        slave.doStep(t, dt)  # fmpy raises on a status other than OK
        wall = time.perf_counter() - start
        t += dt
        if k >= 4:
            walls.append(wall)
            iterations.append(slave.getInteger([vr["solver.iterations"]])[0])
            done = len(walls)
            if done == window:
                memory["first"] = rss_mib()
            if done == args.steps:
                memory["last"] = rss_mib()
    fed = slave.getReal([vr["strip.fed"]])[0]
    slave.terminate()
    slave.freeInstance()

    first, last = walls[:window], walls[-window:]
    m0, m1 = statistics.median(first), statistics.median(last)
    wraps = fed / (math.pi * 100.05)
    print(f"{args.steps} steps, {wraps:.1f} wrap lengths fed ({fed:.0f} mm)")
    print(f"median doStep: first {window} {m0 * 1e3:.2f} ms, last {window} {m1 * 1e3:.2f} ms, ratio {m1 / m0:.3f}")
    print(
        f"Newton iterations per step: first {window} median {statistics.median(iterations[:window])} "
        f"max {max(iterations[:window])}, last {window} median {statistics.median(iterations[-window:])} "
        f"max {max(iterations[-window:])}"
    )
    print(f"resident memory: after the first {window} steps {memory['first']:.1f} MiB, at the end {memory['last']:.1f} MiB")
    return 0


if __name__ == "__main__":
    sys.exit(main())
