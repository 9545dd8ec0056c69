"""The rubber sheet in a converging channel (Section 4.2, Figs. 10-12): runs
scenes/rubber_sheet.toml with the command line for the paper's four friction
cases and draws Fig. 12, the normal and tangential tractions along the
channel at t = 8, 14 (pushed in), 18 (just reversed) and 24 (pulled out).

    .venv/bin/python scripts/paper/rubber_sheet.py [--bin target/release/contact2d] [--out docs/figures]

`figure(binary, out_dir, work_dir)` is what scripts/paper_figures.py calls;
it returns the lines to print (per case and time: Fn, Ft, stick/slip/open
counts, the current x range of the contact zone; per case the run time).
"""

import sys
from pathlib import Path

# The sibling modules, also when this file runs on its own.
if str(Path(__file__).resolve().parents[1]) not in sys.path:
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from paper import cli  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
SCENE = REPO / "scenes" / "rubber_sheet.toml"
PAIR = "channel"
TIMES = (8.0, 14.0, 18.0, 24.0)
# The shipped [[contact]] coefficients, and what each case puts in their place.
SHIPPED = "mu_s = 0.15\nmu_d = 0.15"
CASES = (
    ("mu_s = mu_d = 0.15", SHIPPED, dict(color="C0", ls="-", marker="o", ms=3)),
    (
        "mu_s = 0.20, mu_d = 0.15 (once slid, mu_d)",
        "mu_s = 0.20\nmu_d = 0.15",
        dict(color="C2", ls="none", marker="x", ms=5),
    ),
    (
        "mu_s = 0.20, mu_d = 0.15 (mu_s kept: experiment)",
        'mu_s = 0.20\nmu_d = 0.15\nrule = "always_mu_s"',
        dict(color="C3", ls="--", marker="none"),
    ),
    ("frictionless", "mu_s = 0.0", dict(color="C7", ls=":", marker="s", ms=2)),
)


def solve(binary, text, stem, work_dir):
    """Writes the scene text, runs it, returns (summary steps by time, seconds)."""
    summary, seconds = cli.run_text(binary, text, stem, work_dir)
    steps = summary["steps"]
    assert steps[-1]["converged"], f"{stem}: no convergence at t = {steps[-1]['time']}"
    return {round(s["time"], 9): s for s in steps}, seconds


def closed(nodes):
    """(x, tn, tt) of the contactor nodes in contact, in order of x."""
    rows = sorted(
        (x, tn, tt)
        for x, tn, tt, state in zip(nodes["x"], nodes["tn"], nodes["tt"], nodes["state"])
        if state != 0
    )
    return [r[0] for r in rows], [r[1] for r in rows], [r[2] for r in rows]


def figure(binary, out_dir, work_dir):
    """Runs the four cases, saves rubber_sheet.png in out_dir, returns the
    lines to print."""
    base = SCENE.read_text()
    assert base.count(SHIPPED) == 1, "the shipped scene's [[contact]] coefficients changed"
    fig, axes = plt.subplots(2, len(TIMES), figsize=(16, 7), sharex="col")
    lines = []
    for i, (label, coefficients, style) in enumerate(CASES):
        # The paper's decisions (the scene runs the default ones).
        paper = coefficients + '\ndecisions = "paper"'
        steps, seconds = solve(binary, base.replace(SHIPPED, paper), f"rubber_sheet_{i}", work_dir)
        for j, t in enumerate(TIMES):
            step = steps[t]
            pair = step["pairs"][PAIR]
            x, tn, tt = closed(pair["nodes"])
            axes[0, j].plot(x, tn, label=label, **style)
            axes[1, j].plot(x, tt, label=label, **style)
            lines.append(
                f"rubber sheet  {label:48s} t = {t:4.0f}  Fn {pair['Fn']:9.4f}  Ft {pair['Ft']:+8.4f}  "
                f"|Ft|/Fn {abs(pair['Ft']) / pair['Fn']:.4f}  stick/slip/open "
                f"{pair['n_stick']}/{pair['n_slip']}/{pair['n_open']}  contact x {x[0]:7.2f} .. {x[-1]:6.2f}"
            )
        bisections = sum(s["substeps"] for s in steps.values())
        lines.append(
            f"rubber sheet  {label:48s} {len(steps)} increments, {bisections} bisections, run {seconds:.2f} s"
        )
    for j, t in enumerate(TIMES):
        motion = "pushed in" if t < 16 else ("just reversed" if t < 20 else "pulled out")
        axes[0, j].set_title(f"t = {t:g} ({motion})")
        axes[1, j].set_xlabel("x (current, mm)")
        axes[1, j].axhline(0.0, color="k", lw=0.5)
    axes[0, 0].set_ylabel("normal traction t_n (MPa)")
    axes[1, 0].set_ylabel("tangential traction t_t (MPa)\n(+: toward the sheet's front, -x)")
    axes[0, 0].legend(fontsize=7, loc="upper left")
    fig.suptitle(
        "Rubber sheet in a converging channel (Section 4.2, Fig. 12): tractions on the contact "
        "nodes, scenes/rubber_sheet.toml"
    )
    fig.tight_layout()
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    fig.savefig(out / "rubber_sheet.png", dpi=100)
    plt.close(fig)
    return lines


if __name__ == "__main__":
    cli.standalone(figure, __doc__.splitlines()[0])
