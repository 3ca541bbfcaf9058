"""Lower HMPL statements and function bodies to Python `ast` statements.

Loops get a budgeted back-edge so a busy loop yields to the scheduler:
    while (x < 10) x++;
becomes
    while v_x < 10:
        v_x = (v_x + 1 + 2147483648 & 4294967295) - 2147483648
        _budget -= 1
        if _budget < 0:
            yield
`continue` repeats the loop's step and back-edge before jumping. A `switch` becomes a
one-pass `while True:` whose groups test `matched or value == case`, so C fall-through and
`break` keep their meaning. Locals whose address is taken live in a stack frame pushed
on entry and popped in a `finally`.
"""

from __future__ import annotations

import ast
import copy
from dataclasses import dataclass, field

from motionvm.lang.hmpl import ctypes_ as ct
from motionvm.lang.hmpl import nodes as n
from motionvm.lang.hmpl.cmemory import RED_ZONE
from motionvm.lang.hmpl.lower_access import AccessLowering
from motionvm.lang.hmpl.lower_expr import ExprLowering, SemanticError
from motionvm.lang.hmpl.lvalues import call, const, name, view_code
from motionvm.lang.hmpl.symbols import FuncSym, Scope, VarSym


@dataclass
class _LoopCtx:
    kind: str  # 'loop' | 'switch'
    cont: list = field(default_factory=list)  # statements a `continue` runs (loops)
    flag: str = ""  # switch: temp set when a `continue` leaves the switch
    flag_used: bool = False


# A loop charges the task's budget in units of CHUNK back-edges, counting down a local
# (much cheaper per iteration than a global); the kernel refills `_budget` each cycle.
CHUNK = 64


def _countdown_init(counter: str) -> ast.stmt:
    return ast.Assign(targets=[name(counter, True)], value=ast.Constant(CHUNK))


def _backedge(counter: str) -> list[ast.stmt]:
    """`counter -= 1; if counter < 0: counter = CHUNK; _budget -= CHUNK; if _budget < 0: yield`."""
    dec = ast.AugAssign(target=name(counter, True), op=ast.Sub(), value=ast.Constant(1))
    charge = ast.AugAssign(target=name("_budget", True), op=ast.Sub(), value=ast.Constant(CHUNK))
    over = ast.Compare(left=name("_budget"), ops=[ast.Lt()], comparators=[ast.Constant(0)])
    refill = [
        ast.Assign(targets=[name(counter, True)], value=ast.Constant(CHUNK)),
        charge,
        ast.If(test=over, body=[ast.Expr(value=ast.Yield(value=None))], orelse=[]),
    ]
    test = ast.Compare(left=name(counter), ops=[ast.Lt()], comparators=[ast.Constant(0)])
    return [dec, ast.If(test=test, body=refill, orelse=[])]


_AST = ast.AST
_EXPR_CONTEXT = (ast.Load, ast.Store, ast.Del)


def _at(stmts: list[ast.stmt], pos) -> list[ast.stmt]:
    """Give every generated node without a location the user's position `pos`.

    Subtrees that already carry a location were placed by an inner statement and are
    skipped, so each node is visited about once however deep the nesting.
    """
    line, col = pos.line, max(0, pos.col - 1)
    stack: list[ast.AST] = list(stmts)
    pop, push = stack.pop, stack.append
    while stack:
        node = pop()
        if "lineno" in node._attributes:
            if getattr(node, "lineno", None) is not None:
                continue
            node.lineno = node.end_lineno = line
            node.col_offset = node.end_col_offset = col
        for value in node.__dict__.values():
            if type(value) is list:
                for v in value:
                    if isinstance(v, _AST) and not isinstance(v, _EXPR_CONTEXT):
                        push(v)
            elif isinstance(value, _AST) and not isinstance(value, _EXPR_CONTEXT):
                push(value)
    return stmts


