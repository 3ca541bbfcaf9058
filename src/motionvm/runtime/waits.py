"""Where a suspended task waits: the innermost frame of the user's code in a generator.

A task is a Python generator (an HMPL task, a PDL drive task); while it is suspended
its frames, down the chain of generators it delegates to (`yield from`), show where it
waits. Used to tell the user which task still ran when a run ended (`--until`,
`--timeout`), with `FILE:LINE:COL` as every diagnostic.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Generator
from dataclasses import dataclass
from types import GeneratorType

from motionvm.source.files import SourceFile

_WORD = re.compile(r"\s*([A-Za-z_]\w*)")
_LOOPS = frozenset({"while", "for", "do", "goto", "loop", "until", "repeat", "if", "else"})


@dataclass(frozen=True, slots=True)
class Waiting:
    """One part of a run that had not finished, and where (if a file line says it)."""

    who: str
    """`task 0`, `drive 1 task 2`, `axis 3`, ..."""
    file: str | None = None
    line: int = 0
    col: int = 1
    why: str = ""
    """What it waits for, when known (`moving`, `a scenario event at t=...`)."""

    def render(self, severity: str, message: str) -> str:
        """`FILE:LINE:COL: severity: WHO MESSAGE`, or `motionvm: severity: ...` with no file."""
        text = f"{self.who}" + (f" ({self.why})" if self.why else "") + f" {message}"
        if self.file is None:
            return f"motionvm: {severity}: {text}"
        return f"{self.file}:{self.line}:{self.col}: {severity}: {text}"

    def forever(self) -> str:
        """The error of a part that waits on what nothing left in the run can change:
        `FILE:LINE:COL: error: task 0 waits forever: in Till`."""
        why = f": {self.why}" if self.why else ""
        where = "motionvm" if self.file is None else f"{self.file}:{self.line}:{self.col}"
        return f"{where}: error: {self.who} waits forever{why}"


def never_ends(waiting: list[Waiting], sim_time: float) -> list[str]:
    """The errors of a run that can never end (`Controller.run`'s FOREVER): one per part
    that waits, then what ended the run."""
    return [w.forever() for w in waiting] + [
        f"motionvm: error: the run can never end: at t={sim_time:g} s nothing left in it "
        "(no scenario event, sleeping task, moving axis or listening server) can change what "
        "it waits on"
    ]


def suspended_at(
    gen: Generator | None, is_user_file: Callable[[str], bool]
) -> tuple[str, int, int] | None:
    """(file, line, col) of the innermost frame of a user file in the suspended `gen`,
    following `yield from` delegation; None if no frame of `gen` is a user's."""
    found = None
    while isinstance(gen, GeneratorType):  # (`yield from` may delegate to any iterator)
        frame = gen.gi_frame
        if frame is None:
            break
        code = frame.f_code
        if is_user_file(code.co_filename):
            col = 1
            positions = list(code.co_positions())
            i = frame.f_lasti // 2
            if 0 <= i < len(positions) and positions[i][2] is not None:
                col = positions[i][2] + 1
            found = (code.co_filename, frame.f_lineno, col)
        gen = gen.gi_yieldfrom
    return found


def not_started(gen: Generator | None) -> bool:
    """True for a task's generator that has not run yet (a run that ended before the
    task's first slice): its frame stands at the function's first line, where it waits
    for nothing."""
    return (
        isinstance(gen, GeneratorType)
        and gen.gi_frame is not None
        and not gen.gi_suspended
        and not gen.gi_running
    )


def why_waiting(
    place: tuple[str, int, int] | None,
    wake_time: float | None = None,
    gen: Generator | None = None,
) -> str:
    """What a suspended task waits for, for `Waiting.why`: `not started yet` if its
    generator `gen` has not run, `sleeping until t=S s` while it sleeps (`wake_time`
    [s]), else the name of the call or statement at its `place` (file, line, col) in the
    user's source: `in Till`, `in MutexLock`, `in a loop` (a loop that used up its slice
    of the cycle), `running` when the source says nothing."""
    if not_started(gen):
        return "not started yet"
    if wake_time is not None:
        return f"sleeping until t={wake_time:.6g} s"
    if place is None:
        return "running"
    file, line, col = place
    sf = SourceFile.lookup(file)
    text = sf.line(line) if sf is not None else ""
    m = _WORD.match(text, max(0, col - 1)) if text else None
    if m is None and text:
        m = _WORD.match(text)
    if m is None:
        return "running"
    word = m.group(1)
    return "in a loop" if word.lower() in _LOOPS else f"in {word}"
