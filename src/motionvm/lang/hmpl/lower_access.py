"""Lower HMPL names, lvalues, indexing, members, assignments, `++`/`--` and calls.

Objects reached through names are trusted (their layout is known): one bounds check,
no shadow check. An access through a pointer tests the shadow memory inline and falls
back to a checked helper (`_ld_i32(p)`, `_st_i32(p, v)`). A call of a function that
can block becomes `yield from`:

    int a[10]; int *q;  ...  a[i] = 1; *q = 2; f2();        (f2 sleeps)
becomes
    g_a[v_i if 0 <= v_i < 10 else _oob(v_i, 10)] = 1
    if not g_q & -16777213 and _SH[g_q] > 3:
        _I32[g_q >> 2] = 2
    else:
        _st_i32(g_q, 2)
    yield from g_f2()
"""

from __future__ import annotations

import ast

from motionvm.lang.hmpl import ctypes_ as ct
from motionvm.lang.hmpl import nodes as n
from motionvm.lang.hmpl.formatcheck import check_format, is_printf_like
from motionvm.lang.hmpl.lower_context import FunctionContext, SemanticError
from motionvm.lang.hmpl.lower_expr import ExprLowerer
from motionvm.lang.hmpl.lower_values import Val
from motionvm.lang.hmpl.lvalues import (
    AggLV,
    GpoLV,
    ListLV,
    LValue,
    MemLV,
    NameLV,
    PtrLV,
    call,
    const,
    name,
)
from motionvm.lang.hmpl.symbols import FuncSym, VarSym
from motionvm.source.suggest import did_you_mean

_SHIFT = {1: 0, 2: 1, 4: 2, 8: 3}


class _ListRow(LValue):
    """A row of a list-backed array of several dimensions (only ever indexed further)."""

    def __init__(self, t: ct.CType, pyname: str, offset: ast.expr) -> None:
        super().__init__(t)
        self.pyname = pyname
        self.offset = offset


def _add(node: ast.expr, k: int) -> ast.expr:
    if k == 0:
        return node
    if isinstance(node, ast.Constant):
        return ast.Constant(node.value + k)
    return ast.BinOp(left=node, op=ast.Add(), right=ast.Constant(k))


