"""Small pieces shared by the statement lowering modules: source positions on generated
nodes, the loop context stack entries, the loop bodies' interface, and the budgeted
back-edge every loop ends with:

    backedge("_t1")
is
    _t1 -= 1
    if not _t1:
        _t1 = 65
        _budget -= 64
        if _budget < 0:
            yield
"""

from __future__ import annotations

import ast
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Protocol

from motionvm.lang.hmpl.lvalues import name


@dataclass
class LoopCtx:
    kind: str  # 'loop' | 'switch'
    cont: list = field(default_factory=list)  # statements a `continue` runs (loops)
    flag: str = ""  # switch: temp set when a `continue` leaves the switch
    flag_used: bool = False
    split: bool = False  # lowered as a nested Python function of its own (lower_split.py)
    returns: bool = False  # split: a `return` inside leaves through the nested function
    breaks: int = 0  # `break` statements that leave this loop or switch


@dataclass
class PollCtx:
    """The polling loop whose body is being lowered (`lower_poll.fixed_point`)."""

    mark: str  # the effect marker: set to 1 by each statement that may act
    on_events: bool = True  # its quiet iterations read only what a computed cycle changes
    inner: set[str] = field(default_factory=set)  # the Python locals its body declares


class LoopBodies(Protocol):
    """What the counting loops and pointer walks ask of the loop lowering
    (`lower_loops.LoopLowerer`)."""

    def loop_body(self, body, cont: list[ast.stmt], blocks: int = 1,
                  polling: PollCtx | None = None) -> tuple[list[ast.stmt], LoopCtx]:  # fmt: skip
        """The lowered body of a loop and its context; `cont`: what a `continue` runs."""


# Python allows 20 statically nested blocks (loops, try) in one function. A function
# lowers with up to 3 of its own (the frame's try/finally, the goto dispatcher's loop and
# try) and one more may come innermost (the wait loop of a `Till`); the rest hold the
# user's loops and switches (one block each; a counting loop in chunks takes two while
# there is room for them). A loop or switch that would pass them is lowered as a nested
# Python function, which starts with all its blocks free.
PY_BLOCKS = 20
LOOP_BLOCKS = PY_BLOCKS - 4
"""Python blocks of loops and switches in one generated function, at most."""
MAX_LOOP_NESTING = 256
"""Loops and switches nested in one function, at most (a documented HMPL limit)."""


# A loop charges the task's budget in units of CHUNK back-edges, counting down a local
# (much cheaper per iteration than a global); the kernel refills `_budget` each cycle.
# The countdown starts at CHUNK + 1 and fires when it reaches 0 (a truth test is cheaper
# than a comparison), so a loop yields after every CHUNK + 1 back-edges.
CHUNK = 64


def countdown_init(counter: str) -> ast.stmt:
    return ast.Assign([name(counter, True)], ast.Constant(CHUNK + 1))


def backedge(counter: str) -> list[ast.stmt]:
    """`counter -= 1; if not counter: counter = CHUNK + 1; _budget -= CHUNK; if _budget < 0: yield`."""
    dec = ast.AugAssign(name(counter, True), ast.Sub(), ast.Constant(1))
    charge = ast.AugAssign(name("_budget", True), ast.Sub(), ast.Constant(CHUNK))
    over = ast.Compare(name("_budget"), [ast.Lt()], [ast.Constant(0)])
    refill = [
        ast.Assign([name(counter, True)], ast.Constant(CHUNK + 1)),
        charge,
        ast.If(over, [ast.Expr(ast.Yield(None))], []),
    ]
    test = ast.UnaryOp(ast.Not(), name(counter))
    return [dec, ast.If(test, refill, [])]


# Fields that never hold a node with a location: names, flags, contexts and operators.
_LEAF_FIELDS = frozenset(
    ("ctx", "op", "ops", "id", "arg", "attr", "name", "type_comment", "kind", "level")
    + ("is_async", "module", "conversion")
)
_WALK: dict[type, tuple[bool, tuple[str, ...]]] = {type(None): (False, ())}


