"""Where in the user's program a task faulted: file, line and column of each user frame.

Generated code is compiled with the user's file name, lines and columns (each language's
lowering copies `lineno`/`col_offset` from its nodes), so the traceback of a task's
exception holds the place: the line of each frame, and, through the code object's
position table (`co_positions()`), the column of the instruction that raised.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from itertools import islice
from types import CodeType, TracebackType


@dataclass(frozen=True, slots=True)
class FramePos:
    """One frame of the user's generated code in a traceback."""

    file: str
    line: int
    col: int
    """1-based column of the faulting expression; 1 when Python does not know it."""
    first_line: int
    """The first line of the frame's code (`co_firstlineno`)."""


def column_of(code: CodeType, lasti: int) -> int:
    """1-based column of the instruction at byte offset `lasti` of `code` (1 if unknown)."""
    if lasti < 0:
        return 1
    # one entry per 2-byte code unit: (line, end_line, col_offset, end_col_offset)
    pos = next(islice(code.co_positions(), lasti // 2, None), None)
    if pos is None or pos[2] is None:
        return 1
    return pos[2] + 1


def user_frames(tb: TracebackType | None, is_user: Callable[[str], bool]) -> list[FramePos]:
    """The frames of `tb` whose file is the user's (`is_user(filename)`), outermost first."""
    out: list[FramePos] = []
    while tb is not None:
        code = tb.tb_frame.f_code
        if is_user(code.co_filename):
            line = tb.tb_lineno or code.co_firstlineno
            out.append(
                FramePos(code.co_filename, line, column_of(code, tb.tb_lasti), code.co_firstlineno)
            )
        tb = tb.tb_next
    return out
