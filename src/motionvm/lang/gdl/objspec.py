"""The shapes of GDL object-type descriptions: parameters, state variables, operators.

`objects.py` holds the catalogue built from these. Value kinds: 'int' (|v| <= 999999999,
narrowed by lo..hi), 'digital' (ON/OFF stored as bool), 'set' (one keyword of `values`),
'config' (a device configuration: PRESENT, ABSENT, or an object-type keyword reserving
the device for that type), 'name' (an object of one of `types`), 'string' (one or two
strings, two display languages). Access codes: 'r', 'w', 'rw', with an 'f' suffix when
the debugger may force the variable.
"""

from __future__ import annotations

from dataclasses import dataclass

INT_LIMIT = 999_999_999
"""Largest absolute value of a GDL integer [T]."""


@dataclass(frozen=True, slots=True)
class ParamSpec:
    """One declaration parameter of a type."""

    keyword: str
    kind: str
    lo: int = -INT_LIMIT
    hi: int = INT_LIMIT
    values: tuple[str, ...] = ()
    types: tuple[str, ...] = ()
    role: str = "plain"  # 'parent' | 'channel' | 'size' | 'ref' | 'plain'
    mandatory: bool = False
    default: object = None


@dataclass(frozen=True, slots=True)
class StateSpec:
    """One state variable; `activator` when a change of it can start procedures."""

    keyword: str
    kind: str
    access: str
    values: tuple[str, ...] = ()
    lo: int = -INT_LIMIT
    hi: int = INT_LIMIT
    activator: bool = False
    default: object = None
    init_param: str | None = None  # declaration parameter giving the initial value
    machine: bool = False  # updated by the RTS from the machine (an input)

    @property
    def readable(self) -> bool:
        return "r" in self.access

    @property
    def writable(self) -> bool:
        return "w" in self.access

    @property
    def forceable(self) -> bool:
        return "f" in self.access


@dataclass(frozen=True, slots=True)
class ArgSpec:
    """One operator parameter; `limit` names a dynamic limit ('travel', 'max_speed')."""

    name: str
    kind: str
    lo: int = -INT_LIMIT
    hi: int = INT_LIMIT
    limit: str | None = None


@dataclass(frozen=True, slots=True)
class OperatorSpec:
    """An operator (opcode): a keyword, the object it acts on, typed arguments."""

    keyword: str
    args: tuple[ArgSpec, ...]
    doc: str


@dataclass(frozen=True, slots=True)
class DeviceSpec:
    """A connection device of a parent: its configuration parameter and channels."""

    config_param: str
    channels: tuple[int, int]
    child_types: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class ObjType:
    """One object type of the catalogue."""

    name: str
    category: str  # 'hardware' | 'software' | 'user'
    doc: str
    params: tuple[ParamSpec, ...] = ()
    states: tuple[StateSpec, ...] = ()
    operators: tuple[OperatorSpec, ...] = ()
    devices: tuple[DeviceSpec, ...] = ()
    array: bool = False  # accepts ARRAY$SIZE

    def param(self, keyword: str) -> ParamSpec | None:
        return next((p for p in self.params if p.keyword == keyword), None)

    def state(self, keyword: str) -> StateSpec | None:
        return next((s for s in self.states if s.keyword == keyword), None)

    def operator(self, keyword: str) -> OperatorSpec | None:
        return next((o for o in self.operators if o.keyword == keyword), None)

    @property
    def activators(self) -> tuple[str, ...]:
        return tuple(s.keyword for s in self.states if s.activator)

    def parent_params(self) -> tuple[ParamSpec, ...]:
        return tuple(p for p in self.params if p.role == "parent")


def format_value(kind: str, value: object) -> str:
    """A state value as GDL writes it: ON/OFF, a keyword, or a decimal integer."""
    if kind == "digital":
        return "ON" if value else "OFF"
    return str(value)
