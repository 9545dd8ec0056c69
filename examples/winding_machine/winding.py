"""The wire-winding machine example: builds its two FMUs and runs them
coupled, in fmpy (a master loop written here) and in libcosim (from
OspSystemStructure.xml), and draws the plots.

    python examples/winding_machine/winding.py --binary target/release/contact2d --out out/winding_machine

The machine's system model (machine.py, packaged by pythonfmu as
WindingMachine.fmu) and the contact FMU of the strip on the capstan
(capstan.toml, exported by `contact2d export`) exchange, at every
communication point:

    machine.back_Fy -> capstan.back.Fy    back tension from the dancer
    machine.pull_uy -> capstan.pull.uy    the strip drawn by the winder
    capstan.pull.Ry -> machine.Ry_capstan the tension delivered to the winder
    capstan.back.uy -> machine.uy_back    the slack end's slide

Both masters are Jacobi (each FMU steps from the other's outputs at the start
of the step), so fmpy and libcosim compute the same run. The summary prints
what the tests assert (tests/python/test_winding_machine.py) and the cost per
capstan doStep.
"""

import argparse
import math
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
SCENE = HERE / "capstan.toml"
MACHINE = HERE / "machine.py"
OSP = HERE / "OspSystemStructure.xml"

# The capstan's friction coefficient, wrap and radius (capstan.toml).
MU = 0.25
WRAP = math.pi
SCENE_RADIUS = 100.0

# (machine output, capstan input) and (capstan output, machine input).
TO_CAPSTAN = [("back_Fy", "back.Fy"), ("pull_uy", "pull.uy")]
TO_MACHINE = [("pull.Ry", "Ry_capstan"), ("back.uy", "uy_back")]

MACHINE_RECORD = ["T1", "T2", "T2_demand", "v_line", "v_capstan", "v_winder", "u_pull", "trim", "R_winder", "x_dancer"]
CAPSTAN_REAL = ["pull.Ry", "back.uy", "wrap.Fn", "wrap.Ft", "wrap.stick_length", "wrap.slip_length"]
CAPSTAN_INT = ["wrap.n_stick", "wrap.n_slip", "wrap.n_open", "solver.iterations", "solver.substeps"]


