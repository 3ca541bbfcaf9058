"""Chunked loops (lower_chunk) change no observable behaviour.

Each program under tests/programs/pdl/chunk/ runs lowered with and without chunking
(scalar promotion on in both), at several statement budgets: the messages (with their
phase and task), the fault reports, the final drive memory and the phase count must
be identical, and the same as with neither. The programs step counters up to the 32-
and 16-bit limits, index past an array's end (forward and backward into promoted
scalars of other declarations, and from a procedure's frame back into the globals)
and out of memory, step by conditional amounts, and share arrays between tasks.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from motionvm.lang.pdl.drive_rt import Drive, DriveConfig
from motionvm.lang.pdl.front import front_end
from motionvm.lang.pdl.lower import lower_program
from motionvm.source import DiagnosticSink, render_diagnostic

CHUNK = Path(__file__).parents[2] / "programs" / "pdl" / "chunk"
PROGRAMS = sorted(CHUNK.glob("*.pdl"))


def _run(path: Path, promote: bool, budget: int, chunk: bool = True) -> tuple[object, ...]:
    sink = DiagnosticSink()
    result = front_end(str(path), sink=sink)
    assert result is not None, "\n".join(render_diagnostic(d) for d in sink.items)
    program = lower_program(str(path), result.symbols, promote=promote, chunk=chunk)
    received = []
    drive = Drive(program, DriveConfig(budget=budget), on_message=received.append)
    drive.run(2.0)
    messages = [(m.phase, m.task, m.text) for m in received]
    return messages, drive.faults, bytes(drive.mem.buf), drive.phase


def _same(a: tuple[object, ...], b: tuple[object, ...]) -> None:
    assert a[0] == b[0]
    assert a[1] == b[1]
    assert a[2] == b[2], "final memory differs"
    assert a[3] == b[3]
    assert a[0] or a[1], "the program printed nothing"


@pytest.mark.parametrize("budget", [1, 7, 64, 100_000])
@pytest.mark.parametrize("path", PROGRAMS, ids=lambda p: p.name)
def test_chunked_loops_behave_like_unchunked_ones(path: Path, budget: int) -> None:
    _same(_run(path, True, budget), _run(path, True, budget, chunk=False))


@pytest.mark.parametrize("budget", [1, 7, 64, 100_000])
@pytest.mark.parametrize("path", PROGRAMS, ids=lambda p: p.name)
def test_chunked_loops_behave_like_plain_ones(path: Path, budget: int) -> None:
    _same(_run(path, True, budget), _run(path, False, budget))


@pytest.mark.parametrize("budget", [1, 100_000])
def test_index_past_an_array_reaches_promoted_scalars_of_a_later_declaration(
    budget: int,
) -> None:
    # a[8..11] are j, t, s, k (manual §1.2): the loops keep them in Python locals
    messages, faults, _mem, _phase = _run(CHUNK / "forward_index.pdl", True, budget)
    assert [m[2] for m in messages] == [  # type: ignore[attr-defined]
        "read: s=50 k=19 t=18 j=12",
        "write: s=20840 k=1980 t=1880",
        "mixed: j=40 t=11 s=48 k=39",
        "short: w=458762 u=1048603",
        "float: q=-1086324736",
    ]
    assert faults == []


def test_chunked_loop_drops_provable_checks() -> None:
    path = CHUNK / "past_end_split.pdl"
    sink = DiagnosticSink()
    result = front_end(str(path), sink=sink)
    assert result is not None
    source = lower_program(str(path), result.symbols).python_source()
    assert "for _ in range(_k" in source  # a chunk
    assert "vM" in source  # an index proved in range uses a view without a check
