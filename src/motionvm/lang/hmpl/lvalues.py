"""Places a value can be stored (C lvalues) and how generated Python reads and writes them.

Each kind knows three things: the Python expression that loads it, the statement(s)
that store into it, and (if it lives in memory) the expression of its address.
`bind()` moves side-effecting sub-expressions (an index, a pointer) into temporaries so
a compound assignment or `x++` evaluates them exactly once, as C requires.
"""

from __future__ import annotations

import ast
from collections.abc import Callable
from dataclasses import dataclass

from motionvm.lang.hmpl import ctypes_ as ct
from motionvm.lang.hmpl.cmemory import ADDRESS_SIGN_MASK

VIEW_NAMES = {
    "i8": "_I8",
    "u8": "_U8",
    "i16": "_I16",
    "u16": "_U16",
    "i32": "_I32",
    "u32": "_U32",
    "i64": "_I64",
    "u64": "_U64",
    "f32": "_F32",
    "f64": "_F64",
}


def view_code(t: ct.CType) -> str:
    """The memory view used for a scalar type; pointers are stored as 64-bit integers."""
    if isinstance(t, (ct.IntT, ct.FloatT)):
        return t.code
    if isinstance(t, ct.PtrT):
        return "i64"
    raise TypeError(f"no scalar view for {t}")


_LOAD, _STORE = ast.Load(), ast.Store()  # context objects are immutable and may be shared


def name(id_: str, store: bool = False) -> ast.Name:
    return ast.Name(id_, _STORE if store else _LOAD)


const = ast.Constant
"""`const(v)`: a constant node (the class itself, with no call in between)."""


def call(fn: str, *args: ast.expr) -> ast.Call:
    return ast.Call(name(fn), list(args), [])  # positional: half the cost of keywords


def is_simple(e: ast.expr) -> bool:
    """True for expressions that are cheap and side-effect free to evaluate twice."""
    if isinstance(e, (ast.Name, ast.Constant)):
        return True
    if isinstance(e, ast.UnaryOp) and isinstance(e.operand, ast.Constant):
        return True
    if isinstance(e, ast.BinOp):
        return is_simple(e.left) and is_simple(e.right)
    return False


TempMaker = Callable[[], str]


@dataclass
class LValue:
    type: ct.CType

    def load(self) -> ast.expr:
        raise NotImplementedError

    def store(self, value: ast.expr) -> list[ast.stmt]:
        raise NotImplementedError

    def store_expr(self, value: ast.expr) -> ast.expr:
        """An expression that stores `value` and evaluates to it."""
        raise NotImplementedError

    def addr(self) -> ast.expr | None:
        return None

    def bind(self, temp: TempMaker) -> tuple[list[ast.expr], LValue]:
        """(walrus expressions to evaluate first, an equivalent LValue using temporaries)."""
        return [], self


@dataclass
class NameLV(LValue):
    """A Python local or global variable."""

    pyname: str = ""

    def load(self) -> ast.expr:
        return name(self.pyname)

    def store(self, value: ast.expr) -> list[ast.stmt]:
        return [ast.Assign([name(self.pyname, True)], value)]

    def store_expr(self, value: ast.expr) -> ast.expr:
        return ast.NamedExpr(name(self.pyname, True), value)


@dataclass
class MemLV(LValue):
    """Element `index` of the typed view of this scalar type (address = index * size)."""

    index: ast.expr | None = None

    @property
    def view(self) -> str:
        return VIEW_NAMES[view_code(self.type)]

    def load(self) -> ast.expr:
        return ast.Subscript(value=name(self.view), slice=self.index, ctx=ast.Load())

    def store(self, value: ast.expr) -> list[ast.stmt]:
        tgt = ast.Subscript(value=name(self.view), slice=self.index, ctx=ast.Store())
        return [ast.Assign(targets=[tgt], value=value)]

    def store_expr(self, value: ast.expr) -> ast.expr:
        return call("_stv", name(self.view), self.index, value)

    def addr(self) -> ast.expr:
        size = self.type.size
        if isinstance(self.index, ast.Constant):
            return ast.Constant(self.index.value * size)
        return ast.BinOp(left=self.index, op=ast.Mult(), right=ast.Constant(size))

    def bind(self, temp: TempMaker) -> tuple[list[ast.expr], LValue]:
        if is_simple(self.index):
            return [], self
        t = temp()
        pre = [ast.NamedExpr(target=name(t, True), value=self.index)]
        return pre, MemLV(self.type, name(t))


