"""Scope channels of a GDL application: its state variables, named `OBJECT.STATE`.

A channel is one state variable of one object element, named as the GDL source writes
the object and the keyword: `cooling_fan.VALUE`, `main_motor.OPERATING$CONDITION`,
`photocell{2}.STATUS` (an element of an array object; an array needs the element).
Names are case-insensitive, like GDL's. The value is the one procedures read (a forced
value while forced), as a number:
- ON/OFF: 1/0, unit `bool`;
- a set value: its position in the keyword's value list as the reference tables give it
  (STOPPED 0, RUNNING 1; ENABLED 0, DISABLED 1), unit `bool` for a set of two values,
  else `raw`;
- an integer: itself, unit `raw` (GDL positions and speeds are in the object's units).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING

from motionvm.lang.gdl.app import ObjectInfo
from motionvm.lang.gdl.objects import StateSpec
from motionvm.lang.gdl.scenario import Target, parse_value
from motionvm.runtime.scope import BIT_UNIT, RAW_UNIT, ChannelSource, ScopeError
from motionvm.source.suggest import did_you_mean

if TYPE_CHECKING:
    from motionvm.lang.gdl.rts import Rts

_NAME = re.compile(r"([A-Za-z_]\w*)(?:\{(\d+)\})?\.([A-Za-z_$][\w$]*)")
SUGGESTED_ELEMENTS = 4
"""Elements of each array object offered as suggestions."""


def _unit(spec: StateSpec) -> str:
    if spec.kind == "digital" or (spec.kind == "set" and len(spec.values) == 2):
        return BIT_UNIT
    return RAW_UNIT


class GdlScopeSource(ChannelSource):
    """The `ChannelSource` (runtime/scope.py) of one application's RTS."""

    def __init__(self, rts: Rts) -> None:
        self.rts = rts

    def resolve(self, name: str) -> tuple[Callable[[], float], str] | None:
        m = _NAME.fullmatch(name)
        if m is None:
            return None
        obj = self.rts.app.objects.get(m.group(1).lower())
        if obj is None:
            return None  # not one of ours: another source may know it
        spec = obj.type.state(m.group(3).upper())
        if spec is None:
            hint = did_you_mean(m.group(3), [s.keyword for s in obj.type.states])
            raise ScopeError(
                f"scope channel '{name}': {obj.type.name} has no state variable {m.group(3)}{hint}"
            )
        element = self._element(name, obj, m.group(2), spec)
        return self._getter(obj, spec, element), _unit(spec)

    @staticmethod
    def _element(name: str, obj: ObjectInfo, index: str | None, spec: StateSpec) -> int:
        if obj.size is None:
            if index is not None:
                raise ScopeError(f"scope channel '{name}': {obj.name} is not an array")
            return 0
        if index is None:
            raise ScopeError(
                f"scope channel '{name}': {obj.name} is an array of {obj.size}; record one "
                f"element, e.g. '{obj.name}{{1}}.{spec.keyword}'"
            )
        i = int(index)
        if not 1 <= i <= obj.size:
            raise ScopeError(
                f"scope channel '{name}': index {i} of {obj.name} is outside 1..{obj.size}"
            )
        return i

    def write(self, name: str, value: object) -> bool:
        """Change `OBJECT.STATE` as a scenario input does (printed, triggers procedures);
        `value`: ON/OFF or a bool for a digital state, a value name or its index for a set,
        an integer. False if `name` is not one of ours; ValueError for a bad value."""
        if self.resolve(name) is None:
            return False
        m = _NAME.fullmatch(name)
        obj = self.rts.app.objects[m.group(1).lower()]  # type: ignore[union-attr]
        spec = obj.type.state(m.group(3).upper())  # type: ignore[union-attr]
        assert spec is not None
        element = self._element(name, obj, m.group(2), spec)  # type: ignore[union-attr]
        if spec.kind == "set" and isinstance(value, int) and not isinstance(value, bool):
            if not 0 <= value < len(spec.values):
                raise ValueError(
                    f"{name} takes one of {', '.join(spec.values)} (0..{len(spec.values) - 1})"
                )
            value = spec.values[value]
        elif spec.kind == "digital" and isinstance(value, (int, float)):
            value = bool(value)
        elif spec.kind == "int" and isinstance(value, float) and value.is_integer():
            value = int(value)
        self.rts.input(
            obj, spec.keyword, element, parse_value(Target(obj, spec, (element,)), value)
        )
        return True

    def _getter(self, obj: ObjectInfo, spec: StateSpec, element: int) -> Callable[[], float]:
        read, keyword = self.rts.read, spec.keyword
        if spec.kind == "set":
            index = {v: float(i) for i, v in enumerate(spec.values)}
            return lambda: index[read(obj, keyword, element)]  # type: ignore[index]
        return lambda: float(read(obj, keyword, element))  # type: ignore[arg-type]

    def channel_names(self) -> Iterable[str]:
        for obj in self.rts.app.objects.values():
            for spec in obj.type.states:
                if obj.size is None:
                    yield f"{obj.name}.{spec.keyword}"
                else:
                    for i in range(1, min(obj.size, SUGGESTED_ELEMENTS) + 1):
                        yield f"{obj.name}{{{i}}}.{spec.keyword}"
