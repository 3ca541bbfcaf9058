"""Which Till conditions wait on an event: they can change only in a computed cycle.

`Till(cond)` polls `cond` once per cycle. If `cond` tests only what changes in a cycle
the controller computes (never in one it jumps over), the task need not be resumed in
the cycles between: an axis's status flags (IsInPos, IsMoving, IsEnabled, IsHomed,
IsHoming, IsErrorStop), an axis group's (IsGrpEnabled, IsGrpMoving, IsGrpInPos,
IsGrpErrorStop), the digital inputs and outputs of the controller (HIMC_GPI,
HIMC_GPO, GetGPI, GetGPO) and of the I/O slaves (GetSlvGPI, GetSlvGPO, GetSlvAllGPI,
GetSlvAllGPO), and the task's own variables, combined by operators and constants. Such a Till is lowered as

    Till(IsInPos(a));   ->   if not b_IsInPos(g_a):
                                 yield -2                  # EVENT_WAIT
                                 while not b_IsInPos(g_a):
                                     yield -1              # EVENT_POLL

so the controller may jump past it (runtime/kernel.py). A condition that tests only
an axis's status flags (`STATUS_BUILTINS`), with arguments that are constants or the
task's own plain local variables, which no other task can write, yields -4 and -3
instead (STATUS_WAIT, STATUS_POLL): the controller then records the flags the poll
read and passes the task over while they answer the same, whatever the other tasks
did (`status_only`). A comparison of the time,
`system_timeInMs >= X` (or >, <=, < with the operands swapped) with X such an
expression, sleeps until the first cycle whose time passes X:

    Till(system_timeInMs >= t);   ->   while not _I32[16] >= g_t:
                                           yield _till_ms(g_t, False)

A comparison of an axis's position feedback with such an expression,
`GetPosFb(a) >= X` (or >, <=, <, either way round, alone or `||` an event condition),
polls, and hands the controller the position it waits for (`position_wait`):

    Till(GetPosFb(a) >= x);   ->   if not b_GetPosFb(v_a) >= v_x:
                                       yield _till_pos(v_a, v_x, True, -2)
                                       while not b_GetPosFb(v_a) >= v_x:
                                           yield _till_pos(v_a, v_x, True, -1)

Any other condition (velocities, an array or a pointer, a call of a user's function,
the time combined with anything else) keeps polling every cycle.

A busy loop that only waits (`idle_body`: `while (c);`, `while (c) RunScheduler();`)
on a condition that changes nothing (`reads_only`) is decided by its first test in each
cycle; it is lowered as the same wait as `Till(!c)` (lower_loops.py).
"""

from __future__ import annotations

from motionvm.lang.hmpl import nodes as n

EVENT_BUILTINS = frozenset({
    "IsInPos", "IsMoving", "IsEnabled", "IsHomed", "IsHoming", "IsErrorStop",
    "IsGrpEnabled", "IsGrpMoving", "IsGrpInPos", "IsGrpErrorStop", "HIMC_GPI", "HIMC_GPO", "GetGPI", "GetGPO", "GetSlvGPI", "GetSlvGPO", "GetSlvAllGPI",
    "GetSlvAllGPO",
})  # fmt: skip
"""Built-ins whose answer changes only in a computed cycle (given the same arguments)."""

STATUS_BUILTINS = frozenset(
    {
        "IsInPos",
        "IsMoving",
        "IsEnabled",
        "IsHomed",
        "IsErrorStop",
        "IsGrpEnabled",
        "IsGrpMoving",
        "IsGrpInPos",
        "IsGrpErrorStop",
    }
)
"""Event built-ins that answer an axis's or an axis group's status flag (each call is
recorded). IsHoming
is not among them: asking it notices a homing cut off from outside, which must happen
when the task asks (motion/homing.py)."""

_PURE_UNARY = frozenset({"-", "+", "!", "~"})


def _pure(expr, resolve, storages: tuple[str, ...], builtins: frozenset[str]) -> bool:
    """True if `expr` is built of literals, constants, names of a storage class in
    `storages`, pure operators and calls of `builtins` with such arguments."""
    if isinstance(expr, (n.IntLit, n.FloatLit, n.CharLit)):
        return True
    if isinstance(expr, n.Name):
        sym = resolve(expr.id)
        if not sym:
            return False
        if getattr(sym, "const_value", None) is not None:
            return True
        return getattr(sym, "storage", None) in storages
    if isinstance(expr, n.Unary):
        return expr.op in _PURE_UNARY and _pure(expr.operand, resolve, storages, builtins)
    if isinstance(expr, n.Binary):
        return _pure(expr.left, resolve, storages, builtins) and _pure(
            expr.right, resolve, storages, builtins
        )
    if isinstance(expr, n.Cond):
        return all(
            _pure(x, resolve, storages, builtins) for x in (expr.cond, expr.then, expr.else_)
        )
    if isinstance(expr, n.Call):
        f = expr.func
        if isinstance(f, n.Name) and f.id == "HIMC_GPO" and len(expr.args) != 1:
            return False  # HIMC_GPO(n, v) sets an output
        return (isinstance(f, n.Name) and f.id in builtins and resolve(f.id) is None
                and all(_pure(x, resolve, storages, builtins) for x in expr.args))  # fmt: skip
    return False


def waits_on_event(expr, resolve) -> bool:
    """True if `expr` tests only what changes in computed cycles (see the module
    docstring); `resolve(name)` gives a name's symbol, None for a built-in function,
    False for an unknown name. Names: plain scalar variables (static storage holds the
    system variables and arrays)."""
    return _pure(expr, resolve, ("local", "pyglobal", "frame"), EVENT_BUILTINS)


