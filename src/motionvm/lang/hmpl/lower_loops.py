"""Lower HMPL loops: `while`, `do`/`while`, `for`, with budgeted back-edges.

A loop yields to the scheduler when the task's slice is used up: a local countdown
charges the task budget every CHUNK iterations. Counting loops whose counter and bound
the body leaves alone become `range` loops, in chunks of CHUNK values:

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

A polling loop (one that reads what may change outside it: see `_fixed_point`) ends
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

from motionvm.lang.hmpl import ctypes_ as ct
from motionvm.lang.hmpl import nodes as n
from motionvm.lang.hmpl.analysis import _children_of, walk
from motionvm.lang.hmpl.lower_expr import SemanticError
from motionvm.lang.hmpl.lower_util import (
    CHUNK,
    LOOP_BLOCKS,
    MAX_LOOP_NESTING,
    LoopCtx,
    PollCtx,
    at,
    backedge,
    countdown_init,
)
from motionvm.lang.hmpl.lower_walk import PointerWalkLowering, alias_globals
from motionvm.lang.hmpl.lvalues import call, const, name
from motionvm.lang.hmpl.symbols import Scope, VarSym
from motionvm.lang.hmpl.till_events import (
    READ_BUILTINS,
    idle_body,
    negated,
    reads_only,
    waits_on_event,
)
from motionvm.runtime.kernel import EVENT_POLL, EVENT_WAIT


class LoopLowering(PointerWalkLowering):
    """Mixin of the function lowerer: loops."""

    def nest(self, pos, blocks: int = 1) -> bool:
        """Enter a loop or switch taking `blocks` Python blocks; past the limit of nested
        loops and switches, a compile error at `pos`. True if it must be lowered as a
        nested function (the generated one has no blocks left for it): `split_off`.
        Pair with `unnest`."""
        if len(self.loops) >= MAX_LOOP_NESTING:
            raise self.fail(
                pos,
                f"loops and switches nested more than {MAX_LOOP_NESTING} deep in one function"
                " (the limit of HMPL); move the inner ones into a function",
            )
        split = self.py_blocks + blocks > LOOP_BLOCKS
        self.outer_blocks.append(self.py_blocks)
        self.py_blocks = blocks if split else self.py_blocks + blocks
        return split

    def unnest(self) -> None:
        self.py_blocks = self.outer_blocks.pop()

    def _room_for_chunks(self, body) -> bool:
        """A counting loop may take two blocks if the deeper loops still find one each."""
        return self.py_blocks + 2 + _loop_depth(body) <= LOOP_BLOCKS

    def _loop_body(self, body, cont: list[ast.stmt], blocks: int = 1,
                   polling: PollCtx | None = None):  # fmt: skip
        """The lowered body and the loop's context (split: see `split_off`); `polling`: a
        polling loop's (`_fixed_point`), None for any other loop, whose statements mark
        nothing (in a polling loop the loop itself marks an effect)."""
        self.has_yield = True  # every loop has a budgeted back-edge
        ctx = LoopCtx("loop", cont)
        ctx.split = self.nest(body.pos, blocks)
        self.loops.append(ctx)
        outer, self.polling = self.polling, polling
        declared = set(self._pynames) if polling is not None else None
        try:
            lowered = self.block(body)
            if polling is not None:  # block-scope locals of the body: dead at the back-edge
                polling.inner = self._pynames - declared
            return lowered, ctx
        finally:
            self.polling = outer
            self.loops.pop()
            self.unnest()

    def _fixed_point(self, cond, body) -> PollCtx | None:
        """A new `PollCtx` if `while (cond) body` (cond None: forever) is a polling loop
        that ends its slice at a fixed point: one that reads what may change outside it
        (`_reads_outside`), whose condition changes nothing, and in which no loop or
        switch will be lowered as a function of its own (its statements would set a
        marker of their own). None for any other loop: those keep spinning (the check
        would only slow them down)."""
        resolve = self._event_symbol
        if cond is not None and not reads_only(cond, resolve):
            return None
        if not (_reads_outside(cond, resolve) or _reads_outside(body, resolve)):
            return None  # it cannot be waiting for anything
        if self.py_blocks + 1 + _loop_depth(body) > LOOP_BLOCKS:
            return None
        return PollCtx(self.temp(), cond is None or waits_on_event(cond, resolve))

    def _fixed_point_end(self, polling: PollCtx, b: str, body: list[ast.stmt]):
        """(statements before the loop, the back-edge) of polling loop `polling` with
        countdown `b` whose lowered body is `body` (see the module docstring): the slice
        ends at an iteration that ran no marked statement and left the locals it writes
        as they were (those declared outside it: a block-scope local of the body lives
        for one iteration). It yields EVENT_POLL if that iteration is the first since the
        task's last yield, else EVENT_WAIT, when its quiet iterations read only what a
        computed cycle changes (`PollCtx.on_events`: the clock may jump), else None."""
        mark = polling.mark
        written = sorted({
            x.id for st in body for x in ast.walk(st)
            if type(x) is ast.Name and type(x.ctx) is ast.Store and x.id.startswith("v_")
        } - polling.inner)  # fmt: skip
        seen = self.temp()

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
            kind = self.temp()  # EVENT_WAIT until the first quiet iteration after a yield
            before.append(ast.Assign([name(kind, True)], ast.Constant(EVENT_WAIT)))
            record.append(ast.Assign([name(kind, True)], ast.Constant(EVENT_WAIT)))
            repeat += [ast.Expr(ast.Yield(name(kind))),
                       ast.Assign([name(kind, True)], ast.Constant(EVENT_POLL))]  # fmt: skip
        else:
            repeat.append(ast.Expr(ast.Yield(None)))
        check = ast.If(changed, record + backedge(b), repeat)
        _FillContinues(check).visit(ast.Module(body, []))  # a `continue` checks as well
        return before, [check]

    def quiet_statement(self, s, polling: PollCtx) -> bool:
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
        resolve = self._event_symbol
        if t is n.If:
            reads = [s.cond]
        elif t is n.Switch:
            reads = [s.expr]
        elif t is n.ExprStmt:
            e = s.expr
            if type(e) is n.Assign:
                if not self._plain_int_local(e.target):
                    return False
                reads = [e.value]
            elif type(e) in (n.Postfix, n.Unary) and e.op in ("++", "--"):
                return self._plain_int_local(e.operand)
            else:
                reads = [e]
        elif t is n.DeclStmt:
            reads = []
            for d in s.decls:
                if type(d) is not n.VarDecl:
                    continue
                if d.is_static or d.dims or not self._plain_int_local(d):
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

    def _plain_int_local(self, target) -> bool:
        """True if `target` (a Name, or a VarDecl once lowered) is an integer variable
        kept in a Python local of this function."""
        if type(target) not in (n.Name, n.VarDecl):
            return False
        sym = self.scope.lookup(target.id if type(target) is n.Name else target.name)
        return (isinstance(sym, VarSym) and sym.storage == "local"
                and sym.type.is_integer)  # fmt: skip

    def _assigned_in(self, body) -> set[str]:
        """`_assigned_names(body)` of a `for` body, found for every `for` inside it in the
        same pass (nested counting loops would otherwise walk their bodies again)."""
        cache = self.__dict__.setdefault("_assigned_cache", {})
        got = cache.get(id(body))
        if got is None:
            _fill_assigned(body, cache)
            got = cache[id(body)]
        return got

    def _placed(self, ctx: LoopCtx, loop: ast.stmt) -> list[ast.stmt]:
        return self.split_off(ctx, loop) if ctx.split else [loop]

    def _s_While(self, s: n.While) -> list[ast.stmt]:
        waiting = self._busy_wait(s)
        if waiting is not None:
            return waiting
        body = s.body
        if type(body) is n.Block and len(body.items) > 1 and type(body.items[-1]) is n.ExprStmt:
            fast = self._pointer_walk(s.cond, body.items[-1].expr, body, body.items[:-1], s.pos)
            if fast is not None:
                return fast
        test = self.cond(s.cond)
        b = self.temp()
        polling = self._fixed_point(s.cond, s.body)
        cont = [_continue_check() if polling else backedge(b), ast.Continue()]
        body, ctx = self._loop_body(s.body, _flat(cont), polling=polling)
        before, end = self._fixed_point_end(polling, b, body) if polling else ([], backedge(b))
        loop = ast.While(test=test, body=body + end, orelse=[])
        return [countdown_init(b), *before] + self._placed(ctx, loop)

    def _busy_wait(self, s: n.While) -> list[ast.stmt] | None:
        """A loop that only waits, `while (c);` or `while (c) RunScheduler();` (or the same
        as `for (; c;)`, `for (;;)`) with a condition that changes nothing (`reads_only`),
        polled once per cycle: nothing else runs in its task's slice, so the first test
        of a cycle decides the rest of it, and spinning on to the end of the slice
        changes nothing a program can see.
        It is lowered as `Till(!c)`: on an event the controller may jump past it, on
        the time it sleeps, on a position it tells the controller. None for any other
        loop."""
        resolve = self._event_symbol
        if not (idle_body(s.body, resolve) and reads_only(s.cond, resolve)):
            return None
        test = self.cond(s.cond)
        waited = self.event_wait(s.cond, test)
        if waited is not None:
            return waited
        return self.poll_until(negated(s.cond), test)

    def _s_DoWhile(self, s: n.DoWhile) -> list[ast.stmt]:
        # `do ; while (c);` is `while (c);`; `do RunScheduler(); while (c);` yields first
        waiting = self._busy_wait(n.While(s.pos, s.cond, s.body))
        if waiting is not None:
            body = s.body.items[0] if type(s.body) is n.Block and s.body.items else s.body
            first = [] if type(body) in (n.Empty, n.Block) else [ast.Expr(ast.Yield(None))]
            return first + waiting
        b = self.temp()
        exit_ = [
            ast.If(
                test=ast.UnaryOp(op=ast.Not(), operand=self.cond(s.cond)),
                body=[ast.Break()],
                orelse=[],
            )
        ]
        cont = at(exit_, s.cond.pos) + backedge(b) + [ast.Continue()]
        body, ctx = self._loop_body(s.body, cont)
        exit2 = [
            ast.If(
                test=ast.UnaryOp(op=ast.Not(), operand=self.cond(s.cond)),
                body=[ast.Break()],
                orelse=[],
            )
        ]
        loop = ast.While(
            test=ast.Constant(True), body=body + at(exit2, s.cond.pos) + backedge(b), orelse=[]
        )
        return [countdown_init(b)] + self._placed(ctx, loop)

    def _s_For(self, s: n.For) -> list[ast.stmt]:
        if s.init is None and s.step is None:  # for (;;); and for (; c;) RunScheduler();
            cond = n.IntLit(s.pos, 1) if s.cond is None else s.cond
            waiting = self._busy_wait(n.While(s.pos, cond, s.body))
            if waiting is not None:
                return waiting
        saved = self.scope
        self.scope = Scope(saved, "block")
        try:
            out: list[ast.stmt] = []
            if s.init is not None:
                out.extend(at(self.stmt(s.init), s.init.pos))
            fast = self._range_for(s)
            if fast is None and s.cond is not None and s.step is not None:
                fast = self._pointer_walk(s.cond, s.step, s.body, None, s.pos)
            if fast is not None:
                return _start_in_range(out, fast) if isinstance(s.init, n.DeclStmt) else out + fast
            b = self.temp()
            test = self.cond(s.cond) if s.cond is not None else ast.Constant(True)
            step = (
                at(self._s_ExprStmt(n.ExprStmt(s.step.pos, s.step)), s.step.pos)
                if s.step is not None
                else []
            )
            polling = self._fixed_point(s.cond, s.body) if s.step is None else None
            cont = _flat([step, _continue_check() if polling else backedge(b), ast.Continue()])
            body, ctx = self._loop_body(s.body, cont, polling=polling)
            step2 = (
                at(self._s_ExprStmt(n.ExprStmt(s.step.pos, s.step)), s.step.pos)
                if s.step is not None
                else []
            )
            before, end = self._fixed_point_end(polling, b, body) if polling else ([], backedge(b))
            out += [countdown_init(b), *before]
            loop = ast.While(test=test, body=body + step2 + end, orelse=[])
            return out + self._placed(ctx, loop)
        finally:
            self.scope = saved

    def _range_for(self, s: n.For) -> list[ast.stmt] | None:
        """`for (i = a; i < b; i += c)` with i and b untouched by the body -> `for v_i in range(...)`.

        Only for a local int32/int64 (or increasing uint32) counter and a bound built from
        constants and locals the body does not assign; the C value of i after the loop is
        restored in the loop's `else` when i outlives the loop.
        """
        ivar = self._counter_of(s)
        if ivar is None:
            return None
        sym = self.scope.lookup(ivar)
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
        assigned = self._assigned_in(s.body)
        step_var = None
        step_rng = None
        if (
            inc is None
            and isinstance(step, n.Assign)
            and step.op == "+="
            and isinstance(step.target, n.Name)
            and step.target.id == ivar
            and cond.op in ("<", "<=")
            and self._invariant(step.value, assigned)
        ):
            try:
                sv = self.expr(step.value)
            except SemanticError:
                return None
            if not sv.type.is_integer or ct.common_arith(sym.type, sv.type) != sym.type:
                return None
            step_var = self.convert(sv, sym.type, step.pos)
            step_rng = sv.rng
            inc = "var"
        if inc is None:
            return None
        if inc != "var" and (
            (inc > 0) != (cond.op in ("<", "<=")) or (inc < 0 and not sym.type.signed)
        ):
            return None
        if ivar in assigned or not self._invariant(cond.right, assigned):
            return None
        try:
            bound = self.expr(cond.right)
        except SemanticError:
            return None
        if not bound.type.is_integer or ct.common_arith(sym.type, bound.type) != sym.type:
            return None
        stop = self.convert(bound, sym.type, cond.pos)
        if cond.op in ("<=", ">="):
            up = inc == "var" or inc > 0
            if type(stop) is ast.Constant:
                stop = const(stop.value + (1 if up else -1))
            else:
                stop = ast.BinOp(
                    left=stop, op=ast.Add() if up else ast.Sub(), right=ast.Constant(1)
                )
        chunked = not _breaks_out(s.body) and self._room_for_chunks(s.body)
        b = self.temp()
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
            self.known_ranges[sym.pyname] = known  # lets indexing skip its bounds check
        try:
            body, ctx = self._loop_body(s.body, cont, 2 if chunked else 1)
            if not chunked:
                body += backedge(b)
        finally:
            self.known_ranges.pop(sym.pyname, None)
        pre: list[ast.stmt] = []
        if inc == "var" and step_rng is not None and step_rng[0] > 0:
            step_node = step_var  # known positive (range analysis): nothing to check
        elif inc == "var":
            # a run-time step must be positive (0 or less would never reach the bound)
            st = self.temp()
            pre.append(ast.Assign(targets=[name(st, True)], value=step_var))
            ok = ast.Compare(left=name(st), ops=[ast.Gt()], comparators=[ast.Constant(0)])
            step_node = ast.IfExp(test=ok, body=name(st), orelse=call("_bad_step", name(st)))
        else:
            step_node = const(inc)
        if chunked:
            loops = self._chunked_range(
                sym, stop, step_node, body, outlives=not isinstance(s.init, n.DeclStmt)
            )
            return pre + loops[:-1] + self._placed(ctx, loops[-1])
        pre.append(countdown_init(b))
        rng = _range_call(name(sym.pyname), stop, step_node)
        outlives = not isinstance(s.init, n.DeclStmt)
        orelse: list[ast.stmt] = []
        if outlives:
            r = self.temp()
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
        return pre + self._placed(ctx, loop)

    def _chunked_range(
        self, sym: VarSym, stop: ast.expr, step: ast.expr, body: list[ast.stmt], outlives: bool
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
        inside another loop takes its chunks inline (`_inline_chunks`).
        """
        k = self.temp()
        rng: ast.expr = _range_call(name(sym.pyname), stop, step)
        pre: list[ast.stmt] = []
        orelse: list[ast.stmt] = []
        if outlives:
            r = self.temp()
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
        aliases = alias_globals(inner.body, self.temp)
        if any(c.kind == "loop" for c in self.loops):
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
            r = self.temp()
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
        saved = self.sink.items[:]
        try:
            return self.expr(e).rng
        except SemanticError:
            return None
        finally:
            self.sink.items[:] = saved

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

    def _invariant(self, e, assigned: set[str]) -> bool:
        """True if `e` is built from constants and locals that the loop body does not assign."""
        if isinstance(e, (n.IntLit, n.CharLit)):
            return True
        if isinstance(e, n.Name):
            if e.id in assigned:
                return False
            sym = self.scope.lookup(e.id) or self.prog.global_symbol(e.id, self.task)
            return isinstance(sym, VarSym) and (
                sym.storage == "local" or sym.const_value is not None
            )
        if isinstance(e, n.Binary) and e.op in ("+", "-", "*", "<<", ">>", "&", "|"):
            return self._invariant(e.left, assigned) and self._invariant(e.right, assigned)
        if isinstance(e, n.Unary) and e.op in ("-", "+"):
            return self._invariant(e.operand, assigned)
        if isinstance(e, n.SizeOf):
            return True
        return False


