"""Lower HMPL statements to Python `ast` statements: blocks, expression statements, `if`,
`return`, and the waits `Till(c)` and `while (c);`.

`StatementLowerer` walks a function's statements and hands each to the part that owns
its kind: declarations (lower_decl.py), loops (lower_loops.py), `switch`
(lower_switch.py), jumps (lower_jumps.py). Python `ast` nodes are built with positional
arguments (in the order of the class's `_fields`): a keyword call costs about twice as
much, and a compile builds tens of thousands of nodes.

    if (x > 0) Till(GetGPI(4)); else return;
becomes
    if v_x > 0:
        if not b_GetGPI(4):     # the controller may jump to the cycle that changes it
            yield -2
            while not b_GetGPI(4):
                yield -1
    else:
        return
"""

from __future__ import annotations

import ast
import copy

from motionvm.lang.hmpl import ctypes_ as ct
from motionvm.lang.hmpl import nodes as n
from motionvm.lang.hmpl.lower_access import AccessLowerer
from motionvm.lang.hmpl.lower_context import FunctionContext, SemanticError
from motionvm.lang.hmpl.lower_expr import ExprLowerer
from motionvm.lang.hmpl.lower_poll import mark_effect, quiet_statement
from motionvm.lang.hmpl.lower_split import Nesting
from motionvm.lang.hmpl.lower_util import PollCtx
from motionvm.lang.hmpl.lvalues import call
from motionvm.lang.hmpl.symbols import Scope, VarSym
from motionvm.lang.hmpl.till_events import position_wait, status_only, time_wait, waits_on_event
from motionvm.runtime.kernel import EVENT_POLL, EVENT_WAIT, STATUS_POLL, STATUS_WAIT


