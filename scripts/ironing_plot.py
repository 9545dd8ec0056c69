"""The ironing scene (scenes/verification/ironing.toml) under both
formulations and with either surface as contactor (node-to-segment with
the ring as contactor also against the block's smoothed top): the ring's reaction
forces Rx, Ry over the slide, plotted into docs/figures/ironing.png, with
each run's iterations, bisections, run time and largest force jump printed.

    .venv/bin/python scripts/ironing_plot.py [--bin target/release/contact2d] [--out docs/figures]

The largest force jump (as tests/ironing.rs measures it): per component,
the largest second difference |R(k+1) - 2 R(k) + R(k-1)| over the slide's
increments (t > 1), divided by the mean magnitude |R| of the ring's force
over the slide. A run that fails stops the plot's curve where it failed.
"""

import statistics
import sys
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from paper import cli  # noqa: E402

SCENE = cli.REPO / "scenes" / "verification" / "ironing.toml"
SLIDE_START = 1.0
# The scene slides the ring by 3.5 over t in [1, 2].
SLIDE = 3.5
CONTACTOR_RING = 'contactor = "ring.outer"\ntarget = "block.top"'
CONTACTOR_BLOCK = 'contactor = "block.top"\ntarget = "ring.outer"'
NODE_TO_SEGMENT = 'formulation = "node_to_segment"'
SMOOTH = NODE_TO_SEGMENT + "\nsmooth_target = true"
# (name, mortar, ring as contactor, smoothed target)
VARIANTS = [
    ("node_to_segment, ring contactor", False, True, False),
    ("node_to_segment, ring contactor, smoothed target", False, True, True),
    ("node_to_segment, block contactor", False, False, False),
    ("mortar, ring contactor", True, True, False),
    ("mortar, block contactor", True, False, False),
]


def scene_text(mortar, ring_contactor, smooth):
    text = SCENE.read_text()
    for old, new, on in [
        (NODE_TO_SEGMENT, 'formulation = "mortar"', mortar),
        (NODE_TO_SEGMENT, SMOOTH, smooth),
        (CONTACTOR_BLOCK, CONTACTOR_RING, ring_contactor),
    ]:
        if on:
            assert old in text, old
            text = text.replace(old, new)
    return text


def ring_forces(summary):
    """(time, Rx, Ry) of the ring (its two driven ends) per converged step."""
    out = []
    for s in summary["steps"]:
        if not s["converged"]:
            break
        d = s["drivers"]
        out.append(
            (
                s["time"],
                d["left_end"]["Rx"] + d["right_end"]["Rx"],
                d["left_end"]["Ry"] + d["right_end"]["Ry"],
            )
        )
    return out


def largest_jump(forces):
    """[Rx, Ry] largest second difference over the slide / mean |R|."""
    slide = [f for f in forces if f[0] > SLIDE_START + 1e-9]
    if len(slide) < 3:
        return [float("nan")] * 2
    mean = statistics.fmean((rx * rx + ry * ry) ** 0.5 for _, rx, ry in slide)
    return [
        max(abs(slide[k + 1][c] - 2 * slide[k][c] + slide[k - 1][c]) for k in range(1, len(slide) - 1)) / mean
        for c in (1, 2)
    ]


def figure(binary, out, work):
    fig, (ax_x, ax_y) = plt.subplots(2, 1, figsize=(8, 7), sharex=True)
    lines = []
    for name, mortar, ring, smooth in VARIANTS:
        stem = name.replace(", ", "_").replace(" ", "_")
        summary, wall = cli.run_text(binary, scene_text(mortar, ring, smooth), stem, work)
        steps = summary["steps"]
        done = [s for s in steps if s["converged"]]
        its = [s["iterations"] for s in done]
        bisections = sum(s["substeps"] for s in done)
        forces = ring_forces(summary)
        jump = largest_jump(forces)
        failed = "" if len(done) == len(steps) else f", failed at t = {steps[-1]['time']:.4g}"
        lines.append(
            f"{name}: {len(done)} increments{failed}, iterations median {statistics.median(its):g} "
            f"max {max(its)}, bisections {bisections}, largest jump Rx {jump[0]:.4f} Ry {jump[1]:.4f} "
            f"of |R|, {wall:.2f} s"
        )
        slide = [f for f in forces if f[0] >= SLIDE_START]
        xs = [SLIDE * (t - SLIDE_START) for t, _, _ in slide]
        style = "-" if mortar else (":" if smooth else "--")
        ax_x.plot(xs, [rx for _, rx, _ in slide], style, marker=".", label=name)
        ax_y.plot(xs, [ry for _, _, ry in slide], style, marker=".", label=name)
    ax_x.set_ylabel("ring Rx")
    ax_y.set_ylabel("ring Ry")
    ax_y.set_xlabel("slide distance")
    ax_x.legend(fontsize=8)
    ax_x.set_title("Ironing: the ring's reaction over the slide (frictionless)")
    for ax in (ax_x, ax_y):
        ax.grid(alpha=0.3)
    fig.tight_layout()
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    fig.savefig(out / "ironing.png", dpi=120)
    lines.append(f"wrote {out / 'ironing.png'}")
    return lines


if __name__ == "__main__":
    cli.standalone(figure, __doc__.splitlines()[0])
