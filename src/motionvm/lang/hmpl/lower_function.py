"""Lower one HMPL function (or one task's global initializers) to a Python function.

`FunctionLowerer` assembles the parts that lower a function and own their state, each
given the shared `lower_context.FunctionContext` and the parts it talks to:

    ExprLowerer       lower_expr.py     values, conversions, operators (lower_values.py)
    AccessLowerer     lower_access.py   places, assignments, calls
    DeclLowerer       lower_decl.py     local declarations
    StatementLowerer  lower_stmt.py     statements, `if`, `return`, waits
    Nesting           lower_split.py    enclosing loops and switches, nested functions
    JumpLowerer       lower_jumps.py    break, continue, goto
    SwitchLowerer     lower_switch.py   switch
    LoopLowerer       lower_loops.py    loops (lower_range.py, lower_walk.py, lower_poll.py)

Locals whose address is taken live in a stack frame pushed on entry and popped in a
`finally`; the function is a generator if anything in it may wait:

    int f(int n) { int a[2]; int *p = &n; return *p; }
becomes
    def g_f(v_n):
        _s = _stack
        _fp = _s.push(24, b'...')
        try:
            _I32[_fp >> 2] = v_n
            v_a = [0] * 2
            v_p = (_fp >> 2) * 4
            return _I32[v_p >> 2] if not v_p & -16777213 and _SH[v_p] > 3 else _ld_i32(v_p)
        finally:
            _s.pop(_fp)
"""

from __future__ import annotations

import ast

from motionvm.lang.hmpl import ctypes_ as ct
from motionvm.lang.hmpl import nodes as n
from motionvm.lang.hmpl.lower_access import AccessLowerer
from motionvm.lang.hmpl.lower_context import FunctionContext
from motionvm.lang.hmpl.lower_decl import DeclLowerer
from motionvm.lang.hmpl.lower_expr import ExprLowerer
from motionvm.lang.hmpl.lower_facts import AssignedNames
from motionvm.lang.hmpl.lower_jumps import JumpLowerer
from motionvm.lang.hmpl.lower_loops import LoopLowerer
from motionvm.lang.hmpl.lower_split import Nesting, bind_splits
from motionvm.lang.hmpl.lower_stmt import RETURNS, StatementLowerer, ends_in
from motionvm.lang.hmpl.lower_switch import SwitchLowerer
from motionvm.lang.hmpl.lvalues import name
from motionvm.lang.hmpl.symbols import FuncSym, Scope, VarSym


class FunctionLowerer:
    """Lowers one function body (or one task's global initializers) of one task."""

    def __init__(
        self,
        prog,
        task: int,
        scope: Scope,
        func: FuncSym | None,
        addr_taken: set[str],
        assigned: dict[int, set[str]] | None = None,
    ) -> None:
        """`assigned`: the names assigned in the body and in each `for` body, by `id` of
        the body, when the analysis already found them (`analysis.FuncFacts`)."""
        self.ctx = ctx = FunctionContext(prog, task, scope, func, addr_taken)
        self.x = x = ExprLowerer(ctx)
        self.access = access = AccessLowerer(ctx, x)
        x.attach(access)
        self.assigned = AssignedNames(assigned)
        self.nesting = nesting = Nesting(ctx)
        self.decls = decls = DeclLowerer(ctx, x, access)
        self.stmts = stmts = StatementLowerer(ctx, x, access, nesting)
        self.jumps = jumps = JumpLowerer(ctx, stmts, nesting, decls)
        switch = SwitchLowerer(ctx, x, stmts, nesting, jumps, decls)
        loops = LoopLowerer(ctx, x, access, stmts, nesting, self.assigned)
        for part in (decls, jumps, switch, loops):
            stmts.attach(part.handlers())

    # ------------------------------------------------------------ what the program asks

    @property
    def globals_stored(self) -> set[str]:
        """Module globals the lowered code assigns."""
        return self.ctx.globals_stored

    @property
    def has_yield(self) -> bool:
        """The lowered code may wait."""
        return self.ctx.has_yield

    def init_var(self, sym: VarSym, init, pos) -> list[ast.stmt]:
        """Statements giving a variable its initial value (a global's, at task start)."""
        return self.decls.init_var(sym, init, pos)

    # ------------------------------------------------------------ functions

    def function(self, f: n.FuncDef, sym: FuncSym) -> ast.FunctionDef:
        ctx = self.ctx
        ctx.func_assigned = self.assigned.of(f.body)  # fills every inner `for` too
        params: list[ast.arg] = []
        copies: list[ast.stmt] = []
        for p, pt in zip(f.params, sym.type.params):
            if not p.name:
                continue
            if p.name in ctx.scope.names:
                ctx.sink.error(p.pos, f"redefinition of parameter '{p.name}'")
                continue
            pyname = ctx.unique_local(p.name)
            params.append(ast.arg(pyname))
            if p.name in ctx.addr_taken and pt.is_scalar:
                sym_p = VarSym(p.name, pt, "frame", p.pos, offset=ctx.frame_alloc(pt))
                copies.extend(self.ctx.at(self.access.var_lvalue(sym_p).store(name(pyname)), p.pos))
            else:
                sym_p = VarSym(p.name, pt, "local", p.pos, pyname=pyname, is_const=p.type.is_const)
            ctx.scope.names[p.name] = sym_p
        body = copies + self.jumps.function_body(f.body)
        if not isinstance(sym.type.ret, ct.VoidT) and not ends_in(f.body, RETURNS):
            zero = ast.Constant(0.0 if sym.type.ret.is_float else 0)
            body.append(self.ctx.at([ast.Return(zero)], f.pos)[0])
        if ctx.frame_size or ctx.list_bytes:
            push = [
                ast.Assign([name("_s", True)], name("_stack")),
                ast.Assign(
                    [name("_fp", True)],
                    ast.Call(
                        ast.Attribute(name("_s"), "push", ast.Load()),
                        [
                            ast.Constant(ctx.frame_size + ctx.list_bytes),
                            ast.Constant(bytes(ctx.frame_valid)),
                        ],
                        [],
                    ),
                ),
            ]
            pop = ast.Expr(
                ast.Call(ast.Attribute(name("_s"), "pop", ast.Load()), [name("_fp")], [])
            )
            body = push + [ast.Try(body or [ast.Pass()], [], [], [pop])]
        gl = sorted(ctx.globals_stored | ({"_budget"} if ctx.has_yield else set()))
        if gl:
            body.insert(0, ast.Global(gl))
        if sym.is_generator and not ctx.has_yield:
            body.append(ast.If(ast.Constant(False), [ast.Expr(ast.Yield(None))], []))
        fn = ast.FunctionDef(
            sym.pyname,
            ast.arguments([], params, None, [], [], None, []),
            self.ctx.at(body or [ast.Pass()], f.pos),
            [],
            None,
        )
        fn = self.ctx.at([fn], f.pos)[0]
        if self.nesting.has_splits:
            bind_splits(fn, set(gl))
        return fn
