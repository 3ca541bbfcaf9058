"""The nesting of loops and switches, and deep loop nests split into nested Python functions.

`Nesting` keeps the stack of enclosing loops and switches (`lower_util.LoopCtx`) that
`break`, `continue` and `return` consult, and counts the Python blocks they take.

Python compiles at most 20 statically nested blocks (loops, try) into one function, far
fewer than the loops HMPL lets a function nest. A loop or switch that would pass the
blocks left in the generated function becomes a nested function of its own, called
where the loop stood:

    def _t9():
        nonlocal v_i, _t4          # the enclosing locals the loop assigns
        global _budget
        while ...:                 # the loop, with all 20 blocks free again
            ...
    _t10 = yield from _t9()        # a plain call when nothing inside waits
    if _t10 is not None:           # only when a `return` stands inside
        return _t10[0]             # `return _t10` from a split inside another one

Jumps keep their meaning: `break` and `continue` of the loop itself stay inside the
function; a `continue` that leaves a split switch sets the switch's flag, tested after
the call as before; a `return` inside returns `(value,)`, handed out level by level; a
`goto` raises `_Goto`, which passes through the calls. Ordinary programs never nest this
deep, so their generated code is unchanged.
"""

from __future__ import annotations

import ast

from motionvm.lang.hmpl import ctypes_ as ct
from motionvm.lang.hmpl.lower_context import FunctionContext
from motionvm.lang.hmpl.lower_util import LOOP_BLOCKS, MAX_LOOP_NESTING, LoopCtx
from motionvm.lang.hmpl.lvalues import name
from motionvm.lang.placing import child_fields

_NO_ARGS = ast.arguments(
    posonlyargs=[], args=[], vararg=None, kwonlyargs=[], kw_defaults=[], kwarg=None, defaults=[]
)


class Nesting:
    """The loops and switches enclosing the statement being lowered, the Python blocks
    they take, and the nested functions that those past the limit become."""

    def __init__(self, ctx: FunctionContext) -> None:
        self.ctx = ctx
        self.loops: list[LoopCtx] = []
        """The enclosing loops and switches, innermost last."""
        self.py_blocks = 0
        """Python blocks of the enclosing loops and switches (in the generated function)."""
        self.outer_blocks: list[int] = []
        """`py_blocks` outside each enclosing loop."""
        self.has_splits = False
        """A loop became a nested function: `bind_splits` must declare its names."""

    def nest(self, pos, blocks: int = 1) -> bool:
        """Enter a loop or switch taking `blocks` Python blocks; past the limit of nested
        loops and switches, a compile error at `pos`. True if it must be lowered as a
        nested function (the generated one has no blocks left for it): `split_off`.
        Pair with `unnest`."""
        if len(self.loops) >= MAX_LOOP_NESTING:
            raise self.ctx.fail(
                pos,
                f"loops and switches nested more than {MAX_LOOP_NESTING} deep in one function"
                " (the limit of HMPL); move the inner ones into a function",
            )
        split = self.py_blocks + blocks > LOOP_BLOCKS
        self.outer_blocks.append(self.py_blocks)
        self.py_blocks = blocks if split else self.py_blocks + blocks
        return split

    def unnest(self) -> None:
        self.py_blocks = self.outer_blocks.pop()

    def room(self, blocks: int) -> bool:
        """True if `blocks` more Python blocks fit inside the enclosing ones."""
        return self.py_blocks + blocks <= LOOP_BLOCKS

    def placed(self, ctx: LoopCtx, loop: ast.stmt) -> list[ast.stmt]:
        """The loop where it stands, or the call of the nested function it became."""
        return self.split_off(ctx, loop) if ctx.split else [loop]

    def split_off(self, ctx, loop: ast.stmt) -> list[ast.stmt]:
        """The call of a new nested function holding `loop` (ctx: the loop's LoopCtx)."""
        fname = self.ctx.temp()
        fn = ast.FunctionDef(
            name=fname,
            args=_NO_ARGS,
            body=[loop],
            decorator_list=[],
            returns=None,
        )
        fn._split = True  # bind_splits gives it its nonlocal and global declarations
        self.has_splits = True
        fcall = ast.Call(func=name(fname), args=[], keywords=[])
        if ctx.kind == "loop" or _yields([loop]):
            fcall = ast.YieldFrom(value=fcall)
        if not ctx.returns:
            return [fn, ast.Expr(value=fcall)]
        code = self.ctx.temp()
        if any(c.split for c in self.loops):
            out: ast.expr | None = name(code)  # still inside a split: hand the code out
        elif self.ctx.func is not None and isinstance(self.ctx.func.type.ret, ct.VoidT):
            out = None
        else:
            out = ast.Subscript(value=name(code), slice=ast.Constant(0), ctx=ast.Load())
        test = ast.Compare(left=name(code), ops=[ast.IsNot()], comparators=[ast.Constant(None)])
        return [
            fn,
            ast.Assign(targets=[name(code, True)], value=fcall),
            ast.If(test=test, body=[ast.Return(value=out)], orelse=[]),
        ]

    def split_return(self, value: ast.expr | None) -> ast.stmt | None:
        """Inside a split loop, the `return` statement leaving it: `return (value,)`;
        None outside one."""
        inside = False
        for c in self.loops:
            if c.split:
                c.returns = inside = True
        if not inside:
            return None
        return ast.Return(value=ast.Tuple(elts=[value or ast.Constant(None)], ctx=ast.Load()))


