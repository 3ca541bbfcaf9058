"""Lower PDL's compound statements: `if`/`else`, `while`, `loop` (manual §2.2.7-§2.2.9).

A statement without labels or jumps inside stays native Python (`if`, `while`,
`for _ in range(n)`), with a budgeted back-edge at the end of each pass; its global
scalars may live in locals meanwhile (lower_cache). An innermost `loop(n)` runs in
budget-sized chunks without the checks its guard proves (lower_chunk). One that contains a label or a
jump is flattened into dispatcher segments (lower_body):

    loop(n) do                _c1 = M[1] & 65535 or 65536
       a: ...                 (segment k)  ...
       if (x) goto a;                      _c1 -= 1
    end;                                   if _c1 > 0: pc = k; <budget>; continue
"""

from __future__ import annotations

import ast
from typing import Protocol

from motionvm.lang.pdl import nodes as n
from motionvm.lang.pdl.lower_base import ProgramContext, assign, binop, call, const, nm
from motionvm.lang.pdl.lower_cache import Promotion, promote
from motionvm.lang.pdl.lower_chunk import chunk_loop
from motionvm.lang.pdl.lower_expr import ExprLowering

SLEEP, WAIT = 1, 2
_JUMPY = (n.Label, n.Goto, n.CallLabel)


def is_jumpy(s: object) -> bool:
    """True if a statement contains a label or a jump, so it cannot stay native Python."""
    if isinstance(s, _JUMPY):
        return True
    if isinstance(s, n.Simple):
        return s.command == "ret"
    if isinstance(s, n.Print):
        return s.command == "retprintl"
    if isinstance(s, n.If):
        return any(map(is_jumpy, s.then_body)) or any(map(is_jumpy, s.else_body or ()))
    if isinstance(s, (n.Loop, n.While)):
        return any(map(is_jumpy, s.body))
    return False


NATIVE_LOOP_DEPTH = 8
"""Loops nested deeper than this are flattened into dispatcher segments like jumpy ones:
Python allows only 20 nested blocks in a function, PDL 200 nested loops (manual §2.2.8)."""


def _loop_depth(body) -> int:
    """How deep `while` and `loop` statements nest in a statement list (0: none)."""
    deepest = 0
    stack = [(s, 0) for s in body]
    while stack:
        s, d = stack.pop()
        if isinstance(s, (n.Loop, n.While)):
            deepest = max(deepest, d + 1)
            stack.extend((x, d + 1) for x in s.body)
        elif isinstance(s, n.If):
            stack.extend((x, d) for x in s.then_body)
            stack.extend((x, d) for x in s.else_body or ())
    return deepest


def needs_flat(s: object) -> bool:
    """True if a statement must be flattened into dispatcher segments: it holds a label
    or a jump, or loops nested deeper than NATIVE_LOOP_DEPTH."""
    return is_jumpy(s) or _loop_depth((s,)) > NATIVE_LOOP_DEPTH


def check_budget(promo: Promotion | None = None) -> ast.stmt:
    """`if b <= 0: b = yield b`, saving and reloading promoted scalars around the yield."""
    test = ast.Compare(nm("b"), [ast.LtE()], [const(0)])
    body = [assign(nm("b", True), ast.Yield(nm("b")))]
    if promo is not None:
        body = promo.stores() + body + promo.loads()
    return ast.If(test, body, [])


class BodyContext(Protocol):
    """What the compound statements use of the body they stand in (`lower_body.BodyLowerer`,
    which inherits them from `FlowLowering`)."""

    prog: ProgramContext
    x: ExprLowering
    pending: int
    counter: int
    uses_dispatch: bool

    def emit(self, stmts: list[ast.stmt], pos: object) -> None:
        """Append statements placed at `pos` to the current segment."""

    def flush(self) -> None:
        """Charge the pending statements to the budget."""

    def new_segment(self) -> int:
        """Start a dispatcher segment; its number."""

    def jump(self, target: ast.Constant, pos: object, check: bool) -> None:
        """Go to the segment `target` names."""

    def block(self, items: tuple[n.Item, ...], flat: bool) -> None:
        """Lower the items of a nested block into the current segments."""

    def native_block(self, items: tuple[n.Item, ...], depth: int, loop_top: bool) -> list[ast.stmt]:
        """The items of a nested block as native Python statements."""

    def begin_promotion(self, s: n.Loop | n.While) -> Promotion | None: ...

    def end_promotion(self, promo: Promotion | None, stmts: list[ast.stmt]) -> list[ast.stmt]: ...


