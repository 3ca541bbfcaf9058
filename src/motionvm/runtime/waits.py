"""Where a suspended task waits: the innermost frame of the user's code in a generator.

A task is a Python generator (an HMPL task, a PDL drive task); while it is suspended
its frames, down the chain of generators it delegates to (`yield from`), show where it
waits. Used to tell the user which task still ran when a run ended (`--until`,
`--timeout`), with `FILE:LINE:COL` as every diagnostic.
"""

from __future__ import annotations

from collections.abc import Callable, Generator
from dataclasses import dataclass


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


def suspended_at(
    gen: Generator | None, is_user_file: Callable[[str], bool]
) -> tuple[str, int, int] | None:
    """(file, line, col) of the innermost frame of a user file in the suspended `gen`,
    following `yield from` delegation; None if no frame of `gen` is a user's."""
    found = None
    while gen is not None:
        frame = getattr(gen, "gi_frame", None)
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
        gen = getattr(gen, "gi_yieldfrom", None)
    return found