def status_only(expr, resolve) -> bool:
    """True if `expr` is an event condition (`waits_on_event`) that depends on nothing
    but the answers of `STATUS_BUILTINS` calls: its names are constants or plain local
    variables of the task (no global, no variable in the task's memory), so that the
    same answers give the same value."""
    return _pure(expr, resolve, ("local",), STATUS_BUILTINS)


READ_BUILTINS = EVENT_BUILTINS | frozenset({
    "IsHWLL", "IsHWRL", "IsSWLL", "IsSWRL", "IsDriveErr", "IsPosErr", "IsAcc",
    "GetPosFb", "GetPosErr", "GetVelFb", "GetVelErr", "GetCurrFb", "GetRefPos",
    "GetRefVel", "GetRefAcc", "GetPosOut", "GetVelOut", "GetAccOut",
    "IsGrpEnabled", "IsGrpMoving", "IsGrpInPos", "IsGrpErrorStop",
    "GetAllGPI", "GetAllGPO", "GetSlvAI", "GetSlvAIRaw", "GetSlvAO", "GetSlvAORaw",
})  # fmt: skip
"""Built-ins that only read the machine: asking again in the same cycle gives the same
answer and leaves the same state (a bad axis id stores the same last error again)."""


def reads_only(expr, resolve) -> bool:
    """True if evaluating `expr` changes nothing (`READ_BUILTINS`, scalar variables of
    any storage, operators without assignment), so that evaluating it again within one
    slice of its task, in which nothing else runs, gives the same value: a busy loop on
    it (`while (c);`) is decided by its first test in each cycle."""
    return _pure(expr, resolve, ("local", "pyglobal", "frame", "static"), READ_BUILTINS)


def idle_body(body, resolve) -> bool:
    """True if loop body `body` does nothing but give up the task's slice: empty (`;`,
    `{}`) or the built-in `RunScheduler();` alone (`resolve` as for `waits_on_event`)."""
    if type(body) is n.Block:
        if not body.items:
            return True
        if len(body.items) != 1:
            return False
        body = body.items[0]
    if type(body) is n.Empty:
        return True
    if type(body) is not n.ExprStmt:
        return False
    e = body.expr
    return (type(e) is n.Call and type(e.func) is n.Name and e.func.id == "RunScheduler"
            and not e.args and resolve("RunScheduler") is None)  # fmt: skip


_RISING = {">=": True, ">": True, "<=": False, "<": False}
_SWAPPED = {">=": "<=", ">": "<", "<=": ">=", "<": ">"}


def position_wait(expr, resolve):
    """(A, X, rising) if `expr` is `GetPosFb(A) >= X` (rising: >=, >; falling: <=, <),
    or the same with the operands swapped, with A and X event expressions, or such a
    comparison `||` an event condition (`waits_on_event`); else None. Such a `Till`
    polls as any other, and tells the controller the position it waits for, so that a
    jump ends where the axis reaches it (motion/position_watch.py); the event part is
    watched as a `Till` on it is."""
    if not isinstance(expr, n.Binary):
        return None
    if expr.op == "||":
        for pos, other in ((expr.left, expr.right), (expr.right, expr.left)):
            found = position_wait(pos, resolve)
            if found is not None and waits_on_event(other, resolve):
                return found
        return None
    if expr.op not in _RISING:
        return None
    op, left, right = expr.op, expr.left, expr.right
    if not _is_pos_fb(left, resolve):
        op, left, right = _SWAPPED[op], right, left
        if not _is_pos_fb(left, resolve):
            return None
    if not waits_on_event(right, resolve):
        return None
    return left.args[0], right, _RISING[op]


def _is_pos_fb(e, resolve) -> bool:
    return (isinstance(e, n.Call) and isinstance(e.func, n.Name) and e.func.id == "GetPosFb"
            and resolve("GetPosFb") is None and len(e.args) == 1
            and waits_on_event(e.args[0], resolve))  # fmt: skip


_TIME = "system_timeInMs"
_FLIPPED = {"<=": ">=", "<": ">", ">=": ">=", ">": ">"}


_NEGATED = {"<": ">=", "<=": ">", ">": "<=", ">=": "<"}


def negated(expr):
    """The comparison that holds where comparison `expr` fails (`a < b` -> `a >= b`), or
    None for any other expression. Not where an operand is a NaN; a loop `while (expr)`
    waiting until it holds tests `expr` itself again each time it wakes, and a NaN ends
    it before any wait."""
    if not isinstance(expr, n.Binary) or expr.op not in _NEGATED:
        return None
    return n.Binary(expr.pos, _NEGATED[expr.op], expr.left, expr.right)


def time_wait(expr, resolve):
    """(X, strict) if `expr` is `system_timeInMs >= X` (strict: `>`), or the same with
    the operands swapped, X an event expression; else None."""
    if not isinstance(expr, n.Binary) or expr.op not in _FLIPPED:
        return None
    left, right, op = expr.left, expr.right, expr.op
    if op in ("<=", "<"):
        left, right = right, left
    if not (isinstance(left, n.Name) and left.id == _TIME):
        return None
    sym = resolve(_TIME)
    if not sym or getattr(sym, "storage", None) != "static" or getattr(sym, "name", "") != _TIME:
        return None
    if not waits_on_event(right, resolve):
        return None
    return right, _FLIPPED[expr.op] == ">"
