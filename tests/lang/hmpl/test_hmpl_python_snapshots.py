"""Snapshots of the generated Python for a few programs: a change in the
lowering shows up as a reviewed diff. Refresh with MOTIONVM_REGEN=1."""

from __future__ import annotations

import os
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
def test_generated_python_matches_snapshot(rel: str, monkeypatch) -> None:
    path = REPO / rel
    monkeypatch.chdir(path.parent)
    sink = DiagnosticSink()
    prog, _mem = compile_tasks([TaskFile(0, path.name)], sink)
    assert prog is not None, [d.headline() for d in sink.items]
    text = prog.python_source()
    snap = GOLDEN / (path.stem + ".py.txt")
    if os.environ.get("MOTIONVM_REGEN"):
        snap.parent.mkdir(parents=True, exist_ok=True)
        snap.write_text(text, encoding="utf-8")
    assert snap.is_file(), f"no snapshot {snap.name}: run with MOTIONVM_REGEN=1"
    assert text == snap.read_text(encoding="utf-8"), (
        f"{snap.name} changed: review, then MOTIONVM_REGEN=1"
    )
