"""The command line for the paper's figures (scripts/paper_figures.py and the
modules of scripts/paper/): one place that runs `contact2d run`."""

import argparse
import json
import subprocess
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def run(binary, scene, summary, *extra):
    """`contact2d run SCENE --summary SUMMARY [EXTRA...]`: (the summary, wall
    seconds). A run with a failed increment still writes its summary (the
    last step `converged: false`); one that writes none raises with the
    command's message."""
    start = time.perf_counter()
    done = subprocess.run(
        [str(binary), "run", str(scene), "--summary", str(summary), *map(str, extra)],
        capture_output=True,
        text=True,
    )
    wall = time.perf_counter() - start
    if not Path(summary).exists():
        raise RuntimeError(f"{scene}: {done.stderr.strip()}")
    return json.loads(Path(summary).read_text()), wall


def run_text(binary, text, stem, work_dir, *extra):
    """Writes the scene text to WORK_DIR/STEM.toml and runs it (summary in
    WORK_DIR/STEM.json)."""
    work_dir = Path(work_dir)
    scene = work_dir / f"{stem}.toml"
    scene.write_text(text)
    return run(binary, scene, work_dir / f"{stem}.json", *extra)


def standalone(figure, description):
    """A module's own command line: --bin, --out; prints what figure()
    returns."""
    ap = argparse.ArgumentParser(description=description)
    ap.add_argument("--bin", default=str(REPO / "target" / "release" / "contact2d"))
    ap.add_argument("--out", default=str(REPO / "docs" / "figures"))
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as work:
        for line in figure(args.bin, args.out, work):
            print(line)