def build(binary, out_dir):
    """Exports the capstan FMU and packages the machine FMU into out_dir;
    copies the system structure beside them. Returns (machine, capstan)."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    capstan = out_dir / "capstan.fmu"
    subprocess.run([str(binary), "export", str(SCENE), "-o", str(capstan)], check=True, stdout=subprocess.DEVNULL)
    subprocess.run(
        [sys.executable, "-m", "pythonfmu", "build", "-f", str(MACHINE), "-d", str(out_dir)],
        check=True,
        stdout=subprocess.DEVNULL,
    )
    shutil.copy(OSP, out_dir / OSP.name)
    return out_dir / "WindingMachine.fmu", capstan


class Slave:
    """One FMU in fmpy: instantiated, initialised, with its variables by name."""

    def __init__(self, path, name, parameters=None):
        from fmpy import extract, read_model_description
        from fmpy.fmi2 import FMU2Slave

        self.md = read_model_description(str(path))
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.dir = extract(str(path))
        self.fmu = FMU2Slave(
            guid=self.md.guid,
            unzipDirectory=self.dir,
            modelIdentifier=self.md.coSimulation.modelIdentifier,
            instanceName=name,
        )
        self.fmu.instantiate(loggingOn=False)
        self.fmu.setupExperiment(startTime=0.0)
        for key, value in (parameters or {}).items():
            self.fmu.setReal([self.vr[key]], [float(value)])
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()

    def get(self, names):
        return self.fmu.getReal([self.vr[n] for n in names])

    def get_int(self, names):
        return self.fmu.getInteger([self.vr[n] for n in names])

    def set(self, names, values):
        self.fmu.setReal([self.vr[n] for n in names], list(values))

    def close(self):
        self.fmu.terminate()
        self.fmu.freeInstance()
        shutil.rmtree(self.dir, ignore_errors=True)


def run_fmpy(machine_fmu, capstan_fmu, stop_time, step, parameters=None, profiles_at=()):
    """Runs the coupled machine step by step in fmpy. Returns a dict of lists
    (one entry per communication point after t = 0) and the capstan's
    contact profile (node angle, tn, tt, state) at the times in profiles_at."""
    from fmpy.fmi1 import FMICallException

    machine = Slave(machine_fmu, "machine", parameters)
    capstan = Slave(capstan_fmu, "capstan")
    nodes = sum(1 for n in capstan.vr if n.startswith("wrap.x["))
    node_names = {k: [f"wrap.{k}[{i}]" for i in range(1, nodes + 1)] for k in ("x", "y", "tn", "tt")}
    state_names = [f"wrap.state[{i}]" for i in range(1, nodes + 1)]
    rec = {k: [] for k in ["t", "wall_capstan", "wall_machine", "status", "layer"] + MACHINE_RECORD + CAPSTAN_REAL + CAPSTAN_INT}
    profiles = []
    n_steps = round(stop_time / step)
    t = 0.0
    start = time.perf_counter()
    for k in range(n_steps):
        # Jacobi: both FMUs step from the outputs at t.
        to_capstan = machine.get([m for m, _ in TO_CAPSTAN])
        to_machine = capstan.get([c for c, _ in TO_MACHINE])
        capstan.set([c for _, c in TO_CAPSTAN], to_capstan)
        machine.set([m for _, m in TO_MACHINE], to_machine)
        t0 = time.perf_counter()
        try:
            capstan.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=step)
            status = 0
        except FMICallException as e:
            status = e.status
        t1 = time.perf_counter()
        machine.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=step)
        t2 = time.perf_counter()
        t = (k + 1) * step
        rec["t"].append(t)
        rec["status"].append(int(status))
        rec["wall_capstan"].append(t1 - t0)
        rec["wall_machine"].append(t2 - t1)
        if status != 0:
            # A Discard (2) leaves the capstan at its last converged state;
            # the example stops there and reports it (the tests assert none).
            print(f"capstan doStep at t = {t - step:.3f}: status {status} (2: Discard)", file=sys.stderr)
            break
        for name, value in zip(MACHINE_RECORD, machine.get(MACHINE_RECORD)):
            rec[name].append(value)
        rec["layer"].append(machine.get_int(["layer"])[0])
        for name, value in zip(CAPSTAN_REAL, capstan.get(CAPSTAN_REAL)):
            rec[name].append(value)
        for name, value in zip(CAPSTAN_INT, capstan.get_int(CAPSTAN_INT)):
            rec[name].append(value)
        if any(abs(t - tp) < 0.5 * step for tp in profiles_at):
            x, y, tn, tt = (capstan.get(node_names[key]) for key in ("x", "y", "tn", "tt"))
            states = capstan.get_int(state_names)
            angles = [math.atan2(yy, xx) for xx, yy in zip(x, y)]
            profiles.append({"t": t, "angle": angles, "tn": tn, "tt": tt, "state": states})
    rec["wall_total"] = time.perf_counter() - start
    machine.close()
    capstan.close()
    return rec, profiles


def run_libcosim(out_dir, stop_time, step):
    """Runs the system structure in out_dir with libcosim, step by step.
    Returns per communication point the machine's T2, u_pull and layer, and
    the capstan's iterations, and whether every step succeeded."""
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver

    log_output_level(CosimLogLevel.WARNING)
    execution = CosimExecution.from_osp_config_file(str(Path(out_dir) / OSP.name))
    observer = CosimObserver.create_last_value()
    execution.add_observer(observer=observer)
    machine = execution.slave_index_from_instance_name("machine")
    capstan = execution.slave_index_from_instance_name("capstan")
    mref = {v.name.decode(): v.reference for v in execution.slave_variables(machine)}
    cref = {v.name.decode(): v.reference for v in execution.slave_variables(capstan)}
    rec = {"t": [], "T2": [], "u_pull": [], "layer": [], "iterations": []}
    ok = True
    start = time.perf_counter()
    for k in range(round(stop_time / step)):
        if not execution.step():
            ok = False
            break
        rec["t"].append(execution.status().current_time * 1e-9)
        t2, u = observer.last_real_values(machine, [mref["T2"], mref["u_pull"]])
        rec["T2"].append(t2)
        rec["u_pull"].append(u)
        rec["layer"].append(observer.last_integer_values(machine, [mref["layer"]])[0])
        rec["iterations"].append(observer.last_integer_values(capstan, [cref["solver.iterations"]])[0])
    rec["wall_total"] = time.perf_counter() - start
    return rec, ok


