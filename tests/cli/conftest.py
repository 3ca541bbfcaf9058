"""Running the real command in a subprocess (`python -m motionvm ...`) for the CLI tests."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest


def run_motionvm(
    *argv, cwd: Path, env: dict[str, str] | None = None, stderr=subprocess.PIPE
) -> subprocess.CompletedProcess:
    """`motionvm ARGV` in `cwd`, stdout captured (and stderr unless given), text mode."""
    full_env = dict(os.environ)
    full_env.update(env or {})
    return subprocess.run(
        [sys.executable, "-m", "motionvm", *map(str, argv)],
        cwd=cwd,
        stdout=subprocess.PIPE,
        stderr=stderr,
        text=True,
        env=full_env,
        timeout=120,
    )


@pytest.fixture
def motionvm():
    return run_motionvm
