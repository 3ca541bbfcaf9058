"""Lower HMPL statements and function bodies to Python `ast` statements.

Declarations, expression statements, `if`, `return`, and whole functions live here; loops
are in `lower_loops.py`, jumps (switch, break, continue, goto) in `lower_jumps.py`. Locals
whose address is taken live in a stack frame pushed on entry and popped in a `finally`;
arrays that never decay to a pointer are Python lists. Python `ast` nodes are built with
positional arguments (in the order of the class's `_fields`): a keyword call costs about
twice as much, and a compile builds tens of thousands of nodes.
"""

from __future__ import annotations

import ast
import copy

from motionvm.lang.hmpl import ctypes_ as ct
from motionvm.lang.hmpl import nodes as n
from motionvm.lang.hmpl.cmemory import RED_ZONE, shadow_pattern
from motionvm.lang.hmpl.lower_access import AccessLowering
from motionvm.lang.hmpl.lower_expr import ExprLowering, SemanticError
from motionvm.lang.hmpl.lower_jumps import JumpLowering
from motionvm.lang.hmpl.lower_loops import LoopLowering, mark_effect
from motionvm.lang.hmpl.lower_split import SplitLowering, bind_splits
from motionvm.lang.hmpl.lower_util import LoopCtx, PollCtx, at
from motionvm.lang.hmpl.lvalues import call, name, view_code
from motionvm.lang.hmpl.symbols import FuncSym, Scope, VarSym, error_symbol
from motionvm.lang.hmpl.till_events import position_wait, status_only, time_wait, waits_on_event
from motionvm.runtime.kernel import EVENT_POLL, EVENT_WAIT, STATUS_POLL, STATUS_WAIT

# node class -> its `_s_` method of FunctionLowerer
_S_METHODS: dict[type, object] = {}


