"""Lower PDL operands, values, conditions and stores to Python `ast` expressions.

Every variable lives in drive memory (rt_memory): a global long `pos1` at word 7 reads
`M[7]`, a float `f1` `F[9]`, a short `N` (half-word 41) `H[41]`, a procedure local in
slot 2 `M[bp + 2]`; system variables are slots of the list `S`, states bytes of `ST`.
An index that is a variable is bounds-checked against user memory (the manual allows
running past a variable into the next one, not out of memory):

    My_array[N] = Benny;
becomes
    H[_i if 2 <= (_i := 10 + H[211]) < 32002 else _oob('My_array', H[211])] = H[6]

Stores of integer results that may leave 32 bits are wrapped only when they do:

    pos1 = pos1 + pos2;
becomes
    try:
        M[7] = M[7] + M[8]
    except ValueError:
        M[7] = _w32(M[7] + M[8])

A float stored into an integer rounds (`_rnd`, halves away from zero); `/` always
divides as real numbers.
"""

from __future__ import annotations

import ast
from typing import TYPE_CHECKING

from motionvm.lang.pdl import nodes as n
from motionvm.lang.pdl.lower_base import (
    ProgramContext,
    assign,
    binop,
    call,
    clone,
    const,
    nm,
    storage_kind,
    subscript,
)
from motionvm.lang.pdl.rt_memory import FLOAT, LONG, SHORT, SHORT_TAG, USER_BASE
from motionvm.lang.pdl.symbols import USER_MEMORY_WORDS, LabelSym, VarSym

if TYPE_CHECKING:
    from motionvm.lang.pdl.lower_cache import Promotion

# Value kinds: INT fits 32 bits, I16 fits 16 bits, WIDE may need wrapping, FLT is float.
INT, I16, WIDE, FLT = "int", "i16", "wide", "float"
USER_END = USER_BASE + USER_MEMORY_WORDS


def _cmp(left: ast.expr, op: ast.cmpop, right: ast.expr) -> ast.Compare:
    return ast.Compare(left, [op], [right])


_BINOPS = {"+": ast.Add, "-": ast.Sub, "*": ast.Mult, "/": ast.Div, "&": ast.BitAnd,
           "|": ast.BitOr, "@": ast.BitXor}  # fmt: skip
_RELOPS = {"=": ast.Eq, "<>": ast.NotEq, "<": ast.Lt, ">": ast.Gt, "<=": ast.LtE, ">=": ast.GtE}


def _store_local(local: str, bits: int, value: ast.expr, kind: str) -> list[ast.stmt]:
    """`local = value`, rounded or wrapped to the variable's width like a memory store.

    bits 0 is a float, rounded to float32 through the one-float scratch view `_FS`.
    """
    if bits == 0:
        return [
            assign(subscript("FS", const(0), True), value),
            assign(nm(local, True), subscript("FS", const(0))),
        ]
    if kind == FLT:
        return [assign(nm(local, True), call("_rnd", value, const(bits)))]
    out = [assign(nm(local, True), value)]
    if kind == I16 or (kind == INT and bits == 32):
        return out
    lo, hi = (-0x8000, 0x7FFF) if bits == 16 else (-0x8000_0000, 0x7FFF_FFFF)
    fix = assign(nm(local, True), wrap_inline(nm(local), bits))
    step = _constant_step(value)
    if step is not None and step > 0:  # x + 1 can only overflow upwards
        test: ast.expr = ast.Compare(nm(local), [ast.Gt()], [const(hi)])
    elif step is not None:
        test = ast.Compare(nm(local), [ast.Lt()], [const(lo)])
    else:
        inside = ast.Compare(const(lo), [ast.LtE(), ast.LtE()], [nm(local), const(hi)])
        test = ast.UnaryOp(ast.Not(), inside)
    return out + [ast.If(test, [fix], [])]


