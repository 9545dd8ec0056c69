"""The paper's sample problems (Section 4) as figures: runs the shipped scenes
with the command line and plots them beside what they are compared with.

    .venv/bin/python scripts/paper_figures.py [--bin target/release/contact2d] [--out docs/figures]

Hertz (Section 4.1, Figs. 6-9) here, plane strain (R = 10) and
axisymmetric (R = 100), small strain, materially-nonlinear-only and total
Lagrangian, normal tractions against Hertz at each load step; and the
contactor refined, to show the extra solution points its extra segments
give (the paper's remark under Fig. 7). Prints per run the RMS error over
the contact zone (% of p0) and the run time; docs/paper-problems.md quotes
them.
"""

import argparse
import importlib
import math
import re
import subprocess
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from paper import cli  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
# Sections 4.2, 4.3 and 4.4: modules of scripts/paper/.
PROBLEMS = ["rubber_sheet", "wire_winding", "buried_pipe"]
E, NU = 200000.0, 0.3
E_STAR = E / (1 - NU * NU)


def run(binary, scene_text, name, workdir):
    """Runs an edited scene; returns (summary, wall seconds)."""
    return cli.run_text(binary, scene_text, name, workdir)


def reference_x(binary, scene_text, name, workdir):
    """Contactor node x before loading, read from the scene's FMU at rest
    (the summary reports current positions; linear theory, and the small-
    strain tractions, live on the reference geometry)."""
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave

    scene = workdir / f"{name}.toml"
    scene.write_text(scene_text)
    fmu = workdir / f"{name}.fmu"
    subprocess.run([str(binary), "export", str(scene), "-o", str(fmu)], check=True, capture_output=True)
    md = read_model_description(str(fmu))
    xs = sorted(
        (int(v.name.split("[")[1][:-1]), v.valueReference)
        for v in md.modelVariables
        if re.fullmatch(r"[^.]+\.x\[\d+\]", v.name)
    )
    slave = FMU2Slave(guid=md.guid, unzipDirectory=extract(str(fmu)), modelIdentifier="contact2d", instanceName=name)
    slave.instantiate()
    slave.setupExperiment(startTime=0.0)
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    x = slave.getReal([vr for _, vr in xs])
    slave.terminate()
    slave.freeInstance()
    return x


def hertz(kind, fn, radius):
    """(a, p0, p(x)) with P from the computed resultant."""
    if kind == "plane":
        p = 2.0 * fn  # the quarter model carries P/2
        a = math.sqrt(4 * p * radius / (math.pi * E_STAR))
        p0 = 2 * p / (math.pi * a)
    else:
        p = fn  # axisymmetric resultants are over the full circle
        a = (3 * p * radius / (4 * E_STAR)) ** (1 / 3)
        p0 = 3 * p / (2 * math.pi * a * a)
    return a, p0, lambda x: p0 * math.sqrt(max(0.0, 1 - (x / a) ** 2))


def rms(xref, nodes, a, p0, law):
    """RMS of tn - p(X) over the contact zone (closed nodes, and open ones
    with X < a), X the reference position, in units of p0: the metric of
    tests/contact_hertz.rs."""
    errs = [tn - law(x) for x, tn, s in zip(xref, nodes["tn"], nodes["state"]) if s != 0 or x < a]
    return math.sqrt(sum(e * e for e in errs) / max(len(errs), 1)) / p0


