"""Where the debugger sees a statement run: line events of the user's generated code.

Generated code carries the user's file names and lines (each language's lowering), so
Python's trace hook (`sys.settrace`, per thread: only the simulation's) reports a line
event for every statement of every task, drive task and procedure. The tracer counts
the line events of the user's code within each cycle (the count starts again when the
controller's cycle changes; cycles a jump passes run no user code): `(cycle, count)`
is a position in the run that a replay of the same inputs reaches again, which is what
time travel goes back to. It is switched on only at cycle boundaries, so a traced
cycle is traced whole, and a run with the tracer on still skips idle time.

`on_line(frame, count)` decides what happens at a line (a breakpoint, a step that ends
here); it may block: the program is paused inside that statement until it returns.
"""

from __future__ import annotations

import sys
from collections.abc import Callable


def is_user_file(filename: str) -> bool:
    """Generated code is compiled with the user's file name (`x.hmpl`, an included
    header); Python's own modules end in `.py`, and `<...>` names are no file."""
    return not (filename.endswith((".py", ".pyx", ".so")) or filename.startswith("<"))


class LineTracer:
    """Counts the user's line events of each cycle and hands each to `on_line`."""

    def __init__(self, on_line: Callable[[object, int], None], clock) -> None:
        self.on_line = on_line
        self.clock = clock
        """Whose `cycle` the counts are of (the controller's clock)."""
        self.count = 0
        """Line events of the user's code in cycle `cycle` so far."""
        self.cycle = -1
        self.counts: dict[int, int] = {}
        """Line events of every traced cycle that had any."""
        self.active = False
        self._user: dict[str, bool] = {}

    def enable(self) -> None:
        if not self.active:
            self.active = True
            sys.settrace(self._call)

    def disable(self) -> None:
        if self.active:
            self.active = False
            sys.settrace(None)

    def _call(self, frame, event, arg):
        name = frame.f_code.co_filename
        user = self._user.get(name)
        if user is None:
            user = self._user[name] = is_user_file(name)
        return self._line if user else None

    def _line(self, frame, event, arg):
        if event == "line":
            cycle = self.clock.cycle
            if cycle != self.cycle:
                self.cycle, self.count = cycle, 0
            self.count += 1
            self.counts[cycle] = self.count
            self.on_line(frame, self.count)
        return self._line