class FlowLowering:
    """The compound-statement half of `BodyLowerer` (a mixin: it uses its state,
    `BodyContext`)."""

    def s_If(self: BodyContext, s: n.If, flat: bool) -> None:
        self.pending += 1
        if not (flat and needs_flat(s)):
            self.flush()
            then = self.native_block(s.then_body, 0, False)
            orelse = self.native_block(s.else_body, 0, False) if s.else_body else []
            self.emit([ast.If(self.x.cond(s.cond), then, orelse)], s.pos)
            return
        skip = const(-1)
        self.flush()
        self.emit([ast.If(ast.UnaryOp(ast.Not(), self.x.cond(s.cond)), [assign(nm("pc", True), skip), ast.Continue()], [])], s.pos)  # fmt: skip
        self.uses_dispatch = True
        self.block(s.then_body, flat=True)
        if s.else_body is not None:
            end = const(-1)
            self.jump(end, s.pos, check=False)
            skip.value = self.new_segment()
            self.block(s.else_body, flat=True)
            end.value = self.new_segment()
        else:
            skip.value = self.new_segment()

    def s_While(self: BodyContext, s: n.While, flat: bool) -> None:
        if not (flat and needs_flat(s)):
            self.pending += 1
            self.flush()
            promo = self.begin_promotion(s)
            body = self.native_block(s.body, 1, True)
            self.emit(
                self.end_promotion(promo, [ast.While(self.x.cond(s.cond), body, [])]),
                s.pos,
            )
            return
        head = self.new_segment()
        self.pending += 1
        self.flush()
        exit_ = const(-1)
        self.emit([ast.If(ast.UnaryOp(ast.Not(), self.x.cond(s.cond)), [assign(nm("pc", True), exit_), ast.Continue()], [])], s.pos)  # fmt: skip
        self.block(s.body, flat=True)
        self.jump(const(head), s.pos, check=True)
        exit_.value = self.new_segment()

    def s_Loop(self: BodyContext, s: n.Loop, flat: bool) -> None:
        self.pending += 1
        count, _ = self.x.read(s.count)
        # n is read once as an unsigned 16-bit count, 0 meaning 65536.
        times = ast.BoolOp(ast.Or(), [binop(count, ast.BitAnd(), const(0xFFFF)), const(65536)])
        if not (flat and needs_flat(s)):
            self.flush()
            promo = self.begin_promotion(s)
            body = self.native_block(s.body, 1, False)
            if promo is not None:
                count, _ = self.x.read(s.count)
                times = ast.BoolOp(
                    ast.Or(), [binop(count, ast.BitAnd(), const(0xFFFF)), const(65536)]
                )
            tail = check_budget(self.x.promo)
            chunked = (
                chunk_loop(self, s, body, times, self.x.promo, tail) if self.prog.chunk else None
            )
            if chunked is None:
                chunked = [ast.For(nm("_", True), call("range", times), body + [tail], [])]  # fmt: skip
                if self.x.promo is not None:
                    chunked = self.x.promo.flush_lists() + chunked
            self.emit(self.end_promotion(promo, chunked), s.pos)
            return
        self.counter += 1
        c = f"_c{self.counter}"
        self.emit([assign(nm(c, True), times)], s.pos)
        top = self.new_segment()
        self.block(s.body, flat=True)
        self.pending += 1
        self.flush()
        dec = ast.AugAssign(nm(c, True), ast.Sub(), const(1))
        again = [assign(nm("pc", True), const(top)), check_budget(), ast.Continue()]
        test = ast.Compare(nm(c), [ast.Gt()], [const(0)])
        self.emit([dec, ast.If(test, again, [])], s.pos)
        self.new_segment()

    def begin_promotion(self: BodyContext, s: n.Loop | n.While) -> Promotion | None:
        """Keep the loop's global scalars in locals, if nothing else can see them (lower_cache)."""
        if self.x.promo is not None or not self.prog.promote:
            return None
        self.x.promo = promote(self.prog, s)
        return self.x.promo

    def end_promotion(
        self: BodyContext, promo: Promotion | None, stmts: list[ast.stmt]
    ) -> list[ast.stmt]:
        if promo is None:
            return stmts
        self.x.promo = None
        return promo.wrap(stmts)
