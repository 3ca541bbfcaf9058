"""Lower HMPL loops: `while`, `do`/`while`, `for`, with budgeted back-edges.

A loop yields to the scheduler when the task's slice is used up: a local countdown
charges the task budget every CHUNK iterations (`lower_util.backedge`):

    while (x < n) x += 2;
becomes
    _t1 = 65
    while v_x < v_n:
        v_x = v_x + 2 if v_x <= 2147483645 else v_x - 4294967294
        _t1 -= 1
        if not _t1:
            _t1 = 65
            _budget -= 64
            if _budget < 0:
                yield

`LoopLowerer` hands a loop to the part that makes it faster where it can: a counting
loop to `lower_range.RangeLowerer`, a pointer walk to `lower_walk.PointerWalkLowerer`,
a loop that only waits to the statement lowerer's wait (`Till`), a polling loop's
back-edge to lower_poll.py; a loop its task never leaves may end the task's records of
status reads (lower_records.py).
"""

from __future__ import annotations

import ast

from motionvm.lang.hmpl import nodes as n
from motionvm.lang.hmpl.lower_access import AccessLowerer
from motionvm.lang.hmpl.lower_context import FunctionContext
from motionvm.lang.hmpl.lower_expr import ExprLowerer
from motionvm.lang.hmpl.lower_facts import AssignedNames, _fill_assigned
from motionvm.lang.hmpl.lower_poll import continue_check, fixed_point, fixed_point_end
from motionvm.lang.hmpl.lower_range import RangeLowerer
from motionvm.lang.hmpl.lower_records import records_end
from motionvm.lang.hmpl.lower_split import Nesting
from motionvm.lang.hmpl.lower_stmt import StatementLowerer
from motionvm.lang.hmpl.lower_util import LoopCtx, PollCtx, backedge, countdown_init
from motionvm.lang.hmpl.lower_walk import PointerWalkLowerer
from motionvm.lang.hmpl.lvalues import const
from motionvm.lang.hmpl.symbols import Scope
from motionvm.lang.hmpl.till_events import idle_body, negated, reads_only

__all__ = ["LoopLowerer", "_fill_assigned"]  # the analysis tests read `_fill_assigned` here


