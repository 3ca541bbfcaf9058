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


class Fault(str):
    """A runtime fault report: the one line the CLI prints, carrying its parts.

    It is a `str` (its text, `FILE:LINE:COL: runtime error in task N at t=S s: MESSAGE`,
    or for an internal error `FILE:LINE:COL: internal error in task N: DETAIL` and a
    second line asking for a report),
    so every receiver of report lines takes it as one; the run side that produced it fills
    the fields, nothing parses the text back. `who` is what faulted as the text names it
    (`task 3`, `drive 1 task 0`, `procedure fan_control`).
    """

    file: str
    line: int
    """1-based line of the user's file (0: unknown)."""
    col: int
    time: float
    """Simulated time of the fault [s]."""
    message: str
    language: str
    """"HMPL", "PDL" or "GDL"."""
    task: int | None
    """The HMPL task id or the PDL drive's task number (None: a GDL procedure)."""
    drive: int | None
    """The PDL drive (the axis id it sits on; None: not a drive, or a standalone one)."""
    procedure: str | None
    """The GDL procedure (None: not GDL)."""
    kind: str
    """"runtime": an error of the user's program; "internal": an error of motionvm itself
    while it ran the program (a bug, or an exception of a host callback), whose report
    says so."""

    def __new__(
        cls,
        text: str,
        *,
        file: str,
        line: int,
        col: int,
        time: float,
        message: str,
        language: str,
        task: int | None = None,
        drive: int | None = None,
        procedure: str | None = None,
        kind: str = "runtime",
    ) -> Fault:
        self = super().__new__(cls, text)
        fields = {"file": file, "line": line, "col": col, "time": time, "message": message,
                  "language": language, "task": task, "drive": drive, "procedure": procedure,
                  "kind": kind}  # fmt: skip
        for key, value in fields.items():
            object.__setattr__(self, key, value)
        return self

    def __setattr__(self, key: str, value: object) -> None:
        raise AttributeError("a Fault is read-only")

    @property
    def text(self) -> str:
        """The report line, as a plain `str`."""
        return str.__str__(self)

    @property
    def who(self) -> str:
        """`task 3`, `drive 1 task 0` or `procedure P`."""
        if self.procedure is not None:
            return f"procedure {self.procedure}"
        drive = f"drive {self.drive} " if self.drive is not None else ""
        return f"{drive}task {self.task}"

    def fields(self) -> dict[str, object]:
        """The parts of the report, by field name."""
        return dict(vars(self))  # (`__new__` sets exactly the fields, in order)

    def with_text(self, text: str, **changes: object) -> Fault:
        """The same fault with another report line (and fields), e.g. naming its drive."""
        return Fault(text, **{**self.fields(), **changes})  # type: ignore[arg-type]

    def __reduce__(self) -> tuple:
        """Pickled with its fields (a worker process hands its faults back)."""
        return _rebuild_fault, (self.text, self.fields())

    def __repr__(self) -> str:
        return f"Fault({self.text!r})"


def _rebuild_fault(text: str, fields: dict) -> Fault:
    return Fault(text, **fields)
