"""Snapshots of the generated Python for a few programs: a change in the
lowering shows up as a reviewed diff. Refresh with MOTIONVM_UPDATE_GOLDEN=1 (the one
switch of every golden file, tests/conftest.py)."""

from __future__ import annotations

from pathlib import Path

import pytest

from motionvm.lang.hmpl.compiler import TaskFile, compile_tasks
from motionvm.source.diagnostics import DiagnosticSink

REPO = Path(__file__).resolve().parents[3]
GOLDEN = REPO / "tests" / "golden" / "hmpl"
PROGRAMS = [
    "examples/01_hello.hmpl",
    "tests/programs/hmpl/lang/switch_fallthrough.hmpl",
    "tests/programs/hmpl/lang/pointer_arithmetic.hmpl",
    "tests/programs/hmpl/lang/goto_labels.hmpl",
    "tests/programs/hmpl/lang/arrays_2d.hmpl",
    "tests/programs/hmpl/lang/loops_for.hmpl",
]


@pytest.mark.parametrize("rel", PROGRAMS)
def test_generated_python_matches_snapshot(rel: str, monkeypatch, golden) -> None:
    path = REPO / rel
    monkeypatch.chdir(path.parent)
    sink = DiagnosticSink()
    prog, _mem = compile_tasks([TaskFile(0, path.name)], sink)
    assert prog is not None, [d.headline() for d in sink.items]
    golden(GOLDEN / (path.stem + ".py.txt"), prog.python_source())
