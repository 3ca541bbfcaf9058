"""Symbols and scopes of an HMPL program (manual 1.5): global, task, function and block scope.

Storage of a variable decides how generated code reaches it:
- 'local'  — a Python local of the generated function (plain scalars, address never taken);
- 'pyglobal' — a Python global of the shared program namespace (global/task scalars);
- 'static' — a fixed address in memory (arrays, structs, address-taken globals, system vars);
- 'frame'  — an offset in the function's stack frame (memory-resident locals).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from motionvm.lang.hmpl import ctypes_ as ct
from motionvm.source.files import SourcePos


@dataclass(slots=True)
class VarSym:
    name: str
    type: ct.CType
    storage: str  # 'local' | 'pyglobal' | 'static' | 'frame'
    pos: SourcePos | None
    pyname: str = ""  # for 'local' / 'pyglobal'
    addr: int = 0  # for 'static'
    offset: int = 0  # for 'frame'
    is_const: bool = False
    const_value: int | float | None = None  # named constants


def error_symbol(name: str, pos: SourcePos) -> VarSym:
    """The symbol of a name whose declaration failed: declared, so that its uses add no
    "undeclared" errors, with the error type, so that they report nothing at all."""
    return VarSym(name, ct.ERROR, "local", pos, pyname="_error")


@dataclass(slots=True)
class FuncSym:
    name: str
    type: ct.FuncT
    pos: SourcePos
    pyname: str
    task: int  # owning task (0 for global functions)
    defined: bool = False
    is_generator: bool = False
    param_names: tuple[str, ...] = ()
    node: object = None  # the FuncDef with a body


@dataclass(slots=True)
class Scope:
    """One level of name lookup; `parent` is the enclosing scope."""

    parent: Scope | None
    kind: str  # 'global' | 'task' | 'function' | 'block'
    names: dict[str, VarSym | FuncSym] = field(default_factory=dict)
    types: dict[str, ct.CType] = field(default_factory=dict)  # typedef names
    tags: dict[str, ct.StructT] = field(default_factory=dict)  # struct/union tags

    def _find(self, table: str, key: str):
        s: Scope | None = self
        while s is not None:
            found = getattr(s, table).get(key)
            if found is not None:
                return found
            s = s.parent
        return None

    def lookup(self, name: str) -> VarSym | FuncSym | None:
        s: Scope | None = self
        while s is not None:  # `_find` without its `getattr`: the lowering's most asked
            found = s.names.get(name)
            if found is not None:
                return found
            s = s.parent
        return None

    def lookup_type(self, name: str) -> ct.CType | None:
        return self._find("types", name)

    def lookup_tag(self, tag: str) -> ct.StructT | None:
        return self._find("tags", tag)

    def visible_names(self) -> list[str]:
        out: list[str] = []
        s: Scope | None = self
        while s is not None:
            out.extend(s.names)
            s = s.parent
        return out
