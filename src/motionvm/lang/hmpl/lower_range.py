"""Lower HMPL counting loops to Python `range` loops, run in chunks of CHUNK values.

A counting loop whose counter and bound the body leaves alone becomes a `range` loop,
in chunks of CHUNK values, charging the task's budget once per chunk:

    for (int i = 0; i < n; i++) s += a[i];
becomes
    _t1 = range(v_i, v_n, 1)
    if _t1:
        for _t2 in range(0, len(_t1), 64):
            for v_i in (_t1[_t2:_t2 + 64] if _t2 or len(_t1) > 64 else _t1):
                v_s = ...
            _budget -= 64
            if _budget < 0:
                yield
"""

from __future__ import annotations

import ast

from motionvm.lang.hmpl import ctypes_ as ct
from motionvm.lang.hmpl import nodes as n
from motionvm.lang.hmpl.lower_context import FunctionContext, SemanticError
from motionvm.lang.hmpl.lower_expr import ExprLowerer
from motionvm.lang.hmpl.lower_facts import AssignedNames, breaks_out, invariant, loop_depth
from motionvm.lang.hmpl.lower_split import Nesting
from motionvm.lang.hmpl.lower_util import CHUNK, LoopBodies, backedge, countdown_init
from motionvm.lang.hmpl.lower_walk import alias_globals
from motionvm.lang.hmpl.lvalues import call, const, name
from motionvm.lang.hmpl.symbols import VarSym


