"""Lower pointer walks: a loop that steps a pointer through an object, checked per chunk.

    while (p < end) { s += *p; p++; }        (or `for (...; p < end; p++) ...`)

When the pointer is a local that only the step moves, the bound does not change in the
loop and the body is straight-line code (no call, loop, jump or `&`), the pointer's
values are known when the loop starts: `range(p, end, 4)`. The loop runs in chunks of
CHUNK + 1 values, the back-edges after which the `while` loop's countdown charges the
budget, so the yield cadence is the `while` loop's. Before each chunk one helper call
(`_inobj`) tests that the bytes the chunk's `*p` accesses lie inside one live object,
suitably aligned; if so the chunk runs a copy of the body whose `*p` reads and writes
the typed view without a check (nothing in straight-line code can end an object's life,
and no other task runs inside a chunk), else the ordinary, checked body, which faults
at the access, line and iteration it always did.

In the unchecked copy an `int` that the body only adds to or subtracts from
(`s += x;`, `s -= x;`, and reads nowhere else) is wrapped to 32 bits once per chunk,
not per element: wrapping is exact for sums at any point, and nothing can see the
local in between.

    _r = range(v_p, v_end, 4)
    for _k in range(0, len(_r), 65):
        _c = _r[_k:_k + 65]
        if _inobj(_c, 4):
            for v_p in _c:
                v_s = v_s + _I32[v_p >> 2]
            v_s = WRAP(v_s)
        else:
            for v_p in _c:
                CHECKED BODY
        if len(_c) == 65:
            _budget -= 64
            if _budget < 0:
                yield
    v_p = _r.start + len(_r) * 4
"""

from __future__ import annotations

import ast

from motionvm.lang.hmpl import ctypes_ as ct
from motionvm.lang.hmpl import nodes as n
from motionvm.lang.hmpl.analysis import walk
from motionvm.lang.hmpl.lower_access import AccessLowerer
from motionvm.lang.hmpl.lower_context import FunctionContext
from motionvm.lang.hmpl.lower_expr import ExprLowerer
from motionvm.lang.hmpl.lower_facts import assigned_in_nodes, invariant
from motionvm.lang.hmpl.lower_split import Nesting
from motionvm.lang.hmpl.lower_util import CHUNK, LoopBodies
from motionvm.lang.hmpl.lower_values import wrap_node
from motionvm.lang.hmpl.lvalues import VIEW_NAMES, call, name
from motionvm.lang.hmpl.symbols import VarSym
from motionvm.lang.placing import CHILD_FIELDS, child_fields, placed_like

_STRAIGHT = (n.Block, n.ExprStmt, n.If, n.Empty, n.DeclStmt)
"""Statements a walk's body may hold (any other: loop, switch, jump, label, return)."""


