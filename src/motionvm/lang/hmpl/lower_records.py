"""Loops a task never leaves that have no status wait: their task's slices need no
record of the status flags they read (lower_loops.py asks here).

While a task runs, the axis status flags it reads are recorded (motion/commands/
status_flags.py), for a slice that ends in a status wait (STATUS_WAIT, STATUS_POLL:
lower_stmt.py `event_wait`, runtime/kernel.py). A loop that never ends (`for (;;)`,
`for (; 1;)`, `while (1)`) whose body cannot leave it (no `break` of its own, no
`return`, no `goto`) is where its task stays once it entered it: every later slice of
the task starts and ends in it. If nothing in it can yield a status wait (no `Till` or
busy wait on status flags alone, no call of a user's function that may block), no
record of those slices would ever be taken, and the loop is entered through
`_end_records()` (`Kernel.end_records`): the task records no reads any more.

    for (;;) { for (i = 0; i < 4; i++) if (IsInPos(i)) MoveAbs(i, x); RunScheduler(); }
becomes
    _end_records()
    while True:
        ...
"""

from __future__ import annotations

import ast

from motionvm.lang.hmpl import nodes as n
from motionvm.lang.hmpl.analysis import walk
from motionvm.lang.hmpl.lvalues import call
from motionvm.runtime.kernel import STATUS_POLL, STATUS_WAIT

_OWN_BREAKS = (n.While, n.DoWhile, n.For, n.Switch)
"""The statements whose body's `break` leaves them, not the loop around them."""
_TILL_YIELDS = frozenset({"_till_ms", "_till_pos"})
"""Helpers whose answer a time or position wait yields (never a status wait)."""


def records_end(cond, body, lowered: list[ast.stmt]) -> list[ast.stmt]:
    """`[_end_records()]` if the loop `cond` (None: none), `body` (HMPL), lowered as the
    statements `lowered`, is one its task never leaves and in which it yields no status
    wait (see the module docstring); else []."""
    if not (_forever(cond) and _stays(body) and _no_status_wait(lowered)):
        return []
    return [ast.Expr(call("_end_records"))]


def _forever(cond) -> bool:
    return cond is None or (type(cond) is n.IntLit and cond.value != 0)


def _stays(body) -> bool:
    """True if nothing in `body` leaves the loop around it: no return, no goto, no break
    but those of the loops and switches in it."""
    nodes = walk(body)
    inner = set()
    for x in nodes:
        t = type(x)
        if t is n.Return or t is n.Goto:
            return False
        if t in _OWN_BREAKS:
            inner.update(id(y) for y in walk(x.body) if type(y) is n.Break)
    return all(id(x) in inner for x in nodes if type(x) is n.Break)


def _no_status_wait(lowered: list[ast.stmt]) -> bool:
    """True if the Python statements `lowered` yield no status wait: each yield is a
    plain one, a constant that is no status wait, a variable (a polling loop's
    EVENT_WAIT or EVENT_POLL: lower_poll.py) or a time or position wait's, and each
    `yield from` calls a built-in (a blocking built-in yields no status wait) or a
    function defined in them (a split loop: its body is among them)."""
    nodes = [x for st in lowered for x in ast.walk(st)]
    local = {x.name for x in nodes if type(x) is ast.FunctionDef}
    for x in nodes:
        t = type(x)
        if t is ast.Yield:
            v = x.value
            if v is None or type(v) is ast.Name:
                continue
            if type(v) is ast.Constant and v.value not in (STATUS_WAIT, STATUS_POLL):
                continue
            if type(v) is ast.Call and type(v.func) is ast.Name and v.func.id in _TILL_YIELDS:
                continue
            return False
        if t is ast.YieldFrom:
            v = x.value
            if not (type(v) is ast.Call and type(v.func) is ast.Name):
                return False
            f = v.func.id
            if not (f.startswith("b_") or f in local):
                return False
    return True