def full_slip_ratios(rec, b):
    """T2/T1 at the communication points where the whole wrap slides
    forward (no sticking node, T2 > T1), with T1 the force the capstan
    carries (-Fy b, the input it stepped to)."""
    out = []
    for i, t in enumerate(rec["t"]):
        if rec["wrap.n_stick"][i] == 0 and rec["T2"][i] > rec["T1"][i]:
            out.append((t, -rec["pull.Ry"][i] * b / rec["T1"][i]))
    return out


def summary(rec, b):
    """What the example shows, as numbers (printed and asserted by tests)."""
    wall = sorted(rec["wall_capstan"])
    slips = full_slip_ratios(rec, b)
    return {
        "steps": len(rec["t"]),
        "discards": sum(1 for s in rec["status"] if s != 0),
        "layers": rec["layer"][-1] if rec["layer"] else 0,
        "capstan_ratio_full_slip": [r for _, r in slips],
        "capstan_ratio_closed_form": math.exp(MU * WRAP),
        "doStep_median_ms": 1e3 * statistics.median(wall),
        "doStep_max_ms": 1e3 * wall[-1],
        "iterations_median": statistics.median(rec["solver.iterations"]),
        "iterations_max": max(rec["solver.iterations"]),
        "held_steps": sum(1 for i in rec["solver.iterations"] if i == 0),
        "wall_total_s": rec["wall_total"],
        "simulated_s": rec["t"][-1],
    }


