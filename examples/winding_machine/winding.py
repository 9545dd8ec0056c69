"""The wire-winding machine example: builds its two FMUs and runs them
coupled, in fmpy (a master loop written here) and in libcosim (from
OspSystemStructure.xml), and draws the plots.

    python examples/winding_machine/winding.py --binary target/release/contact2d --out out/winding_machine

The machine's system model (machine.py, packaged by pythonfmu as
WindingMachine.fmu) and the contact FMU of the strip on the capstan
(capstan.toml, exported by `contact2d export`) exchange, at every
communication point:

    machine.theta_capstan -> capstan.drum.theta  the capstan drive's angle
    machine.back_Fy -> capstan.back.Fy           back tension from the dancer
    machine.pull_Fy -> capstan.pull.Fy           the winder span's tension
    capstan.strip.speed_in -> machine.speed_in   material run into the wrap
    capstan.strip.speed_out -> machine.speed_out material run out to the winder

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

# The capstan's friction coefficient, wrap, radius and tape thickness
# (capstan.toml).
MU = 0.25
WRAP = math.pi
SCENE_RADIUS = 100.0
THICKNESS = 0.05
# The strip's bends at the tangent points carry their reactions over the
# first five elements (of 128 over the wrap) from each.
BENDS = 5 * WRAP / 128

# The default schedule (machine.py): T2's set point 30 N, stepped to 36 N at
# 8 s; the line stops from 16 s and runs again from 19 s. Steady running is
# read at the end of each stretch at constant tensions; the tension along
# the wrap is drawn before the step, during its transient and at its end.
STEADY_AT = (7.95, 15.95, 26.0)
PROFILES_AT = (7.95, 8.75, 15.95)

# (machine output, capstan input) and (capstan output, machine input).
TO_CAPSTAN = [("theta_capstan", "drum.theta"), ("back_Fy", "back.Fy"), ("pull_Fy", "pull.Fy")]
TO_MACHINE = [("strip.speed_in", "speed_in"), ("strip.speed_out", "speed_out")]

MACHINE_RECORD = ["T1", "T2", "T2_demand", "v_line", "v_capstan", "v_winder", "trim", "R_winder", "x_dancer", "theta_capstan"]
CAPSTAN_REAL = [
    "strip.speed_in",
    "strip.speed_out",
    "strip.strain_in",
    "strip.strain_out",
    "strip.fed",
    "back.Fy",
    "pull.Fy",
    "drum.Mz",
    "wrap.Fn",
    "wrap.Ft",
    "wrap.stick_length",
    "wrap.slip_length",
]
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


def zones(angle, state, tn):
    """The slip arc at the exit and the stick arc (radians) from the nodes'
    angles along the wrap (from the tight end's tangent point) and their
    contact states (1 stick, 2 slip): the slip arc ends midway between the
    last sliding node from the exit and the first sticking one; the stick
    arc spans the sticking nodes from there, plus half a node spacing at
    its far end. No sticking node: the whole wrap slides. Also the stick
    zone's tension per mm of width, tn R averaged over its nodes beyond the
    entry's bend (BENDS; None without one)."""
    rows = sorted((a, st, p) for a, st, p in zip(angle, state, tn) if 0.0 < a < WRAP)
    sticking = [a for a, st, _ in rows if st == 1]
    if not sticking:
        return WRAP, 0.0, None
    first = sticking[0]
    slipping = [a for a, st, _ in rows if st == 2 and a < first]
    arc = 0.5 * (first + slipping[-1]) if slipping else 0.0
    spacing = statistics.median(y[0] - x[0] for x, y in zip(rows, rows[1:]))
    held = [p * SCENE_RADIUS for a, st, p in rows if st == 1 and a < WRAP - BENDS]
    return arc, sticking[-1] + 0.5 * spacing - arc, statistics.mean(held) if held else None


def steady_slip_arc(t1, t2):
    """The steady creep theory's slip arc at the exit (Johnson, Contact
    Mechanics, section 8.3): ln(T2 / T1) / mu, the whole wrap beyond
    T1 exp(mu theta)."""
    if t2 <= t1:
        return 0.0
    return min(WRAP, math.log(t2 / t1) / MU)


def run_fmpy(machine_fmu, capstan_fmu, stop_time, step, parameters=None, profiles_at=()):
    """Runs the coupled machine step by step in fmpy. Returns a dict of lists
    (one entry per communication point after t = 0, with the slip and
    stick arcs read from the capstan's nodes) and the capstan's contact
    profile (node angle along the wrap, tn, tt, state) at the times in
    profiles_at."""
    from fmpy.fmi1 import FMICallException

    machine = Slave(machine_fmu, "machine", parameters)
    capstan = Slave(capstan_fmu, "capstan")
    nodes = sum(1 for n in capstan.vr if n.startswith("wrap.x["))
    node_names = {k: [f"wrap.{k}[{i}]" for i in range(1, nodes + 1)] for k in ("angle", "tn", "tt")}
    state_names = [f"wrap.state[{i}]" for i in range(1, nodes + 1)]
    rec = {
        k: []
        for k in ["t", "wall_capstan", "wall_machine", "status", "layer", "slip_arc", "stick_arc", "stick_tension"] + MACHINE_RECORD + CAPSTAN_REAL + CAPSTAN_INT
    }
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
        angle, tn, states = capstan.get(node_names["angle"]), capstan.get(node_names["tn"]), capstan.get_int(state_names)
        slip, stick, held = zones(angle, states, tn)
        rec["slip_arc"].append(slip)
        rec["stick_arc"].append(stick)
        rec["stick_tension"].append(held)
        if any(abs(t - tp) < 0.5 * step for tp in profiles_at):
            tt = capstan.get(node_names["tt"])
            profiles.append({"t": t, "angle": angle, "tn": tn, "tt": tt, "state": states})
    rec["wall_total"] = time.perf_counter() - start
    machine.close()
    capstan.close()
    return rec, profiles


def run_libcosim(out_dir, stop_time, step):
    """Runs the system structure in out_dir with libcosim, step by step.
    Returns per communication point the machine's T2, capstan angle and
    layer, and the capstan's iterations, and whether every step succeeded."""
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
    rec = {"t": [], "T2": [], "theta_capstan": [], "layer": [], "iterations": []}
    ok = True
    start = time.perf_counter()
    for k in range(round(stop_time / step)):
        if not execution.step():
            ok = False
            break
        rec["t"].append(execution.status().current_time * 1e-9)
        t2, theta = observer.last_real_values(machine, [mref["T2"], mref["theta_capstan"]])
        rec["T2"].append(t2)
        rec["theta_capstan"].append(theta)
        rec["layer"].append(observer.last_integer_values(machine, [mref["layer"]])[0])
        rec["iterations"].append(observer.last_integer_values(capstan, [cref["solver.iterations"]])[0])
    rec["wall_total"] = time.perf_counter() - start
    return rec, ok


def capstan_tensions(rec, i, b):
    """T1 and T2 as the capstan carried them at communication point i (the
    end forces it stepped to, times the width)."""
    return -rec["back.Fy"][i] * b, -rec["pull.Fy"][i] * b


def creep_theory(rec, i):
    """(1 + e2) / (1 + e1) at communication point i, e the strain of the
    strip's mid-line at each end (the contact FMU's strip.strain_in and
    strain_out): how much faster material leaves the wrap than it enters
    in steady running."""
    return (1 + rec["strip.strain_out"][i]) / (1 + rec["strip.strain_in"][i])


def steady(rec, b, times):
    """At each time (after several wrap lengths at constant tensions), the
    measured zones and creep against the steady theory."""
    rows = []
    element = WRAP / 128  # capstan.toml: 128 elements over the wrap
    for t in times:
        i = min(range(len(rec["t"])), key=lambda k: abs(rec["t"][k] - t))
        t1, t2 = capstan_tensions(rec, i, b)
        arc, theory = rec["slip_arc"][i], steady_slip_arc(t1, t2)
        rows.append(
            {
                "t": rec["t"][i],
                "T1": t1,
                "T2": t2,
                "slip_arc_deg": math.degrees(arc),
                "slip_arc_theory_deg": math.degrees(theory),
                "slip_arc_error_elements": (arc - theory) / element,
                "stick_arc_deg": math.degrees(rec["stick_arc"][i]),
                "stick_tension": rec["stick_tension"][i] * b if rec["stick_tension"][i] else None,
                "speed_ratio": rec["strip.speed_out"][i] / rec["strip.speed_in"][i],
                "winder_over_capstan": rec["v_winder"][i] / rec["v_capstan"][i],
                "creep_theory": creep_theory(rec, i),
                # The winder against the capstan's surface: the creep and the
                # mid-line's radius over the drum's.
                "winder_theory": creep_theory(rec, i) * (1 + THICKNESS / (2 * SCENE_RADIUS)),
                "torque": rec["drum.Mz"][i] * b,
                "torque_theory": (t2 - t1) * (SCENE_RADIUS + THICKNESS / 2),
            }
        )
    return rows


def summary(rec, b, steady_at=()):
    """What the example shows, as numbers (printed and asserted by tests)."""
    wall = sorted(rec["wall_capstan"])
    return {
        "steps": len(rec["t"]),
        "discards": sum(1 for s in rec["status"] if s != 0),
        "layers": rec["layer"][-1] if rec["layer"] else 0,
        "fed_wraps": rec["strip.fed"][-1] / (WRAP * (SCENE_RADIUS + THICKNESS / 2)),
        "steady": steady(rec, b, steady_at),
        "doStep_median_ms": 1e3 * statistics.median(wall),
        "doStep_max_ms": 1e3 * wall[-1],
        "iterations_median": statistics.median(rec["solver.iterations"]),
        "iterations_max": max(rec["solver.iterations"]),
        "substeps": sum(rec["solver.substeps"]),
        "held_steps": sum(1 for i in rec["solver.iterations"] if i == 0),
        "wall_total_s": rec["wall_total"],
        "simulated_s": rec["t"][-1],
    }


def plots(rec, profiles, b, out_dir):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = rec["t"]
    fig, ax = plt.subplots(3, 2, figsize=(12, 11))
    a = ax[0][0]
    a.plot(t, rec["T2"], label="T2, the winder span's tension")
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
        # Nodes on the wrap in contact; angles from the tight end's tangent
        # point, along the wrap.
        i = min(range(len(t)), key=lambda k: abs(t[k] - p["t"]))
        keep = [k for k in range(len(p["angle"])) if 0 < p["angle"][k] < WRAP and p["state"][k] != 0]
        phi = [math.degrees(p["angle"][k]) for k in keep]
        line = a.plot(phi, [p["tn"][k] * SCENE_RADIUS * b for k in keep], ".", ms=3, label=f"t = {p['t']:.2f} s: tn R b")
        t1, t2 = capstan_tensions(rec, i, b)
        arc = steady_slip_arc(t1, t2)
        phis = [WRAP * x / 180 for x in range(181)]
        theory = [t2 * math.exp(-MU * x) if x < arc else t1 for x in phis]
        a.plot([math.degrees(x) for x in phis], theory, "-", lw=0.8, color=line[0].get_color())
    a.set_title("tension along the wrap; lines: steady creep theory")
    a.set_xlabel("angle from the tight end's tangent point (deg)")
    a.set_ylabel("N")
    a.legend(fontsize=7)
    a = ax[1][1]
    # At line speed only (gaps elsewhere): while the line stops and starts
    # the speeds' ratios carry the drives' lags.
    top = max(rec["v_line"])

    def at_speed(f):
        return [100 * (f(i) - 1) if rec["v_line"][i] == top else math.nan for i in range(len(t))]

    a.plot(t, at_speed(lambda i: rec["v_winder"][i] / rec["v_capstan"][i]), label="winder take-up / capstan surface")
    a.plot(t, at_speed(lambda i: rec["strip.speed_out"][i] / rec["strip.speed_in"][i]), ".", ms=2, label="speed_out / speed_in")
    a.plot(t, at_speed(lambda i: creep_theory(rec, i)), "k--", lw=0.8, label="(1 + e2) / (1 + e1), e the spans' strains")
    a.set_title("creep: what the winder must run faster than the capstan")
    a.set_ylabel("%")
    a.legend(fontsize=7)
    a = ax[2][0]
    a.plot(t, [math.degrees(x) for x in rec["slip_arc"]], label="slip arc (exit)")
    a.plot(t, [math.degrees(x) for x in rec["stick_arc"]], label="stick arc (entry)")
    # The steady theory while the capstan turns (standing still, the wrap
    # keeps the pattern it stopped with).
    theory = [steady_slip_arc(*capstan_tensions(rec, i, b)) if rec["v_capstan"][i] > 1.0 else math.nan for i in range(len(t))]
    a.plot(t, [math.degrees(x) for x in theory], "k--", lw=0.8, label="steady: ln(T2 / T1) / mu")
    a.plot(t, [180 - math.degrees(x) for x in theory], "k:", lw=0.8, label="steady: theta - ln(T2 / T1) / mu")
    a.set_title("stick and slip zones on the capstan")
    a.set_ylabel("deg")
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
    ap.add_argument("--stop", type=float, default=26.0, help="simulated time (s)")
    ap.add_argument("--step", type=float, default=0.025, help="communication step (s); the OSP file has 0.025")
    args = ap.parse_args()

    machine_fmu, capstan_fmu = build(args.binary, args.out)
    b = 2.0  # machine.py's strip width
    print(f"built {machine_fmu} and {capstan_fmu}")
    print(f"\n== fmpy, step by step: {args.stop:g} s in steps of {args.step:g} s")
    rec, profiles = run_fmpy(machine_fmu, capstan_fmu, args.stop, args.step, profiles_at=PROFILES_AT)
    s = summary(rec, b, [x for x in STEADY_AT if x <= args.stop])
    every = max(1, round(1.0 / args.step))
    print(
        f"{'t':>6} {'v_line':>7} {'T1':>7} {'T2':>7} {'set':>6} {'slip':>6} {'theory':>6} {'stick':>6} "
        f"{'creep%':>7} {'layer':>5} {'iter':>4} {'ms':>6}"
    )
    for i in range(every - 1, len(rec["t"]), every):
        theory = steady_slip_arc(*capstan_tensions(rec, i, b))
        creep = rec["v_winder"][i] / rec["v_capstan"][i] - 1 if rec["v_capstan"][i] > 0 else float("nan")
        print(
            f"{rec['t'][i]:6.2f} {rec['v_line'][i]:7.1f} {rec['T1'][i]:7.3f} {rec['T2'][i]:7.3f} {rec['T2_demand'][i]:6.1f} "
            f"{math.degrees(rec['slip_arc'][i]):6.1f} {math.degrees(theory):6.1f} {math.degrees(rec['stick_arc'][i]):6.1f} "
            f"{100 * creep:7.3f} {rec['layer'][i]:5d} {rec['solver.iterations'][i]:4d} {1e3 * rec['wall_capstan'][i]:6.1f}"
        )
    print(f"\nsteps {s['steps']}, Discards {s['discards']}, layers wound {s['layers']}, {s['fed_wraps']:.1f} wrap lengths run through")
    for row in s["steady"]:
        print(
            f"steady at t = {row['t']:.2f} s (T1 {row['T1']:.2f} N, T2 {row['T2']:.2f} N): slip arc {row['slip_arc_deg']:.2f} deg, "
            f"theory {row['slip_arc_theory_deg']:.2f} ({row['slip_arc_error_elements']:+.2f} elements); stick arc {row['stick_arc_deg']:.2f} "
            f"at {row['stick_tension']:.3f} N; "
            f"speed_out/speed_in {row['speed_ratio']:.5f}, (1+e2)/(1+e1) {row['creep_theory']:.5f}; "
            f"winder/capstan surface {row['winder_over_capstan']:.5f}, times (R+t/2)/R {row['winder_theory']:.5f}; drum torque {row['torque']:.2f} N mm, (T2-T1)(R+t/2) {row['torque_theory']:.2f}"
        )
    print(
        f"capstan doStep: median {s['doStep_median_ms']:.1f} ms, max {s['doStep_max_ms']:.1f} ms; "
        f"Newton iterations median {s['iterations_median']}, max {s['iterations_max']}; bisections {s['substeps']}; "
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
