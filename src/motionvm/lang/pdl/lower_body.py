"""Lower one PDL body (the top level or a procedure) to the statements of a generator.

Design: a dispatcher over *segments*. PDL jumps anywhere (`goto`, `call`/`ret`,
`goto label[i]` by code units, tasks started at any `_label` or `#task/n`), so a body
with labels becomes a loop over a chain of `if pc <= k:` segments, in source order:
entering at segment k runs k, k+1, ... by falling through, and a jump is
`pc = k; continue`. Structured statements that contain no label and no jump
(`goto`, `call`, `ret`, `retprintl`) stay native Python `if`/`while`/`for`, which is
where the hot loops are; a statement that does contain one is flattened into
segments too (its loop counter becomes a Python local).

    lp:  x = x + 1;              while True:
         if (x < 10) goto lp;        if pc <= 0:
         halt;                           b -= 2; (x = x + 1)
                             ->          if M[1] < 10:
                                             pc = 0
                                             if b <= 0: b = yield b
                                             continue
                                         return

Budget: each task gets `B` statements per phase. Straight-line code charges its
statement count in one `b -= k` per run; back-edges (loop ends, jumps) yield with
`b = yield b` once the budget is used up, and the scheduler turns an overdraft into
phases the task then sits out. `bench/pdl.py` measures the dispatcher: a label loop
costs one comparison per segment before its label.
"""

from __future__ import annotations

import ast
from collections.abc import Callable

from motionvm.lang.pdl import nodes as n
from motionvm.lang.pdl.lower_assign import lower_assign
from motionvm.lang.pdl.lower_base import (
    ProgramContext,
    assign,
    binop,
    call,
    const,
    nm,
    subscript,
)
from motionvm.lang.pdl.lower_expr import FLT, ExprLowering
from motionvm.lang.pdl.lower_flow import SLEEP, WAIT, FlowLowering, check_budget, is_jumpy
from motionvm.lang.pdl.rt_memory import FLOAT
from motionvm.lang.pdl.symbols import LabelSym, ProcSym, VarSym, code_units
from motionvm.lang.placing import place
from motionvm.source.files import SourcePos