def _breaks_out(body) -> bool:
    """True if a `break` in `body` would leave this loop (not a nested loop or switch)."""
    stack = [body]
    while stack:
        x = stack.pop()
        t = type(x)
        if t is n.Break:
            return True
        if t in (n.While, n.DoWhile, n.For, n.Switch):
            continue
        if t is n.Block:
            stack.extend(x.items)
        elif t is n.If:
            stack.append(x.then)
            if x.else_ is not None:
                stack.append(x.else_)
    return False


def _assigned_names(body) -> set[str]:
    """Names the statement assigns, increments or takes the address of."""
    out: set[str] = set()
    for x in walk(body):
        t = type(x)
        if t is n.Assign and type(x.target) is n.Name:
            out.add(x.target.id)
        elif (
            (t is n.Postfix or t is n.Unary)
            and x.op in ("++", "--", "&")
            and type(x.operand) is n.Name
        ):
            out.add(x.operand.id)
    return out


def _fill_assigned(root, cache: dict[int, set[str]]) -> None:
    """`cache[id(b)] = _assigned_names(b)` for `root` and the body `b` of every `for` in it:
    one walk, each name added to its innermost `for` body, then merged outwards."""
    sets: list[set[str]] = [set()]
    parents: list[int] = [-1]
    keys: list[int] = [id(root)]
    stack: list = [(root, 0)]
    children = _children_of
    while stack:
        x, frame = stack.pop()
        t = type(x)
        if t is tuple or t is list:
            stack.extend((y, frame) for y in x)
            continue
        if x is None:
            continue
        if t is n.Assign:
            if type(x.target) is n.Name:
                sets[frame].add(x.target.id)
        elif (t is n.Postfix or t is n.Unary) and x.op in ("++", "--", "&"):
            if type(x.operand) is n.Name:
                sets[frame].add(x.operand.id)
        for fname in children(t):
            v = getattr(x, fname)
            if v is None:
                continue
            if t is n.For and fname == "body" and id(v) not in cache:
                sets.append(set())
                parents.append(frame)
                keys.append(id(v))
                stack.append((v, len(sets) - 1))
            else:
                stack.append((v, frame))
    for k in range(len(sets) - 1, 0, -1):
        sets[parents[k]] |= sets[k]
    for k, key in enumerate(keys):
        cache[key] = sets[k]


