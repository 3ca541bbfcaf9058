"""Polling loops, whose quiet iterations end their task's slice (lower_loops.py asks here).

A polling loop (one that reads what may change outside it: see `fixed_point`) ends
its task's slice at the first iteration that changes nothing: nothing else runs in the
slice, so every later iteration of it would repeat that one. The loop's back-edge
compares the locals its body writes (those declared outside it) with those of the
back-edge before, and a marker tells whether any statement that may act ran in between:

    while (1) { int in = GetGPI(4); if (in && !last) DisableAll(); last = in; }
becomes
    _t3 = 1
    _t4 = None
    _t5 = -2
    while True:
        v_in = b_GetGPI(4)
        if v_in and not v_last:
            _t3 = 1
            b_DisableAll()
        v_last = v_in
        if _t3 or _t4 != (v_last,):
            _t4 = (v_last,)
            _t3 = 0
            _t5 = -2
            <the budgeted back-edge>
        else:
            _t1 = 65          # the countdown as the spin would leave it at its yield
            yield _t5         # EVENT_WAIT or EVENT_POLL: GetGPI changes in computed cycles
            _t5 = -1
"""

from __future__ import annotations

import ast
import copy

from motionvm.lang.hmpl import nodes as n
from motionvm.lang.hmpl.analysis import walk
from motionvm.lang.hmpl.lower_context import FunctionContext
from motionvm.lang.hmpl.lower_facts import loop_depth
from motionvm.lang.hmpl.lower_split import Nesting
from motionvm.lang.hmpl.lower_util import PollCtx, backedge, countdown_init
from motionvm.lang.hmpl.lvalues import name
from motionvm.lang.hmpl.symbols import VarSym
from motionvm.lang.hmpl.till_events import READ_BUILTINS, reads_only, waits_on_event
from motionvm.runtime.kernel import EVENT_POLL, EVENT_WAIT


def fixed_point(ctx: FunctionContext, nesting: Nesting, cond, body) -> PollCtx | None:
    """A new `PollCtx` if `while (cond) body` (cond None: forever) is a polling loop
    that ends its slice at a fixed point: one that reads what may change outside it
    (`_reads_outside`), whose condition changes nothing, and in which no loop or
    switch will be lowered as a function of its own (its statements would set a
    marker of their own). None for any other loop: those keep spinning (the check
    would only slow them down)."""
    resolve = ctx.event_symbol
    if cond is not None and not reads_only(cond, resolve):
        return None
    if not (_reads_outside(cond, resolve) or _reads_outside(body, resolve)):
        return None  # it cannot be waiting for anything
    if not nesting.room(1 + loop_depth(body)):
        return None
    return PollCtx(ctx.temp(), cond is None or waits_on_event(cond, resolve))


def fixed_point_end(ctx: FunctionContext, polling: PollCtx, b: str, body: list[ast.stmt]):
    """(statements before the loop, the back-edge) of polling loop `polling` with
    countdown `b` whose lowered body is `body` (see the module docstring): the slice
    ends at an iteration that ran no marked statement and left the locals it writes
    as they were (those declared outside it: a block-scope local of the body lives
    for one iteration). It yields EVENT_POLL if that iteration is the first since the
    task's last yield, else EVENT_WAIT, when its quiet iterations read only what a
    computed cycle changes (`PollCtx.on_events`: the clock may jump), else None.
    A body whose first statement may act marks every iteration: it never reaches a
    fixed point, and has the plain back-edge (no mark, no check)."""
    mark = polling.mark
    if _marks_first(body, mark):
        del body[0]
        _FillContinues(backedge(b)).visit(ast.Module(body, []))
        return [], backedge(b)
    written = sorted({
        x.id for st in body for x in ast.walk(st)
        if type(x) is ast.Name and type(x.ctx) is ast.Store and x.id.startswith("v_")
    } - polling.inner)  # fmt: skip
    seen = ctx.temp()

    def now() -> ast.Tuple:
        return ast.Tuple([name(v) for v in written], ast.Load())

    changed = ast.BoolOp(ast.Or(), [
        name(mark), ast.Compare(name(seen), [ast.NotEq()], [now()])
    ])  # fmt: skip
    record = [
        ast.Assign([name(seen, True)], now()),
        ast.Assign([name(mark, True)], ast.Constant(0)),
    ]
    before = [mark_effect(mark), ast.Assign([name(seen, True)], ast.Constant(None))]
    repeat = [countdown_init(b)]
    if polling.on_events:
        kind = ctx.temp()  # EVENT_WAIT until the first quiet iteration after a yield
        before.append(ast.Assign([name(kind, True)], ast.Constant(EVENT_WAIT)))
        record.append(ast.Assign([name(kind, True)], ast.Constant(EVENT_WAIT)))
        repeat += [ast.Expr(ast.Yield(name(kind))),
                   ast.Assign([name(kind, True)], ast.Constant(EVENT_POLL))]  # fmt: skip
    else:
        repeat.append(ast.Expr(ast.Yield(None)))
    check = ast.If(changed, record + backedge(b), repeat)
    _FillContinues([check]).visit(ast.Module(body, []))  # a `continue` checks as well
    return before, [check]


