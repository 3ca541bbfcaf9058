"""What the HMPL loop lowerings need to know of a statement before lowering it: the names
it assigns, how deep its loops nest, whether a `break` leaves it, whether an expression
stays the same while it runs.

    for (int i = 0; i < n; i++) { s += a[i]; for (j = 0; j < 4; j++) t = j; }
assigns {s, j, t} (i only in its step), nests loops 1 deep, and `n` is invariant in it:
so it can become `for v_i in range(v_n)` (lower_range.py).
"""

from __future__ import annotations

from motionvm.lang.hmpl import nodes as n
from motionvm.lang.hmpl.analysis import _children_of, walk
from motionvm.lang.hmpl.lower_context import FunctionContext
from motionvm.lang.hmpl.symbols import VarSym


class AssignedNames:
    """The names each `for` body of one function assigns, found in one pass per body."""

    def __init__(self, cache: dict[int, set[str]] | None = None) -> None:
        """`cache`: the names found already, by `id` of the body (`analysis.FuncFacts`)."""
        self.cache = {} if cache is None else cache

    def of(self, body) -> set[str]:
        """`_assigned_names(body)` of a `for` body, found for every `for` inside it in the
        same pass (nested counting loops would otherwise walk their bodies again)."""
        got = self.cache.get(id(body))
        if got is None:
            _fill_assigned(body, self.cache)
            got = self.cache[id(body)]
        return got


def breaks_out(body) -> bool:
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


def _fill_assigned(root, cache: dict[int, set[str]]) -> None:
    """`cache[id(b)] = _assigned_names(b)` for `root` and the body `b` of every `for` in it:
    one walk, each name added to its innermost `for` body, then merged outwards."""
    sets: list[set[str]] = [set()]
    parents: list[int] = [-1]
    keys: list[int] = [id(root)]
    stack: list = [(root, 0)]
    children = _children_of
    while stack:
        x, frame = stack.pop()
        t = type(x)
        if t is tuple or t is list:
            stack.extend((y, frame) for y in x)
            continue
        if x is None:
            continue
        if t is n.Assign:
            if type(x.target) is n.Name:
                sets[frame].add(x.target.id)
        elif (t is n.Postfix or t is n.Unary) and x.op in ("++", "--", "&"):
            if type(x.operand) is n.Name:
                sets[frame].add(x.operand.id)
        for fname in children(t):
            v = getattr(x, fname)
            if v is None:
                continue
            if t is n.For and fname == "body" and id(v) not in cache:
                sets.append(set())
                parents.append(frame)
                keys.append(id(v))
                stack.append((v, len(sets) - 1))
            else:
                stack.append((v, frame))
    for k in range(len(sets) - 1, 0, -1):
        sets[parents[k]] |= sets[k]
    for k, key in enumerate(keys):
        cache[key] = sets[k]


_NESTING = (n.While, n.DoWhile, n.For, n.Switch)


def loop_depth(stmt) -> int:
    """How deep loops and switches nest inside a statement (0: none)."""
    deepest = 0
    stack = [(stmt, 0)]
    while stack:
        x, d = stack.pop()
        t = type(x)
        if t in _NESTING:
            d += 1
            deepest = max(deepest, d)
            stack.append((x.body, d))
        elif t is n.Block:
            stack.extend((y, d) for y in x.items)
        elif t is n.If:
            stack.append((x.then, d))
            if x.else_ is not None:
                stack.append((x.else_, d))
    return deepest


def invariant(ctx: FunctionContext, e, assigned: set[str]) -> bool:
    """True if `e` is built from constants and locals that the loop body does not assign."""
    if isinstance(e, (n.IntLit, n.CharLit)):
        return True
    if isinstance(e, n.Name):
        if e.id in assigned:
            return False
        sym = ctx.scope.lookup(e.id) or ctx.prog.global_symbol(e.id, ctx.task)
        return isinstance(sym, VarSym) and (sym.storage == "local" or sym.const_value is not None)
    if isinstance(e, n.Binary) and e.op in ("+", "-", "*", "<<", ">>", "&", "|"):
        return invariant(ctx, e.left, assigned) and invariant(ctx, e.right, assigned)
    if isinstance(e, n.Unary) and e.op in ("-", "+"):
        return invariant(ctx, e.operand, assigned)
    if isinstance(e, n.SizeOf):
        return True
    return False


def assigned_in_nodes(nodes: list) -> set[str]:
    """Names the nodes assign, increment or take the address of."""
    out: set[str] = set()
    for x in nodes:
        t = type(x)
        if t is n.Assign and type(x.target) is n.Name:
            out.add(x.target.id)
        elif (t is n.Postfix or t is n.Unary) and x.op in ("++", "--", "&"):
            if type(x.operand) is n.Name:
                out.add(x.operand.id)
    return out
