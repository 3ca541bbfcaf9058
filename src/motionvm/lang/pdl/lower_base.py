"""What the PDL lowering's parts share: Python `ast` builders, a walk over PDL nodes, the
storage of a variable, and the interface of the program lowering they are handed.

`ProgramLowering` (lower.py) hands itself to the parts below it (`lower_expr.py`,
`lower_cache.py`, `lower_body.py`) as a `ProgramContext`; the interface lives here, at the
bottom, so that no lowering module imports one that imports it back.

    nm("x")                  ->  x
    assign(nm("x", True), const(1))  ->  x = 1
    subscript("M", const(7)) ->  M[7]
"""

from __future__ import annotations

import ast
from typing import Protocol, TypeVar

from motionvm.lang.pdl import nodes as n
from motionvm.lang.pdl.rt_memory import FLOAT, LONG, SHORT
from motionvm.lang.pdl.symbols import LabelSym, Symbols, VarSym
from motionvm.lang.placing import PLACED

T = TypeVar("T")


def clone(node: T) -> T:
    """A deep copy of a generated tree or list of trees, locations included
    (`copy.deepcopy` without its memo and reduce protocol); operator and context nodes,
    which hold nothing, are shared. The copy is not marked placed."""
    AST = ast.AST
    if type(node) is list:
        return [clone(x) for x in node]  # type: ignore[return-value]
    cls = type(node)
    new = cls.__new__(cls)
    nd = new.__dict__
    for k, v in node.__dict__.items():
        if type(v) is list:
            nd[k] = [clone(x) if isinstance(x, AST) else x for x in v]
        elif isinstance(v, AST):
            nd[k] = clone(v) if v._fields or v._attributes else v
        elif k != PLACED:
            nd[k] = v
    return new


_LOAD, _STORE = ast.Load(), ast.Store()
"""The contexts every generated name and subscript shares (as `ast.parse`'s do)."""


def nm(ident: str, store: bool = False) -> ast.Name:
    return ast.Name(ident, _STORE if store else _LOAD)


def const(v: object) -> ast.Constant:
    return ast.Constant(v)


def call(func: str, *args: ast.expr) -> ast.Call:
    return ast.Call(nm(func), list(args), [])


def binop(left: ast.expr, op: ast.operator, right: ast.expr) -> ast.expr:
    if (
        isinstance(left, ast.Constant)
        and isinstance(right, ast.Constant)
        and isinstance(op, ast.Add)
    ):
        return const(left.value + right.value)
    if isinstance(right, ast.Constant) and right.value == 0 and isinstance(op, ast.Add):
        return left
    return ast.BinOp(left, op, right)


def subscript(view: str, index: ast.expr, store: bool = False) -> ast.Subscript:
    return ast.Subscript(nm(view), index, _STORE if store else _LOAD)


def assign(target: ast.expr, value: ast.expr) -> ast.stmt:
    return ast.Assign([target], value)


def storage_kind(sym: VarSym) -> int:
    """LONG, SHORT or FLOAT: how the variable's elements are stored."""
    if sym.pointer or sym.type in ("long", "instate"):
        return LONG
    return SHORT if sym.type == "short" else FLOAT


def walk_nodes(node: object):
    """Every AST node under `node` (itself included)."""
    yield node
    fields = getattr(node, "__dataclass_fields__", None)
    if not fields:
        return
    for f in fields:
        v = getattr(node, f)
        if isinstance(v, tuple):
            for x in v:
                if hasattr(x, "__dataclass_fields__"):
                    yield from walk_nodes(x)
        elif hasattr(v, "__dataclass_fields__") and f != "pos":
            yield from walk_nodes(v)


class ProgramContext(Protocol):
    """What the bodies' lowering uses of the program lowering (`lower.ProgramLowering`)."""

    syms: Symbols
    sys_base: dict[str, int]
    keep: list[object]
    promote: bool
    chunk: bool
    views: dict[str, tuple[str, int, int]]
    uses_lists: bool

    def line_of(self, pos: object) -> int:
        """The generated line of a source position (files after the first are offset)."""

    def global_index(self, sym: VarSym) -> int:
        """The index of a global variable in its memory view."""

    def state_bit(self, sym: VarSym) -> int:
        """The byte of a state in `ST`."""

    def label_address(self, label: LabelSym, in_proc: bool) -> int:
        """The address `<label>` denotes."""

    def add_format(self, s: n.Print) -> int:
        """The index of a printl statement's compiled format."""

    def table_name(self, body, label: str) -> str:
        """The name of the jump table of `body`'s label `label`."""

    def proc_pyname(self, name: str) -> str:
        """The Python name of procedure `name`."""