class BodyLowerer(FlowLowering):
    """Builds the segments of one body; `self.cur` is the statement list being filled."""

    def __init__(
        self, prog: ProgramContext, proc: ProcSym | None, frame: dict[int, int] | None
    ) -> None:
        self.prog = prog
        self.proc = proc
        self.x = ExprLowering(prog, frame)
        self.segments: list[list[ast.stmt]] = [[]]
        self.cur = self.segments[0]
        self.pending = 0
        self.label_seg: dict[str, int] = {}
        self.task_seg: dict[int, int] = {}
        self.fixups: list[tuple[ast.Constant, str]] = []  # pc constants naming a label
        self.landings: dict[int, list[tuple[str, int]]] = {}  # id(stmt) -> [(label, offset)]
        self.tables: dict[str, dict[int, int]] = {}  # label -> {code offset: segment}
        self.counter = 0
        self.uses_dispatch = False

    # ------------------------------------------------------------ helpers

    def at(self, stmts: list[ast.stmt], pos: object) -> list[ast.stmt]:
        line = self.prog.line_of(pos)
        col = pos.col - 1 if isinstance(pos, SourcePos) else 0  # a fault names the column
        return place(stmts, line, col)

    def emit(self, stmts: list[ast.stmt], pos: object) -> None:
        self.cur.extend(self.at(stmts, pos))

    def flush(self) -> None:
        if self.pending:
            self.cur.append(ast.AugAssign(nm("b", True), ast.Sub(), const(self.pending)))
            self.pending = 0

    def new_segment(self) -> int:
        self.flush()
        if not self.segments[-1] and self.cur is self.segments[-1]:
            return len(self.segments) - 1
        self.uses_dispatch = True
        self.segments.append([])
        self.cur = self.segments[-1]
        return len(self.segments) - 1

    def jump(self, target: ast.Constant, pos: object, check: bool) -> None:
        self.flush()
        self.uses_dispatch = True
        out: list[ast.stmt] = [assign(nm("pc", True), target)]
        if check:
            out.append(check_budget())
        out.append(ast.Continue())
        self.emit(out, pos)

    def label_target(self, label: str) -> ast.Constant:
        c = const(-1)
        self.fixups.append((c, label))
        return c

    def end_task(self) -> list[ast.stmt]:
        """End the whole task: from the top level `return`, from a procedure `raise _Exit`."""
        if self.proc is None:
            return [ast.Return(None)]
        return [ast.Raise(nm("_Exit"), None)]

    def leave_proc(self) -> list[ast.stmt]:
        """Return from a procedure: drop its frame, give the budget back to the caller."""
        return [
            assign(ast.Attribute(nm("T"), "sp", ast.Store()), nm("bp")),
            assign(ast.Attribute(nm("T"), "depth", ast.Store()), nm("d0")),
            ast.Return(nm("b")),
        ]

    # ------------------------------------------------------------ bodies

    def prepare_landings(self, labels: dict[str, LabelSym], items: tuple[n.Item, ...]) -> None:
        """Mark the statements an indirect `goto label[i]` may land on."""
        indirect = {s.label for s in _walk(items) if isinstance(s, n.Goto) and s.index is not None}
        for name in sorted(indirect):
            lab = labels.get(name)
            if lab is None:
                continue
            offset = 0
            for item in lab.block[lab.index + 1 :]:
                units = code_units(item)
                if units:
                    self.landings.setdefault(id(item), []).append((name, offset))
                offset += units
            self.tables[name] = {}

    def body(self, items: tuple[n.Item, ...]) -> None:
        for s in items:
            self.stmt(s, flat=True)

    def block(self, items: tuple[n.Item, ...], flat: bool) -> None:
        for s in items:
            self.stmt(s, flat)

    def native_block(
        self, items: tuple[n.Item, ...], extra_cost: int, back_edge: bool
    ) -> list[ast.stmt]:
        saved_cur, saved_pending = self.cur, self.pending
        self.cur, self.pending = [], extra_cost
        self.block(items, flat=False)
        self.flush()
        if back_edge:
            self.cur.append(check_budget(self.x.promo))
        out = self.cur or [ast.Pass()]
        self.cur, self.pending = saved_cur, saved_pending
        return out

    # ------------------------------------------------------------ statements

    def stmt(self, s: n.Item, flat: bool) -> None:
        land = self.landings.get(id(s))
        if land:
            seg = self.new_segment()
            for label, offset in land:
                self.tables[label][offset] = seg
        if _reads_clock(s):
            # Pay for the statements before it first, so `t0 = fclk;` sees the right time.
            self.flush()
            self.cur.append(check_budget())
        key = (type(self), type(s))
        method = _DISPATCH.get(key)
        if method is None:
            method = _DISPATCH[key] = getattr(key[0], "s_" + key[1].__name__)
        method(self, s, flat)

    def s_Label(self, s: n.Label, flat: bool) -> None:
        self.label_seg[s.name] = self.new_segment()

    def s_TaskDirective(self, s: n.TaskDirective, flat: bool) -> None:
        self.task_seg[s.task] = self.new_segment()

    def s_VarDecl(self, s: n.VarDecl, flat: bool) -> None:
        pass

    def s_ProcDef(self, s: n.ProcDef, flat: bool) -> None:
        pass

    s_ProcProto = s_ProcDef

    def s_Assign(self, s: n.Assign, flat: bool) -> None:
        self.pending += 1
        self.emit(lower_assign(self.x, s), s.pos)

    def s_IncDec(self, s: n.IncDec, flat: bool) -> None:
        self.pending += 1
        e, _ = self.x.read(s.target)
        op = ast.Add() if s.op == "++" else ast.Sub()
        out = self.x.store(s.target, binop(e, op, const(1)), "wide")
        self.emit(out + self.x.auto_increments(s.target), s.pos)

    def s_StateAssign(self, s: n.StateAssign, flat: bool) -> None:
        self.pending += 1
        bit, _ = self.x.state_ref(s.state)
        value = ast.IfExp(self.x.cond(s.cond), const(1), const(0))
        self.emit([ast.Expr(call("_set", bit, value))], s.pos)

    def s_SetState(self, s: n.SetState, flat: bool) -> None:
        self.pending += 1
        bit, _ = self.x.state_ref(s.target)
        if s.command == "toggle":
            self.emit([ast.Expr(call("_tog", bit))], s.pos)
        else:
            self.emit([ast.Expr(call("_set", bit, const(1 if s.command == "seton" else 0)))], s.pos)

    def s_Goto(self, s: n.Goto, flat: bool) -> None:
        self.pending += 1
        if s.index is None:
            self.jump(self.label_target(s.label), s.pos, check=True)
            return
        table = self.prog.table_name(self, s.label)
        if isinstance(s.index, n.IntConst):
            target: ast.expr = call("_land", nm(table), const(s.index.value), const(s.label))
        else:
            target = call("_land", nm(table), self.x.read(s.index)[0], const(s.label))
        self.flush()
        self.uses_dispatch = True
        self.emit([assign(nm("pc", True), target), check_budget(), ast.Continue()], s.pos)

    def s_CallLabel(self, s: n.CallLabel, flat: bool) -> None:
        self.pending += 1
        ret = const(-1)
        self.emit([ast.Expr(ast.Call(ast.Attribute(nm("rs"), "append", ast.Load()), [ret], [])),
                   ast.Expr(call("_push", nm("T")))], s.pos)  # fmt: skip
        self.jump(self.label_target(s.label), s.pos, check=True)
        ret.value = self.new_segment()

    def ret(self, pos: object) -> None:
        """`ret`: back to the last `call`, or the end of the task if there is none."""
        self.flush()
        self.uses_dispatch = True
        pop = ast.Call(ast.Attribute(nm("rs"), "pop", ast.Load()), [], [])
        back = [
            ast.Expr(call("_pop", nm("T"))),
            assign(nm("pc", True), pop),
            check_budget(),
            ast.Continue(),
        ]
        self.emit([ast.If(nm("rs"), back, [])] + self.end_task(), pos)

    def s_Simple(self, s: n.Simple, flat: bool) -> None:
        self.pending += 1
        c = s.command
        if c == "halt":
            self.emit(self.end_task(), s.pos)
        elif c == "ret":
            self.ret(s.pos)
        elif c == "exitproc":
            self.flush()
            self.emit(self.leave_proc(), s.pos)
        else:  # lock, unlock
            self.emit([ast.Expr(call("_" + c, nm("T")))], s.pos)

    def s_Delay(self, s: n.Delay, flat: bool) -> None:
        self.pending += 1
        self.flush()
        amount, _ = self.x.read(s.amount)
        req = ast.Tuple(
            [const(SLEEP if s.command == "sleep" else WAIT), amount, nm("b")], ast.Load()
        )
        self.emit([assign(nm("b", True), ast.Yield(req))], s.pos)

    def s_Kill(self, s: n.Kill, flat: bool) -> None:
        self.pending += 1
        self.emit([ast.Expr(call("_kill", nm("T"), self.x.read(s.task)[0]))], s.pos)

    def s_Print(self, s: n.Print, flat: bool) -> None:
        self.pending += 1
        k = self.prog.add_format(s)
        args = ast.Tuple([self.x.read(a)[0] for a in s.args], ast.Load())
        self.emit([ast.Expr(call("_print", nm("T"), const(k), args))], s.pos)
        if s.command == "retprintl":
            self.ret(s.pos)

    def s_ProcCall(self, s: n.ProcCall, flat: bool) -> None:
        self.pending += 1
        self.flush()
        proc = self.x.sym(s)
        assert isinstance(proc, ProcSym)
        args = [nm("T"), nm("b")] + [self.arg(a, p) for a, p in zip(s.args, proc.params)]
        gen = call(self.prog.proc_pyname(proc.name), *args)
        self.emit([assign(nm("b", True), ast.YieldFrom(gen))], s.pos)

    def arg(self, a: n.Operand, p: n.Param) -> ast.expr:
        if p.type == "instate":
            if isinstance(a, n.VarRef):
                sym = self.x.sym(a)
                if isinstance(sym, VarSym) and sym.type == "state":
                    return const(self.prog.state_bit(sym))
            if isinstance(a, n.AngleRef):
                return self.x.state_ref(a)[0]
        e, kind = self.x.read(a)
        if p.type == "long" and not p.pointer and kind == FLT:
            return call("_rnd", e)
        return e

    def s_Till(self, s: n.Till, flat: bool) -> None:
        self.pending += 1
        self.flush()
        wait = assign(nm("b", True), ast.Yield(const(0)))
        test = ast.UnaryOp(ast.Not(), self.x.cond(s.cond))
        self.emit([ast.While(test, [wait], [])], s.pos)

    # ------------------------------------------------------------ assembly

    def dispatcher(self) -> list[ast.stmt]:
        """`while True: if pc <= 0: ... if pc <= 1: ... <end>` (or straight code)."""
        self.flush()
        for c, label in self.fixups:
            c.value = self.label_seg[label]
        tail = self.end_task() if self.proc is None else self.leave_proc()
        if not self.uses_dispatch:
            return self.segments[0] + tail
        chain: list[ast.stmt] = []
        for k, seg in enumerate(self.segments):
            if not seg:
                continue
            test = ast.Compare(nm("pc"), [ast.LtE()], [const(k)])
            chain.append(ast.If(test, seg, []))
        return [ast.While(const(True), chain + tail, [])]


