"""The Rust command-line programs the tests compare with (built here when the release build
is not there yet)."""

import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


def binary(name):
    """The path of the release binary `name` of the mcint-cli package."""
    path = REPO / "target" / "release" / name
    if not path.exists():
        if shutil.which("cargo") is None:
            pytest.skip(f"needs cargo to build the Rust CLI `{name}`")
        subprocess.run(
            ["cargo", "build", "--release", "-q", "-p", "mcint-cli", "--bin", name],
            cwd=REPO,
            check=True,
        )
    return path
