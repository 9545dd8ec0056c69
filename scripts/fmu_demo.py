"""Drives a contact2d FMU step by step in fmpy, as a system model would.

    python scripts/fmu_demo.py X.fmu --input press.uy --path 0:0 1:-0.07 1.6:-0.02 \
        --steps 8 5 --pair contact --out DIR [--set NAME=VALUE ...]

The input follows the piecewise linear path (time:value pairs), each leg cut
into the given number of steps; after every step the script prints the
contact resultants, the stick/slip/open counts and the Newton work, and at
the end it writes DIR/tractions.png: the normal and tangential tractions
over the contact surface at a few steps, in the scene's units, with Hertz's
pressure when the FMU's scene is a Hertz problem and without a panel of
round-off (scripts/traction_plots.py).
"""

import argparse
import os
import sys

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import traction_plots as tp  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("fmu")
    ap.add_argument("--input", required=True, help="input variable driven along --path")
    ap.add_argument("--path", nargs="+", required=True, help="time:value points, first at the start time")
    ap.add_argument("--steps", nargs="+", type=int, required=True, help="steps per leg of the path")
    ap.add_argument("--set", nargs="*", default=[], help="NAME=VALUE inputs held from the first step on")
    ap.add_argument("--pair", required=True, help="contact pair whose tractions are plotted")
    ap.add_argument("--out", required=True, help="folder for tractions.png")
    args = ap.parse_args()

    points = [tuple(float(v) for v in p.split(":")) for p in args.path]
    if len(args.steps) != len(points) - 1:
        ap.error("--steps needs one count per leg of --path")

    md = read_model_description(args.fmu)
    vars_ = {v.name: v for v in md.modelVariables}
    held = [(n, float(v)) for n, v in (a.split("=") for a in args.set)]
    for name in [args.input, f"{args.pair}.Fn"] + [n for n, _ in held]:
        if name not in vars_:
            ap.error(f"{args.fmu} has no variable {name}")
    nodes = sum(1 for n in vars_ if n.startswith(f"{args.pair}.x["))
    vr = lambda name: vars_[name].valueReference  # noqa: E731
    reals = [f"{args.pair}.{k}" for k in ("Fx", "Fy", "Fn", "Ft")] + ["solver.residual"]
    ints = [f"{args.pair}.{k}" for k in ("n_stick", "n_slip", "n_open")] + ["solver.iterations", "solver.substeps"]
    node_vars = {k: [vr(f"{args.pair}.{k}[{i}]") for i in range(1, nodes + 1)] for k in ("x", "tn", "tt")}
    state_vrs = [vr(f"{args.pair}.state[{i}]") for i in range(1, nodes + 1)]

    unpacked = extract(args.fmu)
    fmu = FMU2Slave(
        guid=md.guid,
        unzipDirectory=unpacked,
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="demo",
    )
    fmu.instantiate(loggingOn=False)
    t = points[0][0]
    fmu.setupExperiment(startTime=t)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    for name, value in held:
        fmu.setReal([vr(name)], [value])

    print(f"{md.modelName}: {len(md.modelVariables)} variables, {nodes} contactor nodes in pair '{args.pair}'")
    head = f"{'step':>4} {'time':>7} {args.input:>12} " + " ".join(f"{r.split('.')[-1]:>12}" for r in reals[:4])
    head += f" {'stick':>5} {'slip':>5} {'open':>5} {'iter':>4} {'sub':>3} {'|r|/F':>9}"
    print(head)
    snapshots = []
    step = 0
    for (t0, v0), (t1, v1), n in zip(points, points[1:], args.steps):
        for k in range(1, n + 1):
            s = k / n
            t_next, value = t0 + s * (t1 - t0), v0 + s * (v1 - v0)
            fmu.setReal([vr(args.input)], [value])
            fmu.doStep(currentCommunicationPoint=t, communicationStepSize=t_next - t)
            t = t_next
            step += 1
            fx, fy, fn, ft, res = fmu.getReal([vr(n_) for n_ in reals])
            stick, slip, open_, its, subs = fmu.getInteger([vr(n_) for n_ in ints])
            print(
                f"{step:4d} {t:7.3f} {value:12.5g} {fx:12.5g} {fy:12.5g} {fn:12.5g} {ft:12.5g} "
                f"{stick:5d} {slip:5d} {open_:5d} {its:4d} {subs:3d} {res:9.2e}"
            )
            if k == n or k == n // 2:
                x = fmu.getReal(node_vars["x"])
                tn = fmu.getReal(node_vars["tn"])
                tt = fmu.getReal(node_vars["tt"])
                st = fmu.getInteger(state_vrs)
                label = f"t = {t:g}, {args.input} = {value:.4g}"
                snapshots.append(tp.Snapshot(label, x, tn, tt, st, fn))
    fmu.terminate()
    fmu.freeInstance()

    # The scene travels in the FMU: its units, and whether it is a Hertz
    # problem.
    scene = tp.load_scene(os.path.join(unpacked, "resources", "scene.toml"))
    hertz = tp.hertz_reference(scene, args.pair)
    plan = tp.plan(args.pair, snapshots, tp.scene_units(scene), hertz)
    for c in (c for panel in plan.panels for c in panel.curves if c.analytic_of):
        print(c.label)
    for d in plan.dropped:
        print(d)
    png = tp.draw([plan], os.path.join(args.out, "tractions.png"))
    print(f"plot: {png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
