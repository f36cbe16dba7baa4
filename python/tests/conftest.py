"""Shared fixtures: the repository root, the `hysteron` CLI binary."""

from __future__ import annotations

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def root() -> pathlib.Path:
    return ROOT


@pytest.fixture(scope="session")
def cli() -> pathlib.Path:
    """The `hysteron` program: $HYSTERON_BIN, else built with cargo."""
    env = os.environ.get("HYSTERON_BIN")
    if env:
        return pathlib.Path(env)
    subprocess.run(
        ["cargo", "build", "--release", "-q", "-p", "hysteron-cli"], cwd=ROOT, check=True
    )
    return ROOT / "target" / "release" / "hysteron"