def _scaled_index(addr: ast.expr, size: int) -> ast.expr:
    """Index into a view of element `size` for an address known to be aligned."""
    if isinstance(addr, ast.Constant):
        return ast.Constant(addr.value // size)
    if size == 1:
        return addr
    return ast.BinOp(left=addr, op=ast.RShift(), right=ast.Constant(_SHIFT[size]))


def _plus(a: ast.expr, b: ast.expr) -> ast.expr:
    if isinstance(a, ast.Constant) and a.value == 0:
        return b
    if isinstance(b, ast.Constant) and b.value == 0:
        return a
    if isinstance(a, ast.Constant) and isinstance(b, ast.Constant):
        return ast.Constant(a.value + b.value)
    return ast.BinOp(left=a, op=ast.Add(), right=b)


def _as_expr(st: ast.stmt) -> ast.expr:
    """An initializing store as an expression: `V[i] = x` becomes `V.__setitem__(i, x)`."""
    if isinstance(st, ast.Expr):
        return st.value
    assert isinstance(st, ast.Assign) and isinstance(st.targets[0], ast.Subscript)
    target = st.targets[0]
    setitem = ast.Attribute(value=target.value, attr="__setitem__", ctx=ast.Load())
    return ast.Call(func=setitem, args=[target.slice, st.value], keywords=[])


def _trusted_lv(t: ct.CType, addr: ast.expr) -> LValue:
    """An object at an address known to be inside a live object and aligned for `t`."""
    if t.is_scalar:
        return MemLV(t, _scaled_index(addr, t.size))
    return AggLV(t, addr)


class AccessLowerer:
    """Lowers the places of one function (names, `a[i]`, `s.f`, `p->f`, `*p`, compound
    literals), assignments, `++`/`--` and calls; values go through its expression
    lowerer `x`."""

    def __init__(self, ctx: FunctionContext, x: ExprLowerer) -> None:
        self.ctx = ctx
        self.x = x
        self.prog = ctx.prog
        self.fail = ctx.fail
        self.temp = ctx.temp
        self.trusted_ptrs: dict[str, int] = {}
        """While a pointer walk's unchecked body is lowered (lower_walk.py): pointer
        pyname -> bytes its `*p` may access without a check."""
        self.lazy_sums: frozenset[str] = frozenset()
        """... and the int locals whose sums wrap once per chunk."""

    # ------------------------------------------------------------ names

    def resolve(self, ident: str, pos):
        sym = self.ctx.scope.lookup(ident)
        if sym is None:
            sym = self.prog.global_symbol(ident, self.ctx.task)
        if sym is None:
            if ident in self.prog.builtins:
                raise self.fail(
                    pos, f"built-in function '{ident}' used as a value (call it: {ident}(...))"
                )
            hint = did_you_mean(
                ident, self.ctx.scope.visible_names() + self.prog.global_names(self.ctx.task)
            )
            raise self.fail(pos, f"'{ident}' undeclared{hint}")
        if sym.type is ct.ERROR:  # its declaration failed and was reported
            raise SemanticError(f"'{ident}' has no valid declaration")
        return sym

    def var_lvalue(self, sym: VarSym) -> LValue:
        t = sym.type
        if sym.storage in ("local", "pyglobal", "pylist"):
            return NameLV(t, sym.pyname)
        if sym.storage == "static":
            return _trusted_lv(t, ast.Constant(sym.addr))
        if sym.storage == "frame":
            return _trusted_lv(t, _add(name("_fp"), sym.offset))
        raise AssertionError(sym.storage)

    def lvalue(self, e) -> LValue:
        """The place an expression designates; an error if it designates none."""
        if isinstance(e, n.Name):
            sym = self.resolve(e.id, e.pos)
            if isinstance(sym, FuncSym) or sym.const_value is not None:
                raise self.fail(e.pos, f"'{e.id}' is not assignable")
            if sym.storage == "pyglobal":
                self.ctx.globals_stored.add(sym.pyname)
            return self.var_lvalue(sym)
        if isinstance(e, n.Unary) and e.op == "*":
            p = self.x.expr(e.operand)
            if not isinstance(p.type, ct.PtrT):
                raise self.fail(e.pos, f"cannot dereference a value of type '{p.type}'")
            t = p.type.target
            if isinstance(t, ct.VoidT):
                raise self.fail(e.pos, "cannot dereference a 'void *' pointer (cast it first)")
            if t.is_scalar:
                if (
                    type(p.node) is ast.Name
                    and self.trusted_ptrs.get(p.node.id, 0) >= t.size
                    and type(e.operand) is n.Name
                ):
                    # a pointer walk's chunk checked in advance (lower_walk.py)
                    return MemLV(t, _scaled_index(p.node, t.size))
                return PtrLV(t, p.node, self.temp())
            return AggLV(
                t, call("_chkp", p.node, ast.Constant(max(t.size, 1)), ast.Constant(t.align))
            )
        if isinstance(e, n.Index):
            return self._index_lv(e)
        if isinstance(e, n.Member):
            return self._member_lv(e)
        if isinstance(e, n.CompoundLit):
            return self._compound_lv(e)
        if isinstance(e, n.Call) and isinstance(e.func, n.Name) and e.func.id == "HIMC_GPO":
            if len(e.args) != 1:
                raise self.fail(e.pos, f"HIMC_GPO takes 1 argument, got {len(e.args)}")
            return GpoLV(ct.INT, self.x.convert(self.x.expr(e.args[0]), ct.INT, e.pos))
        raise self.fail(e.pos, "expression is not assignable (not an lvalue)")

    def _index_lv(self, e: n.Index) -> LValue:
        base = self.x.value(e.base)
        idx = self.x.expr(e.index)
        if not idx.type.is_integer:
            if idx.type.is_pointer and base.type.is_integer:
                raise self.fail(e.pos, "write the array before the index: a[i], not i[a]")
            raise self.fail(e.index.pos, f"array subscript is not an integer (it is '{idx.type}')")
        if isinstance(base.type, ct.ArrayT):
            elem, count = base.type.elem, base.type.n
            if count is not None:
                # a bounds-checked index needs no wrap: an overflowed value is out of bounds too
                i_node = (
                    idx.node
                    if isinstance(idx.type, ct.IntT) and idx.type.size >= 4
                    else self.x.exact(idx)
                )
                if isinstance(idx.const, int):
                    if not 0 <= idx.const < count:
                        raise self.fail(
                            e.index.pos,
                            f"array index {idx.const} is out of bounds (the array has {count} elements)",
                        )
                    i_node = const(idx.const)
                elif idx.rng is not None and 0 <= idx.rng[0] and idx.rng[1] < count:
                    pass  # range analysis proves the index in bounds
                else:
                    if isinstance(i_node, ast.Name):
                        grab, ref = i_node, i_node
                    else:
                        t = self.temp()
                        grab, ref = ast.NamedExpr(target=name(t, True), value=i_node), name(t)
                    chk = ast.Compare(
                        left=ast.Constant(0),
                        ops=[ast.LtE(), ast.Lt()],
                        comparators=[grab, ast.Constant(count)],
                    )
                    i_node = ast.IfExp(
                        test=chk, body=ref, orelse=call("_oob", ref, ast.Constant(count))
                    )
            else:
                i_node = self.x.convert(idx, ct.I64, e.pos)
            if base.listy:
                inner = 1
                e2 = elem
                while isinstance(e2, ct.ArrayT):
                    inner, e2 = inner * (e2.n or 0), e2.elem
                if isinstance(i_node, ast.Constant):
                    scaled = ast.Constant(i_node.value * inner)
                elif inner == 1:
                    scaled = i_node
                else:
                    scaled = ast.BinOp(left=i_node, op=ast.Mult(), right=ast.Constant(inner))
                flat = _plus(base.loff, scaled)
                if isinstance(elem, ct.ArrayT):
                    return _ListRow(elem, base.listy, flat)
                return ListLV(elem, base.listy, flat)
            # array objects are always reached through names, members or checked pointers
            if elem.is_scalar and elem.size in _SHIFT:
                return MemLV(elem, _plus(_scaled_index(base.node, elem.size), i_node))
            off = (
                i_node
                if elem.size == 1
                else ast.BinOp(left=i_node, op=ast.Mult(), right=ast.Constant(elem.size))
            )
            addr = _plus(base.node, off)
            if elem.is_scalar:
                return PtrLV(elem, addr, self.temp())
            return AggLV(elem, addr)
        base = self.x.expr(e.base)
        if not isinstance(base.type, ct.PtrT):
            raise self.fail(
                e.pos, f"subscripted value is neither array nor pointer (it is '{base.type}')"
            )
        elem = base.type.target
        if isinstance(elem, ct.VoidT) or elem.size == 0:
            raise self.fail(e.pos, f"subscript of a pointer to incomplete type '{base.type}'")
        if isinstance(idx.const, int):
            off = const(idx.const * elem.size)
        else:
            i_node = self.x.exact(idx)
            off = (
                i_node
                if elem.size == 1
                else ast.BinOp(left=i_node, op=ast.Mult(), right=ast.Constant(elem.size))
            )
        addr = _plus(base.node, off)
        if elem.is_scalar:
            return PtrLV(elem, addr, self.temp())
        return AggLV(elem, call("_chkp", addr, ast.Constant(elem.size), ast.Constant(elem.align)))

    def _member_lv(self, e: n.Member) -> LValue:
        if e.arrow:
            p = self.x.expr(e.base)
            if not (isinstance(p.type, ct.PtrT) and isinstance(p.type.target, ct.StructT)):
                raise self.fail(
                    e.pos,
                    f"'->' applied to '{p.type}', which is not a pointer to a struct or union",
                )
            st = p.type.target
            base_addr = call("_chkp", p.node, ast.Constant(st.size), ast.Constant(st.align))
        else:
            b = self.x.value(e.base)
            if not isinstance(b.type, ct.StructT):
                hint = " (use '->' for a pointer)" if isinstance(b.type, ct.PtrT) else ""
                raise self.fail(
                    e.pos,
                    f"'.{e.name}' applied to '{b.type}', which is not a struct or union{hint}",
                )
            st = b.type
            base_addr = b.node
        found = st.field(e.name)
        if not st.fields:
            raise self.fail(e.pos, f"'{st}' is an incomplete type (declared, never defined)")
        if found is None or e.name.startswith("_") and st.tag == "Timer":
            names = [f for f, _, _ in st.fields if not f.startswith("_")]
            raise self.fail(e.pos, f"'{st}' has no member '{e.name}'{did_you_mean(e.name, names)}")
        off, ft = found
        if st.align < ft.align and ft.is_scalar:
            return PtrLV(ft, _add(base_addr, off))  # packed (Data_t): may be unaligned
        return _trusted_lv(ft, _add(base_addr, off))

    def compound_type(self, e: n.CompoundLit) -> ct.CType:
        """The type of a compound literal (`(int[]){1, 2}` counts its elements)."""
        d = n.VarDecl(e.pos, e.type, "compound literal", e.dims, e.init)
        t = self.prog.decl_type(d, self.ctx.scope, self.ctx.task)
        if isinstance(t, ct.VoidT) or t.size == 0:
            raise self.fail(e.pos, f"a compound literal of incomplete type '{t}'")
        return t

    def _compound_lv(self, e: n.CompoundLit) -> LValue:
        """`(T){...}`: an unnamed object. In a function it has a place in the frame and is
        initialized where the expression is evaluated, each time (C99 6.5.2.5); outside
        (a file-scope initializer) it is static, its constant value set at load."""
        t = self.compound_type(e)
        prog = self.prog
        what = "compound literal"
        if self.ctx.func is None:
            addr = prog.alloc_static_at(e.pos, t.size, what, align=max(8, t.align))
            image, stores = prog.aggregate_init(self.x, t, e.init, ast.Constant(addr), what)
            if stores:
                raise self.fail(e.pos, "a compound literal outside a function must be a constant")
            prog.mem.buf[addr : addr + len(image)] = image
            return _trusted_lv(t, ast.Constant(addr))
        off = self.ctx.frame_alloc(t)
        image, stores = prog.aggregate_init(self.x, t, e.init, _add(name("_fp"), off), what)
        steps: list[ast.expr] = [call("_fill", _add(name("_fp"), off), ast.Constant(bytes(image)))]
        steps.extend(_as_expr(st) for st in stores)
        steps.append(_add(name("_fp"), off))
        seq = ast.Subscript(
            value=ast.Tuple(elts=steps, ctx=ast.Load()), slice=const(-1), ctx=ast.Load()
        )
        return _trusted_lv(t, seq)

    def x_CompoundLit(self, e: n.CompoundLit) -> Val:
        lv = self._compound_lv(e)
        return Val(lv.load(), lv.type)

    def x_Index(self, e: n.Index) -> Val:
        lv = self._index_lv(e)
        if isinstance(lv, _ListRow):
            return Val(name(lv.pyname), lv.type, True, None, None, lv.pyname, lv.offset)
        return Val(lv.load(), lv.type)

    def x_Member(self, e: n.Member) -> Val:
        lv = self._member_lv(e)
        return Val(lv.load(), lv.type)

    def address_of(self, operand, pos) -> Val:
        if isinstance(operand, n.Name):
            sym = self.resolve(operand.id, operand.pos)
            if isinstance(sym, FuncSym):
                return Val(name(sym.pyname), ct.pointer_to(sym.type))
        if isinstance(operand, n.Call):
            raise self.fail(pos, "cannot take the address of a call result")
        lv = self.lvalue(operand)
        a = lv.addr()
        if a is None:
            raise self.fail(pos, "cannot take the address of this expression")
        return Val(a, ct.pointer_to(lv.type))

    # ------------------------------------------------------------ assignment

    def _check_const(self, e, lv: LValue) -> None:
        if isinstance(e, n.Name):
            sym = self.ctx.scope.lookup(e.id) or self.prog.global_symbol(e.id, self.ctx.task)
            if isinstance(sym, VarSym) and sym.is_const:
                raise self.fail(e.pos, f"assignment of read-only variable '{e.id}'")
        if isinstance(lv.type, ct.ArrayT):
            raise self.fail(
                e.pos,
                "an array is not an assignable lvalue (copy arrays with MemoryCopy or StringCopy)",
            )

    def assignment(self, e: n.Assign, as_stmt: bool):
        """Lower `target op= value`; a list of statements, or a Val when used as a value."""
        lv = self.lvalue(e.target)
        self._check_const(e.target, lv)
        if e.op == "=":
            v = self.x.expr(e.value)
            node = self.x.assign_convert(v, lv.type, e.pos, " in assignment")
            if as_stmt:
                return lv.store(node)
            return Val(lv.store_expr(node), lv.type)
        op = e.op[:-1]
        pre, blv = lv.bind(self.temp)
        cur = Val(blv.load(), lv.type)
        if isinstance(lv.type, ct.StructT):
            raise self.fail(e.pos, f"invalid operands to '{e.op}' ('{lv.type}')")
        res = self.x.binary(op, cur, self.x.expr(e.value), e.pos)
        if (
            as_stmt
            and type(blv) is NameLV
            and blv.pyname in self.lazy_sums
            and res.type == ct.INT
            and op in ("+", "-")
        ):
            # a pointer walk's sum, wrapped once per chunk (lower_walk.py)
            return blv.store(res.node)
        node = self.x.convert(res, lv.type, e.pos)
        if as_stmt:
            return [ast.Expr(value=p) for p in pre] + blv.store(node)
        return Val(self._seq(pre, blv.store_expr(node)), lv.type)

    def x_Assign(self, e: n.Assign) -> Val:
        return self.assignment(e, as_stmt=False)

    @staticmethod
    def _seq(pre: list[ast.expr], last: ast.expr) -> ast.expr:
        if not pre:
            return last
        tup = ast.Tuple(elts=pre + [last], ctx=ast.Load())
        return ast.Subscript(value=tup, slice=const(-1), ctx=ast.Load())

    def incdec(self, operand, op: str, prefix: bool, pos, as_stmt: bool = False):
        lv = self.lvalue(operand)
        self._check_const(operand, lv)
        if not lv.type.is_scalar:
            raise self.fail(pos, f"cannot apply '{op}' to a value of type '{lv.type}'")
        pre, blv = lv.bind(self.temp)
        one = Val(ast.Constant(1), ct.INT, True, 1)
        bop = "+" if op == "++" else "-"
        if as_stmt:
            res = self.x.binary(bop, Val(blv.load(), lv.type), one, pos)
            return [ast.Expr(value=p) for p in pre] + blv.store(self.x.convert(res, lv.type, pos))
        if prefix:
            res = self.x.binary(bop, Val(blv.load(), lv.type), one, pos)
            return Val(self._seq(pre, blv.store_expr(self.x.convert(res, lv.type, pos))), lv.type)
        if not pre and isinstance(blv, NameLV) and isinstance(lv.type, ct.PtrT):
            # p++ on a pointer variable: `(p := p + k) - k`, the old value without a tuple
            step = self.x.convert(
                self.x.binary(bop, Val(blv.load(), lv.type), one, pos), lv.type, pos
            )
            if (
                isinstance(step, ast.BinOp)
                and isinstance(step.op, (ast.Add, ast.Sub))
                and isinstance(step.left, ast.Name)
                and step.left.id == blv.pyname
                and isinstance(step.right, ast.Constant)
            ):
                back = ast.Sub() if isinstance(step.op, ast.Add) else ast.Add()
                return Val(ast.BinOp(left=blv.store_expr(step), op=back, right=step.right), lv.type)
        t = self.temp()
        grab = ast.NamedExpr(target=name(t, True), value=blv.load())
        res = self.x.binary(bop, Val(name(t), lv.type), one, pos)
        store = blv.store_expr(self.x.convert(res, lv.type, pos))
        tup = ast.Tuple(elts=pre + [grab, store], ctx=ast.Load())
        return Val(ast.Subscript(value=tup, slice=ast.Constant(len(pre)), ctx=ast.Load()), lv.type)

    # ------------------------------------------------------------ calls

    def x_Call(self, e: n.Call) -> Val:
        if not isinstance(e.func, n.Name):
            raise self.fail(e.pos, "called object is not a function")
        fname = e.func.id
        if fname == "Till":
            raise self.fail(e.pos, "Till(condition) is a statement; it has no value")
        if fname in ("HIMC_GPI", "HIMC_GPO"):
            if len(e.args) != 1:
                raise self.fail(
                    e.pos,
                    f"{fname} takes 1 argument ({'gpi' if fname == 'HIMC_GPI' else 'gpo'}_idx), got {len(e.args)}",
                )
            idx = self.x.convert(self.x.expr(e.args[0]), ct.INT, e.pos)
            return Val(call("_gpi" if fname == "HIMC_GPI" else "_gpo", idx), ct.INT)
        sym = self.ctx.scope.lookup(fname) or self.prog.global_symbol(fname, self.ctx.task)
        if sym is not None and sym.type is ct.ERROR:
            raise SemanticError(f"'{fname}' has no valid declaration")
        if isinstance(sym, VarSym):
            raise self.fail(e.pos, f"'{fname}' is a variable, not a function")
        if isinstance(sym, FuncSym):
            if not sym.defined:
                raise self.fail(
                    e.func.pos,
                    f"function '{fname}' is declared (at {sym.pos}) but never defined",
                )
            args = self._call_args(
                e, fname, [(pn, pt) for pn, pt in zip(sym.param_names, sym.type.params)], False
            )
            node = call(sym.pyname, *args)
            if sym.is_generator:
                node = ast.YieldFrom(value=node)
                self.ctx.has_yield = True
            return Val(node, sym.type.ret)
        sig = self.prog.builtins.get(fname)
        if sig is None:
            cands = self.prog.function_names(self.ctx.task)
            raise self.fail(
                e.func.pos, f"call to undeclared function '{fname}'{did_you_mean(fname, cands)}"
            )
        args = self._call_args(e, fname, list(sig.params), sig.variadic)
        impl = self.prog.builtin_impl.get(fname)
        if impl is None:
            self.prog.warn(
                e.pos,
                f"{fname} (manual {sig.section}) is not implemented; the task will stop here",
            )
            node = call("_notimpl", ast.Constant(fname), *args)
        else:
            node = call("b_" + fname, *args)
            if fname == "RunScheduler":
                node = ast.Yield(value=None)  # what b_RunScheduler does, without a generator
                self.ctx.has_yield = True
            elif impl:  # blocking
                node = ast.YieldFrom(value=node)
                self.ctx.has_yield = True
        return Val(node, sig.ret)

    def _call_args(self, e: n.Call, fname: str, params, variadic: bool) -> list[ast.expr]:
        nargs, nparams = len(e.args), len(params)
        if nargs < nparams or (nargs > nparams and not variadic):
            few = "few" if nargs < nparams else "many"
            expect = f"at least {nparams}" if variadic else str(nparams)
            proto = self.prog.prototype(fname, self.ctx.task)
            raise self.fail(
                e.pos, f"too {few} arguments to '{fname}' (expected {expect}, got {nargs}){proto}"
            )
        out: list[ast.expr] = []
        extra: list[tuple[ct.CType, object]] = []  # (type, pos) of each variadic argument
        for i, a in enumerate(e.args):
            v = self.x.expr(a)
            if i < nparams:
                pname, ptype = params[i]
                what = f" (argument {i + 1} '{pname}' of '{fname}')"
                out.append(self.x.assign_convert(v, ptype, a.pos, what))
            else:
                out.append(self._vararg(v, a.pos))
                extra.append((v.type, a.pos))
        if is_printf_like(params, variadic) and type(e.args[nparams - 1]) is n.StrLit:
            fmt = e.args[nparams - 1]
            check_format(fmt.value, fmt.pos, nparams + 1, extra, self.prog.warn)
        return out

    def _vararg(self, v: Val, pos) -> ast.expr:
        t = v.type
        if isinstance(t, ct.IntT):
            return self.x.convert(v, ct.promote(t), pos)
        if isinstance(t, ct.FloatT):
            return v.node
        if isinstance(t, (ct.PtrT, ct.FuncT)):
            return v.node
        raise self.fail(pos, f"cannot pass a value of type '{t}' as a variadic argument")