def edit(text, kinematics=None, divisions=None):
    if kinematics:
        text = re.sub(r'^kinematics = ".*"', f'kinematics = "{kinematics}"', text, flags=re.M)
    if divisions:
        text = re.sub(r"divisions = \d+", f"divisions = {divisions}", text)
    return text


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default=str(REPO / "target" / "release" / "contact2d"))
    ap.add_argument("--out", default=str(REPO / "docs" / "figures"))
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    work = Path(tempfile.mkdtemp(prefix="paper_figures_"))

    cases = [
        ("plane", "hertz_plane_strain.toml", 10.0, "Hertz, cylinder R = 10, plane strain"),
        ("axi", "hertz_axisymmetric.toml", 100.0, "Hertz, sphere R = 100, axisymmetric"),
    ]
    kinematics = [("small_strain", "small strain"), ("mno", "M.N.O."), ("total_lagrangian", "T.L.")]
    print(f"{'problem':<34} {'kinematics':<13} {'P (last)':>10} {'a':>7} {'rms/p0 per step':<32} {'run s':>6}")
    for kind, file, radius, title in cases:
        text = (REPO / "scenes" / file).read_text()
        xref = reference_x(args.bin, text, f"{kind}_rest", work)
        fig, axes = plt.subplots(1, 3, figsize=(15, 4.3), sharey=True)
        for ax, (kin, label) in zip(axes, kinematics):
            summary, wall = run(args.bin, edit(text, kin), f"{kind}_{kin}", work)
            errors = []
            for step in summary["steps"]:
                pair = next(iter(step["pairs"].values()))
                nodes = pair["nodes"]
                a, p0, law = hertz(kind, pair["Fn"], radius)
                # Small strain and M.N.O. report tractions per reference area
                # (linear theory, as Hertz's): compare at the reference X.
                # T.L. reports Cauchy tractions: compare at the current x.
                at = nodes["x"] if kin == "total_lagrangian" else xref
                errors.append(rms(at, nodes, a, p0, law))
                closed = [k for k, s in enumerate(nodes["state"]) if s != 0]
                hi = min(max(closed) + 2, len(nodes["x"]))
                xs = at[:hi]
                line = ax.plot(xs, nodes["tn"][:hi], "o", ms=3, label=f"t = {step['time']:g}")[0]
                grid = [a * i / 100 for i in range(101)]
                ax.plot(grid, [law(x) for x in grid], "-", color=line.get_color(), lw=0.8)
            p_last = 2 * pair["Fn"] if kind == "plane" else pair["Fn"]
            ax.set_title(f"{label}: points computed, lines Hertz")
            ax.set_xlabel("current x (r)" if kin == "total_lagrangian" else "reference X (r)")
            ax.set_xlim(0, 1.3 * a)
            ax.grid(True)
            ax.legend(fontsize=7)
            errs = " ".join(f"{100 * e:.2f}%" for e in errors)
            print(f"{title:<34} {label:<13} {p_last:10.1f} {a:7.4f} {errs:<32} {wall:6.2f}")
        axes[0].set_ylabel("normal traction tn")
        fig.suptitle(title)
        fig.tight_layout()
        fig.savefig(out / f"{Path(file).stem}.png", dpi=100)
        plt.close(fig)

    # The paper's remark under Fig. 7: a finer contactor mesh has more
    # segments in the contact zone, hence more solution points.
    text = (REPO / "scenes" / "hertz_plane_strain.toml").read_text()
    fig, ax = plt.subplots(figsize=(7, 4.3))
    for div, marker in [(15, "s"), (30, "^"), (60, "o")]:
        summary, wall = run(args.bin, edit(text, divisions=div), f"plane_div{div}", work)
        xref = reference_x(args.bin, edit(text, divisions=div), f"plane_div{div}_rest", work)
        pair = next(iter(summary["steps"][-1]["pairs"].values()))
        nodes = pair["nodes"]
        a, p0, law = hertz("plane", pair["Fn"], 10.0)
        closed = [k for k, s in enumerate(nodes["state"]) if s != 0]
        hi = min(max(closed) + 2, len(nodes["x"]))
        ax.plot(xref[:hi], nodes["tn"][:hi], marker, ms=4, mfc="none",
                label=f"{div} divisions: {len(closed)} nodes in contact, rms {100 * rms(xref, nodes, a, p0, law):.2f}% p0")
        print(f"{'refinement, plane strain':<34} {div:>3} divisions  {len(closed):3d} nodes in contact  "
              f"rms {100 * rms(xref, nodes, a, p0, law):.2f}% of p0  {wall:.2f} s")
    grid = [a * i / 200 for i in range(201)]
    ax.plot(grid, [law(x) for x in grid], "k-", lw=0.8, label="Hertz")
    ax.set_xlim(0, 1.3 * a)
    ax.set_xlabel("reference X")
    ax.set_ylabel("normal traction tn")
    ax.set_title("Hertz plane strain, P = 6600: contactor refined")
    ax.grid(True)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "hertz_refinement.png", dpi=100)
    plt.close(fig)

    # The other problems, one module each in scripts/paper/: figure(binary,
    # out_dir, work_dir) runs its scene's cases, writes its PNG and returns
    # the lines to print.
    for module in PROBLEMS:
        for line in importlib.import_module(f"paper.{module}").figure(args.bin, out, work):
            print(line)
    print(f"figures: {out}")


if __name__ == "__main__":
    main()
