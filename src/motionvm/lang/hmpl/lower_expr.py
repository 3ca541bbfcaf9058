"""Type-check HMPL expressions and lower them to Python `ast` expressions.

`ExprLowerer` owns conversions, operators, literals, names, `sizeof`, casts and
conditions, and what range analysis knows of the function's integer locals
(`known_ranges`); the values it builds are `lower_values.Val`s. Places (indexing,
members, `*p`), assignments and calls belong to its `access` part (lower_access.py).

    for (int i = 0; i < 10; i++) x = i / 4 + b;
gives `x` (i known in 0..9: C's division is Python's floor division; the sum may
leave int, so it is wrapped: lower_values.py)
    v_x = _w if -2147483648 <= (_w := v_i // 4 + v_b) <= 2147483647 else _wrapi(_w)
and `x << n` (an int n) becomes `v_x << _shc(v_n, 32)`, wrapped where it is used.
"""

from __future__ import annotations

import ast
from collections.abc import Callable
from typing import Protocol

from motionvm.lang.hmpl import ctypes_ as ct
from motionvm.lang.hmpl import nodes as n
from motionvm.lang.hmpl.cmemory import to_f32
from motionvm.lang.hmpl.lower_context import FunctionContext, SemanticError
from motionvm.lang.hmpl.lower_values import (
    Val,
    const_truth,
    exact,
    fold_int,
    literal_type,
    step_node,
    wrap_node,
)
from motionvm.lang.hmpl.lvalues import LValue, call, const, name
from motionvm.lang.hmpl.rthelpers import float_to_int
from motionvm.lang.hmpl.symbols import FuncSym, VarSym

__all__ = ["ExprLowerer", "SemanticError", "Val", "step_node", "wrap_node"]

_BINOPS = {
    "+": ast.Add,
    "-": ast.Sub,
    "*": ast.Mult,
    "<<": ast.LShift,
    ">>": ast.RShift,
    "&": ast.BitAnd,
    "|": ast.BitOr,
    "^": ast.BitXor,
}
_CMPOPS = {"<": ast.Lt, ">": ast.Gt, "<=": ast.LtE, ">=": ast.GtE, "==": ast.Eq, "!=": ast.NotEq}
_RING_OPS = frozenset("+-*&|^") | {"<<"}
# operator objects are immutable and may be shared: one of each, made once
_BINOP_NODES = {k: v() for k, v in _BINOPS.items()}
_CMP_NODES = {k: v() for k, v in _CMPOPS.items()}
_BITAND = _BINOP_NODES["&"]