class StatementLowerer:
    """Lowers the statements of one function, in its current block scope."""

    def __init__(
        self, ctx: FunctionContext, x: ExprLowerer, access: AccessLowerer, nesting: Nesting
    ) -> None:
        self.ctx = ctx
        self.x = x
        self.access = access
        self.nesting = nesting
        self.prog = ctx.prog
        self.fail = ctx.fail
        self.polling: PollCtx | None = None
        """The polling loop whose body is being lowered (lower_poll.py), set by the loops."""
        self._handlers: dict[type, object] = {
            n.Block: self.s_Block,
            n.Empty: self.s_Empty,
            n.ExprStmt: self.s_ExprStmt,
            n.If: self.s_If,
            n.Return: self.s_Return,
        }

    def attach(self, handlers: dict[type, object]) -> None:
        """Hand the statements of kind `node class` to the part's method (declarations,
        loops, switch, jumps)."""
        self._handlers.update(handlers)

    def stmts(self, items) -> list[ast.stmt]:
        out: list[ast.stmt] = []
        saved = dict(self.x.known_ranges)
        methods = self._handlers
        ctx = self.ctx
        try:
            # in a polling loop's body the statements up to the first one that may act
            # run in its quiet iterations; that one sets the loop's marker (see
            # lower_loops.py), and what follows it runs only after it
            polling = self.polling
            for s in items:
                fn = methods.get(type(s))  # `stmt` inline
                try:
                    lowered = fn(s) if fn is not None else self.stmt(s)
                    if polling is not None and not quiet_statement(ctx, s, polling):
                        lowered = [mark_effect(polling.mark), *lowered]
                        polling = None
                    out.extend(ctx.at(lowered, s.pos))
                except SemanticError:
                    pass
                if type(s) is n.If and s.else_ is None and ends_in(s.then, _LEAVES):
                    self._learn_from_guard(s.cond)
        finally:
            self.x.known_ranges = saved
        return out

    def _learn_from_guard(self, cond) -> None:
        """After `if (v < c) return ...;` the rest of the block knows v >= c.

        Only for a local integer that the function never assigns (a parameter, usually),
        compared with a constant; the fact holds until the end of the enclosing block,
        which no goto can enter (labels stand at the function's top level, each lowered
        as a block of its own). It lets range analysis drop wraps, as in `fib(n - 1)`.
        """
        if not (
            type(cond) is n.Binary
            and cond.op in ("<", "<=", ">", ">=")
            and type(cond.left) is n.Name
        ):
            return
        right = cond.right
        neg = type(right) is n.Unary and right.op == "-" and type(right.operand) is n.IntLit
        if not (type(right) is n.IntLit or neg):
            return
        c = -right.operand.value if neg else right.value
        name_ = cond.left.id
        if name_ in self.ctx.func_assigned:
            return
        sym = self.ctx.scope.lookup(name_)
        if (
            not isinstance(sym, VarSym)
            or sym.storage != "local"
            or not isinstance(sym.type, ct.IntT)
        ):
            return
        t = sym.type
        lo, hi = self.x.known_ranges.get(sym.pyname, (t.min, t.max))
        if cond.op == "<":
            lo = max(lo, c)
        elif cond.op == "<=":
            lo = max(lo, c + 1)
        elif cond.op == ">":
            hi = min(hi, c)
        else:
            hi = min(hi, c - 1)
        if lo <= hi:
            self.x.known_ranges[sym.pyname] = (lo, hi)

    def stmt(self, s) -> list[ast.stmt]:
        return self._handlers[type(s)](s)

    def block(self, s, kind: str = "block") -> list[ast.stmt]:
        ctx = self.ctx
        saved = ctx.scope
        ctx.scope = Scope(saved, kind)
        try:
            items = s.items if isinstance(s, n.Block) else (s,)
            return self.stmts(items)
        finally:
            ctx.scope = saved

    def s_Block(self, s: n.Block) -> list[ast.stmt]:
        return self.block(s)

    def s_Empty(self, s) -> list[ast.stmt]:
        return []

    def s_ExprStmt(self, s: n.ExprStmt) -> list[ast.stmt]:
        e = s.expr
        if isinstance(e, n.Assign):
            return self.access.assignment(e, as_stmt=True)
        if isinstance(e, (n.Postfix, n.Unary)) and e.op in ("++", "--"):
            return self.access.incdec(e.operand, e.op, prefix=True, pos=e.pos, as_stmt=True)
        if isinstance(e, n.Call) and isinstance(e.func, n.Name) and e.func.id == "Till":
            return self._till(e)
        v = self.x.expr(e)
        return [ast.Expr(v.node)]

    def _till(self, e: n.Call) -> list[ast.stmt]:
        if len(e.args) != 1:
            raise self.fail(e.pos, f"Till takes 1 argument (condition), got {len(e.args)}")
        if self.ctx.in_init:
            raise self.fail(e.pos, "Till cannot be used in a global initializer")
        cond = self.x.cond(e.args[0])
        test = ast.UnaryOp(ast.Not(), cond)
        waited = self.event_wait(e.args[0], test)
        if waited is not None:
            return waited
        return self.poll_until(e.args[0], test)

    def poll_until(self, until, waiting: ast.expr) -> list[ast.stmt]:
        """The wait of a task, polled once per cycle, while the Python test `waiting`
        holds, that is until HMPL condition `until` (None: not known as a condition)
        holds: on the time it sleeps until the first cycle that passes it (`_till_ms`);
        on an axis's position it polls, handing the position to the controller's jumps
        (`_till_pos`); else it polls."""
        self.ctx.has_yield = True
        resolve = self.ctx.event_symbol
        timed = None if until is None else time_wait(until, resolve)
        if timed is not None:  # sleep until the first cycle whose time passes X
            wake = call("_till_ms", self.x.expr(timed[0]).node, ast.Constant(timed[1]))
            return [ast.While(waiting, [ast.Expr(ast.Yield(wake))], [])]
        watched = None if until is None else position_wait(until, resolve)
        if watched is not None:
            args = [self.x.expr(watched[0]).node, self.x.expr(watched[1]).node,
                    ast.Constant(watched[2])]  # fmt: skip
            wait = ast.Yield(call("_till_pos", *args, ast.Constant(EVENT_WAIT)))
            again = [copy.deepcopy(x) for x in args]
            poll = ast.Yield(call("_till_pos", *again, ast.Constant(EVENT_POLL)))
            loop = ast.While(copy.deepcopy(waiting), [ast.Expr(poll)], [])
            return [ast.If(waiting, [ast.Expr(wait), loop], [])]
        return [ast.While(waiting, [ast.Expr(ast.Yield(None))], [])]

    def event_wait(self, expr, waiting: ast.expr) -> list[ast.stmt] | None:
        """The wait of a task while the Python test `waiting` holds, polled once per
        cycle, if what decides it, HMPL condition `expr`, waits on an event
        (till_events.py): `Till(c)` (waiting: not c) and the busy loops `while (c);`
        and `while (c) RunScheduler();` (waiting: c). None if `expr` does not."""
        if not waits_on_event(expr, self.ctx.event_symbol):
            return None
        self.ctx.has_yield = True
        status = status_only(expr, self.ctx.event_symbol)
        poll = ast.While(
            copy.deepcopy(waiting), [_yield(STATUS_POLL if status else EVENT_POLL)], []
        )
        wait = _yield(STATUS_WAIT if status else EVENT_WAIT)
        return [ast.If(waiting, [wait, poll], [])]

    def s_If(self, s: n.If) -> list[ast.stmt]:
        test = self.x.cond(s.cond)
        body = self.block(s.then) or [ast.Pass()]
        orelse = self.block(s.else_) if s.else_ is not None else []
        return [ast.If(test, body, orelse)]

    def s_Return(self, s: n.Return) -> list[ast.stmt]:
        if self.ctx.func is None:
            raise self.fail(s.pos, "'return' outside a function")
        ret = self.ctx.func.type.ret
        if s.value is None:
            if not isinstance(ret, ct.VoidT):
                raise self.fail(
                    s.pos,
                    f"'return' with no value in function '{self.ctx.func.name}' returning '{ret}'",
                )
            return [self.nesting.split_return(None) or ast.Return(None)]
        v = self.x.expr(s.value)
        if isinstance(ret, ct.VoidT):
            if not isinstance(v.type, ct.VoidT):
                raise self.fail(
                    s.pos, f"'return' with a value in void function '{self.ctx.func.name}'"
                )
            return [ast.Expr(v.node), self.nesting.split_return(None) or ast.Return(None)]
        value = self.x.assign_convert(
            v, ret, s.value.pos, f" in the return value of '{self.ctx.func.name}'"
        )
        return [self.nesting.split_return(value) or ast.Return(value)]


def ends_in(s, kinds: tuple) -> bool:
    """True if statement `s` never falls through: every path ends in a statement of one
    of `kinds` (`RETURNS`: a function whose body always returns needs no `return 0`
    after it; `_LEAVES`: return, break, continue, goto)."""
    t = type(s)
    if t in kinds:
        return True
    if t is n.Block:
        return bool(s.items) and ends_in(s.items[-1], kinds)
    if t is n.If:
        return s.else_ is not None and ends_in(s.then, kinds) and ends_in(s.else_, kinds)
    return False


RETURNS = (n.Return,)
_LEAVES = (n.Return, n.Break, n.Continue, n.Goto)


def _contains_yield(body: list[ast.stmt]) -> bool:
    return any(isinstance(x, (ast.Yield, ast.YieldFrom)) for s in body for x in ast.walk(s))


def _yield(value: int) -> ast.stmt:
    """`yield value` as a statement (a task's wait, runtime/kernel.py)."""
    return ast.Expr(ast.Yield(ast.Constant(value)))