def bind_splits(fn: ast.FunctionDef, declared_global: set[str]) -> None:
    """Give each split function in `fn` its declarations: `nonlocal` for the names it
    assigns that an enclosing function binds, `global` for the globals it assigns."""
    todo: list[tuple[ast.FunctionDef, frozenset[str]]] = [(fn, frozenset())]
    while todo:
        f, above = todo.pop()
        stores, nested = _scan(f.body)
        if getattr(f, "_split", False):
            decls: list[ast.stmt] = []
            glob = sorted(stores & declared_global)
            if glob:
                decls.append(ast.Global(names=glob))
            outer = sorted((stores & above) - declared_global)
            if outer:
                decls.append(ast.Nonlocal(names=outer))
            for d in decls:
                ast.copy_location(d, f)
            f.body[:0] = decls
        else:
            stores |= {a.arg for a in f.args.args}
        bound = above | (stores - declared_global)
        todo.extend((g, bound) for g in nested)


def _scan(body: list[ast.stmt]) -> tuple[set[str], list[ast.FunctionDef]]:
    """Names assigned in `body` (not in nested functions), and those nested functions."""
    stores: set[str] = set()
    nested: list[ast.FunctionDef] = []
    stack: list = list(body)
    pop, push, extend = stack.pop, stack.append, stack.extend
    while stack:
        x = pop()
        t = type(x)
        if t is ast.Name:
            if type(x.ctx) is ast.Store:
                stores.add(x.id)
            continue
        if t is ast.FunctionDef:
            stores.add(x.name)
            nested.append(x)
            continue
        if t is ast.ExceptHandler and x.name:
            stores.add(x.name)
        fields = child_fields(t)
        if not fields:
            continue
        d = x.__dict__
        for f in fields:
            v = d.get(f)
            if v is not None:
                if type(v) is list:
                    extend(v)
                else:
                    push(v)
    return stores, nested


def _yields(body: list[ast.stmt]) -> bool:
    """`body` yields (not counting nested functions): its function is a generator."""
    stack: list = list(body)
    while stack:
        x = stack.pop()
        t = type(x)
        if t is ast.Yield or t is ast.YieldFrom:
            return True
        fields = child_fields(t)
        if t is ast.FunctionDef or not fields:
            continue
        d = x.__dict__
        for f in fields:
            v = d.get(f)
            if v is not None:
                if type(v) is list:
                    stack.extend(v)
                else:
                    stack.append(v)
    return False