class RangeLowerer:
    """Lowers the counting loops of one function that can run over a `range`."""

    def __init__(
        self,
        ctx: FunctionContext,
        x: ExprLowerer,
        nesting: Nesting,
        loops: LoopBodies,
        assigned: AssignedNames,
    ) -> None:
        self.ctx = ctx
        self.x = x
        self.nesting = nesting
        self.loops = loops
        self.assigned = assigned

    def _room_for_chunks(self, body) -> bool:
        """A counting loop may take two blocks if the deeper loops still find one each."""
        return self.nesting.room(2 + loop_depth(body))

    def range_for(self, s: n.For) -> list[ast.stmt] | None:
        """`for (i = a; i < b; i += c)` with i and b untouched by the body -> `for v_i in range(...)`.

        Only for a local int32/int64 (or increasing uint32) counter and a bound built from
        constants and locals the body does not assign; the C value of i after the loop is
        restored in the loop's `else` when i outlives the loop.
        """
        ivar = self._counter_of(s)
        if ivar is None:
            return None
        sym = self.ctx.scope.lookup(ivar)
        if (
            not isinstance(sym, VarSym)
            or sym.storage != "local"
            or sym.type not in (ct.INT, ct.I64, ct.U32)
        ):
            return None
        cond, step = s.cond, s.step
        if not (
            isinstance(cond, n.Binary)
            and cond.op in ("<", "<=", ">", ">=")
            and isinstance(cond.left, n.Name)
            and cond.left.id == ivar
        ):
            return None
        inc = self._step_of(step, ivar)
        assigned = self.assigned.of(s.body)
        step_var = None
        step_rng = None
        if (
            inc is None
            and isinstance(step, n.Assign)
            and step.op == "+="
            and isinstance(step.target, n.Name)
            and step.target.id == ivar
            and cond.op in ("<", "<=")
            and invariant(self.ctx, step.value, assigned)
        ):
            try:
                sv = self.x.expr(step.value)
            except SemanticError:
                return None
            if not sv.type.is_integer or ct.common_arith(sym.type, sv.type) != sym.type:
                return None
            step_var = self.x.convert(sv, sym.type, step.pos)
            step_rng = sv.rng
            inc = "var"
        if inc is None:
            return None
        if inc != "var" and (
            (inc > 0) != (cond.op in ("<", "<=")) or (inc < 0 and not sym.type.signed)
        ):
            return None
        if ivar in assigned or not invariant(self.ctx, cond.right, assigned):
            return None
        try:
            bound = self.x.expr(cond.right)
        except SemanticError:
            return None
        if not bound.type.is_integer or ct.common_arith(sym.type, bound.type) != sym.type:
            return None
        stop = self.x.convert(bound, sym.type, cond.pos)
        if cond.op in ("<=", ">="):
            up = inc == "var" or inc > 0
            if type(stop) is ast.Constant:
                stop = const(stop.value + (1 if up else -1))
            else:
                stop = ast.BinOp(
                    left=stop, op=ast.Add() if up else ast.Sub(), right=ast.Constant(1)
                )
        chunked = not breaks_out(s.body) and self._room_for_chunks(s.body)
        b = self.ctx.temp()
        cont = [ast.Continue()] if chunked else backedge(b) + [ast.Continue()]
        start = self._start_range(s)
        known = None
        tmin, tmax = sym.type.min, sym.type.max
        if start is not None and tmin <= start[0] and start[1] <= tmax:
            # the counter runs from its start towards the bound: a bound of unknown value
            # (or one that converts) is still in the counter's type
            b_lo, b_hi = bound.rng or (tmin, tmax)
            if b_lo < tmin or b_hi > tmax:
                b_lo, b_hi = tmin, tmax
            if inc == "var" or inc > 0:
                known = (start[0], max(start[0], b_hi - (1 if cond.op == "<" else 0)))
            else:
                known = (min(start[1], b_lo + (1 if cond.op == ">" else 0)), start[1])
        if known is not None:
            self.x.known_ranges[sym.pyname] = known  # lets indexing skip its bounds check
        try:
            body, ctx = self.loops.loop_body(s.body, cont, 2 if chunked else 1)
            if not chunked:
                body += backedge(b)
        finally:
            self.x.known_ranges.pop(sym.pyname, None)
        pre: list[ast.stmt] = []
        if inc == "var" and step_rng is not None and step_rng[0] > 0:
            step_node = step_var  # known positive (range analysis): nothing to check
        elif inc == "var":
            # a run-time step must be positive (0 or less would never reach the bound)
            st = self.ctx.temp()
            pre.append(ast.Assign(targets=[name(st, True)], value=step_var))
            ok = ast.Compare(left=name(st), ops=[ast.Gt()], comparators=[ast.Constant(0)])
            step_node = ast.IfExp(test=ok, body=name(st), orelse=call("_bad_step", name(st)))
        else:
            step_node = const(inc)
        if chunked:
            # the counter's start, if known when compiling and in its type (as assigned)
            first = start[0] if known is not None and start[0] == start[1] else None
            loops = self._chunked_range(
                sym,
                stop,
                step_node,
                body,
                outlives=not isinstance(s.init, n.DeclStmt),
                first=first,
            )
            return pre + loops[:-1] + self.nesting.placed(ctx, loops[-1])
        pre.append(countdown_init(b))
        rng = _range_call(name(sym.pyname), stop, step_node)
        outlives = not isinstance(s.init, n.DeclStmt)
        orelse: list[ast.stmt] = []
        if outlives:
            r = self.ctx.temp()
            pre.append(ast.Assign(targets=[name(r, True)], value=rng))
            rng = name(r)
            final = ast.BinOp(
                left=ast.Attribute(value=name(r), attr="start", ctx=ast.Load()),
                op=ast.Add(),
                right=ast.BinOp(
                    left=call("len", name(r)),
                    op=ast.Mult(),
                    right=ast.Attribute(value=name(r), attr="step", ctx=ast.Load()),
                ),
            )
            orelse = [ast.Assign(targets=[name(sym.pyname, True)], value=final)]
        loop = ast.For(target=name(sym.pyname, True), iter=rng, body=body, orelse=orelse)
        return pre + self.nesting.placed(ctx, loop)

    def _chunked_range(
        self,
        sym: VarSym,
        stop: ast.expr,
        step: ast.expr,
        body: list[ast.stmt],
        outlives: bool,
        first: int | None = None,
    ) -> list[ast.stmt]:
        """The counting loop in chunks of CHUNK values, charging the budget once per chunk
        (`_chunks` gives none for an empty range, the range itself for a short one):

        for _k in _chunks(range(v_i, STOP, STEP)):
            for v_i in _k:
                BODY
            _budget -= 64
            if _budget < 0:
                yield

        When i outlives the loop, the range is kept (`_r = range(...)`) and the loop's
        `else` sets C's value after it: `v_i = _r.start + len(_r) * _r.step`. A loop
        inside another loop takes its chunks inline (`_inline_chunks`). A loop known to
        be one chunk (`first`: the counter's start, a constant, as are the bound and the
        step) runs without chunks (`_one_chunk`).
        """
        k = self.ctx.temp()
        rng: ast.expr = _range_call(name(sym.pyname), stop, step)
        pre: list[ast.stmt] = []
        orelse: list[ast.stmt] = []
        if outlives:
            r = self.ctx.temp()
            pre.append(ast.Assign(targets=[name(r, True)], value=rng))
            rng = name(r)
            final = ast.BinOp(
                left=ast.Attribute(value=name(r), attr="start", ctx=ast.Load()),
                op=ast.Add(),
                right=ast.BinOp(
                    left=call("len", name(r)),
                    op=ast.Mult(),
                    right=ast.Attribute(value=name(r), attr="step", ctx=ast.Load()),
                ),
            )
            orelse = [ast.Assign(targets=[name(sym.pyname, True)], value=final)]
        inner = ast.For(
            target=name(sym.pyname, True), iter=name(k), body=body or [ast.Pass()], orelse=[]
        )
        over = ast.Compare(left=name("_budget"), ops=[ast.Lt()], comparators=[ast.Constant(0)])
        charge = [
            ast.AugAssign(target=name("_budget", True), op=ast.Sub(), value=ast.Constant(CHUNK)),
            ast.If(test=over, body=[ast.Expr(value=ast.Yield(value=None))], orelse=[]),
        ]
        # the arrays' local names are bound once a chunk, inside the loop (and so inside
        # its split function, if it has one)
        aliases = alias_globals(inner.body, self.ctx)
        count = _count(first, stop, step)
        if count and count <= CHUNK and not aliases:
            return [_one_chunk(sym, stop, step, inner, charge, first + count * step.value,
                               outlives)]  # fmt: skip
        if any(c.kind == "loop" for c in self.nesting.loops):
            return pre + self._inline_chunks(k, rng, inner, aliases, [inner] + charge, orelse)
        outer = ast.For(
            target=name(k, True),
            iter=call("_chunks", rng),
            body=aliases + [inner] + charge,
            orelse=orelse,
        )
        return pre + [outer]

    def _inline_chunks(
        self, k: str, rng: ast.expr, inner: ast.For, aliases: list, body: list, orelse: list
    ) -> list[ast.stmt]:
        """The chunks of a loop inside another loop, entered once per outer iteration:
        without the call of `_chunks` (a short range runs as it is, an empty one skips
        the set-up)

        _r = range(...)
        if _r:
            for _k in range(0, len(_r), 64):
                for v_i in (_r[_k:_k + 64] if _k or len(_r) > 64 else _r):
                    BODY
                ...   # the budget charge
        """
        if type(rng) is ast.Name:
            r, pre = rng.id, []
        else:
            r = self.ctx.temp()
            pre = [ast.Assign(targets=[name(r, True)], value=rng)]
        sliced = ast.Subscript(
            value=name(r),
            slice=ast.Slice(
                lower=name(k),
                upper=ast.BinOp(left=name(k), op=ast.Add(), right=ast.Constant(CHUNK)),
            ),
            ctx=ast.Load(),
        )
        more = ast.Compare(
            left=call("len", name(r)), ops=[ast.Gt()], comparators=[ast.Constant(CHUNK)]
        )
        inner.iter = ast.IfExp(
            test=ast.BoolOp(op=ast.Or(), values=[name(k), more]), body=sliced, orelse=name(r)
        )
        outer = ast.For(
            target=name(k, True),
            iter=call("range", ast.Constant(0), call("len", name(r)), ast.Constant(CHUNK)),
            body=body,
            orelse=orelse,
        )
        return pre + [ast.If(test=name(r), body=aliases + [outer], orelse=[])]

    def _start_range(self, s: n.For) -> tuple[int, int] | None:
        """Known bounds of a range-for counter's start value."""
        init = s.init
        e = None
        if isinstance(init, n.DeclStmt) and isinstance(init.decls[0], n.VarDecl):
            e = init.decls[0].init
        elif isinstance(init, n.ExprStmt) and isinstance(init.expr, n.Assign):
            e = init.expr.value
        if e is None:
            return None
        saved = self.ctx.sink.items[:]
        try:
            return self.x.expr(e).rng
        except SemanticError:
            return None
        finally:
            self.ctx.sink.items[:] = saved

    @staticmethod
    def _counter_of(s: n.For) -> str | None:
        init = s.init
        if isinstance(init, n.DeclStmt) and len(init.decls) == 1:
            d = init.decls[0]
            if (
                isinstance(d, n.VarDecl)
                and not d.dims
                and d.init is not None
                and not isinstance(d.init, n.InitList)
            ):
                return d.name
        if isinstance(init, n.ExprStmt) and isinstance(init.expr, n.Assign) and init.expr.op == "=":
            if isinstance(init.expr.target, n.Name):
                return init.expr.target.id
        return None

    @staticmethod
    def _step_of(step, ivar: str) -> int | None:
        if isinstance(step, (n.Postfix, n.Unary)) and step.op in ("++", "--"):
            if isinstance(step.operand, n.Name) and step.operand.id == ivar:
                return 1 if step.op == "++" else -1
        if (
            isinstance(step, n.Assign)
            and step.op in ("+=", "-=")
            and isinstance(step.target, n.Name)
        ):
            if step.target.id == ivar and isinstance(step.value, n.IntLit) and step.value.value > 0:
                return step.value.value if step.op == "+=" else -step.value.value
        return None


