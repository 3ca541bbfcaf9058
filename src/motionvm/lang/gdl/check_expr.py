"""Static types of GDL expressions: integer, digital, set, string and name values.

Arithmetic takes integers (constants are folded, so limits can be checked at compile
time); relations compare integers with all six operators and other values with `=` and
`<>` only; a set variable compares only with a variable of the same kind or a constant
of its group [T]; AND, OR and NOT take digital values.
"""

from __future__ import annotations

from dataclasses import dataclass

from motionvm.lang.gdl import nodes as n
from motionvm.lang.gdl.app import ObjectInfo
from motionvm.lang.gdl.objects import StateSpec
from motionvm.source.diagnostics import DiagnosticSink

ARITH = ("+", "-", "*", "/")
ORDER = ("<", ">", "<=", ">=")
KIND_NAMES = {
    "int": "integer",
    "digital": "digital",
    "set": "set",
    "setconst": "set constant",
    "string": "string",
    "name": "object name",
}


@dataclass(frozen=True, slots=True)
class VType:
    """The static type of an expression; kind 'error' silences follow-up errors."""

    kind: str
    values: tuple[str, ...] = ()
    keyword: str = ""
    const: int | None = None


def article(word: str) -> str:
    return ("an " if word[0] in "aeiou" else "a ") + word


ERROR = VType("error")
DIGITAL = VType("digital")


class ExprChecker:
    """Types expressions; subclasses resolve objects and state variables."""

    sink: DiagnosticSink

    def _object(self, name: n.Name) -> ObjectInfo | None:
        raise NotImplementedError

    def _state(self, ref: n.StateRef, write: bool) -> tuple[ObjectInfo, StateSpec] | None:
        raise NotImplementedError

    def _expr(self, e: n.Expr) -> VType:
        if isinstance(e, n.IntLit):
            return VType("int", const=e.value)
        if isinstance(e, n.DigitalLit):
            return DIGITAL
        if isinstance(e, n.SetLit):
            return VType("setconst", (e.word,))
        if isinstance(e, n.StrLit):
            return VType("string")
        if isinstance(e, n.NameLit):
            return VType("name") if self._object(e.name) is not None else ERROR
        if isinstance(e, n.StateRef):
            found = self._state(e, write=False)
            if found is None:
                return ERROR
            spec = found[1]
            return VType(spec.kind, spec.values, spec.keyword)
        if isinstance(e, n.Unary):
            return self._unary(e)
        return self._binary(e)

    def _unary(self, e: n.Unary) -> VType:
        t = self._expr(e.operand)
        if t.kind == "error":
            return ERROR
        if e.op == "NOT":
            if t.kind != "digital":
                self.sink.error(e.pos, f"NOT needs a digital operand, not {KIND_NAMES[t.kind]}")
                return ERROR
            return DIGITAL
        if t.kind != "int":
            self.sink.error(e.pos, f"'{e.op}' needs an integer, not {KIND_NAMES[t.kind]}")
            return ERROR
        return VType(
            "int", const=None if t.const is None else (-t.const if e.op == "-" else t.const)
        )

    def _binary(self, e: n.Binary) -> VType:
        left, right = self._expr(e.left), self._expr(e.right)
        if "error" in (left.kind, right.kind):
            return ERROR
        if e.op in ("AND", "OR"):
            for side in (left, right):
                if side.kind != "digital":
                    self.sink.error(
                        e.pos, f"{e.op} needs digital operands, not {KIND_NAMES[side.kind]}"
                    )
                    return ERROR
            return DIGITAL
        if e.op in ARITH:
            if left.kind != "int" or right.kind != "int":
                bad = left if left.kind != "int" else right
                self.sink.error(e.pos, f"'{e.op}' needs integers, not {KIND_NAMES[bad.kind]}")
                return ERROR
            if right.const == 0 and e.op == "/":
                self.sink.error(e.pos, "division by the constant 0")
                return ERROR
            return VType("int", const=self._fold(e.op, left.const, right.const))
        return self._relation(e, left, right)

    @staticmethod
    def _fold(op: str, a: int | None, b: int | None) -> int | None:
        if a is None or b is None:
            return None
        if op == "+":
            return a + b
        if op == "-":
            return a - b
        if op == "*":
            return a * b
        q = abs(a) // abs(b)
        return q if (a >= 0) == (b >= 0) else -q

    def _relation(self, e: n.Binary, left: VType, right: VType) -> VType:
        kinds = {left.kind, right.kind}
        if e.op in ORDER and kinds != {"int"}:
            self.sink.error(
                e.pos,
                f"'{e.op}' compares integers only; use '=' or '<>' for "
                f"{KIND_NAMES[(kinds - {'int'}).pop()]} values",
            )
            return ERROR
        if kinds <= {"set", "setconst"}:
            sets = [t for t in (left, right) if t.kind == "set"]
            consts = [t.values[0] for t in (left, right) if t.kind == "setconst"]
            if len(sets) == 2 and sets[0].keyword != sets[1].keyword:
                self.sink.error(
                    e.pos,
                    f"cannot compare {sets[0].keyword} with "
                    f"{sets[1].keyword}: different set variables",
                )
                return ERROR
            for word in consts:
                if sets and word not in sets[0].values:
                    group = "{" + ", ".join(sets[0].values) + "}"
                    self.sink.error(
                        e.pos, f"{word} is not in the group {group} of {sets[0].keyword}"
                    )
                    return ERROR
            return DIGITAL
        if len(kinds) != 1:
            a, b = sorted(KIND_NAMES[k] for k in kinds)
            self.sink.error(e.pos, f"cannot compare {article(a)} value with {article(b)} value")
            return ERROR
        return DIGITAL