def plots(rec, profiles, b, out_dir):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = rec["t"]
    fig, ax = plt.subplots(3, 2, figsize=(12, 10))
    a = ax[0][0]
    a.plot(t, rec["T2"], label="T2, delivered to the winder")
    a.plot(t, rec["T2_demand"], "--", label="T2 set point")
    a.plot(t, rec["T1"], label="T1, back tension (dancer)")
    a.plot(t, [math.exp(MU * WRAP) * x for x in rec["T1"]], ":", label="T1 exp(mu theta): the capstan's hold")
    a.set_title("line tension")
    a.set_ylabel("N")
    a.legend(fontsize=7)
    a = ax[0][1]
    a.plot(t, rec["v_line"], label="line speed set point")
    a.plot(t, rec["v_capstan"], label="capstan surface")
    a.plot(t, rec["v_winder"], "--", label="winder take-up")
    a2 = a.twinx()
    a2.step(t, rec["R_winder"], "k:", where="post", label="winding radius")
    a2.set_ylabel("winding radius (mm)")
    a.set_title("speeds; layers change the winding radius")
    a.set_ylabel("mm/s")
    a.legend(fontsize=7, loc="lower center")
    a = ax[1][0]
    for p in profiles:
        # Nodes in contact, the two end nodes left out (their tractions carry
        # the ends' bending); angles from the tight end's tangent point.
        keep = [k for k in range(1, len(p["angle"]) - 1) if p["state"][k] != 0]
        phi = [math.degrees(p["angle"][k] % (2 * math.pi)) for k in keep]
        phi = [x - 360.0 if x > 270.0 else x for x in phi]
        a.plot(phi, [p["tn"][k] * SCENE_RADIUS * b for k in keep], ".", ms=3, label=f"t = {p['t']:.2f} s: tn R b")
        i = min(range(len(t)), key=lambda k: abs(t[k] - p["t"]))
        if rec["wrap.n_stick"][i] == 0:
            phis = [math.radians(x) for x in range(181)]
            a.plot(range(181), [rec["T2"][i] * math.exp(-MU * x) for x in phis], "k-", lw=0.8, label="full slip: T2 exp(-mu phi)")
    a.set_title("tension along the wrap (membrane: T = tn R)")
    a.set_xlabel("angle from the tight end's tangent point (deg)")
    a.set_ylabel("N")
    a.legend(fontsize=7)
    a = ax[1][1]
    a.plot(t, [fn * b for fn in rec["wrap.Fn"]], label="normal resultant Fn b")
    a.plot(t, [ft * b for ft in rec["wrap.Ft"]], label="friction resultant Ft b")
    a.set_title("contact and friction forces on the capstan")
    a.set_ylabel("N")
    a.legend(fontsize=7)
    a = ax[2][0]
    a.plot(t, rec["wrap.stick_length"], label="stick zone")
    a.plot(t, rec["wrap.slip_length"], label="slip zone")
    a.set_title("stick and slip zone lengths")
    a.set_ylabel("mm")
    a.set_xlabel("time (s)")
    a.legend(fontsize=7)
    a = ax[2][1]
    a.plot(t, [1e3 * w for w in rec["wall_capstan"]], ".", ms=2, label="capstan doStep (ms)")
    a.plot(t, rec["solver.iterations"], ".", ms=2, label="Newton iterations")
    a.set_title("cost per step")
    a.set_xlabel("time (s)")
    a.set_yscale("symlog")
    a.legend(fontsize=7)
    fig.tight_layout()
    png = Path(out_dir) / "winding_machine.png"
    fig.savefig(png, dpi=100)
    plt.close(fig)
    return png


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--binary", required=True, help="the contact2d command line (target/release/contact2d)")
    ap.add_argument("--out", required=True, help="folder for the FMUs, plots and system structure")
    ap.add_argument("--stop", type=float, default=22.0, help="simulated time (s)")
    ap.add_argument("--step", type=float, default=0.025, help="communication step (s); the OSP file has 0.025")
    args = ap.parse_args()

    machine_fmu, capstan_fmu = build(args.binary, args.out)
    b = 2.0  # machine.py's strip width
    print(f"built {machine_fmu} and {capstan_fmu}")
    print(f"\n== fmpy, step by step: {args.stop:g} s in steps of {args.step:g} s")
    rec, profiles = run_fmpy(machine_fmu, capstan_fmu, args.stop, args.step, profiles_at=(2.5, 6.0, 11.0))
    s = summary(rec, b)
    every = max(1, round(1.0 / args.step))
    print(f"{'t':>6} {'v_line':>7} {'T1':>7} {'T2':>7} {'set':>6} {'stick':>7} {'slip':>7} {'layer':>5} {'iter':>4} {'ms':>6}")
    for i in range(every - 1, len(rec["t"]), every):
        print(
            f"{rec['t'][i]:6.2f} {rec['v_line'][i]:7.1f} {rec['T1'][i]:7.3f} {rec['T2'][i]:7.3f} {rec['T2_demand'][i]:6.1f} "
            f"{rec['wrap.stick_length'][i]:7.1f} {rec['wrap.slip_length'][i]:7.1f} {rec['layer'][i]:5d} "
            f"{rec['solver.iterations'][i]:4d} {1e3 * rec['wall_capstan'][i]:6.1f}"
        )
    ratios = s["capstan_ratio_full_slip"]
    print(f"\nsteps {s['steps']}, Discards {s['discards']}, layers wound {s['layers']}")
    if ratios:
        err = [r / s["capstan_ratio_closed_form"] - 1 for r in ratios]
        print(
            f"full slip: T2/T1 = {min(ratios):.4f} .. {max(ratios):.4f} over {len(ratios)} steps; "
            f"exp(mu theta) = {s['capstan_ratio_closed_form']:.4f} (error {min(err):+.2%} .. {max(err):+.2%})"
        )
    print(
        f"capstan doStep: median {s['doStep_median_ms']:.1f} ms, max {s['doStep_max_ms']:.1f} ms; "
        f"Newton iterations median {s['iterations_median']}, max {s['iterations_max']}; "
        f"{s['held_steps']} steps with held inputs (0 iterations)"
    )
    print(f"coupled run: {s['wall_total_s']:.1f} s wall for {s['simulated_s']:.1f} s simulated")
    png = plots(rec, profiles, b, args.out)
    print(f"plot: {png}")

    print(f"\n== libcosim, from {Path(args.out) / OSP.name}")
    cosim, ok = run_libcosim(args.out, args.stop, 0.025)
    worst = max(abs(a - c) for a, c in zip(rec["T2"], cosim["T2"])) if args.step == 0.025 else float("nan")
    print(
        f"{'completed' if ok else 'FAILED'}: {len(cosim['t'])} steps, {cosim['wall_total']:.1f} s wall; "
        f"layers {cosim['layer'][-1] if cosim['layer'] else 0}; largest |T2 libcosim - T2 fmpy| = {worst:.2e} N"
    )
    return 0 if ok and s["discards"] == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
