"""Places in a run and what the debugger records of it: positions, stops, breakpoints, inputs.

A `Position` is `(cycle, count)`: the start of controller cycle `cycle` (count 0) or its
`count`-th statement of the user's code (tracer.py). A deterministic run of the same
files and recorded inputs reaches every position again with the same state, so going
back in time is going to an earlier position of a fresh run.
"""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True, order=True)
class Position:
    cycle: int
    count: int = 0
    """0: the start of the cycle, before any task ran in it; n: its n-th statement."""


@dataclass
class Breakpoint:
    """A line breakpoint as asked for, and where it holds."""

    id: int
    file: str
    line: int
    """The line asked for."""
    verified: bool = False
    """There is a statement at or after `line` in the file (then `line` is that line)."""
    condition: str | None = None
    """An expression of the file's language: stop only where it is true."""
    hit_condition: str | None = None
    """`N` or `>= N` / `% N`: stop only on those hits (counted where `condition` holds)."""
    log_message: str | None = None
    """A logpoint: print this (`{expression}` replaced by its value) instead of stopping."""
    hits: int = 0
    message: str = ""
    """Why it is not verified."""

    def hit_allows(self) -> bool:
        """After counting this hit: whether the hit condition lets it stop."""
        op, n = hit_rule(self.hit_condition)
        return {
            "==": self.hits == n,
            ">=": self.hits >= n,
            ">": self.hits > n,
            "%": self.hits % n == 0,
        }[op]


def hit_rule(text: str | None) -> tuple[str, int]:
    """A hit condition (`N`, `== N`, `>= N`, `> N`, `% N`) as (operator, N); ("%", 1)
    for none. ValueError with a message for anything else (`% 0` too)."""
    cond = (text or "").strip()
    if not cond:
        return "%", 1
    op = next((o for o in (">=", "==", ">", "%") if cond.startswith(o)), "==")
    number = cond[len(op) :] if cond.startswith(op) else cond
    try:
        n = int(number.strip())
    except ValueError:
        raise ValueError(
            f"hit condition '{cond}' is not N, == N, >= N, > N or % N (N a whole number)"
        ) from None
    if op == "%" and n < 1:
        raise ValueError(f"hit condition '{cond}': % needs a number of 1 or more")
    return op, n


@dataclass(frozen=True)
class Stop:
    """Why and where the run is paused."""

    reason: str
    """"entry", "breakpoint", "step", "pause", "exception", "data breakpoint", "goto",
    "waits forever" (nothing left can change what the run waits on: `text` says what
    waits where), "exited"."""
    position: Position
    time: float
    """Simulated time of the position [s]."""
    thread: tuple | None = None
    """The key of the thread paused inside a statement (None: at a cycle boundary)."""
    text: str = ""
    """A fault's report, a data breakpoint's change, ..."""
    breakpoints: tuple[int, ...] = ()
    """The breakpoints hit."""


@dataclass(frozen=True)
class Input:
    """A value the user gave the run while it was paused (a forced input, a written
    variable): applied again at its position by every replay, so replay stays exact."""

    position: Position
    name: str
    value: object
    local: tuple | None = None
    """(thread key, depth) of a frame's local variable; None: a variable of the run."""


@dataclass
class History:
    """What a timeline has seen, for going back: the inputs so far, in order."""

    inputs: list[Input] = field(default_factory=list)

    def after(self, position: Position) -> list[Input]:
        return [i for i in self.inputs if i.position > position]

    def cut(self, position: Position) -> None:
        """A new input at `position`: the inputs recorded after it belonged to the future
        that no longer happens."""
        self.inputs = [i for i in self.inputs if i.position <= position]