def wrap_inline(v: ast.expr, bits: int) -> ast.expr:
    """`((v + 2**(bits-1)) & (2**bits - 1)) - 2**(bits-1)`: w32/w16 without a call."""
    half = 1 << (bits - 1)
    masked = binop(ast.BinOp(v, ast.Add(), const(half)), ast.BitAnd(),
                   const((1 << bits) - 1))  # fmt: skip
    return ast.BinOp(masked, ast.Sub(), const(half))


def _constant_step(value: ast.expr) -> int | None:
    """c for `x + c`, -c for `x - c` (x an integer variable, c a small constant), else None."""
    if not (isinstance(value, ast.BinOp) and isinstance(value.right, ast.Constant)):
        return None
    c = value.right.value
    if type(c) is not int or not 0 < abs(c) < 0x8000_0000 or isinstance(value.left, ast.Constant):
        return None
    if isinstance(value.op, ast.Add):
        return c
    if isinstance(value.op, ast.Sub):
        return -c
    return None


def _in_span(
    addr: ast.expr, lo: ast.expr, hi: ast.expr, idx: ast.expr, tmp: str
) -> tuple[ast.expr, ast.expr]:
    """(test, address): `lo - base <= n < hi - base` and `base + n` for a constant base and
    an index in a local n, else `lo <= (tmp := addr) < hi` and `tmp`."""
    if (
        isinstance(addr, ast.BinOp)
        and isinstance(addr.left, ast.Constant)
        and isinstance(idx, ast.Name)
        and isinstance(lo, ast.Constant)
        and isinstance(hi, ast.Constant)
    ):
        base = addr.left.value
        test = ast.Compare(const(lo.value - base), [ast.LtE(), ast.Lt()], [nm(idx.id), const(hi.value - base)])  # fmt: skip
        return test, addr
    walrus = ast.NamedExpr(nm(tmp, True), addr)
    return ast.Compare(lo, [ast.LtE(), ast.Lt()], [walrus, hi]), nm(tmp)