@dataclass
class PtrLV(LValue):
    """A scalar at a run-time address (through a pointer): checked loads and stores.

    Through a pointer variable, both inline their fast path: the address is aligned and
    in range (one mask test) and an access of n bytes fits its live object (one shadow
    byte >= n); any other address takes the helper, which faults or does the slow access.
    """

    address: ast.expr | None = None
    tmp: str = ""
    """A temporary that lets an address expression other than a name take the fast
    path (evaluated once, into it); without one such an access calls the helper."""

    def _fast(self) -> tuple[ast.expr, ast.expr, ast.expr] | None:
        """(the test of the inline fast path, the index into the view, the address for
        the helper) or None."""
        a = self.address
        first = a
        if not isinstance(a, ast.Name):
            if not self.tmp or isinstance(a, ast.Constant):
                return None
            first = ast.NamedExpr(target=name(self.tmp, True), value=a)
            a = name(self.tmp)
        size = self.type.size
        shift = size.bit_length() - 1
        idx = ast.BinOp(left=a, op=ast.RShift(), right=ast.Constant(shift)) if shift else a
        sign_align = ast.UnaryOp(
            op=ast.Not(),
            operand=ast.BinOp(
                left=first, op=ast.BitAnd(), right=ast.Constant(ADDRESS_SIGN_MASK | (size - 1))
            ),
        )
        valid: ast.expr = ast.Subscript(value=name("_SH"), slice=a, ctx=_LOAD)
        if size > 1:
            valid = ast.Compare(left=valid, ops=[ast.Gt()], comparators=[ast.Constant(size - 1)])
        return ast.BoolOp(op=ast.And(), values=[sign_align, valid]), idx, a

    def load(self) -> ast.expr:
        code = view_code(self.type)
        fast = self._fast()
        if fast is None:
            return call("_ld_" + code, self.address)
        test, idx, a = fast
        return ast.IfExp(
            test=test,
            body=ast.Subscript(value=name(VIEW_NAMES[code]), slice=idx, ctx=_LOAD),
            orelse=call("_ld_" + code, a),
        )

    def store(self, value: ast.expr) -> list[ast.stmt]:
        fast = self._fast()
        if fast is None:
            return [ast.Expr(value=self.store_expr(value))]
        # the value first (as the helper call would), then the check and the store
        pre: list[ast.stmt] = []
        if not is_simple(value):
            pre = [ast.Assign(targets=[name("_sv", True)], value=value)]
            value = name("_sv")
        test, idx, a = fast
        code = view_code(self.type)
        tgt = ast.Subscript(value=name(VIEW_NAMES[code]), slice=idx, ctx=_STORE)
        slow = ast.Expr(value=call("_st_" + code, a, value))
        return pre + [
            ast.If(test=test, body=[ast.Assign(targets=[tgt], value=value)], orelse=[slow])
        ]

    def store_expr(self, value: ast.expr) -> ast.expr:
        return call("_st_" + view_code(self.type), self.address, value)

    def addr(self) -> ast.expr:
        return self.address

    def bind(self, temp: TempMaker) -> tuple[list[ast.expr], LValue]:
        if is_simple(self.address):
            return [], self
        t = temp()
        pre = [ast.NamedExpr(target=name(t, True), value=self.address)]
        return pre, PtrLV(self.type, name(t))


@dataclass
class AggLV(LValue):
    """An array, struct, union or Timer in memory: its value is its address."""

    address: ast.expr | None = None

    def load(self) -> ast.expr:
        return self.address

    def addr(self) -> ast.expr:
        return self.address

    def store(self, value: ast.expr) -> list[ast.stmt]:
        # struct assignment: copy the bytes of the source object
        return [ast.Expr(value=call("_copy", self.address, value, ast.Constant(self.type.size)))]

    def store_expr(self, value: ast.expr) -> ast.expr:
        return call("_copy", self.address, value, ast.Constant(self.type.size))


@dataclass
class ListLV(LValue):
    """Element `index` of a list-backed array (flattened for several dimensions)."""

    pyname: str = ""
    index: ast.expr | None = None

    def load(self) -> ast.expr:
        return ast.Subscript(value=name(self.pyname), slice=self.index, ctx=_LOAD)

    def store(self, value: ast.expr) -> list[ast.stmt]:
        tgt = ast.Subscript(value=name(self.pyname), slice=self.index, ctx=_STORE)
        return [ast.Assign(targets=[tgt], value=value)]

    def store_expr(self, value: ast.expr) -> ast.expr:
        return call("_stv", name(self.pyname), self.index, value)

    def bind(self, temp: TempMaker) -> tuple[list[ast.expr], LValue]:
        if is_simple(self.index):
            return [], self
        t = temp()
        pre = [ast.NamedExpr(target=name(t, True), value=self.index)]
        return pre, ListLV(self.type, self.pyname, name(t))


@dataclass
class GpoLV(LValue):
    """HIMC_GPO(i): a controller general-purpose output, readable and assignable."""

    index: ast.expr | None = None

    def load(self) -> ast.expr:
        return call("_gpo", self.index)

    def store(self, value: ast.expr) -> list[ast.stmt]:
        return [ast.Expr(value=self.store_expr(value))]

    def store_expr(self, value: ast.expr) -> ast.expr:
        return call("_gpo_set", self.index, value)

    def bind(self, temp: TempMaker) -> tuple[list[ast.expr], LValue]:
        if is_simple(self.index):
            return [], self
        t = temp()
        return [ast.NamedExpr(target=name(t, True), value=self.index)], GpoLV(self.type, name(t))
