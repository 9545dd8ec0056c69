"""The parameter-sweep example: the capstan ratio T2/T1 against the friction
coefficient and the wrap angle, one FMU run per case, on a Dask cluster, set
against Euler-Eytelwein's exp(mu theta).

    python examples/sweep/capstan_sweep.py --binary target/release/contact2d --out out/sweep

exports capstan_wrap.toml as an FMU, runs the grid (mu x wrap) on a local
Dask cluster of `--workers` processes (or the cluster at `--scheduler`, or
`--serial` here), writes every step of every run to sweep_steps.csv, the
ratio at the onset of full slip per case to capstan_ratio.csv, prints that
table, and plots capstan_ratio.png.

Each run: the back tension T1 (a scene parameter, 10 N/mm) acts on the slack
end from the first step, and the tight end is drawn along its tangent by
pull.uy in steps of 0.5 mm. The strip creeps, then slides over the whole
wrap; from then on the tight side holds T2 = -pull.Ry = T1 exp(mu theta).
The ratio is read at the first step in full slip (no node sticks), before
the slack end has slid round far enough to change the wrap.
"""

import argparse
import math
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from contact2d_sweep import grid, sweep, write_csv  # noqa: E402

SCENE = HERE / "capstan_wrap.toml"
T1 = 10.0  # the scene's back tension, N per mm of width
STEP_MM = 0.5  # the pull per unit of time (one step)
MUS = [0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.45, 0.5]
WRAPS_DEG = [30.0, 60.0, 90.0, 120.0, 150.0, 180.0]
THICKNESS, RADIUS = 1.0, 100.0  # the strip's (capstan_wrap.toml)
OUTPUTS = ["pull.Ry", "back.ux", "back.uy", "wrap.n_stick", "wrap.n_slip", "wrap.n_open", "solver.iterations"]


def cases(mus=MUS, wraps_deg=WRAPS_DEG) -> list[dict]:
    """One friction coefficient (mu_s = mu_d) and one wrap per case."""
    return grid({("wrap.mu_s", "wrap.mu_d"): mus, "wrap_deg": wraps_deg})


def schedule(pull_mm: float = 8.0, step_mm: float = STEP_MM) -> list:
    """T1 applied with the tight end held (t = 1), then the tight end drawn
    by step_mm per unit of time up to pull_mm: 8 mm slides the strip over
    180 deg at mu = 0.5 (full slip needs about 5.5 mm of pull there: the
    stretch from the tension profile exp(-mu phi) that T1 leaves to
    exp(+mu phi), T1 R / (E' t) ((exp(mu theta) - 1) - (1 - exp(-mu theta))) / mu)."""
    n = round(pull_mm / step_mm)
    return [(float(k + 1), {"pull.uy": -step_mm * k}) for k in range(0, n + 1)]


def onset_of_full_slip(rows: list[dict]) -> list[dict]:
    """Per case, its first row in full slip, with T2/T1 and the closed
    form: no node sticks and the tight side pulls (T2 > T1: the strip slides
    toward the tight end; under T1 alone it may creep the other way). A
    case that never slid fully (or failed) has none."""
    table = []
    for case in sorted({r["case"] for r in rows}):
        steps = [r for r in rows if r["case"] == case and r["error"] is None]
        full = [r for r in steps if r["wrap.n_stick"] == 0 and r["wrap.n_slip"] > 0 and -r["pull.Ry"] > T1]
        if not full:
            continue
        r = full[0]
        mu, theta = r["wrap.mu_s"], math.radians(r["wrap_deg"])
        ratio = -r["pull.Ry"] / T1
        exact = math.exp(mu * theta)
        table.append(
            {
                "case": case,
                "mu": mu,
                "wrap_deg": r["wrap_deg"],
                "pull_mm": STEP_MM * (r["time"] - 1.0),
                "T2_over_T1": ratio,
                "exp_mu_theta": exact,
                "rel_error": ratio / exact - 1.0,
            }
        )
    return table


