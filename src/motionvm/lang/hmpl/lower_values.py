"""Lowered values: what an HMPL expression becomes, and the integer wrap it may still owe.

A `Val` is a Python `ast` expression with its C type. Integers are Python ints kept in
the range of their C type, but a ring operation (+ - * << & | ^ ~) may defer that
reduction: a `Val` with `exact=False` is only known modulo 2**bits and is wrapped once,
where an exact value is needed (a store, a comparison, a division, a call):

    int x = a * b + c;
becomes
    v_x = _w if -2147483648 <= (_w := v_a * v_b + v_c) <= 2147483647 else _wrapi(_w)
"""

from __future__ import annotations

import ast
from dataclasses import dataclass

from motionvm.lang.hmpl import ctypes_ as ct
from motionvm.lang.hmpl.lvalues import call, const, name


@dataclass(slots=True)
class Val:
    """A lowered rvalue: Python expression, C type, whether in range, folded constant."""

    node: ast.expr
    type: ct.CType
    exact: bool = True
    const: int | float | None = None
    rng: tuple[int, int] | None = None  # known bounds of an integer value (range analysis)
    listy: str = ""  # a list-backed array (or row of one): the list's Python name
    loff: ast.expr | None = None  # ... and the flattened offset of this row
    step: tuple[str, int] | None = None  # `x + k` of an exact signed name x: (x, k)


_LE_LE = [ast.LtE(), ast.LtE()]  # operator objects are immutable and may be shared
_BITAND = ast.BitAnd()


def wrap_node(node: ast.expr, t: ct.IntT) -> ast.expr:
    """Reduce a Python int to the range of `t`.

    Signed: `(_w if LO <= (_w := x) <= HI else _wrap(_w, BITS))` — two comparisons on the
    common path, no big-int temporaries; unsigned: `x & MASK`.
    """
    bits = t.bits
    if t.signed:
        lo, hi = -(1 << (bits - 1)), (1 << (bits - 1)) - 1
        grab = ast.NamedExpr(name("_w", True), node)
        test = ast.Compare(ast.Constant(lo), _LE_LE, [grab, ast.Constant(hi)])
        slow = (
            call("_wrapi", name("_w"), ast.Constant(bits))
            if bits != 32
            else call("_wrapi", name("_w"))
        )
        return ast.IfExp(test, name("_w"), slow)
    return ast.BinOp(node, _BITAND, ast.Constant((1 << bits) - 1))


def step_node(var: str, k: int, t: ct.IntT) -> ast.expr:
    """`x + k` in signed type t (x exact, 0 < |k| <= t.max) without a temporary: the sum
    leaves t's range only past one end, and then by less than 2**bits.

    before: `x + 1`    after: `(x + 1 if x != 2147483647 else -2147483648)`
    before: `x - 5`    after: `(x - 5 if x >= -2147483643 else x + 4294967291)`
    """
    if k == 1 or k == -1:
        edge = t.max if k == 1 else t.min
        test = ast.Compare(name(var), [ast.NotEq()], [ast.Constant(edge)])
        body = ast.BinOp(name(var), ast.Add() if k == 1 else ast.Sub(), ast.Constant(1))
        return ast.IfExp(test, body, const(t.min if k == 1 else t.max))
    m = 1 << t.bits
    if k > 0:
        test = ast.Compare(name(var), [ast.LtE()], [const(t.max - k)])
        body = ast.BinOp(name(var), ast.Add(), ast.Constant(k))
        over = ast.BinOp(name(var), ast.Sub(), ast.Constant(m - k))
    else:
        test = ast.Compare(name(var), [ast.GtE()], [const(t.min - k)])
        body = ast.BinOp(name(var), ast.Sub(), ast.Constant(-k))
        over = ast.BinOp(name(var), ast.Add(), ast.Constant(m + k))
    return ast.IfExp(test, body, over)


def fold_int(v: int, t: ct.CType) -> int:
    return ct.wrap_int(v, t) if isinstance(t, ct.IntT) else v


# C's candidate types of an integer constant, by suffix (long is 4 bytes in HMPL, so it
# is int / uint32_t here); hexadecimal and octal constants may also take the unsigned ones
_LITERAL_TYPES = {
    ("", True): (ct.INT, ct.I64),
    ("", False): (ct.INT, ct.U32, ct.I64, ct.U64),
    ("l", True): (ct.INT, ct.I64),
    ("l", False): (ct.INT, ct.U32, ct.I64, ct.U64),
    ("ll", True): (ct.I64,),
    ("ll", False): (ct.I64, ct.U64),
    ("u", True): (ct.U32, ct.U64),
    ("ul", True): (ct.U32, ct.U64),
    ("ull", True): (ct.U64,),
}


def literal_type(v: int, suffix: str, decimal: bool) -> ct.IntT:
    """The type of integer constant `v`: the first candidate of its suffix that holds it
    (C99 6.4.4.1); a decimal beyond long long is unsigned long long, as gcc makes it."""
    cands = _LITERAL_TYPES.get((suffix, decimal)) or _LITERAL_TYPES[(suffix, True)]
    for t in cands:
        if v <= t.max:
            return t
    return ct.U64


def const_truth(node: ast.expr) -> bool | None:
    """The truth of a lowered condition that is a constant (`1`, `-1`, `True`), else None."""
    if type(node) is ast.UnaryOp and type(node.op) is ast.USub:
        node = node.operand
    if type(node) is ast.Constant and isinstance(node.value, (int, float)):
        return bool(node.value)
    return None


def exact(v: Val) -> ast.expr:
    """The value's Python expression reduced to the range of its type."""
    if v.exact or not isinstance(v.type, ct.IntT):
        return v.node
    if v.step is not None:
        return step_node(*v.step, v.type)
    return wrap_node(v.node, v.type)