class PointerWalkLowerer:
    """Lowers the pointer walks of one function (see the module docstring)."""

    def __init__(
        self,
        ctx: FunctionContext,
        x: ExprLowerer,
        access: AccessLowerer,
        nesting: Nesting,
        loops: LoopBodies,
    ) -> None:
        self.ctx = ctx
        self.x = x
        self.access = access
        self.nesting = nesting
        self.loops = loops

    def pointer_walk(self, cond, step, body, rest_items, pos) -> list[ast.stmt] | None:
        """The chunked, checked-per-chunk form of `while (p < end) { BODY p++; }`, or
        None if the loop is not such a walk. `rest_items`: the body's statements
        without the step (for a `while`), or None to take `body` whole (a `for`)."""
        if (
            type(cond) is not n.Binary
            or cond.op not in ("<", "<=")
            or type(cond.left) is not n.Name
            or not self.nesting.room(2)
        ):
            return None
        pvar = cond.left.id
        sym = self.ctx.scope.lookup(pvar)
        if not isinstance(sym, VarSym) or sym.storage != "local":
            return None
        pt = sym.type
        if not isinstance(pt, ct.PtrT) or not pt.target.is_scalar or pt.target.size not in _SIZES:
            return None
        size = pt.target.size
        k = _step_count(step, pvar)
        if k is None:
            return None
        stmts = rest_items if rest_items is not None else (body,)
        nodes = walk(tuple(stmts))
        if not _straight(nodes):
            return None
        assigned = assigned_in_nodes(nodes)
        if pvar in assigned or not invariant(self.ctx, cond.right, assigned):
            return None
        test = self.x.cond(cond)
        if not (
            type(test) is ast.Compare
            and type(test.left) is ast.Name
            and test.left.id == sym.pyname
            and len(test.ops) == 1
        ):
            return None
        stop = test.comparators[0]
        if cond.op == "<=":
            stop = ast.BinOp(left=stop, op=ast.Add(), right=ast.Constant(1))
        stride = k * size
        sums = self._lazy_sums(nodes, {n_.id for n_ in walk(cond) if type(n_) is n.Name})
        block = n.Block(pos, tuple(stmts))
        before = len(self.ctx.sink.items)
        checked, _ = self.loops.loop_body(block, [ast.Continue()], 2)
        fast = None
        if not any(d.severity == "error" for d in self.ctx.sink.items[before:]):
            saved_items = self.ctx.sink.items[:]
            access = self.access
            saved_trust, saved_lazy = access.trusted_ptrs, access.lazy_sums
            access.trusted_ptrs = {**saved_trust, sym.pyname: size}
            access.lazy_sums = frozenset(s.pyname for s in sums)
            try:
                fast, _ = self.loops.loop_body(block, [ast.Continue()], 2)
            finally:
                access.trusted_ptrs, access.lazy_sums = saved_trust, saved_lazy
                self.ctx.sink.items[:] = saved_items
        return _chunked_walk(self.ctx, sym.pyname, stop, stride, size, checked, fast, sums)

    def _lazy_sums(self, nodes: list, in_cond: set[str]) -> list[VarSym]:
        """Local ints the body only adds to or subtracts from, as whole statements."""
        declared = {
            d.name for x in nodes if type(x) is n.DeclStmt for d in x.decls if hasattr(d, "name")
        }
        summed: dict[str, int] = {}
        for x in nodes:
            if (
                type(x) is n.ExprStmt
                and type(x.expr) is n.Assign
                and x.expr.op in ("+=", "-=")
                and type(x.expr.target) is n.Name
            ):
                summed[x.expr.target.id] = summed.get(x.expr.target.id, 0) + 1
        if not summed:
            return []
        uses: dict[str, int] = {}
        for x in nodes:
            if type(x) is n.Name and x.id in summed:
                uses[x.id] = uses.get(x.id, 0) + 1
        out = []
        for v, count in summed.items():
            if uses.get(v) != count or v in declared or v in in_cond:
                continue
            sym = self.ctx.scope.lookup(v)
            if isinstance(sym, VarSym) and sym.storage == "local" and sym.type == ct.INT:
                out.append(sym)
        return out


_SIZES = (1, 2, 4, 8)


def _step_count(step, pvar: str) -> int | None:
    """Elements the step `p++`, `++p` or `p += K` moves the pointer by; None otherwise."""
    t = type(step)
    if (t is n.Postfix or t is n.Unary) and step.op == "++":
        if type(step.operand) is n.Name and step.operand.id == pvar:
            return 1
        return None
    if (
        t is n.Assign
        and step.op == "+="
        and type(step.target) is n.Name
        and step.target.id == pvar
        and type(step.value) is n.IntLit
        and step.value.value > 0
    ):
        return step.value.value
    return None


def _straight(nodes: list) -> bool:
    """True if the statements are straight-line code: no call, loop, jump or `&`."""
    for x in nodes:
        t = type(x)
        if t is n.Call or t is n.CompoundLit:
            return False
        if t is n.Unary and x.op == "&":
            return False
        if t is n.DeclStmt:
            for d in x.decls:
                if type(d) is not n.VarDecl or d.dims or d.is_static or type(d.init) is n.InitList:
                    return False
        elif t.__name__ in _STATEMENTS and t not in _STRAIGHT:
            return False
    return True


_STATEMENTS = frozenset(
    ("While", "DoWhile", "For", "Switch", "Case", "Default", "Break", "Continue", "Return")
    + ("Goto", "Label", "FuncDef", "StructDef", "Typedef")
)


