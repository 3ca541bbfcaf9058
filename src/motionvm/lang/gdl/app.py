"""A checked, linked GDL application: objects, procedures and activator tables.

`check.check_app` builds an `App` only when the whole application is free of errors;
the RTS runs nothing else. Names are case-insensitive, so every table is keyed by the
case-folded name (`Name.key`) and keeps the declared spelling for output.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from motionvm.lang.gdl import nodes as n
from motionvm.lang.gdl.objects import ObjType
from motionvm.source.files import SourcePos


@dataclass(frozen=True, slots=True)
class Trigger:
    """One expanded activator: a keyword of an object, one element or all (`index` None)."""

    obj: str
    keyword: str
    index: int | None

    def matches(self, obj: str, keyword: str, element: int) -> bool:
        return (
            self.obj == obj
            and self.keyword == keyword
            and (self.index is None or self.index == element)
        )


@dataclass(slots=True)
class ObjectInfo:
    """A declared object with its parameters resolved (defaults filled in)."""

    name: str
    type: ObjType
    module: str
    pos: SourcePos
    params: dict[str, object] = field(default_factory=dict)
    param_pos: dict[str, SourcePos] = field(default_factory=dict)

    @property
    def key(self) -> str:
        return self.name.lower()

    @property
    def size(self) -> int | None:
        """ARRAY$SIZE, or None for a scalar object."""
        size = self.params.get("ARRAY$SIZE")
        return size if isinstance(size, int) else None

    @property
    def elements(self) -> range:
        """Element numbers: 1..size for an array, (0,) for a scalar."""
        return range(1, self.size + 1) if self.size is not None else range(1)

    def ref(self, keyword: str, element: int) -> str:
        """`KW OF name` or `KW OF name{i}`, as output lines write it."""
        sub = f"{{{element}}}" if element else ""
        return f"{keyword} OF {self.name}{sub}"


@dataclass(slots=True)
class ProcInfo:
    """A procedure in link order with its expanded activator list."""

    name: str
    module: str
    node: n.Procedure
    order: int
    triggers: tuple[Trigger, ...] = ()

    @property
    def file(self) -> str:
        return self.node.pos.file


@dataclass(slots=True)
class App:
    """The linked application: objects in declaration order, procedures in link order."""

    files: list[str]
    modules: list[str]
    objects: dict[str, ObjectInfo]
    procedures: list[ProcInfo]
    functions: dict[str, Callable[..., None]] = field(default_factory=dict)
    """Compiled procedures by case-folded name (filled by `lower.lower_app`)."""

    def procedure(self, name: str) -> ProcInfo | None:
        key = name.lower()
        return next((p for p in self.procedures if p.name.lower() == key), None)
