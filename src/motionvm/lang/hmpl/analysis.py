"""One pass over an HMPL syntax tree: which names are address-taken, how arrays are used
(indexed to full depth, or escaping as pointers), which functions can block and whom they
call. `walk` visits every node; child fields per node class come from `nodes.py`'s
annotations and are computed once."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from operator import attrgetter

from motionvm.lang.hmpl import nodes as n

_SCALAR_FIELD_TYPES = frozenset(("SourcePos", "str", "str | None", "int", "float", "bytes", "bool"))
_CHILDREN: dict[type, tuple[str, ...]] = {}


def _children_of(cls: type) -> tuple[str, ...]:
    """The fields of a node class that can hold nodes (or tuples of them), cached."""
    names = _CHILDREN.get(cls)
    if names is None:
        names = tuple(
            f.name for f in dataclasses.fields(cls) if _spelling(f.type) not in _SCALAR_FIELD_TYPES
        )
        _CHILDREN[cls] = names
    return names


def _no_children(node) -> None:
    return None


_GETTERS: dict[type, object] = {}


def children_getter(cls: type):
    """A function of a node of class `cls` that gives what `_children_of` names in one
    call: None (no such field), the one field's value, or a tuple of the values (the
    walks push it whole: a tuple is spread on the stack when it is popped, in the order
    the fields would have been pushed one by one), cached."""
    get = _GETTERS.get(cls)
    if get is None:
        names = _children_of(cls)
        get = _GETTERS[cls] = attrgetter(*names) if names else _no_children
    return get


def _spelling(annotation) -> str:
    """A field's annotation as written (nodes.py postpones annotations: already a string)."""
    if isinstance(annotation, str):
        return annotation
    return getattr(annotation, "__name__", None) or repr(annotation)


def walk(node) -> list:
    """Every AST node under `node` (inclusive), depth first (a list: cheaper than a
    generator for the small trees it is used on)."""
    out: list = []
    add = out.append
    stack = [node]
    pop, push, extend = stack.pop, stack.append, stack.extend
    getters = _GETTERS
    while stack:
        x = pop()
        t = type(x)
        if t is tuple or t is list:
            extend(x)
            continue
        if x is None:
            continue
        add(x)
        get = getters.get(t) or children_getter(t)
        push(get(x))
    return out


@dataclass
class FuncFacts:
    """What one pass over a function body finds: waits, callees, address-taken names,
    and the names assigned (`=`, `++`, `--`, `&`) in the body and in each `for` body in
    it (by `id` of the body; a `for` body's set holds its inner loops' names too)."""

    waits: bool = False
    callees: list[str] = field(default_factory=list)
    addr_taken: set[str] = field(default_factory=set)
    assigned: dict[int, set[str]] = field(default_factory=dict)


# a label alone makes the function lower to the goto loop, whose budget may yield
_LOOPS_AND_JUMPS = frozenset((n.While, n.DoWhile, n.For, n.Goto, n.Label))


class _ForBody:
    """On the scan's stack: the body of a `for`, whose assigned names start a set."""

    __slots__ = ("body",)

    def __init__(self, body) -> None:
        self.body = body


class _LeaveFor:
    """On the scan's stack under a `for` body's nodes: back to the enclosing set."""

    __slots__ = ("outer",)

    def __init__(self, outer: int) -> None:
        self.outer = outer


_COUNTS = frozenset(("++", "--", "&"))


def scan(root, uses: dict[str, set], facts: FuncFacts | None, blocking: dict[str, bool]) -> None:
    """One pass over `root`: how names are used as arrays (into `uses`) and, if `facts` is
    given, what the code waits on, calls, assigns and takes the address of.

    Array uses: the depth of each full `a[i][j]` chain, or 'escape' (any other use:
    decays to a pointer, `&a[i]`, passed to a function, ...); `sizeof` operands are not
    uses. Facts count everything, `sizeof` operands included.
    """
    sets: list[set[str]] = [set()]
    parents = [-1]
    keys = [id(root)]
    _scan(root, uses, facts, blocking, sets, parents, keys, 0)
    if facts is not None:
        for k in range(len(sets) - 1, 0, -1):
            sets[parents[k]] |= sets[k]
        for k, key in enumerate(keys):
            facts.assigned[key] = sets[k]


def _scan(root, uses, facts, blocking, sets, parents, keys, frame: int) -> None:
    stack = [root]
    pop, push, extend = stack.pop, stack.append, stack.extend
    getters = _GETTERS
    Index, Name, Unary, Call, SizeOf = n.Index, n.Name, n.Unary, n.Call, n.SizeOf
    Assign, Postfix, For = n.Assign, n.Postfix, n.For
    loops = _LOOPS_AND_JUMPS
    counts = _COUNTS
    literals = _LITERALS
    assigned = sets[frame]
    while stack:
        x = pop()
        t = type(x)
        if t is tuple or t is list:
            extend(x)
            continue
        if x is None:
            continue
        if t is Name:
            found = uses.get(x.id)  # (no new set per name, as `setdefault` would make)
            if found is None:
                uses[x.id] = {"escape"}
            else:
                found.add("escape")
            continue
        if t in literals:
            continue
        if t is Index:
            depth, r = 0, x
            while type(r) is Index:
                push(r.index)
                depth, r = depth + 1, r.base
            if type(r) is Name:
                uses.setdefault(r.id, set()).add(depth)
            else:
                push(r)
            continue
        if t is Assign:
            if type(x.target) is Name:
                assigned.add(x.target.id)
        elif (t is Unary or t is Postfix) and x.op in counts:
            r = x.operand
            if type(r) is Name:
                assigned.add(r.id)
            if x.op == "&":
                if type(r) is Name:
                    uses.setdefault(r.id, set()).add("escape")
                    if facts is not None:
                        facts.addr_taken.add(r.id)
                    continue
                while type(r) is Index:
                    push(r.index)
                    r = r.base
                if type(r) is Name:
                    uses.setdefault(r.id, set()).add("escape")
                    continue
        elif t is SizeOf:
            if facts is not None:  # facts only
                _scan((x.target, x.dims), {}, facts, blocking, sets, parents, keys, frame)
            continue
        elif t is _ForBody:
            sets.append(set())
            parents.append(frame)
            keys.append(id(x.body))
            push(_LeaveFor(frame))
            push(x.body)
            frame = len(sets) - 1
            assigned = sets[frame]
            continue
        elif t is _LeaveFor:
            frame = x.outer
            assigned = sets[frame]
            continue
        if facts is not None:
            if t is Call:
                if type(x.func) is Name:
                    cname = x.func.id
                    if cname == "Till" or blocking.get(cname):
                        facts.waits = True
                    facts.callees.append(cname)
            elif t in loops:
                facts.waits = True
                if t is For:
                    push(x.init)
                    push(x.cond)
                    push(x.step)
                    push(_ForBody(x.body))
                    continue
        kids = (getters.get(t) or children_getter(t))(x)
        if type(kids) is tuple:
            extend(kids)
        else:
            push(kids)


_LITERALS = frozenset((n.IntLit, n.FloatLit, n.CharLit, n.StrLit))
"""Expression classes without children (and no name in them)."""


def constant_init(init) -> bool:
    """A brace list (nested) of literal numbers or characters, or a string literal."""
    if isinstance(init, (n.IntLit, n.FloatLit, n.CharLit, n.StrLit)):
        return True
    if isinstance(init, n.Unary) and init.op in ("-", "+"):
        return isinstance(init.operand, (n.IntLit, n.FloatLit, n.CharLit))
    if isinstance(init, n.InitList):
        return all(constant_init(i) for i in init.items)
    return False