class FunctionLowerer(ExprLowering, AccessLowering):
    """Lowers one function body (or one task's global initializers) of one task."""

    def __init__(
        self, prog, task: int, scope: Scope, func: FuncSym | None, addr_taken: set[str]
    ) -> None:
        self.prog = prog
        self.sink = prog.sink
        self.task = task
        self.scope = scope
        self.func = func
        self.addr_taken = addr_taken
        self.globals_stored: set[str] = set()
        self.loops: list[_LoopCtx] = []
        self.frame_size = 0
        self.frame_valid = bytearray()
        self._ntemp = 0
        self._pynames: set[str] = set()
        self.in_init = func is None
        self.known_ranges: dict[
            str, tuple[int, int]
        ] = {}  # range-for counters with constant bounds
        self.has_yield = False  # set whenever a yield is generated

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
        self.frame_valid.extend(b"\x01" * size)
        self.frame_valid.extend(b"\x00" * (end - off - size + RED_ZONE))
        self.frame_size = end + RED_ZONE
        return off

    # ------------------------------------------------------------ declarations

    def declare_local(self, d: n.VarDecl, is_param: bool = False) -> list[ast.stmt]:
        t = self.prog.decl_type(d, self.scope, self.task)
        if d.name in self.scope.names:
            raise self.fail(d.pos, f"redefinition of '{d.name}'")
        if isinstance(t, ct.VoidT):
            raise self.fail(d.pos, f"variable '{d.name}' declared void")
        if self.prog.list_backed(d, t):
            sym = VarSym(d.name, t, "pylist", d.pos, pyname=self.unique_local(d.name))
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
        out: list[ast.stmt] = [ast.Expr(value=call("_fill", addr, ast.Constant(bytes(image))))]
        return out + stores

    def _init_list(self, sym: VarSym, init, pos) -> list[ast.stmt]:
        """`v_a = [0] * N`, or the constant initializer's values unpacked at load time."""
        t = sym.type
        count, elem = 1, t
        while isinstance(elem, ct.ArrayT):
            count, elem = count * (elem.n or 0), elem.elem
        zero = ast.Constant(0.0 if elem.is_float else 0)
        if init is None:
            value = ast.BinOp(left=ast.List(elts=[zero], ctx=ast.Load()), op=ast.Mult(), right=ast.Constant(count))
        else:
            image, stores = self.prog.aggregate_init(self, t, init, ast.Constant(0), sym.name)
            assert not stores  # list_backed() admits constant initializers only
            value = call("_mklist", ast.Constant(bytes(image)), ast.Constant(view_code(elem)))
        if sym.storage == "pylist" and self.func is None:
            self.globals_stored.add(sym.pyname)
        return [ast.Assign(targets=[name(sym.pyname, True)], value=value)]

    # ------------------------------------------------------------ statements

    def stmts(self, items) -> list[ast.stmt]:
        out: list[ast.stmt] = []
        for s in items:
            try:
                out.extend(_at(self.stmt(s), s.pos))
            except SemanticError:
                pass
        return out

    def stmt(self, s) -> list[ast.stmt]:
        return getattr(self, "_s_" + type(s).__name__)(s)

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
                out.extend(_at(self.declare_local(d), d.pos))
            except SemanticError:
                pass
        return out

    def _s_VarDecl(self, s: n.VarDecl) -> list[ast.stmt]:
        return self.declare_local(s)

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
        return [ast.Expr(value=v.node)]

    def _till(self, e: n.Call) -> list[ast.stmt]:
        if len(e.args) != 1:
            raise self.fail(e.pos, f"Till takes 1 argument (condition), got {len(e.args)}")
        if self.in_init:
            raise self.fail(e.pos, "Till cannot be used in a global initializer")
        test = ast.UnaryOp(op=ast.Not(), operand=self.cond(e.args[0]))
        self.has_yield = True
        return [ast.While(test=test, body=[ast.Expr(value=ast.Yield(value=None))], orelse=[])]

    def _s_If(self, s: n.If) -> list[ast.stmt]:
        test = self.cond(s.cond)
        body = self.block(s.then) or [ast.Pass()]
        orelse = self.block(s.else_) if s.else_ is not None else []
        return [ast.If(test=test, body=body, orelse=orelse)]

    def _loop_body(self, body, cont: list[ast.stmt]) -> list[ast.stmt]:
        self.has_yield = True  # every loop has a budgeted back-edge
        self.loops.append(_LoopCtx("loop", cont))
        try:
            return self.block(body)
        finally:
            self.loops.pop()

    def _s_While(self, s: n.While) -> list[ast.stmt]:
        test = self.cond(s.cond)
        b = self.temp()
        cont = _backedge(b) + [ast.Continue()]
        body = self._loop_body(s.body, cont) + _backedge(b)
        return [_countdown_init(b), ast.While(test=test, body=body, orelse=[])]

    def _s_DoWhile(self, s: n.DoWhile) -> list[ast.stmt]:
        b = self.temp()
        exit_ = [
            ast.If(
                test=ast.UnaryOp(op=ast.Not(), operand=self.cond(s.cond)),
                body=[ast.Break()],
                orelse=[],
            )
        ]
        cont = _at(exit_, s.cond.pos) + _backedge(b) + [ast.Continue()]
        body = self._loop_body(s.body, cont)
        exit2 = [
            ast.If(
                test=ast.UnaryOp(op=ast.Not(), operand=self.cond(s.cond)),
                body=[ast.Break()],
                orelse=[],
            )
        ]
        loop = ast.While(
            test=ast.Constant(True), body=body + _at(exit2, s.cond.pos) + _backedge(b), orelse=[]
        )
        return [_countdown_init(b), loop]

    def _s_For(self, s: n.For) -> list[ast.stmt]:
        saved = self.scope
        self.scope = Scope(saved, "block")
        try:
            out: list[ast.stmt] = []
            if s.init is not None:
                out.extend(_at(self.stmt(s.init), s.init.pos))
            fast = self._range_for(s)
            if fast is not None:
                return out + fast
            b = self.temp()
            test = self.cond(s.cond) if s.cond is not None else ast.Constant(True)
            step = (
                _at(self._s_ExprStmt(n.ExprStmt(s.step.pos, s.step)), s.step.pos)
                if s.step is not None
                else []
            )
            cont = step + _backedge(b) + [ast.Continue()]
            body = self._loop_body(s.body, cont)
            step2 = (
                _at(self._s_ExprStmt(n.ExprStmt(s.step.pos, s.step)), s.step.pos)
                if s.step is not None
                else []
            )
            out.append(_countdown_init(b))
            out.append(ast.While(test=test, body=body + step2 + _backedge(b), orelse=[]))
            return out
        finally:
            self.scope = saved

    def _range_for(self, s: n.For) -> list[ast.stmt] | None:
        """`for (i = a; i < b; i += c)` with i and b untouched by the body -> `for v_i in range(...)`.

        Only for a local int32/int64 (or increasing uint32) counter and a bound built from
        constants and locals the body does not assign; the C value of i after the loop is
        restored in the loop's `else` when i outlives the loop.
        """
        ivar = self._counter_of(s)
        if ivar is None:
            return None
        sym = self.scope.lookup(ivar)
        if (
            not isinstance(sym, VarSym)
            or sym.storage != "local"
            or sym.type not in (ct.INT, ct.I64, ct.U32)
        ):
            return None
        cond, step = s.cond, s.step
        if not (
            isinstance(cond, n.Binary)
            and cond.op in ("<", "<=", ">", ">=")
            and isinstance(cond.left, n.Name)
            and cond.left.id == ivar
        ):
            return None
        inc = self._step_of(step, ivar)
        assigned = _assigned_names(s.body)
        step_var = None
        if (
            inc is None
            and isinstance(step, n.Assign)
            and step.op == "+="
            and isinstance(step.target, n.Name)
            and step.target.id == ivar
            and cond.op in ("<", "<=")
            and self._invariant(step.value, assigned)
        ):
            try:
                sv = self.expr(step.value)
            except SemanticError:
                return None
            if not sv.type.is_integer or ct.common_arith(sym.type, sv.type) != sym.type:
                return None
            step_var = self.convert(sv, sym.type, step.pos)
            inc = "var"
        if inc is None:
            return None
        if inc != "var" and (
            (inc > 0) != (cond.op in ("<", "<=")) or (inc < 0 and not sym.type.signed)
        ):
            return None
        if ivar in assigned or not self._invariant(cond.right, assigned):
            return None
        try:
            bound = self.expr(cond.right)
        except SemanticError:
            return None
        if not bound.type.is_integer or ct.common_arith(sym.type, bound.type) != sym.type:
            return None
        stop = self.convert(bound, sym.type, cond.pos)
        if cond.op in ("<=", ">="):
            stop = ast.BinOp(
                left=stop,
                op=ast.Add() if inc == "var" or inc > 0 else ast.Sub(),
                right=ast.Constant(1),
            )
        chunked = not _breaks_out(s.body)
        b = self.temp()
        cont = [ast.Continue()] if chunked else _backedge(b) + [ast.Continue()]
        start = self._start_range(s)
        known = None
        if start is not None and bound.rng is not None:
            if inc == "var" or inc > 0:
                known = (start[0], max(start[0], bound.rng[1] - (1 if cond.op == "<" else 0)))
            else:
                known = (min(start[1], bound.rng[0] + (1 if cond.op == ">" else 0)), start[1])
        if known is not None:
            self.known_ranges[sym.pyname] = known  # lets indexing skip its bounds check
        try:
            body = self._loop_body(s.body, cont) + ([] if chunked else _backedge(b))
        finally:
            self.known_ranges.pop(sym.pyname, None)
        pre: list[ast.stmt] = []
        if inc == "var":
            # a run-time step must be positive (0 or less would never reach the bound)
            st = self.temp()
            pre.append(ast.Assign(targets=[name(st, True)], value=step_var))
            ok = ast.Compare(left=name(st), ops=[ast.Gt()], comparators=[ast.Constant(0)])
            step_node = ast.IfExp(test=ok, body=name(st), orelse=call("_bad_step", name(st)))
        else:
            step_node = const(inc)
        if chunked:
            return pre + self._chunked_range(sym, stop, step_node, body, outlives=not isinstance(s.init, n.DeclStmt))
        pre.append(_countdown_init(b))
        rng = call("range", name(sym.pyname), stop, step_node)
        outlives = not isinstance(s.init, n.DeclStmt)
        orelse: list[ast.stmt] = []
        if outlives:
            r = self.temp()
            pre.append(ast.Assign(targets=[name(r, True)], value=rng))
            rng = name(r)
            final = ast.BinOp(
                left=ast.Attribute(value=name(r), attr="start", ctx=ast.Load()),
                op=ast.Add(),
                right=ast.BinOp(
                    left=call("len", name(r)),
                    op=ast.Mult(),
                    right=ast.Attribute(value=name(r), attr="step", ctx=ast.Load()),
                ),
            )
            orelse = [ast.Assign(targets=[name(sym.pyname, True)], value=final)]
        loop = ast.For(target=name(sym.pyname, True), iter=rng, body=body, orelse=orelse)
        return pre + [loop]

    def _chunked_range(self, sym: VarSym, stop: ast.expr, step: ast.expr, body: list[ast.stmt],
                       outlives: bool) -> list[ast.stmt]:
        """The counting loop in chunks of CHUNK values, charging the budget once per chunk:

            _r = range(v_i, STOP, STEP)
            for _k in range(0, len(_r), 64):
                for v_i in _r[_k:_k + 64]:
                    BODY
                _budget -= 64
                if _budget < 0:
                    yield
            else:
                v_i = _r.start + len(_r) * _r.step   # C's value after the loop, if i outlives it
        """
        r, k = self.temp(), self.temp()
        pre = [ast.Assign(targets=[name(r, True)], value=call("range", name(sym.pyname), stop, step))]
        chunk = ast.Subscript(
            value=name(r),
            slice=ast.Slice(lower=name(k), upper=ast.BinOp(left=name(k), op=ast.Add(), right=ast.Constant(CHUNK))),
            ctx=ast.Load(),
        )
        inner = ast.For(target=name(sym.pyname, True), iter=chunk, body=body or [ast.Pass()], orelse=[])
        over = ast.Compare(left=name("_budget"), ops=[ast.Lt()], comparators=[ast.Constant(0)])
        charge = [
            ast.AugAssign(target=name("_budget", True), op=ast.Sub(), value=ast.Constant(CHUNK)),
            ast.If(test=over, body=[ast.Expr(value=ast.Yield(value=None))], orelse=[]),
        ]
        orelse: list[ast.stmt] = []
        if outlives:
            final = ast.BinOp(
                left=ast.Attribute(value=name(r), attr="start", ctx=ast.Load()),
                op=ast.Add(),
                right=ast.BinOp(left=call("len", name(r)), op=ast.Mult(),
                                right=ast.Attribute(value=name(r), attr="step", ctx=ast.Load())),
            )
            orelse = [ast.Assign(targets=[name(sym.pyname, True)], value=final)]
        outer = ast.For(target=name(k, True), iter=call("range", ast.Constant(0), call("len", name(r)), ast.Constant(CHUNK)),
                        body=[inner] + charge, orelse=orelse)
        return pre + [outer]

    def _start_range(self, s: n.For) -> tuple[int, int] | None:
        """Known bounds of a range-for counter's start value."""
        init = s.init
        e = None
        if isinstance(init, n.DeclStmt):
            e = init.decls[0].init
        elif isinstance(init, n.ExprStmt) and isinstance(init.expr, n.Assign):
            e = init.expr.value
        if e is None:
            return None
        saved = self.sink.items[:]
        try:
            return self.expr(e).rng
        except SemanticError:
            return None
        finally:
            self.sink.items[:] = saved

    @staticmethod
    def _counter_of(s: n.For) -> str | None:
        init = s.init
        if isinstance(init, n.DeclStmt) and len(init.decls) == 1:
            d = init.decls[0]
            if not d.dims and d.init is not None and not isinstance(d.init, n.InitList):
                return d.name
        if isinstance(init, n.ExprStmt) and isinstance(init.expr, n.Assign) and init.expr.op == "=":
            if isinstance(init.expr.target, n.Name):
                return init.expr.target.id
        return None

    @staticmethod
    def _step_of(step, ivar: str) -> int | None:
        if isinstance(step, (n.Postfix, n.Unary)) and step.op in ("++", "--"):
            if isinstance(step.operand, n.Name) and step.operand.id == ivar:
                return 1 if step.op == "++" else -1
        if (
            isinstance(step, n.Assign)
            and step.op in ("+=", "-=")
            and isinstance(step.target, n.Name)
        ):
            if step.target.id == ivar and isinstance(step.value, n.IntLit) and step.value.value > 0:
                return step.value.value if step.op == "+=" else -step.value.value
        return None

    def _invariant(self, e, assigned: set[str]) -> bool:
        """True if `e` is built from constants and locals that the loop body does not assign."""
        if isinstance(e, (n.IntLit, n.CharLit)):
            return True
        if isinstance(e, n.Name):
            if e.id in assigned:
                return False
            sym = self.scope.lookup(e.id) or self.prog.global_symbol(e.id, self.task)
            return isinstance(sym, VarSym) and (
                sym.storage == "local" or sym.const_value is not None
            )
        if isinstance(e, n.Binary) and e.op in ("+", "-", "*", "<<", ">>", "&", "|"):
            return self._invariant(e.left, assigned) and self._invariant(e.right, assigned)
        if isinstance(e, n.Unary) and e.op in ("-", "+"):
            return self._invariant(e.operand, assigned)
        if isinstance(e, n.SizeOf):
            return True
        return False

    def _s_Break(self, s: n.Break) -> list[ast.stmt]:
        if not self.loops:
            raise self.fail(s.pos, "'break' outside a loop or switch")
        return [ast.Break()]

    def _s_Continue(self, s: n.Continue) -> list[ast.stmt]:
        if not any(c.kind == "loop" for c in self.loops):
            raise self.fail(s.pos, "'continue' outside a loop")
        return self._continue_from(len(self.loops) - 1, s.pos)

    def _continue_from(self, level: int, pos) -> list[ast.stmt]:
        while level >= 0 and self.loops[level].kind == "switch":
            sw = self.loops[level]
            sw.flag_used = True
            return [
                ast.Assign(targets=[name(sw.flag, True)], value=ast.Constant(True)),
                ast.Break(),
            ]
        if level < 0:
            raise self.fail(pos, "'continue' outside a loop")
        return [self._clone(x) for x in self.loops[level].cont]

    @staticmethod
    def _clone(node: ast.stmt) -> ast.stmt:
        return copy.deepcopy(node)

    def _s_Switch(self, s: n.Switch) -> list[ast.stmt]:
        v = self.expr(s.expr)
        if not v.type.is_integer:
            raise self.fail(s.expr.pos, f"switch quantity is not an integer (it is '{v.type}')")
        t = ct.promote(v.type)
        sw, matched, flag = self.temp(), self.temp(), self.temp()
        out: list[ast.stmt] = [
            ast.Assign(targets=[name(sw, True)], value=self.convert(v, t, s.pos)),
            ast.Assign(targets=[name(matched, True)], value=ast.Constant(False)),
        ]
        items = s.body.items if isinstance(s.body, n.Block) else (s.body,)
        groups: list[tuple[list, list]] = []  # (labels, statements)
        values: dict[int, object] = {}
        for it in items:
            if isinstance(it, (n.Case, n.Default)):
                if groups and not groups[-1][1]:
                    groups[-1][0].append(it)
                else:
                    groups.append(([it], []))
                if isinstance(it, n.Case):
                    try:
                        cv = ct.wrap_int(self.const_int(it.value), t)
                    except SemanticError:
                        continue
                    if cv in values:
                        self.sink.error(it.pos, f"duplicate case value {cv}")
                    values[cv] = it
            elif groups:
                groups[-1][1].append(it)
            elif not isinstance(it, n.Empty):
                self.sink.warning(it.pos, "statement before the first case label is never executed")
        ctx = _LoopCtx("switch", flag=flag)
        self.loops.append(ctx)
        saved = self.scope
        self.scope = Scope(saved, "block")
        try:
            body: list[ast.stmt] = []
            for labels, stmts in groups:
                tests: list[ast.expr] = [name(matched)]
                for lab in labels:
                    if isinstance(lab, n.Default):
                        others = ast.Tuple(elts=[const(k) for k in values], ctx=ast.Load())
                        tests.append(
                            ast.Compare(left=name(sw), ops=[ast.NotIn()], comparators=[others])
                        )
                    else:
                        try:
                            cv = ct.wrap_int(self.const_int(lab.value), t)
                        except SemanticError:
                            continue
                        tests.append(
                            ast.Compare(left=name(sw), ops=[ast.Eq()], comparators=[const(cv)])
                        )
                inner = [ast.Assign(targets=[name(matched, True)], value=ast.Constant(True))]
                inner += self.stmts(stmts)
                body.extend(
                    _at(
                        [ast.If(test=ast.BoolOp(op=ast.Or(), values=tests), body=inner, orelse=[])],
                        labels[0].pos,
                    )
                )
        finally:
            self.scope = saved
            self.loops.pop()
        body.append(ast.Break())
        if ctx.flag_used:
            out.append(ast.Assign(targets=[name(flag, True)], value=ast.Constant(False)))
        out.append(ast.While(test=ast.Constant(True), body=body, orelse=[]))
        if ctx.flag_used:
            out.append(
                ast.If(
                    test=name(flag), body=self._continue_from(len(self.loops) - 1, s.pos), orelse=[]
                )
            )
        return out

    def _s_Case(self, s: n.Case) -> list[ast.stmt]:
        raise self.fail(s.pos, "'case' label not directly inside a switch")

    def _s_Default(self, s: n.Default) -> list[ast.stmt]:
        raise self.fail(s.pos, "'default' label not directly inside a switch")

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
            return [ast.Return(value=None)]
        v = self.expr(s.value)
        if isinstance(ret, ct.VoidT):
            if not isinstance(v.type, ct.VoidT):
                raise self.fail(s.pos, f"'return' with a value in void function '{self.func.name}'")
            return [ast.Expr(value=v.node), ast.Return(value=None)]
        return [
            ast.Return(
                value=self.assign_convert(
                    v, ret, s.value.pos, f" in the return value of '{self.func.name}'"
                )
            )
        ]

    # ------------------------------------------------------------ constants

    def const_int(self, e) -> int:
        v = self.expr(e)
        if not isinstance(v.const, int):
            raise self.fail(e.pos, "expression is not an integer constant")
        return v.const

    def resolve_type(self, tr: n.TypeRef) -> ct.CType:
        return self.prog.resolve_typeref(tr, self.scope, self.task)

    # ------------------------------------------------------------ goto

    def function_body(self, body: n.Block) -> list[ast.stmt]:
        """The body; with labels, a dispatcher loop over the segments between them.

            _lbl = 0
            while True:
                try:
                    if _lbl <= 0: <statements before the first label>
                    if _lbl <= 1: <statements after label 1>
                    break
                except _Goto as _g:
                    _lbl = _g.args[0]   # plus a budgeted back-edge

        `goto L` raises `_Goto(index of L)`, so it leaves nested loops and switches too.
        Labels must stand at the top level of the function body.
        """
        labels = [it for it in body.items if isinstance(it, n.Label)]
        self.labels = {}
        for lab in labels:
            if lab.name in self.labels:
                self.sink.error(lab.pos, f"duplicate label '{lab.name}'")
            self.labels[lab.name] = len(self.labels) + 1
        if not labels:
            return self.block(body, "function")
        saved = self.scope
        self.scope = Scope(saved, "function")
        try:
            segments: list[list[ast.stmt]] = [[]]
            for it in body.items:
                if isinstance(it, n.Label):
                    segments.append([])
                    continue
                segments[-1].extend(self.stmts([it]))
        finally:
            self.scope = saved
        lbl, g, b = self.temp(), self.temp(), self.temp()
        self.has_yield = True
        tries: list[ast.stmt] = []
        for k, seg in enumerate(segments):
            test = ast.Compare(left=name(lbl), ops=[ast.LtE()], comparators=[ast.Constant(k)])
            tries.append(ast.If(test=test, body=seg or [ast.Pass()], orelse=[]))
        tries.append(ast.Break())
        handler = ast.ExceptHandler(
            type=name("_Goto"),
            name=g,
            body=[
                ast.Assign(
                    targets=[name(lbl, True)],
                    value=ast.Subscript(
                        value=ast.Attribute(value=name(g), attr="args", ctx=ast.Load()),
                        slice=ast.Constant(0),
                        ctx=ast.Load(),
                    ),
                ),
            ]
            + _backedge(b),
        )
        loop = ast.While(
            test=ast.Constant(True),
            body=[ast.Try(body=tries, handlers=[handler], orelse=[], finalbody=[])],
            orelse=[],
        )
        pre = [ast.Assign(targets=[name(lbl, True)], value=ast.Constant(0)), _countdown_init(b)]
        return _at(pre + [loop], body.pos)

    def _s_Goto(self, s: n.Goto) -> list[ast.stmt]:
        k = getattr(self, "labels", {}).get(s.label)
        if k is None:
            from motionvm.source.suggest import did_you_mean

            raise self.fail(
                s.pos,
                f"label '{s.label}' used but not defined{did_you_mean(s.label, list(getattr(self, 'labels', {})))}",
            )
        return [ast.Raise(exc=call("_Goto", ast.Constant(k)), cause=None)]

    def _s_Label(self, s: n.Label) -> list[ast.stmt]:
        raise self.fail(s.pos, f"label '{s.name}' must stand at the top level of the function body")

    # ------------------------------------------------------------ functions

    def function(self, f: n.FuncDef, sym: FuncSym) -> ast.FunctionDef:
        params: list[ast.arg] = []
        copies: list[ast.stmt] = []
        for p, pt in zip(f.params, sym.type.params):
            if not p.name:
                continue
            if p.name in self.scope.names:
                self.sink.error(p.pos, f"redefinition of parameter '{p.name}'")
                continue
            pyname = self.unique_local(p.name)
            params.append(ast.arg(arg=pyname))
            if p.name in self.addr_taken and pt.is_scalar:
                sym_p = VarSym(p.name, pt, "frame", p.pos, offset=self.frame_alloc(pt))
                copies.extend(_at(self.var_lvalue(sym_p).store(name(pyname)), p.pos))
            else:
                sym_p = VarSym(p.name, pt, "local", p.pos, pyname=pyname, is_const=p.type.is_const)
            self.scope.names[p.name] = sym_p
        body = copies + self.function_body(f.body)
        if not isinstance(sym.type.ret, ct.VoidT):
            zero = ast.Constant(0.0 if sym.type.ret.is_float else 0)
            body.append(_at([ast.Return(value=zero)], f.pos)[0])
        if self.frame_size:
            push = [
                ast.Assign(targets=[name("_s", True)], value=name("_stack")),
                ast.Assign(targets=[name("_fp", True)], value=ast.Call(
                    func=ast.Attribute(value=name("_s"), attr="push", ctx=ast.Load()),
                    args=[ast.Constant(self.frame_size), ast.Constant(bytes(self.frame_valid))], keywords=[])),
            ]
            pop = ast.Expr(value=ast.Call(func=ast.Attribute(value=name("_s"), attr="pop", ctx=ast.Load()),
                                          args=[name("_fp")], keywords=[]))
            body = push + [ast.Try(body=body or [ast.Pass()], handlers=[], orelse=[], finalbody=[pop])]
        gl = sorted(self.globals_stored | ({"_budget"} if self.has_yield else set()))
        if gl:
            body.insert(0, ast.Global(names=gl))
        if sym.is_generator and not self.has_yield:
            body.append(
                ast.If(
                    test=ast.Constant(False),
                    body=[ast.Expr(value=ast.Yield(value=None))],
                    orelse=[],
                )
            )
        fn = ast.FunctionDef(
            name=sym.pyname,
            args=ast.arguments(
                posonlyargs=[],
                args=params,
                vararg=None,
                kwonlyargs=[],
                kw_defaults=[],
                kwarg=None,
                defaults=[],
            ),
            body=_at(body or [ast.Pass()], f.pos),
            decorator_list=[],
            returns=None,
        )
        return _at([fn], f.pos)[0]


def _breaks_out(body) -> bool:
    """True if a `break` in `body` would leave this loop (not a nested loop or switch)."""
    stack = [body]
    while stack:
        x = stack.pop()
        t = type(x)
        if t is n.Break:
            return True
        if t in (n.While, n.DoWhile, n.For, n.Switch):
            continue
        if t is n.Block:
            stack.extend(x.items)
        elif t is n.If:
            stack.append(x.then)
            if x.else_ is not None:
                stack.append(x.else_)
    return False


def _assigned_names(body) -> set[str]:
    """Names the statement assigns, increments or takes the address of."""
    from motionvm.lang.hmpl.program import walk

    out: set[str] = set()
    for x in walk(body):
        t = type(x)
        if t is n.Assign and type(x.target) is n.Name:
            out.add(x.target.id)
        elif (
            (t is n.Postfix or t is n.Unary)
            and x.op in ("++", "--", "&")
            and type(x.operand) is n.Name
        ):
            out.add(x.operand.id)
    return out


def _contains_yield(body: list[ast.stmt]) -> bool:
    return any(isinstance(x, (ast.Yield, ast.YieldFrom)) for s in body for x in ast.walk(s))
