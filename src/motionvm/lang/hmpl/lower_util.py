"""Small pieces shared by the statement lowering modules: the loop context stack entries,
the loop bodies' interface, and the budgeted back-edge every loop ends with:

    backedge("_t1")
is
    _t1 -= 1
    if not _t1:
        _t1 = 65
        _budget -= 64
        if _budget < 0:
            yield
"""

from __future__ import annotations

import ast
from dataclasses import dataclass, field
from typing import Protocol

from motionvm.lang.hmpl.lvalues import name


@dataclass
class LoopCtx:
    kind: str  # 'loop' | 'switch'
    cont: list = field(default_factory=list)  # statements a `continue` runs (loops)
    flag: str = ""  # switch: temp set when a `continue` leaves the switch
    flag_used: bool = False
    split: bool = False  # lowered as a nested Python function of its own (lower_split.py)
    returns: bool = False  # split: a `return` inside leaves through the nested function
    breaks: int = 0  # `break` statements that leave this loop or switch


@dataclass
class PollCtx:
    """The polling loop whose body is being lowered (`lower_poll.fixed_point`)."""

    mark: str  # the effect marker: set to 1 by each statement that may act
    on_events: bool = True  # its quiet iterations read only what a computed cycle changes
    inner: set[str] = field(default_factory=set)  # the Python locals its body declares


class LoopBodies(Protocol):
    """What the counting loops and pointer walks ask of the loop lowering
    (`lower_loops.LoopLowerer`)."""

    def loop_body(self, body, cont: list[ast.stmt], blocks: int = 1,
                  polling: PollCtx | None = None) -> tuple[list[ast.stmt], LoopCtx]:  # fmt: skip
        """The lowered body of a loop and its context; `cont`: what a `continue` runs."""


# Python allows 20 statically nested blocks (loops, try) in one function. A function
# lowers with up to 3 of its own (the frame's try/finally, the goto dispatcher's loop and
# try) and one more may come innermost (the wait loop of a `Till`); the rest hold the
# user's loops and switches (one block each; a counting loop in chunks takes two while
# there is room for them). A loop or switch that would pass them is lowered as a nested
# Python function, which starts with all its blocks free.
PY_BLOCKS = 20
LOOP_BLOCKS = PY_BLOCKS - 4
"""Python blocks of loops and switches in one generated function, at most."""
MAX_LOOP_NESTING = 256
"""Loops and switches nested in one function, at most (a documented HMPL limit)."""


# A loop charges the task's budget in units of CHUNK back-edges, counting down a local
# (much cheaper per iteration than a global); the kernel refills `_budget` each cycle.
# The countdown starts at CHUNK + 1 and fires when it reaches 0 (a truth test is cheaper
# than a comparison), so a loop yields after every CHUNK + 1 back-edges.
CHUNK = 64


def countdown_init(counter: str) -> ast.stmt:
    return ast.Assign([name(counter, True)], ast.Constant(CHUNK + 1))


def backedge(counter: str) -> list[ast.stmt]:
    """`counter -= 1; if not counter: counter = CHUNK + 1; _budget -= CHUNK; if _budget < 0: yield`."""
    dec = ast.AugAssign(name(counter, True), ast.Sub(), ast.Constant(1))
    charge = ast.AugAssign(name("_budget", True), ast.Sub(), ast.Constant(CHUNK))
    over = ast.Compare(name("_budget"), [ast.Lt()], [ast.Constant(0)])
    refill = [
        ast.Assign([name(counter, True)], ast.Constant(CHUNK + 1)),
        charge,
        ast.If(over, [ast.Expr(ast.Yield(None))], []),
    ]
    test = ast.UnaryOp(ast.Not(), name(counter))
    return [dec, ast.If(test, refill, [])]
