"""Shared fixtures: the contact2d binary and a way to run it."""

import os
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def contact2d() -> Path:
    """The release binary (CONTACT2D_BIN overrides), built by scripts/test.sh."""
    path = Path(os.environ.get("CONTACT2D_BIN", REPO / "target" / "release" / "contact2d"))
    if not path.is_file():
        pytest.fail(f"{path} not found: build it with `cargo build --release`")
    return path


@pytest.fixture
def run_cli(contact2d, tmp_path):
    """Runs contact2d with the given arguments in tmp_path."""

    def run(*args) -> subprocess.CompletedProcess:
        return subprocess.run(
            [str(contact2d), *map(str, args)],
            cwd=tmp_path,
            capture_output=True,
            text=True,
            timeout=300,
        )

    return run