class FunctionLowerer(ExprLowering, AccessLowering, LoopLowering, JumpLowering, SplitLowering):
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
        if assigned is not None:
            self._assigned_cache = assigned  # read by LoopLowering._assigned_in
        self.prog = prog
        self.sink = prog.sink
        self.task = task
        self.scope = scope
        self.func = func
        self.addr_taken = addr_taken
        self.globals_stored: set[str] = set()
        self.loops: list[LoopCtx] = []
        self.py_blocks = 0  # Python blocks of the enclosing loops and switches
        self.outer_blocks: list[int] = []  # py_blocks outside each enclosing loop
        self.has_splits = False  # a loop became a nested function (lower_split.py)
        self.frame_size = 0
        self.frame_valid = bytearray()
        # bytes of the local arrays kept as Python lists: charged to the task's stack
        # (reserved above the frame, never valid) so that recursion stays bounded
        self.list_bytes = 0
        self._ntemp = 0
        self._pynames: set[str] = set()
        self.in_init = func is None
        self.known_ranges: dict[
            str, tuple[int, int]
        ] = {}  # range-for counters with constant bounds
        self.has_yield = False  # set whenever a yield is generated
        self.polling: PollCtx | None = None  # the polling loop being lowered (lower_loops.py)
        self.func_assigned: set[str] = set()  # names the function body assigns

    # ------------------------------------------------------------ helpers

    def temp(self) -> str:
        self._ntemp += 1
        return f"_t{self._ntemp}"

    def unique_local(self, base: str) -> str:
        cand = f"v_{base}"
        k = 1
        while cand in self._pynames:
            k += 1
            cand = f"v_{base}_{k}"
        self._pynames.add(cand)
        return cand

    def frame_alloc(self, t: ct.CType) -> int:
        align = max(8, t.align)
        off = (self.frame_size + align - 1) // align * align
        size = max(t.size, 1)
        self.frame_valid.extend(b"\x00" * (off - len(self.frame_valid)))
        end = (off + size + 7) // 8 * 8
        self.frame_valid.extend(shadow_pattern(size))
        self.frame_valid.extend(b"\x00" * (end - off - size + RED_ZONE))
        self.frame_size = end + RED_ZONE
        return off

    # ------------------------------------------------------------ declarations

    def declare_local(self, d: n.VarDecl, is_param: bool = False) -> list[ast.stmt]:
        """The statements that initialize a local; a declaration that fails still declares
        its name (with the error type if its own type failed), so that later uses of the
        name add no errors."""
        try:
            return self._declare_local(d, is_param)
        except SemanticError:
            if d.name not in self.scope.names:
                self.scope.names[d.name] = error_symbol(d.name, d.pos)
            raise

    def _declare_local(self, d: n.VarDecl, is_param: bool) -> list[ast.stmt]:
        t = self.prog.decl_type(d, self.scope, self.task)
        if d.name in self.scope.names:
            raise self.fail(d.pos, f"redefinition of '{d.name}'")
        if isinstance(t, ct.VoidT):
            raise self.fail(d.pos, f"variable '{d.name}' declared void")
        if not d.name:  # `struct S { ... };` in a block: the definition alone
            return []
        if d.is_static and self.func is not None:
            return self._declare_static_local(d, t)
        if self.prog.list_backed(d, t):
            sym = VarSym(d.name, t, "pylist", d.pos, pyname=self.unique_local(d.name))
            if self.func is not None:
                self.list_bytes += (max(t.size, 1) + 7) // 8 * 8
            out = self.init_var(sym, d.init, d.pos)
            self.scope.names[d.name] = sym
            return out
        in_mem = not t.is_scalar or d.name in self.addr_taken
        if in_mem:
            sym = VarSym(
                d.name, t, "frame", d.pos, offset=self.frame_alloc(t), is_const=d.type.is_const
            )
        else:
            sym = VarSym(
                d.name,
                t,
                "local",
                d.pos,
                pyname=self.unique_local(d.name),
                is_const=d.type.is_const,
            )
        out = self.init_var(sym, d.init, d.pos, zero_default=not is_param)
        self.scope.names[d.name] = sym
        return out

    def _declare_static_local(self, d: n.VarDecl, t: ct.CType) -> list[ast.stmt]:
        """A `static` local: one object in static memory for the whole run, visible in its
        block, given its constant initial value when the program is loaded (C: before the
        program starts); it generates no statement where it is declared."""
        mem = self.prog.mem
        addr = mem.alloc_static(t.size, d.name, align=max(8, t.align))
        sym = VarSym(d.name, t, "static", d.pos, addr=addr, is_const=d.type.is_const)
        if d.init is not None:
            image, stores = self.prog.aggregate_init(self, t, d.init, ast.Constant(addr), d.name)
            if stores:
                raise self.fail(
                    d.init.pos, f"the initializer of static '{d.name}' must be a constant"
                )
            mem.buf[addr : addr + len(image)] = image
        self.scope.names[d.name] = sym
        return []

    def init_var(self, sym: VarSym, init, pos, zero_default: bool = True) -> list[ast.stmt]:
        """Statements giving a variable its initial value (0 when there is no initializer)."""
        t = sym.type
        if sym.storage == "pylist":
            return self._init_list(sym, init, pos)
        lv = self.var_lvalue(sym)
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
            v = self.expr(init)
            return lv.store(
                self.assign_convert(v, t, init.pos, f" in the initializer of '{sym.name}'")
            )
        addr = lv.addr()
        image, stores = self.prog.aggregate_init(self, t, init, addr, sym.name)
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
            image, stores = self.prog.aggregate_init(self, t, init, ast.Constant(0), sym.name)
            assert not stores  # list_backed() admits constant initializers only
            value = call("_mklist", ast.Constant(bytes(image)), ast.Constant(view_code(elem)))
        if sym.storage == "pylist" and self.func is None:
            self.globals_stored.add(sym.pyname)
        return [ast.Assign([name(sym.pyname, True)], value)]

    # ------------------------------------------------------------ statements

    def stmts(self, items) -> list[ast.stmt]:
        out: list[ast.stmt] = []
        saved = dict(self.known_ranges)
        methods = _S_METHODS
        try:
            # in a polling loop's body the statements up to the first one that may act
            # run in its quiet iterations; that one sets the loop's marker (see
            # lower_loops.py), and what follows it runs only after it
            polling = self.polling
            for s in items:
                fn = methods.get(type(s))  # `stmt` inline
                try:
                    lowered = fn(self, s) if fn is not None else self.stmt(s)
                    if polling is not None and not self.quiet_statement(s, polling):
                        lowered = [mark_effect(polling.mark), *lowered]
                        polling = None
                    out.extend(at(lowered, s.pos))
                except SemanticError:
                    pass
                if type(s) is n.If and s.else_ is None and _ends_in(s.then, _LEAVES):
                    self._learn_from_guard(s.cond)
        finally:
            self.known_ranges = saved
        return out

    def _learn_from_guard(self, cond) -> None:
        """After `if (v < c) return ...;` the rest of the block knows v >= c.

        Only for a local integer that the function never assigns (a parameter, usually),
        compared with a constant; the fact holds until the end of the enclosing block,
        which no goto can enter (labels stand at the function's top level, each lowered
        as a block of its own). It lets range analysis drop wraps, as in `fib(n - 1)`.
        """
        if not (
            type(cond) is n.Binary
            and cond.op in ("<", "<=", ">", ">=")
            and type(cond.left) is n.Name
        ):
            return
        right = cond.right
        neg = type(right) is n.Unary and right.op == "-" and type(right.operand) is n.IntLit
        if not (type(right) is n.IntLit or neg):
            return
        c = -right.operand.value if neg else right.value
        name_ = cond.left.id
        if name_ in self.func_assigned:
            return
        sym = self.scope.lookup(name_)
        if (
            not isinstance(sym, VarSym)
            or sym.storage != "local"
            or not isinstance(sym.type, ct.IntT)
        ):
            return
        t = sym.type
        lo, hi = self.known_ranges.get(sym.pyname, (t.min, t.max))
        if cond.op == "<":
            lo = max(lo, c)
        elif cond.op == "<=":
            lo = max(lo, c + 1)
        elif cond.op == ">":
            hi = min(hi, c)
        else:
            hi = min(hi, c - 1)
        if lo <= hi:
            self.known_ranges[sym.pyname] = (lo, hi)

    def stmt(self, s) -> list[ast.stmt]:
        fn = _S_METHODS.get(type(s))
        if fn is None:
            fn = _S_METHODS[type(s)] = getattr(type(self), "_s_" + type(s).__name__)
        return fn(self, s)

    def block(self, s, kind: str = "block") -> list[ast.stmt]:
        saved = self.scope
        self.scope = Scope(saved, kind)
        try:
            items = s.items if isinstance(s, n.Block) else (s,)
            return self.stmts(items)
        finally:
            self.scope = saved

    def _s_Block(self, s: n.Block) -> list[ast.stmt]:
        return self.block(s)

    def _s_DeclStmt(self, s: n.DeclStmt) -> list[ast.stmt]:
        out: list[ast.stmt] = []
        for d in s.decls:
            try:
                if type(d) is n.Typedef:
                    self._s_Typedef(d)
                    continue
                if type(d) is n.FuncDef:  # a prototype: its name is visible in this block
                    if isinstance(self.scope.names.get(d.name), VarSym):
                        raise self.fail(
                            d.pos, f"'{d.name}' redeclared as a different kind of symbol"
                        )
                    self.scope.names[d.name] = self.prog.block_prototype(d, self.task)
                    continue
                out.extend(at(self.declare_local(d), d.pos))
            except SemanticError:
                pass
        return out

    def _s_VarDecl(self, s: n.VarDecl) -> list[ast.stmt]:
        return self.declare_local(s)

    def _s_Typedef(self, s: n.Typedef) -> list[ast.stmt]:
        """A typedef inside a function: a type name of the current block."""
        try:
            t = self.prog.resolve_typeref(s.type, self.scope, self.task)
            for dim in reversed(s.dims):
                count = self.const_int(dim) if dim is not None else None
                if count is not None and count <= 0:
                    raise self.fail(
                        dim.pos, f"size of array '{s.name}' must be positive (it is {count})"
                    )
                t = ct.array_of(t, count)
        except SemanticError:
            self.scope.types.setdefault(s.name, ct.ERROR)
            raise
        self.scope.types[s.name] = t
        return []

    def _s_Empty(self, s) -> list[ast.stmt]:
        return []

    def _s_ExprStmt(self, s: n.ExprStmt) -> list[ast.stmt]:
        e = s.expr
        if isinstance(e, n.Assign):
            return self.assignment(e, as_stmt=True)
        if isinstance(e, (n.Postfix, n.Unary)) and e.op in ("++", "--"):
            return self.incdec(e.operand, e.op, prefix=True, pos=e.pos, as_stmt=True)
        if isinstance(e, n.Call) and isinstance(e.func, n.Name) and e.func.id == "Till":
            return self._till(e)
        v = self.expr(e)
        return [ast.Expr(v.node)]

    def _till(self, e: n.Call) -> list[ast.stmt]:
        if len(e.args) != 1:
            raise self.fail(e.pos, f"Till takes 1 argument (condition), got {len(e.args)}")
        if self.in_init:
            raise self.fail(e.pos, "Till cannot be used in a global initializer")
        cond = self.cond(e.args[0])
        test = ast.UnaryOp(ast.Not(), cond)
        waited = self.event_wait(e.args[0], test)
        if waited is not None:
            return waited
        return self.poll_until(e.args[0], test)

    def poll_until(self, until, waiting: ast.expr) -> list[ast.stmt]:
        """The wait of a task, polled once per cycle, while the Python test `waiting`
        holds, that is until HMPL condition `until` (None: not known as a condition)
        holds: on the time it sleeps until the first cycle that passes it (`_till_ms`);
        on an axis's position it polls, handing the position to the controller's jumps
        (`_till_pos`); else it polls."""
        self.has_yield = True
        resolve = self._event_symbol
        timed = None if until is None else time_wait(until, resolve)
        if timed is not None:  # sleep until the first cycle whose time passes X
            wake = call("_till_ms", self.expr(timed[0]).node, ast.Constant(timed[1]))
            return [ast.While(waiting, [ast.Expr(ast.Yield(wake))], [])]
        watched = None if until is None else position_wait(until, resolve)
        if watched is not None:
            args = [self.expr(watched[0]).node, self.expr(watched[1]).node,
                    ast.Constant(watched[2])]  # fmt: skip
            wait = ast.Yield(call("_till_pos", *args, ast.Constant(EVENT_WAIT)))
            again = [copy.deepcopy(x) for x in args]
            poll = ast.Yield(call("_till_pos", *again, ast.Constant(EVENT_POLL)))
            loop = ast.While(copy.deepcopy(waiting), [ast.Expr(poll)], [])
            return [ast.If(waiting, [ast.Expr(wait), loop], [])]
        return [ast.While(waiting, [ast.Expr(ast.Yield(None))], [])]

    def event_wait(self, expr, waiting: ast.expr) -> list[ast.stmt] | None:
        """The wait of a task while the Python test `waiting` holds, polled once per
        cycle, if what decides it, HMPL condition `expr`, waits on an event
        (till_events.py): `Till(c)` (waiting: not c) and the busy loops `while (c);`
        and `while (c) RunScheduler();` (waiting: c). None if `expr` does not."""
        if not waits_on_event(expr, self._event_symbol):
            return None
        self.has_yield = True
        status = status_only(expr, self._event_symbol)
        poll = ast.While(
            copy.deepcopy(waiting), [_yield(STATUS_POLL if status else EVENT_POLL)], []
        )
        wait = _yield(STATUS_WAIT if status else EVENT_WAIT)
        return [ast.If(waiting, [wait, poll], [])]

    def _event_symbol(self, ident: str):
        """The symbol of `ident` for `waits_on_event`: a variable's, or None for a
        built-in function (a user's function of that name is a FuncSym)."""
        sym = self.scope.lookup(ident) or self.prog.global_symbol(ident, self.task)
        if sym is None and ident in self.prog.builtins:
            return None
        return sym if sym is not None else False

    def _s_If(self, s: n.If) -> list[ast.stmt]:
        test = self.cond(s.cond)
        body = self.block(s.then) or [ast.Pass()]
        orelse = self.block(s.else_) if s.else_ is not None else []
        return [ast.If(test, body, orelse)]

    def _s_Return(self, s: n.Return) -> list[ast.stmt]:
        if self.func is None:
            raise self.fail(s.pos, "'return' outside a function")
        ret = self.func.type.ret
        if s.value is None:
            if not isinstance(ret, ct.VoidT):
                raise self.fail(
                    s.pos,
                    f"'return' with no value in function '{self.func.name}' returning '{ret}'",
                )
            return [self.split_return(None) or ast.Return(None)]
        v = self.expr(s.value)
        if isinstance(ret, ct.VoidT):
            if not isinstance(v.type, ct.VoidT):
                raise self.fail(s.pos, f"'return' with a value in void function '{self.func.name}'")
            return [ast.Expr(v.node), self.split_return(None) or ast.Return(None)]
        value = self.assign_convert(
            v, ret, s.value.pos, f" in the return value of '{self.func.name}'"
        )
        return [self.split_return(value) or ast.Return(value)]

    # ------------------------------------------------------------ constants

    def const_int(self, e) -> int:
        v = self.expr(e)
        if not isinstance(v.const, int):
            raise self.fail(e.pos, "expression is not an integer constant")
        return v.const

    def resolve_type(self, tr: n.TypeRef) -> ct.CType:
        return self.prog.resolve_typeref(tr, self.scope, self.task)

    # ------------------------------------------------------------ functions

    def function(self, f: n.FuncDef, sym: FuncSym) -> ast.FunctionDef:
        self.func_assigned = self._assigned_in(f.body)  # fills every inner `for` too
        params: list[ast.arg] = []
        copies: list[ast.stmt] = []
        for p, pt in zip(f.params, sym.type.params):
            if not p.name:
                continue
            if p.name in self.scope.names:
                self.sink.error(p.pos, f"redefinition of parameter '{p.name}'")
                continue
            pyname = self.unique_local(p.name)
            params.append(ast.arg(pyname))
            if p.name in self.addr_taken and pt.is_scalar:
                sym_p = VarSym(p.name, pt, "frame", p.pos, offset=self.frame_alloc(pt))
                copies.extend(at(self.var_lvalue(sym_p).store(name(pyname)), p.pos))
            else:
                sym_p = VarSym(p.name, pt, "local", p.pos, pyname=pyname, is_const=p.type.is_const)
            self.scope.names[p.name] = sym_p
        body = copies + self.function_body(f.body)
        if not isinstance(sym.type.ret, ct.VoidT) and not _ends_in(f.body, _RETURNS):
            zero = ast.Constant(0.0 if sym.type.ret.is_float else 0)
            body.append(at([ast.Return(zero)], f.pos)[0])
        if self.frame_size or self.list_bytes:
            push = [
                ast.Assign([name("_s", True)], name("_stack")),
                ast.Assign(
                    [name("_fp", True)],
                    ast.Call(
                        ast.Attribute(name("_s"), "push", ast.Load()),
                        [
                            ast.Constant(self.frame_size + self.list_bytes),
                            ast.Constant(bytes(self.frame_valid)),
                        ],
                        [],
                    ),
                ),
            ]
            pop = ast.Expr(
                ast.Call(ast.Attribute(name("_s"), "pop", ast.Load()), [name("_fp")], [])
            )
            body = push + [ast.Try(body or [ast.Pass()], [], [], [pop])]
        gl = sorted(self.globals_stored | ({"_budget"} if self.has_yield else set()))
        if gl:
            body.insert(0, ast.Global(gl))
        if sym.is_generator and not self.has_yield:
            body.append(ast.If(ast.Constant(False), [ast.Expr(ast.Yield(None))], []))
        fn = ast.FunctionDef(
            sym.pyname,
            ast.arguments([], params, None, [], [], None, []),
            at(body or [ast.Pass()], f.pos),
            [],
            None,
        )
        fn = at([fn], f.pos)[0]
        if self.has_splits:
            bind_splits(fn, set(gl))
        return fn


def _ends_in(s, kinds: tuple) -> bool:
    """True if statement `s` never falls through: every path ends in a statement of one
    of `kinds` (`_RETURNS`: a function whose body always returns needs no `return 0`
    after it; `_LEAVES`: return, break, continue, goto)."""
    t = type(s)
    if t in kinds:
        return True
    if t is n.Block:
        return bool(s.items) and _ends_in(s.items[-1], kinds)
    if t is n.If:
        return s.else_ is not None and _ends_in(s.then, kinds) and _ends_in(s.else_, kinds)
    return False


_RETURNS = (n.Return,)
_LEAVES = (n.Return, n.Break, n.Continue, n.Goto)


def _contains_yield(body: list[ast.stmt]) -> bool:
    return any(isinstance(x, (ast.Yield, ast.YieldFrom)) for s in body for x in ast.walk(s))


def _yield(value: int) -> ast.stmt:
    """`yield value` as a statement (a task's wait, runtime/kernel.py)."""
    return ast.Expr(ast.Yield(ast.Constant(value)))
