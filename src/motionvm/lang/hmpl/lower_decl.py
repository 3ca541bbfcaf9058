"""Lower HMPL declarations inside a function: locals, `static` locals, typedefs.

A local scalar is a Python local; one whose address is taken, and every array, struct
or union, lives in the function's stack frame; an array that never decays to a pointer
is a Python list. A `static` local lives in static memory, initialized at load.

    int n = 3; int a[4] = {1, 2}; int *p = &n;
becomes
    _I32[_fp >> 2] = 3              (n: its address is taken, at offset 0 of the frame)
    v_a = _mklist(b'...', 'i32')    (a list: a constant initializer's values)
    v_p = (_fp >> 2) * 4
"""

from __future__ import annotations

import ast

from motionvm.lang.hmpl import ctypes_ as ct
from motionvm.lang.hmpl import nodes as n
from motionvm.lang.hmpl.lower_access import AccessLowerer
from motionvm.lang.hmpl.lower_context import FunctionContext, SemanticError
from motionvm.lang.hmpl.lower_expr import ExprLowerer
from motionvm.lang.hmpl.lvalues import call, name, view_code
from motionvm.lang.hmpl.symbols import VarSym, error_symbol


class DeclLowerer:
    """Declares the locals of one function, in its current block scope."""

    def __init__(self, ctx: FunctionContext, x: ExprLowerer, access: AccessLowerer) -> None:
        self.ctx = ctx
        self.x = x
        self.access = access
        self.prog = ctx.prog
        self.fail = ctx.fail

    def handlers(self) -> dict[type, object]:
        """The statements this part lowers: node class -> method."""
        return {n.DeclStmt: self.s_DeclStmt, n.VarDecl: self.s_VarDecl, n.Typedef: self.s_Typedef}

    def declare_local(self, d: n.VarDecl, is_param: bool = False) -> list[ast.stmt]:
        """The statements that initialize a local; a declaration that fails still declares
        its name (with the error type if its own type failed), so that later uses of the
        name add no errors."""
        try:
            return self._declare_local(d, is_param)
        except SemanticError:
            if d.name not in self.ctx.scope.names:
                self.ctx.scope.names[d.name] = error_symbol(d.name, d.pos)
            raise

    def _declare_local(self, d: n.VarDecl, is_param: bool) -> list[ast.stmt]:
        t = self.prog.decl_type(d, self.ctx.scope, self.ctx.task)
        if d.name in self.ctx.scope.names:
            raise self.fail(d.pos, f"redefinition of '{d.name}'")
        if isinstance(t, ct.VoidT):
            raise self.fail(d.pos, f"variable '{d.name}' declared void")
        if not d.name:  # `struct S { ... };` in a block: the definition alone
            return []
        self.prog.require_complete(d, t)
        if d.is_static and self.ctx.func is not None:
            return self._declare_static_local(d, t)
        if self.prog.list_backed(d, t):
            sym = VarSym(d.name, t, "pylist", d.pos, pyname=self.ctx.unique_local(d.name))
            if self.ctx.func is not None:
                self.ctx.list_bytes += (max(t.size, 1) + 7) // 8 * 8
            out = self.init_var(sym, d.init, d.pos)
            self.ctx.scope.names[d.name] = sym
            return out
        in_mem = not t.is_scalar or d.name in self.ctx.addr_taken
        if in_mem:
            sym = VarSym(
                d.name, t, "frame", d.pos, offset=self.ctx.frame_alloc(t), is_const=d.type.is_const
            )
        else:
            sym = VarSym(
                d.name,
                t,
                "local",
                d.pos,
                pyname=self.ctx.unique_local(d.name),
                is_const=d.type.is_const,
            )
        out = self.init_var(sym, d.init, d.pos, zero_default=not is_param)
        self.ctx.scope.names[d.name] = sym
        return out

    def _declare_static_local(self, d: n.VarDecl, t: ct.CType) -> list[ast.stmt]:
        """A `static` local: one object in static memory for the whole run, visible in its
        block, given its constant initial value when the program is loaded (C: before the
        program starts); it generates no statement where it is declared."""
        mem = self.prog.mem
        addr = self.prog.alloc_static_at(d.pos, t.size, d.name, align=max(8, t.align))
        sym = VarSym(d.name, t, "static", d.pos, addr=addr, is_const=d.type.is_const)
        if d.init is not None:
            image, stores = self.prog.aggregate_init(self.x, t, d.init, ast.Constant(addr), d.name)
            if stores:
                raise self.fail(
                    d.init.pos, f"the initializer of static '{d.name}' must be a constant"
                )
            mem.buf[addr : addr + len(image)] = image
        self.ctx.scope.names[d.name] = sym
        return []

    def init_var(self, sym: VarSym, init, pos, zero_default: bool = True) -> list[ast.stmt]:
        """Statements giving a variable its initial value (0 when there is no initializer)."""
        t = sym.type
        if sym.storage == "pylist":
            return self._init_list(sym, init, pos)
        lv = self.access.var_lvalue(sym)
        if init is None:
            if sym.storage in ("local", "pyglobal") and zero_default:
                zero = ast.Constant(0.0 if t.is_float else 0)
                return lv.store(zero)
            return []
        if t.is_scalar:
            if isinstance(init, n.InitList):
                if len(init.items) != 1 or isinstance(init.items[0], n.InitList):
                    raise self.fail(init.pos, f"a scalar '{sym.name}' takes one initializer")
                init = init.items[0]
            v = self.x.expr(init)
            return lv.store(
                self.x.assign_convert(v, t, init.pos, f" in the initializer of '{sym.name}'")
            )
        addr = lv.addr()
        image, stores = self.prog.aggregate_init(self.x, t, init, addr, sym.name)
        out: list[ast.stmt] = [ast.Expr(call("_fill", addr, ast.Constant(bytes(image))))]
        return out + stores

    def _init_list(self, sym: VarSym, init, pos) -> list[ast.stmt]:
        """`v_a = [0] * N`, or the constant initializer's values unpacked at load time."""
        t = sym.type
        count, elem = 1, t
        while isinstance(elem, ct.ArrayT):
            count, elem = count * (elem.n or 0), elem.elem
        zero = ast.Constant(0.0 if elem.is_float else 0)
        if init is None:
            value = ast.BinOp(ast.List([zero], ast.Load()), ast.Mult(), ast.Constant(count))
        else:
            image, stores = self.prog.aggregate_init(self.x, t, init, ast.Constant(0), sym.name)
            assert not stores  # list_backed() admits constant initializers only
            value = call("_mklist", ast.Constant(bytes(image)), ast.Constant(view_code(elem)))
        if sym.storage == "pylist" and self.ctx.func is None:
            self.ctx.globals_stored.add(sym.pyname)
        return [ast.Assign([name(sym.pyname, True)], value)]

    def s_DeclStmt(self, s: n.DeclStmt) -> list[ast.stmt]:
        out: list[ast.stmt] = []
        for d in s.decls:
            try:
                if type(d) is n.Typedef:
                    self.s_Typedef(d)
                    continue
                if type(d) is n.FuncDef:  # a prototype: its name is visible in this block
                    if isinstance(self.ctx.scope.names.get(d.name), VarSym):
                        raise self.fail(
                            d.pos, f"'{d.name}' redeclared as a different kind of symbol"
                        )
                    self.ctx.scope.names[d.name] = self.prog.block_prototype(d, self.ctx.task)
                    continue
                out.extend(self.ctx.at(self.declare_local(d), d.pos))
            except SemanticError:
                pass
        return out

    def s_VarDecl(self, s: n.VarDecl) -> list[ast.stmt]:
        return self.declare_local(s)

    def s_Typedef(self, s: n.Typedef) -> list[ast.stmt]:
        """A typedef inside a function: a type name of the current block."""
        try:
            t = self.prog.resolve_typeref(s.type, self.ctx.scope, self.ctx.task)
            for dim in reversed(s.dims):
                count = self.x.const_int(dim) if dim is not None else None
                if count is not None and count <= 0:
                    raise self.fail(
                        dim.pos, f"size of array '{s.name}' must be positive (it is {count})"
                    )
                t = ct.array_of(t, count)
        except SemanticError:
            self.ctx.scope.types.setdefault(s.name, ct.ERROR)
            raise
        self.ctx.scope.types[s.name] = t
        return []