def plot(table, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, ax_err) = plt.subplots(1, 2, figsize=(11, 4.5))
    wraps = sorted({r["wrap_deg"] for r in table})
    for wrap in wraps:
        rs = [r for r in table if r["wrap_deg"] == wrap]
        line = ax.plot([r["mu"] for r in rs], [r["T2_over_T1"] for r in rs], "o", label=f"FMU, wrap {wrap:g} deg")
        mu = [i / 100 for i in range(0, round(100 * max(r["mu"] for r in table)) + 2)]
        ax.plot(mu, [math.exp(m * math.radians(wrap)) for m in mu], "-", color=line[0].get_color(), lw=1)
        ax_err.plot(
            [r["mu"] * math.radians(wrap) for r in rs], [100 * r["rel_error"] for r in rs], "o-", label=f"wrap {wrap:g} deg"
        )
    ax.set_xlabel("friction coefficient mu")
    ax.set_ylabel("T2 / T1 at the onset of full slip")
    ax.set_title("Capstan: FMU runs (dots) against exp(mu theta) (lines)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    ax_err.axhline(0.0, color="k", lw=0.8)
    # The tension acts at the strip's mid-line, the friction at the drum:
    # the exponent is smaller by t / (2 R) (scenes/stress/capstan_half_wrap.toml).
    top = max(r["mu"] * math.radians(r["wrap_deg"]) for r in table)
    ax_err.plot([0.0, top], [0.0, -100 * top * THICKNESS / (2 * RADIUS)], "k--", lw=1, label="exp(-mu theta t / 2R) - 1")
    ax_err.set_xlabel("mu theta")
    ax_err.set_ylabel("T2/T1 / exp(mu theta) - 1  [%]")
    ax_err.set_title("Departure from the membrane formula")
    ax_err.legend(fontsize=8)
    ax_err.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--binary", default="target/release/contact2d", help="contact2d, to export the FMU")
    ap.add_argument("--fmu", help="an FMU of capstan_wrap.toml already exported (then --binary is not used)")
    ap.add_argument("--out", default="out/sweep")
    ap.add_argument("--mu", type=float, nargs="+", default=MUS, help="friction coefficients (mu_s = mu_d)")
    ap.add_argument("--wrap", type=float, nargs="+", default=WRAPS_DEG, help="wrap angles, degrees (up to 180)")
    where = ap.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, default=2, help="processes of the local Dask cluster (default 2)")
    where.add_argument("--scheduler", help="address of a running Dask scheduler (tcp://host:8786) instead")
    where.add_argument("--serial", action="store_true", help="run the cases here, one after the other")
    args = ap.parse_args(argv)

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    fmu = Path(args.fmu) if args.fmu else out / "capstan_wrap.fmu"
    if not args.fmu:
        subprocess.run([args.binary, "export", str(SCENE), "-o", str(fmu)], check=True, stdout=subprocess.DEVNULL)

    runs = cases(args.mu, args.wrap)
    start = time.perf_counter()
    if args.serial:
        where, rows = "serially", sweep(fmu, runs, schedule(), OUTPUTS, record="all")
    else:
        from distributed import Client, LocalCluster

        if args.scheduler:
            client, cluster = Client(args.scheduler), None
            where = f"on {args.scheduler}"
        else:
            cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True, dashboard_address=None)
            client = Client(cluster)
            where = f"on a LocalCluster of {args.workers} workers"
        try:
            rows = sweep(fmu, runs, schedule(), OUTPUTS, client=client, record="all")
        finally:
            client.close()
            if cluster is not None:
                cluster.close()
    wall = time.perf_counter() - start

    write_csv(rows, out / "sweep_steps.csv")
    table = onset_of_full_slip(rows)
    write_csv(table, out / "capstan_ratio.csv")
    plot(table, out / "capstan_ratio.png")

    print(f"{len(runs)} runs of {fmu.name} ({len(schedule())} steps each) {where}: {wall:.1f} s")
    print(f"{'mu':>5} {'wrap':>6} {'pull mm':>8} {'T2/T1':>9} {'exp(mu th)':>10} {'error':>8}")
    for r in table:
        print(
            f"{r['mu']:5.2f} {r['wrap_deg']:6.0f} {r['pull_mm']:8.1f} {r['T2_over_T1']:9.4f}"
            f" {r['exp_mu_theta']:10.4f} {100 * r['rel_error']:7.2f}%"
        )
    failed = [r for r in rows if r["error"] is not None]
    missing = len(runs) - len(table)
    for r in failed:
        print(f"case {r['case']} failed: {r['error']}")
    if missing:
        print(f"{missing} case(s) did not reach full slip")
    print(f"wrote {out / 'sweep_steps.csv'}, {out / 'capstan_ratio.csv'}, {out / 'capstan_ratio.png'}")
    return 1 if failed or missing else 0


if __name__ == "__main__":
    sys.exit(main())
