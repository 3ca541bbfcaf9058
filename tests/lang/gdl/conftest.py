"""Fixtures of the GDL tests: the command line in this process, and a run that may jump
the clock next to one that steps every cycle."""

from __future__ import annotations

import contextlib
import io
from collections.abc import Sequence
from pathlib import Path

import pytest

from motionvm.api import Simulation
from motionvm.cli import main


def run_cli(*argv, merged: bool = False) -> tuple[int, str, str]:
    """`motionvm ARGV...` in this process: (exit code, stdout, stderr). `merged`: stderr
    goes into stdout, in the order written (and the returned stderr is "")."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out if merged else err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


def run_jumped_and_stepped(
    paths: Sequence[str | Path], scenario: str | None, until: float | None = None
) -> list:
    """[(output, exit code, final cycle, faults)] of a run that may jump the clock over
    idle cycles and of one that steps every cycle (`skip=False`)."""
    runs = []
    for skip in (True, False):
        sim = Simulation.from_files(paths, scenario=scenario, skip=skip)
        sim.run(until)
        output = "".join(line + "\n" for line in sim.messages)
        rc = 1 if sim.fault_count else 0  # the command line's exit code
        runs.append((output, rc, sim.controller.cycle, sim.faults))
    return runs


@pytest.fixture(scope="session")
def cli():
    """`run_cli`: `cli("run", "app.gdl", "--until", 1)` -> (exit code, stdout, stderr)."""
    return run_cli


@pytest.fixture(scope="session")
def jumped_and_stepped():
    """`run_jumped_and_stepped`: compare its two results."""
    return run_jumped_and_stepped
