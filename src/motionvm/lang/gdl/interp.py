"""Executes one GDL procedure run on the RTS, instruction by instruction.

The checker has already verified names, access and types, so this module only does
what needs values: dynamic limits (subscripts, travel limits, MAX$SPEED), static limits
of non-constant values (PWM VALUE 0..1000, the integer range), division by zero and the
WHILE iteration budget. Any violation raises `GdlFault`: the assignment is not done and
the run is aborted (GDL.md G9). AND/OR evaluate their right operand only when needed.

Why a tree walker and not lowering to Python `ast` (DESIGN.md): a GDL run must stop at
every instruction boundary so that scenario events can be injected mid-run (GDL.md
9.5.2); `interp` is the only module that knows the AST at run time, so a `lower.py`
can replace it without touching `rts`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from motionvm.lang.gdl import nodes as n
from motionvm.lang.gdl.app import ObjectInfo, ProcInfo
from motionvm.lang.gdl.devices import GdlFault
from motionvm.lang.gdl.objects import INT_LIMIT, format_value

if TYPE_CHECKING:
    from motionvm.lang.gdl.rts import Rts

MAX_LOOP_ITERATIONS = 100_000
"""WHILE iterations allowed in one procedure run before it is aborted (G25)."""


class _Return(Exception):
    """RETURN: ends the current run."""


class ProcedureRun:
    """One execution of one procedure; `pos` is the instruction being executed."""

    def __init__(self, rts: Rts, proc: ProcInfo) -> None:
        self.rts = rts
        self.proc = proc
        self.pos = proc.node.pos
        self.iterations = 0

    def run(self) -> None:
        """Execute the body; raises GdlFault on a run-time error."""
        try:
            self._block(self.proc.node.body)
        except _Return:
            pass

    # ------------------------------------------------------------ instructions

    def _block(self, body: tuple[n.Instr, ...]) -> None:
        for instr in body:
            self.pos = instr.pos
            self.rts.before_instruction(self.proc, instr.pos.line)
            self.pos = instr.pos
            if isinstance(instr, n.Assign):
                self._assign(instr)
            elif isinstance(instr, n.OperatorCall):
                self._operator(instr)
            elif isinstance(instr, n.If):
                self._block(instr.then if self._eval(instr.cond) else instr.orelse)
            elif isinstance(instr, n.While):
                while self._eval(instr.cond):
                    self.iterations += 1
                    if self.iterations > MAX_LOOP_ITERATIONS:
                        self.pos = instr.pos
                        raise GdlFault(f"WHILE loop still running after {MAX_LOOP_ITERATIONS} "
                                       "iterations (wait for an input with an activator, not "
                                       "a loop)")
                    self._block(instr.body)
            else:
                raise _Return()

    def _elements(self, ref: n.ObjectRef) -> tuple[ObjectInfo, list[int]]:
        obj = self.rts.app.objects[ref.name.key]
        if ref.index is None:
            return obj, list(obj.elements)
        index = self._eval(ref.index)
        assert isinstance(index, int)
        size = obj.size or 0
        if not 1 <= index <= size:
            raise GdlFault(f"index {index} of {obj.name} is outside 1..{size} (ARRAY$SIZE)")
        return obj, [index]

    def _assign(self, a: n.Assign) -> None:
        obj, elements = self._elements(a.target.obj)
        value = self._eval(a.value)
        spec = obj.type.state(a.target.keyword)
        assert spec is not None
        if spec.kind == "int":
            assert isinstance(value, int)
            target = f"{spec.keyword} OF {obj.name}"
            if abs(value) > INT_LIMIT:
                raise GdlFault(f"{target} = {value} exceeds the integer range "
                               f"-{INT_LIMIT}..{INT_LIMIT}")
            if not spec.lo <= value <= spec.hi:
                raise GdlFault(f"{target} = {value} exceeds the static limit "
                               f"{spec.lo}..{spec.hi}")
        elif spec.kind == "set" and value not in spec.values:
            raise GdlFault(f"{format_value('set', value)} is not a value of {spec.keyword}")
        for e in elements:
            self.rts.write(obj, spec.keyword, e, value, "set")

    def _operator(self, call: n.OperatorCall) -> None:
        obj, elements = self._elements(call.obj)
        op = obj.type.operator(call.keyword)
        assert op is not None
        args: list[int] = []
        for spec, node in zip(op.args, call.args, strict=True):
            value = self._eval(node)
            assert isinstance(value, int)
            if not spec.lo <= value <= spec.hi:
                raise GdlFault(f"argument {spec.name} of {op.keyword} = {value} exceeds the "
                               f"static limit {spec.lo}..{spec.hi}")
            args.append(value)
        for e in elements:
            self.rts.device(obj).call(self.rts, op.keyword, args, e)

    # ------------------------------------------------------------ expressions

    def _eval(self, e: n.Expr) -> object:
        if isinstance(e, n.IntLit | n.DigitalLit | n.StrLit):
            return e.value
        if isinstance(e, n.SetLit):
            return e.word
        if isinstance(e, n.NameLit):
            return e.name.key
        if isinstance(e, n.StateRef):
            obj, elements = self._elements(e.obj)
            return self.rts.read(obj, e.keyword, elements[0])
        if isinstance(e, n.Unary):
            v = self._eval(e.operand)
            if e.op == "NOT":
                return not v
            assert isinstance(v, int)
            return -v if e.op == "-" else v
        assert isinstance(e, n.Binary)
        if e.op in ("AND", "OR"):
            left = bool(self._eval(e.left))
            if e.op == "AND":
                return left and bool(self._eval(e.right))
            return left or bool(self._eval(e.right))
        a, b = self._eval(e.left), self._eval(e.right)
        return _binary(e.op, a, b)


def _binary(op: str, a: object, b: object) -> object:
    if op == "=":
        return a == b
    if op == "<>":
        return a != b
    assert isinstance(a, int) and isinstance(b, int)
    if op == "+":
        return a + b
    if op == "-":
        return a - b
    if op == "*":
        return a * b
    if op == "/":
        if b == 0:
            raise GdlFault("division by zero")
        q = abs(a) // abs(b)
        return q if (a >= 0) == (b >= 0) else -q
    return {"<": a < b, ">": a > b, "<=": a <= b, ">=": a >= b}[op]