def _marks_first(body: list[ast.stmt], mark: str) -> bool:
    """True if lowered body `body` starts with `mark = 1` (`mark_effect`)."""
    if not body or type(body[0]) is not ast.Assign:
        return False
    st = body[0]
    target = st.targets[0]
    return (type(target) is ast.Name and target.id == mark
            and type(st.value) is ast.Constant and st.value.value == 1)  # fmt: skip


def quiet_statement(ctx: FunctionContext, s, polling: PollCtx) -> bool:
    """True if statement `s` of polling loop `polling`'s body changes nothing but plain
    integer locals, and so need not set the loop's effect marker: it only reads the
    machine and variables (`reads_only`), or is a block, an `if` or a `switch` on
    such a condition (their statements mark themselves), or leaves the loop's
    iteration (`break`, `return`; a `continue` checks as the back-edge does). If what
    it reads is not all a computed cycle changes (`waits_on_event`), the loop's
    quiet iterations poll (`PollCtx.on_events` false)."""
    t = type(s)
    if t in (n.Empty, n.Block, n.Break, n.Continue, n.Return):
        return True
    resolve = ctx.event_symbol
    if t is n.If:
        reads = [s.cond]
    elif t is n.Switch:
        reads = [s.expr]
    elif t is n.ExprStmt:
        e = s.expr
        if type(e) is n.Assign:
            if not _plain_int_local(ctx, e.target):
                return False
            reads = [e.value]
        elif type(e) in (n.Postfix, n.Unary) and e.op in ("++", "--"):
            return _plain_int_local(ctx, e.operand)
        else:
            reads = [e]
    elif t is n.DeclStmt:
        reads = []
        for d in s.decls:
            if type(d) is not n.VarDecl:
                continue
            if d.is_static or d.dims or not _plain_int_local(ctx, d):
                return False
            if d.init is not None:
                reads.append(d.init)
    else:
        return False
    if not all(reads_only(x, resolve) for x in reads):
        return False
    if polling.on_events and not all(waits_on_event(x, resolve) for x in reads):
        polling.on_events = False
    return True


def _plain_int_local(ctx: FunctionContext, target) -> bool:
    """True if `target` (a Name, or a VarDecl once lowered) is an integer variable
    kept in a Python local of this function."""
    if type(target) not in (n.Name, n.VarDecl):
        return False
    sym = ctx.scope.lookup(target.id if type(target) is n.Name else target.name)
    return (isinstance(sym, VarSym) and sym.storage == "local"
            and sym.type.is_integer)  # fmt: skip


_CONTINUE_CHECK = "_continue_check_"


def continue_check() -> ast.stmt:
    """Where a `continue` of a polling loop's body checks for a fixed point, as the loop's
    back-edge does: filled in once the body is lowered (`_FillContinues`), as what the
    check compares (the locals the body writes) is known only then."""
    return ast.Expr(ast.Name(_CONTINUE_CHECK, ast.Load()))


class _FillContinues(ast.NodeTransformer):
    """Replaces each `continue_check()` by a copy of the loop's check (statements)."""

    def __init__(self, check: list[ast.stmt]) -> None:
        self.check = check

    def visit_Expr(self, node: ast.Expr):
        v = node.value
        if type(v) is ast.Name and v.id == _CONTINUE_CHECK:
            check = copy.deepcopy(self.check)
            for st in check:
                for x in ast.walk(st):  # at the `continue`'s place
                    if "lineno" in x._attributes:
                        ast.copy_location(x, node)
            return check
        return node


def mark_effect(mark: str) -> ast.stmt:
    """`mark = 1`: a statement that may act ran in this iteration of a polling loop."""
    return ast.Assign([name(mark, True)], ast.Constant(1))


def _reads_outside(node, resolve) -> bool:
    """True if HMPL `node` reads what may change outside a loop on it: calls a built-in
    of `READ_BUILTINS` or names a global or static variable (a polling loop's sign: a
    loop on the function's own variables alone cannot be waiting for anything)."""
    if node is None:
        return False
    for x in walk(node):
        t = type(x)
        if t is n.Call:
            f = x.func
            if type(f) is n.Name and f.id in READ_BUILTINS and resolve(f.id) is None:
                return True
        elif t is n.Name:
            sym = resolve(x.id)
            if getattr(sym, "storage", None) in ("pyglobal", "static"):
                return True
    return False