def _chunked_walk(low, pvar, stop, stride, size, checked, fast, sums) -> list[ast.stmt]:
    r, k, c = low.temp(), low.temp(), low.temp()
    span = CHUNK + 1  # the back-edges between two charges of a `while` loop's countdown
    pre = [
        ast.Assign(
            targets=[name(r, True)], value=call("range", name(pvar), stop, ast.Constant(stride))
        )
    ]
    chunk = ast.Subscript(
        value=name(r),
        slice=ast.Slice(
            lower=name(k), upper=ast.BinOp(left=name(k), op=ast.Add(), right=ast.Constant(span))
        ),
        ctx=ast.Load(),
    )

    made: dict[str, str] = {}
    for body in (checked, fast):
        if body is not None:
            pre += alias_globals(body, low, made)

    def over(body):
        return ast.For(target=name(pvar, True), iter=name(c), body=body or [ast.Pass()], orelse=[])

    if fast is not None:
        rewrap = [
            ast.Assign(targets=[name(s.pyname, True)], value=wrap_node(name(s.pyname), ct.INT))
            for s in sums
        ]
        run = [
            ast.If(
                test=call("_inobj", name(c), ast.Constant(size)),
                body=[over(fast)] + rewrap,
                orelse=[over(checked)],
            )
        ]
    else:
        run = [over(checked)]
    full = ast.Compare(left=call("len", name(c)), ops=[ast.Eq()], comparators=[ast.Constant(span)])
    charge = ast.If(
        test=full,
        body=[
            ast.AugAssign(target=name("_budget", True), op=ast.Sub(), value=ast.Constant(CHUNK)),
            ast.If(
                test=ast.Compare(
                    left=name("_budget"), ops=[ast.Lt()], comparators=[ast.Constant(0)]
                ),
                body=[ast.Expr(value=ast.Yield(value=None))],
                orelse=[],
            ),
        ],
        orelse=[],
    )
    loop = ast.For(
        target=name(k, True),
        iter=call("range", ast.Constant(0), call("len", name(r)), ast.Constant(span)),
        body=[ast.Assign(targets=[name(c, True)], value=chunk)] + run + [charge],
        orelse=[],
    )
    final = ast.BinOp(
        left=ast.Attribute(value=name(r), attr="start", ctx=ast.Load()),
        op=ast.Add(),
        right=ast.BinOp(left=call("len", name(r)), op=ast.Mult(), right=ast.Constant(stride)),
    )
    return pre + [loop, ast.Assign(targets=[name(pvar, True)], value=final)]


_VIEWS = frozenset(VIEW_NAMES.values()) | {"_SH"}


def alias_globals(
    body: list[ast.stmt], ctx: FunctionContext, made: dict[str, str] | None = None
) -> list[ast.stmt]:
    """Read the arrays a loop body indexes through locals: `_t5 = g_a` before the loop
    and `_t5[i]` in it (a local is cheaper to load than a module global). Only for the
    memory views and list-backed arrays, which are bound once before any task runs
    (global initializers run no loop) and never rebound; `body` is changed in place.
    The statements that bind the locals are returned, to stand before the loop; `made`
    (global -> local) lets several bodies share them (then only new ones are returned).
    Nothing in a check, whose code is not kept (`ctx.bytecode`)."""
    if not ctx.bytecode:
        return []
    if made is None:
        made = {}
    seen: dict[str, list[ast.Subscript]] = {}
    stored: set[str] = set()
    # a walk of the generated body without a generator step per node; names and
    # constants, most of the nodes, are looked at where their parent finds them
    Name, Constant, Subscript, Load = ast.Name, ast.Constant, ast.Subscript, ast.Load
    fields_of = CHILD_FIELDS
    stack: list = body.copy()
    pop, push = stack.pop, stack.append
    while stack:
        node = pop()
        t = type(node)
        if t is Name:
            if type(node.ctx) is not Load:
                stored.add(node.id)
            continue
        if t is Subscript:
            v = node.value
            if type(v) is Name and (v.id in _VIEWS or v.id.startswith("g_")):
                seen.setdefault(v.id, []).append(node)
        elif t is ast.Global or t is ast.Nonlocal:
            stored.update(node.names)
        d = node.__dict__
        for f in fields_of.get(t) or child_fields(t):
            v = d.get(f)
            if v is None or type(v) is Constant:
                continue
            if type(v) is list:
                for x in v:
                    if x is not None and type(x) is not Constant:
                        push(x)
            else:
                push(v)
    out: list[ast.stmt] = []
    for gname, uses in seen.items():
        if gname in stored:
            continue
        local = made.get(gname)
        if local is None:
            local = made[gname] = ctx.temp()
            out.append(ast.Assign(targets=[name(local, True)], value=name(gname)))
        for sub in uses:
            sub.value = placed_like(name(local), sub.value)
    return out