def _walk_info(cls: type) -> tuple[bool, tuple[str, ...]]:
    """(has a location, fields that may hold located nodes) of a node class, cached."""
    if not issubclass(cls, ast.AST) or cls in (ast.Constant, ast.Global, ast.Nonlocal):
        fields: tuple[str, ...] = ()
    else:
        fields = tuple(f for f in cls._fields if f not in _LEAF_FIELDS)
    info = _WALK[cls] = ("lineno" in cls._attributes, fields)
    return info


def child_fields(cls: type) -> tuple[str, ...]:
    """Fields of a node class that may hold nodes with a location (cached)."""
    info = _WALK.get(cls)
    return (info or _walk_info(cls))[1]


def placed_like(new: ast.AST, old: ast.AST) -> ast.AST:
    """`new` at the place of `old` (`ast.copy_location` for the two attributes the
    lowering sets: its attribute tests cost more than the node)."""
    od = old.__dict__
    if "lineno" in od:
        d = new.__dict__
        d["lineno"] = od["lineno"]
        d["col_offset"] = od["col_offset"]
    return new


_code_kept = True
"""False while a check-only compile lowers (`code_discarded`): its trees are never
compiled, so their nodes need no location and loops no aliased globals."""


def code_kept() -> bool:
    """Whether the code being lowered will be compiled (not a check-only compile)."""
    return _code_kept


@contextmanager
def code_discarded(discard: bool) -> Iterator[None]:
    """Inside the block (if `discard`) the lowering skips what only the generated code
    needs, not the diagnostics: `at` leaves nodes unlocated, `alias_globals` aliases
    nothing. For a compile that keeps only its diagnostics (compiles run one at a time:
    `source/deep.py`)."""
    global _code_kept
    was = _code_kept
    _code_kept = not discard
    try:
        yield
    finally:
        _code_kept = was


def at(stmts: list[ast.stmt], pos) -> list[ast.stmt]:
    """Give every generated node without a location the user's position `pos`.

    Subtrees that already carry a location were placed by an inner statement and are
    skipped, so each node is visited about once however deep the nesting. Only `lineno`
    and `col_offset` are set: `compile()` takes a missing end as the start, which is the
    place every node gets (a node class without a location, such as `arguments`, gets
    them too and `compile()` ignores them). Names and constants (most of the nodes) are
    stamped where their parent finds them, without a trip through the stack.
    """
    if not _code_kept:
        return stmts
    line, col = pos.line, pos.col - 1
    if col < 0:
        col = 0
    fields_of = _FIELDS
    leaves = _LEAVES
    stack: list[ast.AST] = stmts.copy()
    pop, push = stack.pop, stack.append
    while stack:
        node = pop()
        d = node.__dict__
        if "lineno" in d:
            continue
        d["lineno"] = line
        d["col_offset"] = col
        try:
            fields = fields_of[type(node)]
        except KeyError:
            fields = fields_of[type(node)] = child_fields(type(node))
        for f in fields:
            v = d.get(f)
            if v is None:
                continue
            tv = type(v)
            if tv is list:
                for x in v:
                    if type(x) in leaves:
                        xd = x.__dict__
                        if "lineno" not in xd:
                            xd["lineno"] = line
                            xd["col_offset"] = col
                    elif x is not None:  # a dict's `**` key, a missing default
                        push(x)
            elif tv in leaves:
                vd = v.__dict__
                if "lineno" not in vd:
                    vd["lineno"] = line
                    vd["col_offset"] = col
            else:
                push(v)
    return stmts


_LEAVES = frozenset((ast.Name, ast.Constant))
"""Located node classes without located children."""
_FIELDS: dict[type, tuple[str, ...]] = {}
"""`child_fields` of the node classes `at` has met."""
generated_fields = _FIELDS


def generated_fields_of(cls: type) -> tuple[str, ...]:
    """`child_fields(cls)`, kept in `generated_fields` (a walk's first look-up there)."""
    fields = _FIELDS[cls] = child_fields(cls)
    return fields
