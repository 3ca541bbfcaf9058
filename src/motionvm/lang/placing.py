"""Source positions on the generated Python `ast` of the HMPL and PDL lowerings.

A lowering builds Python nodes without locations and places each lowered statement at
the user's position: `place` gives every node under it that has none a line and column
(only the starts: `compile()` takes a missing end as the start, which is where a
fault's column points). Nested statements are lowered and placed first, and the walk
does not enter the statements placed before (it marks them), so each node is walked
about once however deep the nesting:

    place([If(test=Compare(Name('x'), ...), body=[<placed at line 5>])], 4, 2)
        the `If`, its test and the names and constants in it get line 4, column 2;
        the body, placed before, is not entered

It also owns the table of the fields that may hold located nodes (`CHILD_FIELDS`),
which the lowerings' other walks over generated trees share, `finish_locations` for a
module whose statements were not all placed, and `placed_like`. (GDL's lowering gives
each node its position as it builds it.)
"""

from __future__ import annotations

import ast

# Fields that never hold a node with a location: names, flags, numbers, contexts and
# operators (the latter are nodes, but hold nothing).
_LEAF_FIELDS = frozenset(
    ("ctx", "op", "ops", "id", "arg", "attr", "name", "asname", "type_comment", "kind")
    + ("level", "is_async", "module", "conversion", "simple", "rest", "kwd_attrs", "tag")
)
_NO_CHILDREN = (ast.Constant, ast.Global, ast.Nonlocal, ast.MatchSingleton)
"""Classes whose other fields hold values, never nodes (a constant's, names)."""

CHILD_FIELDS: dict[type, tuple[str, ...]] = {}
"""Node class -> the fields that may hold nodes with a location (`child_fields`, kept:
a walk's first look-up is here)."""


def child_fields(cls: type) -> tuple[str, ...]:
    """The fields of a node class that may hold nodes with a location (kept in
    `CHILD_FIELDS`). Their values are nodes, None or lists of nodes and None."""
    fields = CHILD_FIELDS.get(cls)
    if fields is None:
        if not issubclass(cls, ast.AST) or issubclass(cls, _NO_CHILDREN):
            fields = ()
        else:
            fields = tuple(f for f in cls._fields if f not in _LEAF_FIELDS)
        CHILD_FIELDS[cls] = fields
    return fields


_LEAVES = frozenset((ast.Name, ast.Constant))
"""Located node classes without located children: stamped where their parent finds
them, without a trip through the stack (they are most of the nodes)."""

PLACED = "_mv_placed"
"""Marks the statements `place` placed: every node under them has a location (the
walks here do not enter them)."""


def place(stmts: list[ast.stmt], line: int, col: int) -> list[ast.stmt]:
    """Give every node under `stmts` that has no location `line` and `col`, and mark
    `stmts` placed; returns `stmts`.

    The walk does not enter the statements an earlier `place` marked: every node under
    them has a location. It does enter a node with a location but no mark: one given
    another node's location (`ast.copy_location`, as PDL's chunked loops do) may hold
    nodes without, which get `line` and `col` too. A node class without a location
    (`arguments`) gets them as well; `compile()` and `ast.dump` ignore them.
    """
    fields_of, leaves = CHILD_FIELDS, _LEAVES
    stack: list[ast.AST] = stmts.copy()
    pop, push = stack.pop, stack.append
    while stack:
        node = pop()
        d = node.__dict__
        if "lineno" in d:
            if PLACED in d:
                continue
        else:
            d["lineno"] = line
            d["col_offset"] = col
        try:
            fields = fields_of[type(node)]
        except KeyError:
            fields = child_fields(type(node))
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
    for s in stmts:
        s.__dict__[PLACED] = True
    return stmts


def finish_locations(module: ast.Module) -> ast.Module:
    """`ast.fix_missing_locations(module)` for the start of every node (its end is left
    unset: `compile()` then puts it at the start, as a fault's column is its start): a
    node without a location takes its parent's. Statements marked `PLACED` are not
    entered."""
    fields_of = CHILD_FIELDS
    stack: list = [(x, 1, 0) for x in reversed(module.body)]
    pop, push = stack.pop, stack.append
    while stack:
        node, line, col = pop()
        d = node.__dict__
        if PLACED in d:
            continue
        cls = type(node)
        if "lineno" in cls._attributes:
            if "lineno" in d:
                line = d["lineno"]
            else:
                d["lineno"] = line
            if "col_offset" in d:
                col = d["col_offset"]
            else:
                d["col_offset"] = col
        try:
            fields = fields_of[cls]
        except KeyError:
            fields = child_fields(cls)
        for f in fields:
            v = d.get(f)
            if type(v) is list:
                for x in v:
                    if x is not None:
                        push((x, line, col))
            elif v is not None:
                push((v, line, col))
    return module


def placed_like(new: ast.AST, old: ast.AST) -> ast.AST:
    """`new` at the place of `old` (`ast.copy_location` for the two attributes the
    lowerings set: its attribute tests cost more than the node)."""
    od = old.__dict__
    if "lineno" in od:
        d = new.__dict__
        d["lineno"] = od["lineno"]
        d["col_offset"] = od["col_offset"]
    return new
