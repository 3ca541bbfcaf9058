"""Chunked loops (lower_chunk) change no observable behaviour.

Each program under tests/programs/pdl/chunk/ runs lowered with and without chunking
(scalar promotion on in both), at several statement budgets: the messages (with their
phase and task), the fault reports, the final drive memory and the phase count must
be identical; and, where promotion cannot be fooled (see SOUND), the same as with
neither. The programs step counters up to the 32- and 16-bit limits, index past
an array's end and out of memory, step by conditional amounts, and share arrays
between tasks.
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


# negative_index.pdl reads a promoted scalar of an earlier declaration through a
# negative index, which scalar promotion (lower_cache) does not see.
SOUND = [p for p in PROGRAMS if p.name != "negative_index.pdl"]


def _run(path: Path, promote: bool, budget: int, chunk: bool = True) -> tuple[object, ...]:
    sink = DiagnosticSink()
    result = front_end(str(path), sink=sink)
    assert result is not None, "\n".join(render_diagnostic(d) for d in sink.items)
    program = lower_program(str(path), result.symbols, promote=promote, chunk=chunk)
    drive = Drive(program, DriveConfig(budget=budget))
    drive.run(2.0)
    messages = [(m.phase, m.task, m.text) for m in drive.messages]
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


@pytest.mark.parametrize("budget", [1, 64, 100_000])
@pytest.mark.parametrize("path", SOUND, ids=lambda p: p.name)
def test_chunked_loops_behave_like_plain_ones(path: Path, budget: int) -> None:
    _same(_run(path, True, budget), _run(path, False, budget))


def test_chunked_loop_drops_provable_checks() -> None:
    path = CHUNK / "past_end_split.pdl"
    sink = DiagnosticSink()
    result = front_end(str(path), sink=sink)
    assert result is not None
    source = lower_program(str(path), result.symbols).python_source()
    assert "for _ in range(_k" in source  # a chunk
    assert "vM" in source  # an index proved in range uses a view without a check