_NESTING = (n.While, n.DoWhile, n.For, n.Switch)


def _loop_depth(stmt) -> int:
    """How deep loops and switches nest inside a statement (0: none)."""
    deepest = 0
    stack = [(stmt, 0)]
    while stack:
        x, d = stack.pop()
        t = type(x)
        if t in _NESTING:
            d += 1
            deepest = max(deepest, d)
            stack.append((x.body, d))
        elif t is n.Block:
            stack.extend((y, d) for y in x.items)
        elif t is n.If:
            stack.append((x.then, d))
            if x.else_ is not None:
                stack.append((x.else_, d))
    return deepest


_CONTINUE_CHECK = "_continue_check_"


def _continue_check() -> ast.stmt:
    """Where a `continue` of a polling loop's body checks for a fixed point, as the loop's
    back-edge does: filled in once the body is lowered (`_FillContinues`), as what the
    check compares (the locals the body writes) is known only then."""
    return ast.Expr(ast.Name(_CONTINUE_CHECK, ast.Load()))


def _flat(items) -> list[ast.stmt]:
    """Statements and lists of statements, as one list."""
    out = []
    for x in items:
        out.extend(x if isinstance(x, list) else [x])
    return out


class _FillContinues(ast.NodeTransformer):
    """Replaces each `_continue_check()` by a copy of the loop's check."""

    def __init__(self, check: ast.stmt) -> None:
        self.check = check

    def visit_Expr(self, node: ast.Expr):
        v = node.value
        if type(v) is ast.Name and v.id == _CONTINUE_CHECK:
            check = copy.deepcopy(self.check)
            for x in ast.walk(check):  # at the `continue`'s place
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


def _range_call(start: ast.expr, stop: ast.expr, step: ast.expr) -> ast.Call:
    """`range(start, stop, step)`, without a step of 1."""
    if type(step) is ast.Constant and step.value == 1:
        return call("range", start, stop)
    return call("range", start, stop, step)


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