class LoopLowerer:
    """Lowers the loops of one function."""

    def __init__(
        self,
        ctx: FunctionContext,
        x: ExprLowerer,
        access: AccessLowerer,
        stmts: StatementLowerer,
        nesting: Nesting,
        assigned: AssignedNames,
    ) -> None:
        self.ctx = ctx
        self.x = x
        self.stmts = stmts
        self.nesting = nesting
        self.walk = PointerWalkLowerer(ctx, x, access, nesting, self)
        self.ranges = RangeLowerer(ctx, x, nesting, self, assigned)

    def handlers(self) -> dict[type, object]:
        """The statements this part lowers: node class -> method."""
        return {n.While: self.s_While, n.DoWhile: self.s_DoWhile, n.For: self.s_For}

    def loop_body(self, body, cont: list[ast.stmt], blocks: int = 1,
                   polling: PollCtx | None = None):  # fmt: skip
        """The lowered body and the loop's context (split: see `lower_split.py`); `polling`:
        a polling loop's (`lower_poll.fixed_point`), None for any other loop, whose statements mark
        nothing (in a polling loop the loop itself marks an effect)."""
        fn = self.ctx
        fn.has_yield = True  # every loop has a budgeted back-edge
        ctx = LoopCtx("loop", cont)
        nesting, stmts = self.nesting, self.stmts
        ctx.split = nesting.nest(body.pos, blocks)
        nesting.loops.append(ctx)
        outer, stmts.polling = stmts.polling, polling
        declared = fn.local_names() if polling is not None else None
        try:
            lowered = stmts.block(body)
            if polling is not None:  # block-scope locals of the body: dead at the back-edge
                polling.inner = fn.locals_since(declared)
            return lowered, ctx
        finally:
            stmts.polling = outer
            nesting.loops.pop()
            nesting.unnest()

    def s_While(self, s: n.While) -> list[ast.stmt]:
        waiting = self._busy_wait(s)
        if waiting is not None:
            return waiting
        body = s.body
        if type(body) is n.Block and len(body.items) > 1 and type(body.items[-1]) is n.ExprStmt:
            fast = self.walk.pointer_walk(s.cond, body.items[-1].expr, body, body.items[:-1], s.pos)
            if fast is not None:
                return fast
        test = self.x.cond(s.cond)
        b = self.ctx.temp()
        polling = fixed_point(self.ctx, self.nesting, s.cond, s.body)
        cont = [continue_check() if polling else backedge(b), ast.Continue()]
        body, ctx = self.loop_body(s.body, _flat(cont), polling=polling)
        before, end = fixed_point_end(self.ctx, polling, b, body) if polling else ([], backedge(b))
        loop = self.nesting.placed(ctx, ast.While(test=test, body=body + end, orelse=[]))
        return [*records_end(s.cond, s.body, loop), countdown_init(b), *before] + loop

    def _busy_wait(self, s: n.While) -> list[ast.stmt] | None:
        """A loop that only waits, `while (c);` or `while (c) RunScheduler();` (or the same
        as `for (; c;)`, `for (;;)`) with a condition that changes nothing (`reads_only`),
        polled once per cycle: nothing else runs in its task's slice, so the first test
        of a cycle decides the rest of it, and spinning on to the end of the slice
        changes nothing a program can see.
        It is lowered as `Till(!c)`: on an event the controller may jump past it, on
        the time it sleeps, on a position it tells the controller. None for any other
        loop."""
        resolve = self.ctx.event_symbol
        if not (idle_body(s.body, resolve) and reads_only(s.cond, resolve)):
            return None
        test = self.x.cond(s.cond)
        waited = self.stmts.event_wait(s.cond, test)
        if waited is not None:
            return waited
        return self.stmts.poll_until(negated(s.cond), test)

    def s_DoWhile(self, s: n.DoWhile) -> list[ast.stmt]:
        # `do ; while (c);` is `while (c);`; `do RunScheduler(); while (c);` yields first
        waiting = self._busy_wait(n.While(s.pos, s.cond, s.body))
        if waiting is not None:
            body = s.body.items[0] if type(s.body) is n.Block and s.body.items else s.body
            first = [] if type(body) in (n.Empty, n.Block) else [ast.Expr(ast.Yield(None))]
            return first + waiting
        b = self.ctx.temp()
        exit_ = [
            ast.If(
                test=ast.UnaryOp(op=ast.Not(), operand=self.x.cond(s.cond)),
                body=[ast.Break()],
                orelse=[],
            )
        ]
        cont = self.ctx.at(exit_, s.cond.pos) + backedge(b) + [ast.Continue()]
        body, ctx = self.loop_body(s.body, cont)
        exit2 = [
            ast.If(
                test=ast.UnaryOp(op=ast.Not(), operand=self.x.cond(s.cond)),
                body=[ast.Break()],
                orelse=[],
            )
        ]
        loop = ast.While(
            test=ast.Constant(True),
            body=body + self.ctx.at(exit2, s.cond.pos) + backedge(b),
            orelse=[],
        )
        return [countdown_init(b)] + self.nesting.placed(ctx, loop)

    def s_For(self, s: n.For) -> list[ast.stmt]:
        if s.init is None and s.step is None:  # for (;;); and for (; c;) RunScheduler();
            cond = n.IntLit(s.pos, 1) if s.cond is None else s.cond
            waiting = self._busy_wait(n.While(s.pos, cond, s.body))
            if waiting is not None:
                return waiting
        fn = self.ctx
        saved = fn.scope
        fn.scope = Scope(saved, "block")
        try:
            out: list[ast.stmt] = []
            if s.init is not None:
                out.extend(self.ctx.at(self.stmts.stmt(s.init), s.init.pos))
            fast = self.ranges.range_for(s)
            if fast is None and s.cond is not None and s.step is not None:
                fast = self.walk.pointer_walk(s.cond, s.step, s.body, None, s.pos)
            if fast is not None:
                return _start_in_range(out, fast) if isinstance(s.init, n.DeclStmt) else out + fast
            b = self.ctx.temp()
            test = self.x.cond(s.cond) if s.cond is not None else ast.Constant(True)
            step = (
                self.ctx.at(self.stmts.s_ExprStmt(n.ExprStmt(s.step.pos, s.step)), s.step.pos)
                if s.step is not None
                else []
            )
            polling = (
                fixed_point(self.ctx, self.nesting, s.cond, s.body) if s.step is None else None
            )
            cont = _flat([step, continue_check() if polling else backedge(b), ast.Continue()])
            body, ctx = self.loop_body(s.body, cont, polling=polling)
            step2 = (
                self.ctx.at(self.stmts.s_ExprStmt(n.ExprStmt(s.step.pos, s.step)), s.step.pos)
                if s.step is not None
                else []
            )
            before, end = (
                fixed_point_end(self.ctx, polling, b, body) if polling else ([], backedge(b))
            )
            loop = self.nesting.placed(
                ctx, ast.While(test=test, body=body + step2 + end, orelse=[])
            )
            out += [*records_end(s.cond, s.body, loop), countdown_init(b), *before]
            return out + loop
        finally:
            fn.scope = saved


def _flat(items) -> list[ast.stmt]:
    """Statements and lists of statements, as one list."""
    out = []
    for x in items:
        out.extend(x if isinstance(x, list) else [x])
    return out


def _start_in_range(init: list[ast.stmt], loop: list[ast.stmt]) -> list[ast.stmt]:
    """A counter declared by the loop with a constant start needs no assignment before it:
    the constant starts the range. `int i = 0; ... range(v_i, n)` -> `range(n)`.
    Not when the loop is a split function (its `nonlocal` wants the outer binding)."""
    if not (
        len(init) == 1
        and type(init[0]) is ast.Assign
        and type(init[0].value) is ast.Constant
        and type(init[0].targets[0]) is ast.Name
        and not any(type(x) is ast.FunctionDef for x in loop)
    ):
        return init + loop
    var = init[0].targets[0].id
    for stmt in loop:
        node = stmt.iter if type(stmt) is ast.For else None
        if type(stmt) is ast.Assign and type(stmt.targets[0]) is ast.Name:
            node = stmt.value  # `_r = range(...)` before the chunks of a nested loop
        elif type(node) is ast.Call and type(node.func) is ast.Name and node.func.id == "_chunks":
            node = node.args[0]
        if (
            type(node) is ast.Call
            and type(node.func) is ast.Name
            and node.func.id == "range"
            and type(node.args[0]) is ast.Name
            and node.args[0].id == var
        ):
            start = init[0].value.value
            if start == 0 and len(node.args) == 2:
                del node.args[0]  # `range(n)`
            else:
                node.args[0] = ast.copy_location(const(start), node.args[0])
            return loop
    return init + loop
