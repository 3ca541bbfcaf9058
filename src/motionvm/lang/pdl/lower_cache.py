"""Keep global scalars in Python locals across a native loop (scalar promotion).

Every PDL variable lives in drive memory, and a memoryview access costs several
times a Python local. Inside a loop that cannot see memory any other way, the
loop's long/short global scalars are loaded into locals before it, used as locals,
and written back after it, before each yield (other tasks share the globals; a yield
is the only place where they can run) and when a fault unwinds it:

    loop(100) do s = s + k; end;
becomes
    m1 = M[1]
    m2 = M[2]
    try:
        for _ in range(100 & 65535 or 65536):
            m1 = m1 + m2
            if not -2147483648 <= m1 <= 2147483647:
                m1 = _w32(m1)
            b -= 2
            if b <= 0:
                M[1] = m1
                b = yield b
                m1 = M[1]
                m2 = M[2]
    except Exception:
        M[1] = m1
        raise
    M[1] = m1

A loop is promoted only if nothing in it reaches memory behind the compiler's back:
no pointer indirection, procedure call, sleep/wait/till, block function (memcpy ...,
initialiser lists, strings), halt/exitproc/kill. A scalar is left in memory if its
address is taken in the loop, if it is indexed there, or if a constant index there
lands on it.

An index that is a variable may run past its array into any other variable, before
or after it (manual §1.2), so it may reach a promoted scalar. Inside a promoted loop
such an access tests the widest span around its array that holds no promoted scalar
(`free_span`) instead of user memory, at the same cost; outside it, the slow path
keeps memory and locals in step (lower_expr):

    read   M[8 + m3 if -4 <= m3 < 15993 else (M.__setitem__(1, m1), <checked>)[-1]]
           (the written scalars stored first, so memory is right for the read)
    write  if -4 <= m3 < 15993: M[8 + m3] = v
           else: <stores>; M[<checked>] = v; <loads>

A chunked loop (lower_chunk) whose guard proves the span drops the test and the slow
path; a write test it cannot prove reloads every scalar, which its range analysis sees.
A float kept in a local is rounded to float32 at each store through the one-element
float view `FS` (`FS[0] = f1 + f3; f1 = FS[0]`), as a store to memory would round it.

One long array may also live in a Python list `L<word>` (`_list_backed`): when it is
the loop's only array indexed by a variable and is used only as `a[i]` inside
innermost loops. The chunks of those loops (lower_chunk) load the list lazily and
use it where their guard keeps every index inside the array; it is written back
(`_wbl`, Memory.write_block) and dropped wherever memory must be right again: before
each yield, before a pass that runs the checked code, at the end, and on a fault.
"""

from __future__ import annotations

import ast

from motionvm.lang.pdl import nodes as n
from motionvm.lang.pdl.lower_base import (
    ProgramContext,
    assign,
    nm,
    storage_kind,
    subscript,
    walk_nodes,
)
from motionvm.lang.pdl.rt_memory import FLOAT, LONG, SHORT
from motionvm.lang.pdl.symbols import VarSym

_BLOCKERS = (n.Deref, n.ProcCall, n.Delay, n.Till, n.InitList, n.StringConst, n.Kill, n.Label, n.Goto,
             n.CallLabel, n.VarDecl)  # fmt: skip
MIN_COUNT = 8
"""A loop with a constant count below this stays a plain `for` (a chunk costs a setup)."""
_BLOCK_FUNCS = ("memcpy", "memset", "memmin", "memmax", "memsum")