def _count(first: int | None, stop: ast.expr, step: ast.expr) -> int | None:
    """The values of a counting loop from `first` (None: not known) to `stop` by `step`
    (None unless all three are constants)."""
    if first is None or type(stop) is not ast.Constant or type(step) is not ast.Constant:
        return None
    return len(range(first, stop.value, step.value))


def _one_chunk(
    sym: VarSym,
    stop: ast.expr,
    step: ast.expr,
    inner: ast.For,
    charge: list,
    last: int,
    outlives: bool,
) -> ast.For:
    """A counting loop of 1 .. CHUNK values (known when compiling: the start, the bound
    and the step are constants) as the one chunk it is, charged after it as a chunk is,
    with C's value of the counter after the loop, `last`, a constant (no `break` leaves a
    chunked loop: its `else` always runs):

    for v_i in range(v_i, 4):
        BODY
    else:
        _budget -= 64
        if _budget < 0:
            yield
        v_i = 4
    """
    inner.iter = _range_call(name(sym.pyname), stop, step)
    after = [ast.Assign(targets=[name(sym.pyname, True)], value=const(last))]
    inner.orelse = charge + (after if outlives else [])
    return inner


def _range_call(start: ast.expr, stop: ast.expr, step: ast.expr) -> ast.Call:
    """`range(start, stop, step)`, without a step of 1."""
    if type(step) is ast.Constant and step.value == 1:
        return call("range", start, stop)
    return call("range", start, stop, step)