class ExprLowering:
    """Operands and stores of one body (the top level, or one procedure)."""

    def __init__(self, prog: ProgramContext, frame: dict[int, int] | None) -> None:
        self.prog = prog
        self.syms = prog.syms
        self.frame = frame
        """Frame slot of each local/parameter VarSym (keyed by id), None at top level."""
        self.promo: Promotion | None = None
        """Scalars held in Python locals while lowering a promoted loop (lower_cache)."""

    def promoted(self, v: n.VarRef | n.Deref) -> tuple[str, int] | None:
        """(local name, bits) if `v` is a scalar the current loop keeps in a local."""
        if self.promo is None or not isinstance(v, n.VarRef) or v.index is not None:
            return None
        sym = self.sym(v)
        if not isinstance(sym, VarSym) or sym.scope != "global" or sym.type == "state":
            return None
        kind = storage_kind(sym)
        view = "H" if kind == SHORT else ("F" if kind == FLOAT else "M")
        local = self.promo.local_of(view, self.prog.global_index(sym))
        return (local, {SHORT: 16, FLOAT: 0}.get(kind, 32)) if local else None

    # ------------------------------------------------------------ names

    def sym(self, node: object) -> object:
        return self.syms.symbol_of(node)

    def index_value(self, idx: n.IntConst | n.VarRef | None) -> ast.expr | None:
        if idx is None:
            return None
        if isinstance(idx, n.IntConst):
            return const(idx.value)
        return self.read(idx)[0]

    def element(self, v: n.VarRef | n.Deref, store: bool = False) -> tuple[str, ast.expr, int]:
        """(view, index expression, storage kind) of a plain or indexed variable.

        A read indexed by a variable inside a promoted loop tests the span that holds
        no written promoted scalar, and stores them before a read outside it
        (lower_cache); a store is split by `store` itself (`store=True`: unguarded).
        """
        sym = self.sym(v)
        assert isinstance(sym, VarSym), v
        kind = storage_kind(sym)
        ix = self._indexed(v, sym)
        if ix is not None:
            view, addr, lo, hi, base, idx = ix
            full = self._checked(addr, lo, hi, v.name, idx)
            span = None if store else self._span(view, base, lo, hi, True)
            if span is None:
                return view, full, kind
            flush = self.promo.flush_exprs()  # type: ignore[union-attr]
            slow = ast.Subscript(ast.Tuple(flush + [full], ast.Load()), const(-1), ast.Load())  # fmt: skip
            fast = self._checked(clone(addr), span[0], span[1], v.name, idx, slow)
            return view, fast, kind
        idx = self.index_value(v.index)
        if sym.scope == "system":
            base = self.prog.sys_base[sym.name]
            if idx is None or (isinstance(idx, ast.Constant) and 0 <= idx.value < sym.size):
                return "S", const(base + (idx.value if idx is not None else 0)), kind
            return (
                "S",
                binop(
                    const(base),
                    ast.Add(),
                    self._checked(idx, const(0), const(sym.size), v.name, idx),
                ),
                kind,
            )
        if sym.scope == "global":
            view = {LONG: "M", SHORT: "H", FLOAT: "F"}[kind]
            base_i = self.prog.global_index(sym)
            hi = USER_END * 2 if kind == SHORT else USER_END
            if idx is None:
                return view, const(base_i), kind
            assert isinstance(idx, ast.Constant)
            if base_i + idx.value < hi:
                return view, const(base_i + idx.value), kind
            return view, call("_oob", const(v.name), idx), kind
        assert self.frame is not None
        view = "F" if kind == FLOAT else "M"
        slot = binop(nm("bp"), ast.Add(), const(self.frame[id(sym)]))
        if idx is None:
            return view, slot, kind
        return view, binop(slot, ast.Add(), idx), kind

    def _indexed(
        self, v: n.VarRef | n.Deref, sym: VarSym
    ) -> tuple[str, ast.expr, ast.expr, ast.expr, int | None, ast.expr] | None:
        """(view, address, lo, hi, first element or None for a frame variable, index) of
        a global or frame element indexed by a variable, checked against [lo, hi)."""
        if sym.scope == "system" or v.index is None or isinstance(v.index, n.IntConst):
            return None
        kind = storage_kind(sym)
        idx = self.index_value(v.index)
        assert idx is not None
        if sym.scope == "global":
            view = {LONG: "M", SHORT: "H", FLOAT: "F"}[kind]
            base_i = self.prog.global_index(sym)
            lo, hi = (USER_BASE * 2, USER_END * 2) if kind == SHORT else (USER_BASE, USER_END)
            addr = binop(const(base_i), ast.Add(), idx)
            return view, addr, const(lo), const(hi), base_i, idx
        assert self.frame is not None
        view = "F" if kind == FLOAT else "M"
        slot = binop(nm("bp"), ast.Add(), const(self.frame[id(sym)]))
        return view, binop(slot, ast.Add(), idx), const(1), nm("_MEND"), None, idx

    def _span(
        self, view: str, base: int | None, lo: ast.expr, hi: ast.expr, reads: bool
    ) -> tuple[ast.expr, ast.expr] | None:
        """The bounds an access of the promoted loop may take without the slow path (no
        promoted scalar between them), or None if they are [lo, hi) (lower_cache)."""
        if self.promo is None:
            return None
        assert isinstance(lo, ast.Constant)
        hi_v = hi.value if isinstance(hi, ast.Constant) else 0
        span = self.promo.free_span(view, base, lo.value, hi_v, reads)
        if span is None:
            return None
        return const(span[0]), (const(span[1]) if isinstance(hi, ast.Constant) else hi)

    @staticmethod
    def _checked(
        addr: ast.expr,
        lo: ast.expr,
        hi: ast.expr,
        name: str,
        idx: ast.expr,
        orelse: ast.expr | None = None,
    ) -> ast.expr:
        """`_i if lo <= (_i := addr) < hi else _oob(name, idx)` (or else `orelse`).

        With a constant base and an index held in a Python local (a promoted scalar),
        the cheaper `base + n if lo - base <= n < hi - base else _oob(name, n)`.
        """
        test, fast = _in_span(addr, lo, hi, idx, "_i")
        if orelse is None:
            orelse = call("_oob", const(name), clone(idx))
        return ast.IfExp(test, fast, orelse)

    # ------------------------------------------------------------ reads

    def read(self, op: n.Operand) -> tuple[ast.expr, str]:
        """(expression, value kind) of an operand in a value context."""
        if isinstance(op, n.IntConst):
            return const(op.value), (I16 if -0x8000 <= op.value <= 0x7FFF else INT)
        if isinstance(op, n.FloatConst):
            return const(float(op.value)), FLT
        if isinstance(op, n.VarRef):
            sym = self.sym(op)
            assert isinstance(sym, VarSym), op
            if sym.type == "state":
                return subscript("ST", const(self.prog.state_bit(sym))), I16
            local = self.promoted(op)
            if local is not None:
                return nm(local[0]), {16: I16, 0: FLT}.get(local[1], INT)
            view, ix, kind = self.element(op)
            vk = FLT if kind == FLOAT else (I16 if kind == SHORT else INT)
            if view == "S" and sym.type == "short":
                vk = I16
            return subscript(view, ix), vk
        if isinstance(op, n.Deref):
            return self.deref_read(op)
        if isinstance(op, n.AddressOf):
            return self.address(op.target), INT
        if isinstance(op, n.AngleRef):
            return self.angle_value(op), INT
        raise AssertionError(f"operand {op!r}")

    def deref_pointer(self, d: n.Deref) -> ast.expr:
        """The address `*p[i]` refers to: the pointer's value plus the index."""
        sym = self.sym(d)
        assert isinstance(sym, VarSym)
        view, ix, _ = self._ptr_elem(d, sym)
        ptr: ast.expr = subscript(view, ix)
        idx = self.index_value(d.index)
        return binop(ptr, ast.Add(), idx) if idx is not None else ptr

    def _ptr_elem(self, d: n.Deref, sym: VarSym) -> tuple[str, ast.expr, int]:
        if sym.scope == "global":
            return "M", const(self.prog.global_index(sym)), LONG
        assert self.frame is not None
        return "M", binop(nm("bp"), ast.Add(), const(self.frame[id(sym)])), LONG

    def deref_read(self, d: n.Deref) -> tuple[ast.expr, str]:
        sym = self.sym(d)
        assert isinstance(sym, VarSym)
        if sym.type == "float":
            return call("_ldf", self.deref_pointer(d)), FLT
        return call("_ldl", self.deref_pointer(d)), INT

    def address(self, v: n.VarRef) -> ast.expr:
        """`&v` / `&v[i]`: an element address (word index, or SHORT_TAG + half index)."""
        sym = self.sym(v)
        assert isinstance(sym, VarSym)
        idx = self.index_value(v.index)
        if sym.scope == "global":
            base: ast.expr = const(
                self.prog.global_index(sym) + (SHORT_TAG if storage_kind(sym) == SHORT else 0)
            )
        else:
            assert self.frame is not None and sym.scope != "system"
            base = binop(nm("bp"), ast.Add(), const(self.frame[id(sym)]))
        return binop(base, ast.Add(), idx) if idx is not None else base

    def target_address(self, t: n.VarRef | n.Deref) -> tuple[ast.expr, int]:
        """(address, element kind) of an assignment target, for block functions."""
        sym = self.sym(t)
        assert isinstance(sym, VarSym)
        if isinstance(t, n.Deref):
            return self.deref_pointer(t), (FLOAT if sym.type == "float" else LONG)
        return self.address(t), storage_kind(sym)

    def angle_value(self, a: n.AngleRef) -> ast.expr:
        """`<name>` as a value: a state's or label's address, or the state a variable names."""
        sym = self.sym(a)
        if isinstance(sym, LabelSym):
            return const(self.prog.label_address(sym, self.frame is not None))
        assert isinstance(sym, VarSym)
        if sym.type == "state":
            return const(self.prog.state_bit(sym))
        return call("_stv", self._var_value(a, sym))

    def _var_value(self, node: n.AngleRef, sym: VarSym) -> ast.expr:
        fake = n.VarRef(node.pos, node.name)
        self.syms.resolved[id(fake)] = sym
        self.prog.keep.append(fake)
        return self.read(fake)[0]

    def state_ref(self, ref: n.VarRef | n.AngleRef) -> tuple[ast.expr, bool]:
        """(bit address expression, is_constant) of a state named directly or through `<var>`."""
        sym = self.sym(ref)
        assert isinstance(sym, VarSym), ref
        if sym.type == "state":
            return const(self.prog.state_bit(sym)), True
        assert isinstance(ref, n.AngleRef)
        return self._var_value(ref, sym), False

    # ------------------------------------------------------------ conditions

    def cond(self, c: n.Cond) -> ast.expr:
        """A Python boolean-valued expression for a PDL condition."""
        if isinstance(c, n.StateTest):
            bit, is_const = self.state_ref(c.ref)
            return subscript("ST", bit) if is_const else call("_stv", bit)
        if isinstance(c, n.Not):
            return ast.UnaryOp(ast.Not(), self.cond(c.operand))
        if isinstance(c, n.Logic):
            e = self.cond(c.terms[0])
            for op, t in zip(c.ops, c.terms[1:]):
                e = ast.BoolOp(ast.And() if op == "&" else ast.Or(), [e, self.cond(t)])
            return e
        if isinstance(c, n.BitTest):
            v = self.read(c.var)[0]
            shifted = binop(v, ast.RShift(), const(c.bit)) if c.bit else v
            return binop(shifted, ast.BitAnd(), const(1))
        if isinstance(c, n.Relation):
            left, _ = self.read(c.left)
            right, _ = self.read(c.right)
            if c.op == "TOUT":
                fclk = subscript("S", const(self.prog.sys_base["fclk"]))
                diff = binop(binop(binop(fclk, ast.Sub(), left), ast.Add(), const(0x8000_0000)),
                             ast.BitAnd(), const(0xFFFF_FFFF))  # fmt: skip
                return _cmp(binop(diff, ast.Sub(), const(0x8000_0000)), ast.GtE(), right)
            return _cmp(left, _RELOPS[c.op](), right)
        raise AssertionError(f"condition {c!r}")

    # ------------------------------------------------------------ values

    def value(self, v: n.Value) -> tuple[ast.expr, str]:
        """(expression, kind) of the right-hand side forms that produce one number."""
        if isinstance(v, n.Neg):
            e, k = self.read(v.operand)
            return ast.UnaryOp(ast.USub(), e), (FLT if k == FLT else WIDE)
        if isinstance(v, n.BinOp):
            return self.binop(v.op, self.read(v.left), self.read(v.right))
        if isinstance(v, n.SttoVar):
            return ast.IfExp(self.cond(v.cond), const(1), const(0)), I16
        if isinstance(v, n.SizeOf):
            sym = self.sym(v)
            size = sym.size if isinstance(sym, VarSym) else 1
            return const(size), (I16 if size <= 0x7FFF else INT)
        return self.read(v)  # type: ignore[arg-type]

    def binop(
        self, op: str, lhs: tuple[ast.expr, str], rhs: tuple[ast.expr, str]
    ) -> tuple[ast.expr, str]:
        (le, lk), (re_, rk) = lhs, rhs
        is_float = FLT in (lk, rk)
        if op == "/":
            return ast.BinOp(le, ast.Div(), re_), FLT
        if op == "%":
            return call("_mod", le, re_), INT
        e = ast.BinOp(le, _BINOPS[op](), re_)
        if is_float:
            return e, FLT
        if op in "&|@":
            return e, (I16 if lk == rk == I16 else INT)
        return e, WIDE

    # ------------------------------------------------------------ stores

    def store(self, t: n.VarRef | n.Deref, value: ast.expr, kind: str) -> list[ast.stmt]:
        """Statements storing `value` (of `kind`) into the target, converting to its type."""
        sym = self.sym(t)
        assert isinstance(sym, VarSym)
        if isinstance(t, n.Deref):
            fn = "_stf" if sym.type == "float" else "_stl"
            return [ast.Expr(call(fn, self.deref_pointer(t), value))]
        local = self.promoted(t)
        if local is not None:
            return _store_local(local[0], local[1], value, kind)
        ix = self._indexed(t, sym) if self.promo is not None else None
        if ix is not None:
            view, _addr, lo, hi, base, _idx = ix
            span = self._span(view, base, lo, hi, False)
            if span is not None:
                return [self._split_store(t.name, ix, span, storage_kind(sym), value, kind)]
        view, ix_e, skind = self.element(t, store=True)
        if view == "S":
            return [ast.Expr(call("_sw", ix_e, value))]
        return self._store_at(view, ix_e, skind, value, kind)

    def _split_store(
        self,
        name: str,
        ix: tuple[str, ast.expr, ast.expr, ast.expr, int | None, ast.expr],
        span: tuple[ast.expr, ast.expr],
        skind: int,
        value: ast.expr,
        kind: str,
    ) -> ast.If:
        """A store indexed by a variable in a promoted loop (lower_cache):

            if <index inside the span without promoted scalars>: <the store>
            else: <store the scalars>; <the checked store>; <load the scalars>

        A chunk whose guard proves the span keeps the first branch (`alias_guard`)."""
        view, addr, lo, hi, base, idx = ix
        promo = self.promo
        assert promo is not None
        test, fast = _in_span(clone(addr), span[0], span[1], idx, "_j")
        full = self._checked(addr, lo, hi, name, idx)
        slow = self._store_at(view, full, skind, clone(value), kind)
        node = ast.If(test, self._store_at(view, fast, skind, value, kind), promo.stores() + slow + promo.loads())  # fmt: skip
        if isinstance(test.comparators[0], ast.Name):
            node.alias_guard = (view, base)  # type: ignore[attr-defined]
        return node

    def _store_at(
        self, view: str, ix: ast.expr, skind: int, value: ast.expr, kind: str
    ) -> list[ast.stmt]:
        """`view[ix] = value`, converted to the element's kind (`skind`)."""
        if skind == FLOAT:
            return [assign(subscript(view, ix, True), value)]
        bits = 16 if skind == SHORT else 32
        if kind == FLT:
            conv = call("_rnd", value) if bits == 32 else call("_rnd", value, const(16))
            return [assign(subscript(view, ix, True), conv)]
        if kind == I16 or (kind == INT and bits == 32):
            return [assign(subscript(view, ix, True), value)]
        wrap = "_w32" if bits == 32 else "_w16"
        if isinstance(value, ast.BinOp) and isinstance(value.op, ast.Mult):
            # a product usually leaves 32 bits: test it instead of raising ValueError
            lo, hi = (-0x8000, 0x7FFF) if bits == 16 else (-0x8000_0000, 0x7FFF_FFFF)
            walrus = ast.NamedExpr(nm("_w", True), value)
            test = ast.Compare(const(lo), [ast.LtE(), ast.LtE()], [walrus, const(hi)])
            wrapped = ast.IfExp(test, nm("_w"), wrap_inline(nm("_w"), bits))
            return [assign(subscript(view, ix, True), wrapped)]
        fast = assign(subscript(view, ix, True), value)
        slow = assign(subscript(view, clone(ix), True), call(wrap, clone(value)))
        handler = ast.ExceptHandler(nm("ValueError"), None, [slow])
        return [ast.Try([fast], [handler], [], [])]

    def auto_increments(self, *operands: object) -> list[ast.stmt]:
        """`n += 1` for every `a[n+]` among the operands, in the order given."""
        out: list[ast.stmt] = []
        for op in operands:
            if isinstance(op, n.VarRef) and op.auto_inc and isinstance(op.index, n.VarRef):
                idx = op.index
                e, _ = self.read(idx)
                out += self.store(idx, binop(e, ast.Add(), const(1)), WIDE)
        return out