class Promotion:
    """The scalars of one loop kept in locals: memory key -> (view, index, local name)."""

    def __init__(
        self,
        slots: dict[tuple[str, int], str],
        written: set[str],
        lists: dict[int, tuple[int, str]] | None = None,
    ) -> None:
        self.slots = slots
        self.written = written
        self.lists = lists or {}
        """Long array kept in a Python list by chunked loops: first word -> (size, local).
        The local is None while memory holds the values (lower_chunk loads it lazily)."""
        halves: dict[str, list[int]] = {"all": [], "written": []}
        for (view, i), local in slots.items():
            hs = [i] if view == "H" else [2 * i, 2 * i + 1]
            halves["all"] += hs
            if local in written:
                halves["written"] += hs
        self._halves = {k: sorted(v) for k, v in halves.items()}

    def free_span(
        self, view: str, base: int | None, lo: int, hi: int, reads: bool
    ) -> tuple[int, int] | None:
        """[lo', hi') in `view` units: the widest span of [lo, hi) around element `base`
        that holds no promoted scalar (for `reads`, none written in the loop: memory is
        right for the others), or None if it is [lo, hi) itself. `base` None: a frame
        array, above every global; hi is then ignored."""
        halves = self._halves["written" if reads else "all"]
        if not halves:
            return None
        units = halves if view == "H" else [h >> 1 for h in halves]
        if base is None:
            return units[-1] + 1, hi
        below = [u for u in units if u < base]
        above = [u for u in units if u >= base]
        span = (below[-1] + 1 if below else lo, above[0] if above else hi)
        return None if span == (lo, hi) else span

    def flush_exprs(self) -> list[ast.expr]:
        """`M.__setitem__(i, m_i)` for each written scalar: memory right for a read."""
        return [
            ast.Call(
                ast.Attribute(nm(view), "__setitem__", ast.Load()), [ast.Constant(i), nm(local)], []
            )
            for (view, i), local in self.slots.items()
            if local in self.written
        ]

    def flush_lists(self) -> list[ast.stmt]:
        """`if L is not None: <write L back>; L = None` for each list-backed array."""
        out: list[ast.stmt] = []
        for base, (_size, local) in self.lists.items():
            test = ast.Compare(nm(local), [ast.IsNot()], [ast.Constant(None)])
            back = ast.Expr(ast.Call(nm("_wbl"), [ast.Constant(base), nm(local),
                                                            ast.Constant(1)], []))  # fmt: skip
            out.append(ast.If(test, [back, assign(nm(local, True), ast.Constant(None))], []))  # fmt: skip
        return out

    def local_of(self, view: str, index: int) -> str | None:
        return self.slots.get((view, index))

    def loads(self) -> list[ast.stmt]:
        return [
            assign(nm(local, True), subscript(view, ast.Constant(i)))
            for (view, i), local in self.slots.items()
        ] + [assign(nm(local, True), ast.Constant(None)) for _s, local in self.lists.values()]

    def stores(self) -> list[ast.stmt]:
        return [
            assign(subscript(view, ast.Constant(i), True), nm(local))
            for (view, i), local in self.slots.items()
            if local in self.written
        ] + self.flush_lists()

    def wrap(self, body: list[ast.stmt]) -> list[ast.stmt]:
        """loads; try: body except Exception: stores; raise; stores."""
        handler = ast.ExceptHandler(nm("Exception"), None, self.stores() + [ast.Raise()])
        guarded = ast.Try(body, [handler], [], [])
        return self.loads() + [guarded] + self.stores()


