"""The run-time API of generated GDL code: the only names a lowered procedure calls.

One `ProcedureApi` serves one procedure run. It checks what needs values: subscripts
against ARRAY$SIZE, static limits of assigned values (PWM VALUE 0..1000, the integer
range), operator arguments, division by zero and the WHILE iteration budget. A
violation raises `GdlFault`: nothing is assigned and the run is aborted;
the RTS reports it at the user's line, read from the generated code's frame.
"""

from __future__ import annotations

from motionvm.lang.gdl.app import ObjectInfo, ProcInfo
from motionvm.lang.gdl.devices import GdlFault, RtsView
from motionvm.lang.gdl.objects import INT_LIMIT, format_value

MAX_LOOP_ITERATIONS = 100_000
"""WHILE iterations allowed in one procedure run before it is aborted."""


class ProcedureApi:
    """What generated code may call: at, loop, read, assign, call, div."""

    def __init__(self, rts: RtsView, proc: ProcInfo) -> None:
        self._rts = rts
        self._proc = proc
        self._iterations = 0
        self._objects: dict[str, tuple[ObjectInfo, int | None]] = {}

    def _object(self, key: str) -> tuple[ObjectInfo, int | None]:
        """The object and its ARRAY$SIZE, looked up once per run of the application
        (a procedure may read the same variable millions of times)."""
        hit = self._objects.get(key)
        if hit is None:
            obj = self._rts.app.objects[key]
            hit = self._objects[key] = (obj, obj.size)
        return hit

    def _element(self, key: str, index: object) -> tuple[ObjectInfo, int]:
        """The object and the element `KW OF obj{index}` names (no index: the first)."""
        obj, size = self._object(key)
        if index is None:
            return obj, 0 if size is None else 1
        assert isinstance(index, int)
        if not 1 <= index <= (size or 0):
            raise GdlFault(f"index {index} of {obj.name} is outside 1..{size or 0} (ARRAY$SIZE)")
        return obj, index

    def _elements(self, key: str, index: object) -> tuple[ObjectInfo, list[int]]:
        if index is None:
            obj, _ = self._object(key)
            return obj, list(obj.elements)
        obj, element = self._element(key, index)
        return obj, [element]

    def at(self, line: int) -> None:
        """An instruction boundary: scenario events may be injected here."""
        self._rts.before_instruction(self._proc, line)

    def loop(self) -> None:
        """One more WHILE iteration in this run."""
        self._iterations += 1
        if self._iterations > MAX_LOOP_ITERATIONS:
            raise GdlFault(
                f"WHILE loop still running after {MAX_LOOP_ITERATIONS} iterations (wait for "
                "an input with an activator, not a loop)"
            )

    def read(self, key: str, keyword: str, index: object) -> object:
        """The value of `KW OF obj{index}` (index None: a scalar)."""
        obj, element = self._element(key, index)
        return self._rts.read(obj, keyword, element)

    def assign(self, key: str, keyword: str, index: object, value: object) -> None:
        """`KW OF obj{index} = value`; index None on an array assigns every element."""
        obj, elements = self._elements(key, index)
        spec = obj.type.state(keyword)
        assert spec is not None
        if spec.kind == "int":
            assert isinstance(value, int)
            target = f"{spec.keyword} OF {obj.name}"
            if abs(value) > INT_LIMIT:
                raise GdlFault(
                    f"{target} = {value} exceeds the integer range -{INT_LIMIT}..{INT_LIMIT}"
                )
            if not spec.lo <= value <= spec.hi:
                raise GdlFault(f"{target} = {value} exceeds the static limit {spec.lo}..{spec.hi}")
        elif spec.kind == "set" and value not in spec.values:
            raise GdlFault(f"{format_value('set', value)} is not a value of {spec.keyword}")
        for e in elements:
            self._rts.write(obj, keyword, e, value, "set")

    def call(self, key: str, keyword: str, index: object, *args: object) -> None:
        """`OPKW OF obj{index} (args)`; index None on an array calls it on every element."""
        obj, elements = self._elements(key, index)
        op = obj.type.operator(keyword)
        assert op is not None
        values: list[int] = []
        for spec, value in zip(op.args, args, strict=True):
            assert isinstance(value, int)
            if not spec.lo <= value <= spec.hi:
                raise GdlFault(
                    f"argument {spec.name} of {op.keyword} = {value} exceeds the static limit "
                    f"{spec.lo}..{spec.hi}"
                )
            values.append(value)
        for e in elements:
            self._rts.device(obj).call(self._rts, op.keyword, values, e)

    @staticmethod
    def div(a: int, b: int) -> int:
        """Integer division truncating toward zero; division by zero is a fault."""
        if b == 0:
            raise GdlFault("division by zero")
        q = abs(a) // abs(b)
        return q if (a >= 0) == (b >= 0) else -q