class ExprLowerer:
    """Types and lowers the expressions of one function; places, assignments and calls
    are its `access` part's (lower_access.py), which it hands the nodes it meets."""

    def __init__(self, ctx: FunctionContext) -> None:
        self.ctx = ctx
        self.prog = ctx.prog
        self.sink = ctx.sink
        self.fail = ctx.fail
        self.access: Places | None = None
        self.known_ranges: dict[str, tuple[int, int]] = {}
        """Python local -> the bounds its integer value is known to lie in (range-for
        counters, guards): lets indexing drop its check and arithmetic its wrap."""
        self._handlers: dict[type, Callable[..., Val]] = {}

    def attach(self, access: Places) -> None:
        """Wire the part that lowers places, assignments and calls (`x_Index`, ...)."""
        self.access = access
        handlers = {t: getattr(self, m) for t, m in _OWN_HANDLERS}
        handlers.update((t, getattr(access, m)) for t, m in _PLACE_HANDLERS)
        self._handlers = handlers

    exact = staticmethod(exact)

    # ------------------------------------------------------------ conversions

    def convert(self, v: Val, to: ct.CType, pos=None, what: str = "") -> ast.expr:
        """Lower an implicit or explicit conversion of `v` to type `to` (exact result)."""
        src = v.type
        tt = type(to)  # the type classes have no subclasses: `is` tests them
        if tt is ct.IntT:
            c = v.const
            if c is not None and isinstance(c, (int, float)):
                if isinstance(c, float):  # as the run time converts: saturate, NaN -> 0
                    return const(float_to_int(c, to.bits, to.signed))
                return const(ct.wrap_int(int(c), to))
            if type(src) is ct.IntT:
                if v.exact and (src is to or src.min >= to.min and src.max <= to.max):
                    return v.node
                if v.step is not None and src == to:
                    return step_node(*v.step, to)
                if v.exact or src.size >= to.size:
                    return wrap_node(v.node, to)  # a modular reduction suffices
                exact = self.exact(v)  # sign- or zero-extend the narrower value first
                return exact if src.min >= to.min and src.max <= to.max else wrap_node(exact, to)
            if isinstance(src, ct.FloatT):
                if to.bits == 32 and to.signed:  # the helper's defaults
                    return call("_f2i", v.node)
                return call("_f2i", v.node, ast.Constant(to.bits), ast.Constant(to.signed))
            if isinstance(src, ct.PtrT):
                return wrap_node(v.node, to) if to.size < 8 else v.node
            raise self.fail(pos, f"cannot convert '{src}' to '{to}'{what}")
        if tt is ct.VoidT:
            return v.node
        if tt is ct.FloatT:
            if isinstance(src, (ct.IntT, ct.FloatT)):
                if v.const is not None:
                    f = float(v.const)
                    return ast.Constant(to_f32(f) if to == ct.FLOAT else f)
                node = self.exact(v) if isinstance(src, ct.IntT) else v.node
                if to == ct.FLOAT and src != ct.FLOAT:
                    return call("_f32", node)
                if isinstance(src, ct.IntT):
                    return call("float", node)
                return node
            raise self.fail(pos, f"cannot convert '{src}' to '{to}'{what}")
        if isinstance(to, ct.PtrT):
            if isinstance(src, ct.PtrT) or isinstance(src, ct.FuncT):
                return v.node
            if isinstance(src, ct.IntT):
                return self.exact(v)
            raise self.fail(pos, f"cannot convert '{src}' to '{to}'{what}")
        if isinstance(to, ct.StructT):
            if src == to:
                return v.node
            raise self.fail(pos, f"cannot convert '{src}' to '{to}'{what}")
        raise self.fail(pos, f"cannot convert '{src}' to '{to}'{what}")

    def assign_convert(self, v: Val, to: ct.CType, pos, what: str) -> ast.expr:
        """Conversion as by assignment: checks pointer/integer compatibility like C."""
        src = v.type
        if isinstance(to, ct.PtrT):
            if isinstance(src, ct.PtrT):
                if not ct.same_pointee_family(src.target, to.target):
                    raise self.fail(
                        pos, f"incompatible pointer type: '{src}' given, '{to}' expected{what}"
                    )
            elif isinstance(src, ct.IntT):
                if v.const != 0:
                    raise self.fail(pos, f"'{src}' given where a pointer '{to}' is expected{what}")
            elif isinstance(src, ct.FuncT):
                pass
            else:
                raise self.fail(pos, f"'{src}' given where a pointer '{to}' is expected{what}")
        elif isinstance(to, (ct.IntT, ct.FloatT)):
            if isinstance(src, ct.PtrT):
                raise self.fail(pos, f"pointer '{src}' given where '{to}' is expected{what}")
            if isinstance(src, (ct.StructT, ct.VoidT, ct.FuncT)):
                raise self.fail(pos, f"'{src}' given where '{to}' is expected{what}")
        elif isinstance(to, ct.StructT):
            if src != to:
                raise self.fail(pos, f"'{src}' given where '{to}' is expected{what}")
        return self.convert(v, to, pos, what)

    # ------------------------------------------------------------ rvalues

    def expr(self, e) -> Val:
        """Lower an expression used for its value (arrays decay to pointers)."""
        fn = self._handlers.get(type(e))
        v = fn(e) if fn is not None else self.value(e)
        if type(v.type) is ct.ArrayT:
            return Val(v.node, ct.pointer_to(v.type.elem))
        return v

    def value(self, e) -> Val:
        """Lower an expression as it is: an array stays an array (an operand of `[]`,
        `.`, `sizeof`)."""
        fn = self._handlers.get(type(e))
        if fn is None:
            raise self.fail(e.pos, f"unsupported expression '{type(e).__name__}'")
        return fn(e)

    def cond(self, e) -> ast.expr:
        """Lower an expression used as a condition (any truthy Python value)."""
        if isinstance(e, n.Binary) and e.op in ("&&", "||"):
            left, right = self.cond(e.left), self.cond(e.right)
            lt, rt = const_truth(left), const_truth(right)
            if lt is not None and rt is not None:  # an integer constant expression
                return ast.Constant((lt and rt) if e.op == "&&" else (lt or rt))
            op = ast.And() if e.op == "&&" else ast.Or()
            return ast.BoolOp(op, [left, right])
        if isinstance(e, n.Unary) and e.op == "!":
            operand = self.cond(e.operand)
            ot = const_truth(operand)
            if ot is not None:
                return ast.Constant(not ot)
            return ast.UnaryOp(ast.Not(), operand)
        v = self.expr(e)
        if isinstance(v.type, (ct.StructT, ct.VoidT)):
            raise self.fail(e.pos, f"'{v.type}' used where a condition is required")
        return self.exact(v)

    def x_IntLit(self, e: n.IntLit) -> Val:
        v = e.value
        if 0 <= v <= 2147483647 and not e.suffix:  # an int: the first candidate of every base
            return Val(ast.Constant(v), ct.INT, True, v, (v, v))
        t = literal_type(v, e.suffix, e.decimal)
        v = fold_int(v, t)
        return Val(const(v), t, True, v, (v, v))

    def x_FloatLit(self, e: n.FloatLit) -> Val:
        if e.is_float:
            f = to_f32(e.value)
            return Val(ast.Constant(f), ct.FLOAT, True, f)
        return Val(ast.Constant(e.value), ct.DOUBLE, True, e.value)

    def x_CharLit(self, e: n.CharLit) -> Val:
        return Val(const(e.value), ct.INT, True, e.value, (e.value, e.value))

    def x_StrLit(self, e: n.StrLit) -> Val:
        addr = self.prog.string_literal(e.value, e.pos)
        return Val(ast.Constant(addr), ct.array_of(ct.CHAR, len(e.value) + 1))

    def x_Name(self, e: n.Name) -> Val:
        sym = self.ctx.scope.lookup(e.id)
        if sym is not None and sym.__class__ is VarSym and sym.storage == "local":
            if sym.type is not ct.ERROR and sym.const_value is None:  # the common case
                pyname = sym.pyname
                return Val(name(pyname), sym.type, True, None, self.known_ranges.get(pyname))
        sym = self.access.resolve(e.id, e.pos)
        if isinstance(sym, FuncSym):
            return Val(name(sym.pyname), sym.type)
        if sym.const_value is not None:
            v = sym.const_value
            return Val(const(v), sym.type, True, v)
        if sym.storage == "pylist":
            return Val(name(sym.pyname), sym.type, True, None, None, sym.pyname, ast.Constant(0))
        lv = self.access.var_lvalue(sym)
        rng = self.known_ranges.get(sym.pyname) if sym.storage == "local" else None
        return Val(lv.load(), sym.type, True, None, rng)

    def x_SizeOf(self, e: n.SizeOf) -> Val:
        if isinstance(e.target, n.TypeRef):
            t = self.resolve_type(e.target)
            for d in reversed(e.dims):
                t = ct.array_of(t, self.const_int(d))
        else:
            t = self._type_only(e.target)
        if isinstance(t, ct.VoidT) or t.size == 0 and not isinstance(t, ct.ArrayT):
            raise self.fail(e.pos, f"sizeof applied to incomplete type '{t}'")
        return Val(ast.Constant(t.size), ct.U32, True, t.size)

    def _type_only(self, e) -> ct.CType:
        """The type of an expression without generating code (sizeof operand)."""
        saved = self.sink.items[:]
        try:
            return self.value(e).type
        finally:
            self.sink.items[:] = saved

    def x_Cast(self, e: n.Cast) -> Val:
        to = self.resolve_type(e.type)
        v = self.expr(e.expr)
        if isinstance(to, ct.VoidT):
            return Val(v.node, ct.VOID)
        if isinstance(to, ct.StructT) or isinstance(v.type, ct.StructT):
            raise self.fail(e.pos, f"cannot cast '{v.type}' to '{to}'")
        node = self.convert(v, to, e.pos)
        c = None
        if v.const is not None and isinstance(to, (ct.IntT, ct.FloatT)):
            c = node.value if isinstance(node, ast.Constant) else None
            if isinstance(node, ast.UnaryOp) and isinstance(node.operand, ast.Constant):
                c = -node.operand.value
        return Val(node, to, True, c)

    def x_Comma(self, e: n.Comma) -> Val:
        parts = [self.expr(x) for x in e.items]
        last = parts[-1]
        tup = ast.Tuple(elts=[p.node for p in parts[:-1]] + [self.exact(last)], ctx=ast.Load())
        return Val(ast.Subscript(value=tup, slice=const(-1), ctx=ast.Load()), last.type)

    def x_Cond(self, e: n.Cond) -> Val:
        c = self.cond(e.cond)
        a, b = self.expr(e.then), self.expr(e.else_)
        if a.type.is_arith and b.type.is_arith:
            t = ct.common_arith(a.type, b.type)
            an, bn = self.convert(a, t, e.pos), self.convert(b, t, e.pos)
            ctruth = const_truth(c)
            chosen = a if ctruth else b
            if ctruth is not None and t.is_integer and isinstance(chosen.const, int):
                k = ct.wrap_int(chosen.const, t)  # an integer constant expression
                return Val(const(k), t, True, k, (k, k))
        elif a.type.is_pointer or b.type.is_pointer:
            t = a.type if a.type.is_pointer else b.type
            an, bn = self.exact(a), self.exact(b)
        else:
            if a.type != b.type:
                raise self.fail(e.pos, f"mismatched types '{a.type}' and '{b.type}' in '?:'")
            t, an, bn = a.type, a.node, b.node
        return Val(ast.IfExp(test=c, body=an, orelse=bn), t)

    # ------------------------------------------------------------ operators

    def x_Unary(self, e: n.Unary) -> Val:
        op = e.op
        if op in ("++", "--"):
            return self.access.incdec(e.operand, op, prefix=True, pos=e.pos)
        if op == "&":
            return self.access.address_of(e.operand, e.pos)
        if op == "*":
            lv = self.access.lvalue(e)
            return Val(lv.load(), lv.type)
        if op == "!":
            test = self.cond(e)
            if (truth := const_truth(test)) is not None:
                k = int(truth)
                return Val(const(k), ct.INT, True, k, (k, k))
            return Val(test, ct.INT)
        v = self.expr(e.operand)
        if not v.type.is_arith:
            raise self.fail(e.pos, f"invalid operand of type '{v.type}' to unary '{op}'")
        if op == "~":
            if not v.type.is_integer:
                raise self.fail(e.pos, f"invalid operand of type '{v.type}' to unary '~'")
            t = ct.promote(v.type)
            node = self.convert(v, t, e.pos)
            c = ct.wrap_int(~v.const, t) if isinstance(v.const, int) else None
            return Val(ast.UnaryOp(op=ast.Invert(), operand=node), t, t.signed, c)
        t = ct.promote(v.type)
        node = self.convert(v, t, e.pos)
        if op == "+":
            return Val(node, t, True, v.const)
        if v.const is not None:
            if t.is_integer:
                c = fold_int(-v.const, t)
                return Val(const(c), t, True, c, (c, c))
            return Val(const(-v.const), t, True, -v.const)
        return Val(ast.UnaryOp(op=ast.USub(), operand=node), t, not t.is_integer)

    def x_Postfix(self, e: n.Postfix) -> Val:
        return self.access.incdec(e.operand, e.op, prefix=False, pos=e.pos)

    def x_Binary(self, e: n.Binary) -> Val:
        op = e.op
        if op in ("&&", "||"):
            test = self.cond(e)
            if (truth := const_truth(test)) is not None:
                k = int(truth)
                return Val(const(k), ct.INT, True, k, (k, k))
            return Val(ast.IfExp(test=test, body=ast.Constant(1), orelse=ast.Constant(0)), ct.INT)
        a, b = self.expr(e.left), self.expr(e.right)
        return self.binary(op, a, b, e.pos)

    def binary(self, op: str, a: Val, b: Val, pos) -> Val:
        ta, tb = a.type, b.type
        if op in _CMPOPS:
            return self._compare(op, a, b, pos)
        if op in ("+", "-") and (ta.is_pointer or tb.is_pointer):
            return self._pointer_arith(op, a, b, pos)
        if not (ta.is_arith and tb.is_arith):
            raise self.fail(pos, f"invalid operands to binary '{op}' ('{ta}' and '{tb}')")
        if op in ("<<", ">>"):
            if not (ta.is_integer and tb.is_integer):
                raise self.fail(pos, f"invalid operands to binary '{op}' ('{ta}' and '{tb}')")
            return self._shift(op, a, b, ct.promote(ta))
        if op == "%" and not (ta.is_integer and tb.is_integer):
            raise self.fail(pos, f"invalid operands to binary '%' ('{ta}' and '{tb}')")
        if op in ("&", "|", "^") and not (ta.is_integer and tb.is_integer):
            raise self.fail(pos, f"invalid operands to binary '{op}' ('{ta}' and '{tb}')")
        t = ct.common_arith(ta, tb)
        if t.is_float:
            return self._float_op(op, a, b, t, pos)
        return self._int_op(op, a, b, t, pos)

    def _shift(self, op: str, a: Val, b: Val, t: ct.IntT) -> Val:
        """`a << b` or `a >> b` in t. A count of t's width or more is taken modulo the width,
        as the controller's shifter does; a negative count (undefined in C) is a run-time
        fault, also when both operands are constants, so folding never changes the outcome.

        before: `x << n` (int n)    after: `x << _shc(n, 32)` (the caller wraps the result)
        before: `x >> 33`           after: `x >> 1`
        """
        an = self.convert(a, t) if op == ">>" or a.type != t else a.node
        if isinstance(b.const, int) and b.const >= 0:
            count = b.const % t.bits
            if isinstance(a.const, int):
                x = ct.wrap_int(a.const, t)
                c = ct.wrap_int(x << count if op == "<<" else x >> count, t)
                return Val(const(c), t, True, c)
            bn = const(count)
        elif isinstance(b.type, ct.IntT) and not b.type.signed and b.const is None:
            bn = ast.BinOp(left=self.exact(b), op=ast.BitAnd(), right=ast.Constant(t.bits - 1))
        else:
            bn = call("_shc", self.exact(b), ast.Constant(t.bits))
        if op == ">>":
            return Val(ast.BinOp(left=an, op=ast.RShift(), right=bn), t, True)
        return Val(ast.BinOp(left=an, op=ast.LShift(), right=bn), t, False)

    def _ring_operand(self, v: Val, t: ct.IntT) -> tuple[ast.expr, bool]:
        """(node, exact in t) of an operand of a ring operation computed in type t."""
        if isinstance(v.const, int):
            return const(ct.wrap_int(v.const, t)), True
        assert isinstance(v.type, ct.IntT)
        if v.type.size == t.size:
            return v.node, v.exact and v.type.signed == t.signed
        # a narrower value fits in t, unless it is signed and t unsigned: a negative one
        # converts to t modulo 2**bits, so the result still needs reducing to t
        return self.exact(v), t.signed or not v.type.signed

    def _int_op(self, op: str, a: Val, b: Val, t: ct.IntT, pos) -> Val:
        if op in _RING_OPS:
            if isinstance(a.const, int) and isinstance(b.const, int):
                pyop = {
                    "+": int.__add__,
                    "-": int.__sub__,
                    "*": int.__mul__,
                    "&": int.__and__,
                    "|": int.__or__,
                    "^": int.__xor__,
                }[op]
                c = ct.wrap_int(pyop(ct.wrap_int(a.const, t), ct.wrap_int(b.const, t)), t)
                return Val(const(c), t, True, c, (c, c))
            an, a_ok = self._ring_operand(a, t)
            bn, b_ok = self._ring_operand(b, t)
            exact = op in ("&", "|", "^") and a_ok and b_ok
            rng = None
            if op in ("+", "-") and a.rng is not None and b.rng is not None and a_ok and b_ok:
                lo, hi = (
                    (a.rng[0] + b.rng[0], a.rng[1] + b.rng[1])
                    if op == "+"
                    else (a.rng[0] - b.rng[1], a.rng[1] - b.rng[0])
                )
                if t.min <= lo and hi <= t.max:
                    rng, exact = (lo, hi), True  # cannot overflow: no wrap needed
            step = None
            if op in ("+", "-") and not exact and t.signed and a_ok and b_ok:
                if isinstance(b.const, int) and type(an) is ast.Name:
                    k = ct.wrap_int(b.const, t)
                    if k != t.min:
                        step = (an.id, k if op == "+" else -k)
                elif op == "+" and isinstance(a.const, int) and type(bn) is ast.Name:
                    k = ct.wrap_int(a.const, t)
                    if k != t.min:
                        step = (bn.id, k)
                if step is not None and step[1] == 0:  # `x + 0`: x itself
                    return Val(
                        name(step[0]), t, True, None, a.rng if b.const is not None else b.rng
                    )
            node = ast.BinOp(an, _BINOP_NODES[op], bn)
            return Val(node, t, exact, None, rng, step=step)
        an, bn = self.convert(a, t, pos), self.convert(b, t, pos)
        if isinstance(b.const, int) and ct.wrap_int(b.const, t) == 0:
            raise self.fail(pos, "division by zero" if op == "/" else "modulo by zero")
        if isinstance(a.const, int) and isinstance(b.const, int):
            x, y = ct.wrap_int(a.const, t), ct.wrap_int(b.const, t)
            q = abs(x) // abs(y) * (1 if (x >= 0) == (y >= 0) else -1)
            c = ct.wrap_int(q if op == "/" else x - q * y, t)
            return Val(const(c), t, True, c)
        if isinstance(b.const, int) and (k := ct.wrap_int(b.const, t)) > 0:
            # a dividend known not negative: C's truncating division is Python's floor
            if a.exact and a.rng is not None and 0 <= a.rng[0] and a.rng[1] <= t.max:
                lo, hi = a.rng
            elif not t.signed:
                lo, hi = 0, t.max
            else:
                lo = None
            if lo is not None:
                if op == "/":
                    node, rng = ast.BinOp(an, ast.FloorDiv(), bn), (lo // k, hi // k)
                else:
                    node, rng = ast.BinOp(an, ast.Mod(), bn), (0, min(k - 1, hi))
                return Val(node, t, True, None, rng)
        fn = "_idiv" if op == "/" else "_imod"
        # only INT_MIN / -1 leaves the type: a quotient by any other constant is in range
        exact = op == "%" or isinstance(b.const, int) and ct.wrap_int(b.const, t) != -1
        return Val(call(fn, an, bn), t, exact)

    def _float_op(self, op: str, a: Val, b: Val, t: ct.FloatT, pos) -> Val:
        an, bn = self.convert(a, t, pos), self.convert(b, t, pos)
        if t == ct.DOUBLE and op != "/":
            # Python converts an int operand of a float operation as `float()` does:
            # `float(v_i) * 0.5` is `v_i * 0.5`
            if a.type.is_integer and a.const is None and b.type.is_float:
                an = self.exact(a)
            elif b.type.is_integer and b.const is None and a.type.is_float:
                bn = self.exact(b)
        if a.const is not None and b.const is not None and op != "/":
            pyop = {"+": float.__add__, "-": float.__sub__, "*": float.__mul__}[op]
            c = pyop(float(a.const), float(b.const))
            c = to_f32(c) if t == ct.FLOAT else c
            return Val(ast.Constant(c), t, True, c)
        if op == "/":
            if b.const is not None and b.const != 0:
                node = ast.BinOp(left=an, op=ast.Div(), right=bn)
            else:
                node = call("_fdiv", an, bn)
        else:
            node = ast.BinOp(an, _BINOP_NODES[op], bn)
        if t is ct.FLOAT:
            node = call("_f32", node)
        return Val(node, t)

    def _compare(self, op: str, a: Val, b: Val, pos) -> Val:
        ta, tb = a.type, b.type
        if ta.is_arith and tb.is_arith:
            t = ct.common_arith(ta, tb)
            if t.is_integer and isinstance(a.const, int) and isinstance(b.const, int):
                x, y = ct.wrap_int(a.const, t), ct.wrap_int(b.const, t)
                k = int(_CMP_FOLD[op](x, y))  # an integer constant expression
                return Val(const(k), ct.INT, True, k, (k, k))
            an, bn = self.convert(a, t, pos), self.convert(b, t, pos)
        elif ta.is_pointer or tb.is_pointer or isinstance(ta, ct.FuncT) or isinstance(tb, ct.FuncT):
            if (ta.is_integer and a.const != 0) or (tb.is_integer and b.const != 0):
                raise self.fail(pos, f"comparison between pointer and integer ('{ta}' and '{tb}')")
            an, bn = self.exact(a), self.exact(b)
        else:
            raise self.fail(pos, f"invalid operands to binary '{op}' ('{ta}' and '{tb}')")
        node = ast.Compare(an, [_CMP_NODES[op]], [bn])
        return Val(node, ct.INT)

    def _pointer_arith(self, op: str, a: Val, b: Val, pos) -> Val:
        ta, tb = a.type, b.type
        if op == "-" and ta.is_pointer and tb.is_pointer:
            size = max(1, ta.target.size)
            diff = ast.BinOp(left=a.node, op=ast.Sub(), right=b.node)
            return Val(ast.BinOp(left=diff, op=ast.FloorDiv(), right=ast.Constant(size)), ct.I64)
        if ta.is_pointer and tb.is_integer:
            p, i = a, b
        elif op == "+" and tb.is_pointer and ta.is_integer:
            p, i = b, a
        else:
            raise self.fail(pos, f"invalid operands to binary '{op}' ('{ta}' and '{tb}')")
        size = p.type.target.size if not isinstance(p.type.target, ct.VoidT) else 1
        if size == 0:
            raise self.fail(pos, f"arithmetic on a pointer to incomplete type '{p.type}'")
        if isinstance(i.const, int):
            off = const(i.const * size)
        else:
            off = self.exact(i)
            if size != 1:
                off = ast.BinOp(left=off, op=ast.Mult(), right=ast.Constant(size))
        pyop = ast.Add() if op == "+" else ast.Sub()
        return Val(ast.BinOp(left=p.node, op=pyop, right=off), p.type)

    # ------------------------------------------------------------ constants and types

    def const_int(self, e) -> int:
        """The value of an integer constant expression; an error if `e` is none."""
        v = self.expr(e)
        if not isinstance(v.const, int):
            raise self.fail(e.pos, "expression is not an integer constant")
        return v.const

    def resolve_type(self, tr: n.TypeRef) -> ct.CType:
        return self.prog.resolve_typeref(tr, self.ctx.scope, self.ctx.task)


_CMP_FOLD = {
    "<": int.__lt__,
    ">": int.__gt__,
    "<=": int.__le__,
    ">=": int.__ge__,
    "==": int.__eq__,
    "!=": int.__ne__,
}


class Places(Protocol):
    """What the expression lowerer asks of the places part (`lower_access.AccessLowerer`)."""

    def resolve(self, ident: str, pos) -> VarSym | FuncSym:
        """The symbol `ident` names here; an error if none."""

    def var_lvalue(self, sym: VarSym) -> LValue:
        """The place of a variable."""

    def lvalue(self, e) -> LValue:
        """The place an expression designates; an error if it designates none."""

    def address_of(self, operand, pos) -> Val:
        """`&operand`."""

    def incdec(self, operand, op: str, prefix: bool, pos, as_stmt: bool = False):
        """`++`/`--` of `operand`."""


_OWN_HANDLERS = [(getattr(n, m[2:]), m) for m in vars(ExprLowerer) if m.startswith("x_")]
"""(node class, method) of the expressions the expression lowerer lowers itself."""
_PLACE_HANDLERS = [
    (getattr(n, m), "x_" + m) for m in ("Index", "Member", "Call", "Assign", "CompoundLit")
]
"""(node class, method of the places part) of the expressions that designate places."""