def promote(prog: ProgramContext, loop: n.Loop | n.While) -> Promotion | None:
    """The promotion for a top-level native loop, or None if it must stay in memory."""
    syms = prog.syms
    scalars: dict[int, VarSym] = {}
    excluded: set[int] = set()
    written: set[int] = set()
    const_hits: set[int] = set()
    """Half-words a constant index reaches."""
    indexed_arrays: list[VarSym] = []
    excluded_refs: set[int] = set()
    for node in walk_nodes(loop):
        if isinstance(node, _BLOCKERS):
            return None
        if isinstance(node, n.Simple) and node.command in ("halt", "exitproc", "ret"):
            return None
        if isinstance(node, n.FuncCall) and node.func in _BLOCK_FUNCS:
            return None
        if isinstance(node, n.AddressOf):
            sym = syms.symbol_of(node.target)
            if isinstance(sym, VarSym):
                excluded.add(id(sym))
                excluded_refs.add(id(sym))
        if isinstance(node, (n.Assign, n.IncDec)) and isinstance(node.target, n.VarRef):
            sym = syms.symbol_of(node.target)
            if isinstance(sym, VarSym):
                written.add(id(sym))
        if isinstance(node, n.VarRef):
            sym = syms.symbol_of(node)
            if not isinstance(sym, VarSym) or sym.scope != "global" or sym.type == "state":
                continue
            if node.auto_inc and isinstance(node.index, n.VarRef):
                isym = syms.symbol_of(node.index)
                if isinstance(isym, VarSym):
                    written.add(id(isym))
            if node.index is None and sym.size == 1:
                scalars[id(sym)] = sym
            elif isinstance(node.index, n.IntConst):
                excluded.add(id(sym))
                const_hits.update(_halves(_view(sym), prog.global_index(sym) + node.index.value))
            elif node.index is not None:
                excluded.add(id(sym))
                indexed_arrays.append(sym)
    lists = _list_backed(prog, loop, indexed_arrays, const_hits, excluded_refs)
    if lists:
        prog.uses_lists = True
    slots: dict[tuple[str, int], str] = {}
    names_written: set[str] = set()
    for key, sym in scalars.items():
        if key in excluded:
            continue
        view = _view(sym)
        index = prog.global_index(sym)
        if const_hits.intersection(_halves(view, index)):
            continue
        local = f"{view.lower()}{index}"
        slots[(view, index)] = local
        if key in written:
            names_written.add(local)
    return Promotion(slots, names_written, lists) if slots or lists else None


def _view(sym: VarSym) -> str:
    kind = storage_kind(sym)
    return "H" if kind == SHORT else ("F" if kind == FLOAT else "M")


def _halves(view: str, index: int) -> tuple[int, ...]:
    """The half-words of element `index` of a view (longs and floats share words)."""
    return (index,) if view == "H" else (2 * index, 2 * index + 1)


MIN_LIST_WORDS = 16
"""Smaller arrays stay in memory: a list pays a copy in and out."""


def _list_backed(
    prog: ProgramContext,
    loop: n.Loop | n.While,
    indexed: list[VarSym],
    const_hits: set[int],
    address_taken: set[int],
) -> dict[int, tuple[int, str]]:
    """The one long array the region may keep in a list (lower_chunk), if any.

    Only when it is the region's only array indexed by a variable, every reference to
    it is `a[i]` with a variable i inside an innermost `loop`, nothing takes its
    address, and no constant index of another variable lands on it.
    """
    arrays = {id(a): a for a in indexed}
    if len(arrays) != 1:
        return {}
    (a,) = arrays.values()
    if (
        a.scope != "global"
        or a.pointer
        or storage_kind(a) != LONG
        or a.size < MIN_LIST_WORDS
        or id(a) in address_taken
    ):
        return {}
    base = prog.global_index(a)
    if any(2 * base <= h < 2 * (base + a.size) for h in const_hits):
        return {}
    for node in walk_nodes(loop):
        if isinstance(node, n.VarRef) and node.index is not None:
            sym = prog.syms.symbol_of(node)
            if isinstance(sym, VarSym) and sym.scope not in ("global", "system"):
                return {}  # a frame index may run back into user memory
    inside: set[int] = set()
    for node in walk_nodes(loop):
        if isinstance(node, n.Loop) and not any(
            isinstance(x, (n.Loop, n.While)) for x in walk_nodes(node) if x is not node
        ):
            if isinstance(node.count, n.IntConst) and 0 < (node.count.value & 0xFFFF) < MIN_COUNT:
                continue
            inside.update(id(x) for x in walk_nodes(node))
    for node in walk_nodes(loop):
        if (
            isinstance(node, n.VarRef)
            and prog.syms.symbol_of(node) is a
            and (id(node) not in inside or not isinstance(node.index, n.VarRef))
        ):
            return {}
        if isinstance(node, (n.SizeOf, n.AngleRef)) and prog.syms.symbol_of(node) is a:
            return {}
    return {base: (a.size, f"L{base}")}
