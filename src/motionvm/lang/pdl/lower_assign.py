"""Lower the PDL assignment forms (manual §2.1) to Python statements.

Forms 1, 4, 6, compound operators, `sttovar` and `sizeof` become one store; form 2
(initialiser lists) and 3 (strings, 4 characters per long, LSB first) write a block
through `_fill`; form 7 calls a built-in. Examples:

    ar[2] = {1, 3, 5};     ->  _fill(12, (1, 3, 5), 1)
    r = p / 4;             ->  M[3] = _rnd(M[4] / 4)
    v1 = bitset(v1, 1);    ->  M[5] = _bitset(M[5], 1)
    mina = memmin(l1, 3);  ->  _t = _memmin(2, 3, 1)
                               if _t is not None: M[6] = _t
    myar1[n+] = myar2[p+]; ->  M[...n...] = M[...p...]; then p += 1, then n += 1
"""

from __future__ import annotations

import ast

from motionvm.lang.pdl import nodes as n
from motionvm.lang.pdl.lower_base import assign, call, const, nm
from motionvm.lang.pdl.lower_expr import FLT, I16, INT, WIDE, ExprLowering
from motionvm.lang.pdl.rt_memory import FLOAT, SHORT
from motionvm.lang.pdl.symbols import VarSym

_COMPOUND = {"+=": "+", "-=": "-", "*=": "*", "/=": "/", "%=": "%", "&=": "&", "|=": "|", "@=": "@"}

# Built-ins of one value: (helper name, result kind, or None for "the argument's kind").
_SIMPLE_FUNCS = {
    "abs": ("abs", None),
    "sign": ("_sign", I16),
    "sin": ("_sin", FLT),
    "cos": ("_cos", FLT),
    "sqrt": ("_sqrt", FLT),
    "divi": ("_divi", WIDE),
    "shift": ("_shift", INT),
    "bitset": ("_bitset", INT),
    "bitclr": ("_bitclr", INT),
    "bittog": ("_bittog", INT),
}


def pack_string(text: str) -> tuple[int, ...]:
    """4 characters per signed 32-bit word, LSB first, the last word zero-padded."""
    data = text.encode("latin-1", "replace")
    words = []
    for k in range(0, max(len(data), 1), 4):
        w = int.from_bytes(data[k : k + 4].ljust(4, b"\0"), "little")
        words.append(w - (1 << 32) if w >= 1 << 31 else w)
    return tuple(words)


def lower_assign(x: ExprLowering, s: n.Assign) -> list[ast.stmt]:
    """The statements of one assignment, auto-increments of `[n+]` indexes last."""
    t, v = s.target, s.value
    if s.op != "=":
        value, kind = x.binop(_COMPOUND[s.op], x.read(t), x.read(v))  # type: ignore[arg-type]
        return x.store(t, value, kind) + x.auto_increments(v, t)
    if isinstance(v, n.InitList):
        addr, ekind = x.target_address(t)
        values = tuple(c.value for c in v.values)
        return [ast.Expr(call("_fill", addr, const(values), const(ekind)))] + x.auto_increments(t)
    if isinstance(v, n.StringConst):
        addr, ekind = x.target_address(t)
        return [
            ast.Expr(call("_fill", addr, const(pack_string(v.value)), const(ekind)))
        ] + x.auto_increments(t)
    if isinstance(v, n.FuncCall):
        return _func(x, t, v) + x.auto_increments(*v.args, t)
    value, kind = x.value(v)
    sources = (
        (v.left, v.right)
        if isinstance(v, n.BinOp)
        else ((v.operand,) if isinstance(v, n.Neg) else (v,))
    )
    return x.store(t, value, kind) + x.auto_increments(*sources, t)


def _func(x: ExprLowering, t: n.VarRef | n.Deref, f: n.FuncCall) -> list[ast.stmt]:
    name, args = f.func, f.args
    if name == "memcpy":
        dst, kind = x.target_address(t)
        src, _ = x.target_address(args[0])  # type: ignore[arg-type]
        return [ast.Expr(call("_memcpy", dst, src, x.read(args[1])[0], const(kind)))]
    if name == "memset":
        dst, kind = x.target_address(t)
        return [ast.Expr(call("_memset", dst, x.read(args[0])[0], x.read(args[1])[0], const(kind)))]
    if name in ("memmin", "memmax", "memsum"):
        src, kind = x.target_address(args[0])  # type: ignore[arg-type]
        got = call("_" + name, src, x.read(args[1])[0], const(kind))
        rkind = FLT if kind == FLOAT else (WIDE if name == "memsum" else INT)
        test = ast.Compare(nm("_t"), [ast.IsNot()], [const(None)])
        return [
            assign(nm("_t", True), got),
            ast.If(test, x.store(t, nm("_t"), rkind), []),
        ]
    values = [x.read(a) for a in args]
    if name in ("max", "min"):
        kinds = {k for _, k in values}
        kind = FLT if FLT in kinds else (I16 if kinds == {I16} else INT)
        return x.store(t, call(name, *(e for e, _ in values)), kind)
    if name == "unsign":
        e, k = values[0]
        sym = x.sym(args[0])
        bits = 16 if k == I16 and isinstance(sym, VarSym) and _is_short(sym) else 32
        return x.store(t, call("_unsign", e, const(bits)), INT if bits == 16 else WIDE)
    helper, kind = _SIMPLE_FUNCS[name]
    if kind is None:
        kind = FLT if values[0][1] == FLT else WIDE
    return x.store(t, call(helper, *(e for e, _ in values)), kind)


def _is_short(sym: VarSym) -> bool:
    return sym.type == "short" and not sym.pointer


__all__ = ["SHORT", "lower_assign", "pack_string"]