_DISPATCH: dict[tuple[type, type], Callable[..., None]] = {}
"""(lowerer class, statement class) -> the `s_<class>` method lowering it."""

_CLOCK_SKIPPED = frozenset({"pos", "body", "then_body", "else_body"})
_ATOMS = frozenset({str, int, float, bool, type(None)})
_CLOCK_FIELDS: dict[type, tuple[str, ...]] = {}
"""Node class -> the fields `_reads_clock` looks into."""


def _reads_clock(node: object) -> bool:
    """True if a statement (not counting nested bodies) reads fclk or tests TOUT."""
    stack = [node]
    pop, push, extend = stack.pop, stack.append, stack.extend
    while stack:
        x = pop()
        cls = type(x)
        if cls is tuple:
            extend(x)
        elif cls is n.VarRef:
            if x.name.lower() == "fclk":
                return True
        elif cls is n.Relation and x.op == "TOUT":
            return True
        else:
            fields = _CLOCK_FIELDS.get(cls)
            if fields is None:
                names = getattr(cls, "__dataclass_fields__", None) or ()
                fields = _CLOCK_FIELDS[cls] = tuple(f for f in names if f not in _CLOCK_SKIPPED)
            for f in fields:
                v = getattr(x, f)
                if type(v) not in _ATOMS:
                    push(v)
    return False


def _walk(items: tuple[n.Item, ...]):
    for s in items:
        yield s
        if isinstance(s, n.If):
            yield from _walk(s.then_body)
            yield from _walk(s.else_body or ())
        elif isinstance(s, (n.Loop, n.While)):
            yield from _walk(s.body)


__all__ = ["FLOAT", "SLEEP", "WAIT", "BodyLowerer", "is_jumpy", "subscript"]
