"""Run an innermost native `loop(n)` in budget-sized chunks without its run-time checks.

A native loop charges its statements to the task budget `b` and tests `b <= 0` after
every pass (lower_flow). When a pass costs at most KMAX statements, the next
`(b - 1) // KMAX` passes cannot use the budget up, so they may run as one plain
`for` chunk: the unconditional statement count is charged once for the chunk, and
no pass tests the budget (exactly the passes that would not have yielded).

Inside a chunk the wrap checks and index bounds checks that cannot fail are dropped,
under a guard evaluated once at chunk entry (range analysis, see `_Ranges`): a
variable the loop never writes keeps its entry value, one it only steps by constants
(`j++`, `n = n - 2`) stays within `v + (_k - 1) * step` of it, so e.g.

    loop(n) do u = a[j]; j++; ... end;
becomes
    _n1 = m4 & 65535 or 65536
    while _n1:
        _k1 = (b - 1) // 8
        if _k1 > _n1:
            _k1 = _n1
        if _k1 > 0 and m3 >= 0 and m3 + _k1 <= 15992:
            _n1 -= _k1
            b -= 5 * _k1
            for _ in range(_k1):
                m6 = vM8[m3]           # vM8 = M[8:USER_END]: the guard proved the index
                m3 = m3 + 1            # no wrap check: m3 + _k1 <= 15992
                ...
        else:
            _n1 -= 1
            <the pass as before: every check, then `b -= ...; if b <= 0: yield`>

If the guard fails (an index runs past the end, a counter would wrap), that pass runs
the checked code, which faults or wraps exactly as before. An index inside a promoted
loop must stay inside the span of memory that holds no promoted scalar (lower_cache):
a read's check is proved like any other, a split store (`if <span>: <store> else:
<store the scalars; store; reload them>`) becomes its first branch; if one cannot be
proved, the analysis runs again seeing the reloads (`retry`). A float assigned an integer
the analysis bounds by 2**24 skips the float32 rounding (`f = (i & 1023) + 0.0`).
"""

from __future__ import annotations

import ast
from dataclasses import dataclass
from typing import Protocol

from motionvm.lang.pdl import nodes as n
from motionvm.lang.pdl.lower_base import (
    ProgramContext,
    assign,
    binop,
    clone,
    const,
    nm,
    walk_nodes,
)
from motionvm.lang.pdl.lower_cache import MIN_COUNT, Promotion
from motionvm.lang.pdl.lower_expr import USER_END, wrap_inline


class LoopHost(Protocol):
    """What a chunked loop uses of the body it stands in (`lower_body.BodyLowerer`)."""

    prog: ProgramContext
    counter: int  # numbers the temporaries of each loop


_LIMITS = {32: (-0x8000_0000, 0x7FFF_FFFF), 16: (-0x8000, 0x7FFF)}
_VIEW_END = {"M": USER_END, "H": USER_END * 2}
_F32_EXACT = 1 << 24


# ---------------------------------------------------------------- eligibility


def _nested_loop(s: n.Loop) -> bool:
    return any(isinstance(x, (n.Loop, n.While)) for x in walk_nodes(s) if x is not s)


def _budget_only(body: list[ast.stmt]) -> bool:
    """True if the pass never yields, and uses `b` only in `b -= constant`."""
    for s in body:
        for node in ast.walk(s):
            if isinstance(node, (ast.Yield, ast.YieldFrom, ast.Await, ast.Continue, ast.Break)):
                return False
            if isinstance(node, ast.Return) and node.value is not None:
                return False
            if isinstance(node, ast.AugAssign) and _is_charge(node):
                continue
            if isinstance(node, ast.Name) and node.id == "b" and not _charged_name(s, node):
                return False
    return True


def _is_charge(s: object) -> bool:
    return (
        isinstance(s, ast.AugAssign)
        and isinstance(s.target, ast.Name)
        and s.target.id == "b"
        and isinstance(s.op, ast.Sub)
        and isinstance(s.value, ast.Constant)
        and type(s.value.value) is int
    )


def _charged_name(root: ast.stmt, name: ast.Name) -> bool:
    return any(_is_charge(x) and x.target is name for x in ast.walk(root))


def _costs(body: list[ast.stmt]) -> tuple[int, int]:
    """(statements charged on every pass, most statements one pass can charge)."""
    fixed = 0
    extra = 0
    for s in body:
        if _is_charge(s):
            fixed += s.value.value  # type: ignore[attr-defined]
        elif isinstance(s, ast.If):
            extra += max(sum(_costs(s.body)), sum(_costs(s.orelse)))
        elif isinstance(s, ast.Try):
            extra += max([sum(_costs(s.body))] + [sum(_costs(h.body)) for h in s.handlers])
    return fixed, extra


# ---------------------------------------------------------------- affine bounds


@dataclass(frozen=True)
class Bound:
    """c + sum(coef * name): names are entry values of locals (coef +-1) or `_k`."""

    c: int
    terms: tuple[tuple[str, int], ...] = ()
    loose: bool = False
    """Derived from a type's range (an unknown value): a guard on it would rarely hold."""

    def __add__(self, o: Bound) -> Bound:
        t = dict(self.terms)
        for k, v in o.terms:
            t[k] = t.get(k, 0) + v
        return Bound(self.c + o.c, _norm(t), self.loose or o.loose)

    def neg(self) -> Bound:
        return Bound(-self.c, tuple((k, -v) for k, v in self.terms), self.loose)

    def shift(self, d: int) -> Bound:
        return Bound(self.c + d, self.terms, self.loose)


def _norm(t: dict[str, int]) -> tuple[tuple[str, int], ...]:
    return tuple(sorted((k, v) for k, v in t.items() if v))


Range = tuple[Bound | None, Bound | None]
_NONE: Range = (None, None)


def _exact(c: int) -> Range:
    return (Bound(c), Bound(c))


def _join(a: Range, b: Range, fallback: Range) -> Range:
    out = []
    for i, (x, y) in enumerate(zip(a, b)):
        if x is None or y is None:
            out.append(None)
        elif x.terms == y.terms:
            pick = min if i == 0 else max
            out.append(Bound(pick(x.c, y.c), x.terms, x.loose or y.loose))
        else:
            return fallback
    return (out[0], out[1])


# ---------------------------------------------------------------- the analysis


@dataclass
class _Var:
    bits: int
    kind: str  # "inv", "ind", "gen"
    up: int = 0
    down: int = 0
    uncond: bool = True


class _Ranges:
    """Drops the checks of one chunk body that its guard proves, and builds the guard."""

    def __init__(
        self,
        ints: dict[str, int],
        k: str,
        views: dict[tuple[str, int], str],
        sizes: dict[int, int] | None = None,
        trust: bool = True,
    ) -> None:
        self.trust = trust
        """Take every split store's fast branch (`alias_guard`, lower_expr) as the one
        that runs: the guard must prove each, else `retry` asks for a run without."""
        self.retry = False
        self.sizes = sizes or {}
        """First word -> size of the list-backed arrays: their indexes must stay inside."""
        self.ints = ints
        self.k = k
        self.views = views
        self.guard_ge: dict[tuple[tuple[str, int], ...], int] = {}
        self.guard_le: dict[tuple[tuple[str, int], ...], int] = {}
        self.vars: dict[str, _Var] = {}
        self.failed = False

    # ------------------------------------------------------------ classification

    def classify(self, body: list[ast.stmt]) -> None:
        for name, bits in self.ints.items():
            self.vars[name] = _Var(bits, "inv")
        self._scan(body, cond=False)

    def _scan(self, body: list[ast.stmt], cond: bool) -> None:
        skip = False
        for i, s in enumerate(body):
            if skip:
                skip = False
                continue
            if isinstance(s, ast.Assign):
                for t in s.targets:
                    if isinstance(t, ast.Name) and t.id in self.vars:
                        self._site(t.id, s, cond)
                if _wrap_target(s) is not None and _is_wrap_check(body, i + 1, _wrap_target(s)):
                    skip = True
            elif isinstance(s, ast.If):
                self._scan(s.body, True)
                if not (self.trust and hasattr(s, "alias_guard")):
                    self._scan(s.orelse, True)  # a split store's slow branch reloads scalars
            elif isinstance(s, ast.Try):
                self._scan(s.body, True)
                for h in s.handlers:
                    self._scan(h.body, True)
            elif isinstance(s, (ast.AugAssign, ast.AnnAssign)):
                t = s.target
                if isinstance(t, ast.Name) and t.id in self.vars:
                    self.vars[t.id].kind = "gen"
            for x in ast.walk(s):
                if isinstance(x, ast.NamedExpr) and x.target.id in self.vars:
                    self.vars[x.target.id].kind = "gen"

    def _site(self, name: str, s: ast.Assign, cond: bool) -> None:
        v = self.vars[name]
        step = _step_of(s, name)
        if v.kind == "gen" or step is None:
            v.kind = "gen"
            return
        v.kind = "ind"
        if step > 0:
            v.up += step
        else:
            v.down -= step
        if cond:
            v.uncond = False

    def start_state(self) -> dict[str, Range]:
        k = self.k
        st: dict[str, Range] = {}
        for name, v in self.vars.items():
            if v.kind == "inv":
                b = Bound(0, ((name, 1),))
                st[name] = (b, b)
            elif v.kind == "ind":
                if v.uncond:
                    d = v.up - v.down
                    lo_s, hi_s = min(d, 0), max(d, 0)
                else:
                    lo_s, hi_s = -v.down, v.up
                st[name] = (_ind_bound(name, k, lo_s), _ind_bound(name, k, hi_s))
            else:
                st[name] = self.type_range(name)
        return st

    def summary(self, name: str) -> Range:
        """Every value a variable takes during the chunk (a safe join)."""
        v = self.vars[name]
        if v.kind == "ind":
            return (
                _ind_bound(name, self.k, -v.down, whole=True),
                _ind_bound(name, self.k, v.up, whole=True),
            )
        if v.kind == "inv":
            b = Bound(0, ((name, 1),))
            return (b, b)
        return self.type_range(name)

    def type_range(self, name: str) -> Range:
        lo, hi = _LIMITS[self.ints[name]]
        return (Bound(lo, (), True), Bound(hi, (), True))

    # ------------------------------------------------------------ expressions

    def rng(self, e: ast.expr, st: dict[str, Range]) -> Range:
        if isinstance(e, ast.Constant) and type(e.value) is int:
            return _exact(e.value)
        if isinstance(e, ast.Name):
            return st.get(e.id, _NONE)
        if isinstance(e, ast.Subscript) and isinstance(e.value, ast.Name):
            v = e.value.id
            if v == "M" or v.startswith("vM"):
                lo, hi = _LIMITS[32]
            elif v == "H" or v.startswith("vH"):
                lo, hi = _LIMITS[16]
            elif v == "ST":
                return (Bound(0), Bound(1))
            else:
                return _NONE
            return (Bound(lo, (), True), Bound(hi, (), True))
        if isinstance(e, ast.UnaryOp) and isinstance(e.op, ast.USub):
            lo, hi = self.rng(e.operand, st)
            return (hi.neg() if hi else None, lo.neg() if lo else None)
        if isinstance(e, ast.BinOp):
            if isinstance(e.op, ast.BitAnd):
                for side in (e.left, e.right):
                    if (
                        isinstance(side, ast.Constant)
                        and type(side.value) is int
                        and side.value >= 0
                    ):
                        return (Bound(0), Bound(side.value))
                return _NONE
            a = self.rng(e.left, st)
            b = self.rng(e.right, st)
            if isinstance(e.op, ast.Add):
                return (_add(a[0], b[0]), _add(a[1], b[1]))
            if isinstance(e.op, ast.Sub):
                return (
                    _add(a[0], b[1].neg() if b[1] else None),
                    _add(a[1], b[0].neg() if b[0] else None),
                )
            if isinstance(e.op, ast.Mult):
                for x, y in ((e.left, b), (e.right, a)):
                    if (
                        isinstance(x, ast.Constant)
                        and type(x.value) is int
                        and x.value in (-1, 0, 1)
                    ):
                        if x.value == 0:
                            return _exact(0)
                        if x.value == 1:
                            return y
                        return (y[1].neg() if y[1] else None, y[0].neg() if y[0] else None)
                if all(r is not None and not r.terms for r in a + b):
                    ps = [p.c * q.c for p in a for q in b]  # type: ignore[union-attr]
                    loose = any(r.loose for r in a + b)  # type: ignore[union-attr]
                    return (Bound(min(ps), (), loose), Bound(max(ps), (), loose))
            return _NONE
        return _NONE

    # ------------------------------------------------------------ guards

    def require(self, r: Range, lo: int | None, hi: int | None) -> bool:
        """Add the guard terms that keep `r` within [lo, hi]; False if they cannot."""
        add_ge: list[tuple[tuple[tuple[str, int], ...], int]] = []
        add_le: list[tuple[tuple[tuple[str, int], ...], int]] = []
        if lo is not None:
            b = r[0]
            if b is None:
                return False
            if not b.terms:
                if b.c < lo:
                    return False
            elif b.loose:
                return False
            else:
                add_ge.append((b.terms, lo - b.c))
        if hi is not None:
            b = r[1]
            if b is None:
                return False
            if not b.terms:
                if b.c > hi:
                    return False
            elif b.loose:
                return False
            else:
                add_le.append((b.terms, hi - b.c))
        for t, v in add_ge:
            self.guard_ge[t] = max(v, self.guard_ge.get(t, v))
        for t, v in add_le:
            self.guard_le[t] = min(v, self.guard_le.get(t, v))
        return True

    def guard(self) -> list[ast.expr]:
        out: list[ast.expr] = []
        for table, op in ((self.guard_ge, ast.GtE), (self.guard_le, ast.LtE)):
            for terms, v in table.items():
                out.append(ast.Compare(_terms_expr(terms), [op()], [const(v)]))
        return out

    # ------------------------------------------------------------ the walk

    def block(self, body: list[ast.stmt], st: dict[str, Range]) -> list[ast.stmt]:
        out: list[ast.stmt] = []
        i = 0
        while i < len(body):
            s = body[i]
            i += 1
            if isinstance(s, ast.Assign):
                s = self.exprs(s, st)
                target = _wrap_target(s)
                if target is not None and target in self.ints:
                    r = self.rng(s.value, st)
                    if i < len(body) and _is_wrap_check(body, i, target):
                        chk = body[i]
                        i += 1
                        lo, hi = _LIMITS[self.ints[target]]
                        need_lo, need_hi = _check_sides(chk, lo, hi)
                        if self.require(r, need_lo, need_hi):
                            out.append(s)
                            st[target] = r
                            continue
                        if self.vars[target].kind == "ind":
                            self.failed = True
                        out += [s, chk]
                        st[target] = self.type_range(target)
                        continue
                    out.append(s)
                    if self.vars[target].kind == "ind":
                        self.failed = True  # a step without a wrap check: not ours
                    # no check: the kind of the value keeps it within the type
                    known = r[0] is not None and r[1] is not None
                    st[target] = r if known else self.type_range(target)
                    continue
                fast = self._exact_float(s, body, i, st)
                if fast is not None:
                    out.append(fast)
                    i += 1
                    continue
                out.append(s)
                for t in s.targets:
                    if isinstance(t, ast.Name) and t.id in self.ints:
                        st[t.id] = self.summary(t.id)
            elif isinstance(s, ast.If) and self.trust and hasattr(s, "alias_guard"):
                out += self._split_store(s, st)
            elif isinstance(s, ast.If):
                s.test = self.expr(s.test, st)
                a, b = dict(st), dict(st)
                s.body = self.block(s.body, a) or [ast.Pass()]
                s.orelse = self.block(s.orelse, b)
                for name in st:
                    st[name] = _join(a[name], b[name], self.summary(name))
                out.append(s)
            elif isinstance(s, ast.Try):
                a = dict(st)
                s.body = self.block(s.body, a)
                joined = a
                for h in s.handlers:
                    hb = dict(st)
                    h.body = self.block(h.body, hb)
                    joined = {k: _join(joined[k], hb[k], self.summary(k)) for k in st}
                st.update(joined)
                out.append(s)
            elif isinstance(s, ast.Expr):
                s.value = self.expr(s.value, st)
                out.append(s)
            else:
                out.append(s)
        return out

    def _split_store(self, s: ast.If, st: dict[str, Range]) -> list[ast.stmt]:
        """The fast branch of a split store (lower_expr) if the guard keeps its index inside
        the span without promoted scalars (on a view if inside the view), else `retry`."""
        view, base = s.alias_guard  # type: ignore[attr-defined]
        test = s.test
        assert isinstance(test, ast.Compare)
        name = test.comparators[0]
        lo, hi = test.left.value, test.comparators[1].value  # type: ignore[attr-defined]
        assert isinstance(name, ast.Name)
        r = st.get(name.id, _NONE)
        if not self.require(r, lo, hi - 1):
            self.retry = True
            return [s]
        if view in _VIEW_END and self.require(r, 0, self._view_limit(view, base, hi) - 1):
            vname = f"v{view}{base}"
            for x in s.body:
                for node in ast.walk(x):
                    if (
                        isinstance(node, ast.Subscript)
                        and isinstance(node.value, ast.Name)
                        and node.value.id == view
                        and isinstance(node.slice, ast.BinOp)
                        and isinstance(node.slice.left, ast.Constant)
                        and node.slice.left.value == base
                        and isinstance(node.slice.op, ast.Add)
                        and isinstance(node.slice.right, ast.Name)
                        and node.slice.right.id == name.id
                    ):
                        node.value = nm(vname)
                        node.slice = nm(name.id)
                        self.views[(view, base)] = vname
        return self.block(s.body, st)

    def _exact_float(
        self, s: ast.Assign, body: list[ast.stmt], i: int, st: dict[str, Range]
    ) -> ast.stmt | None:
        """`FS[0] = e; f = FS[0]` with e an integer |e| <= 2**24 -> `f = e + 0.0`."""
        t = s.targets[0]
        if not (
            isinstance(t, ast.Subscript)
            and isinstance(t.value, ast.Name)
            and t.value.id == "FS"
            and i < len(body)
        ):
            return None
        nxt = body[i]
        if not (
            isinstance(nxt, ast.Assign)
            and isinstance(nxt.targets[0], ast.Name)
            and isinstance(nxt.value, ast.Subscript)
            and isinstance(nxt.value.value, ast.Name)
            and nxt.value.value.id == "FS"
        ):
            return None
        r = self.rng(s.value, st)
        if not self.require(r, -_F32_EXACT, _F32_EXACT):
            return None
        value = ast.BinOp(s.value, ast.Add(), const(0.0))
        return ast.copy_location(assign(nm(nxt.targets[0].id, True), value), nxt)

    def exprs(self, s: ast.Assign, st: dict[str, Range]) -> ast.Assign:
        s.value = self.expr(s.value, st)
        s.targets = [self.expr(t, st) for t in s.targets]  # type: ignore[misc]
        return s

    def expr(self, e: ast.expr, st: dict[str, Range]) -> ast.expr:
        """Replace the provable index checks inside `e`."""
        for node in ast.walk(e):
            for field, value in ast.iter_fields(node):
                if isinstance(value, ast.expr):
                    new = self._index(value, st)
                    if new is not value:
                        setattr(node, field, new)
                elif isinstance(value, list):
                    for j, x in enumerate(value):
                        if isinstance(x, ast.expr):
                            new = self._index(x, st)
                            if new is not x:
                                value[j] = new
        new = self._index(e, st)
        return new

    def _view_limit(self, view: str, base: int, hi: int) -> int:
        """One past the last index of a `v<view><base>` access (below `hi`, which is at
        most the view's end): a list-backed array's size."""
        return min(self.sizes.get(base, hi), hi) if view == "M" else hi

    def _index(self, e: ast.expr, st: dict[str, Range]) -> ast.expr:
        if not (isinstance(e, ast.Subscript) and isinstance(e.value, ast.Name)):
            return e
        view = e.value.id
        chk = e.slice
        if not (isinstance(chk, ast.IfExp) and isinstance(chk.test, ast.Compare)):
            return e
        test = chk.test
        if not (
            len(test.ops) == 2
            and isinstance(test.ops[0], ast.LtE)
            and isinstance(test.ops[1], ast.Lt)
            and isinstance(test.left, ast.Constant)
            and isinstance(test.comparators[1], ast.Constant)
        ):
            return e
        lo, hi = test.left.value, test.comparators[1].value
        mid = test.comparators[0]
        if isinstance(mid, ast.NamedExpr):
            r = self.rng(mid.value, st)
            if self.require(r, lo, hi - 1):
                e.slice = mid.value
            return e
        if not (isinstance(mid, ast.Name) and isinstance(chk.body, ast.BinOp)):
            return e
        addr = chk.body
        r = self.rng(mid, st)
        if (
            view in _VIEW_END
            and isinstance(addr.left, ast.Constant)
            and isinstance(addr.op, ast.Add)
            and hi <= _VIEW_END[view] - addr.left.value
            and self.require(r, 0, self._view_limit(view, addr.left.value, hi) - 1)
        ):
            base = addr.left.value
            vname = f"v{view}{base}"
            self.views[(view, base)] = vname
            return ast.copy_location(ast.Subscript(nm(vname), nm(mid.id), e.ctx), e)
        if self.require(r, lo, hi - 1):
            e.slice = addr
        return e


def _ind_bound(name: str, k: str, step: int, whole: bool = False) -> Bound:
    """v + step * (_k - 1) (at a pass's start), or v + step * _k (anywhere in the chunk)."""
    terms = {name: 1}
    if step:
        terms[k] = step
    return Bound(0 if whole else -step, _norm(terms))


def _add(a: Bound | None, b: Bound | None) -> Bound | None:
    if a is None or b is None:
        return None
    return a + b


def _terms_expr(terms: tuple[tuple[str, int], ...]) -> ast.expr:
    e: ast.expr | None = None
    for name, coef in terms:
        mag = abs(coef)
        term: ast.expr = nm(name) if mag == 1 else ast.BinOp(const(mag), ast.Mult(), nm(name))
        if e is None:
            e = term if coef > 0 else ast.UnaryOp(ast.USub(), term)
        else:
            e = ast.BinOp(e, ast.Add() if coef > 0 else ast.Sub(), term)
    assert e is not None
    return e


def _step_of(s: ast.Assign, name: str) -> int | None:
    """c for `v = v + c` / -c for `v = v - c`, else None."""
    if len(s.targets) != 1 or not isinstance(s.targets[0], ast.Name):
        return None
    v = s.value
    if (
        isinstance(v, ast.BinOp)
        and isinstance(v.left, ast.Name)
        and v.left.id == name
        and isinstance(v.right, ast.Constant)
        and type(v.right.value) is int
    ):
        if isinstance(v.op, ast.Add):
            return v.right.value
        if isinstance(v.op, ast.Sub):
            return -v.right.value
    return None


def _wrap_target(s: ast.stmt) -> str | None:
    if isinstance(s, ast.Assign) and len(s.targets) == 1 and isinstance(s.targets[0], ast.Name):
        return s.targets[0].id
    return None


def _is_wrap_check(body: list[ast.stmt], i: int, name: str) -> bool:
    """`if v > HI: v = wrap` / `if v < LO: ...` / `if not LO <= v <= HI: ...` at body[i]."""
    if i >= len(body):
        return False
    s = body[i]
    if not (isinstance(s, ast.If) and not s.orelse and len(s.body) == 1):
        return False
    fix = s.body[0]
    if _wrap_target(fix) != name:
        return False
    test = s.test
    if isinstance(test, ast.UnaryOp) and isinstance(test.op, ast.Not):
        test = test.operand
    if not isinstance(test, ast.Compare):
        return False
    names = [x for x in [test.left, *test.comparators] if isinstance(x, ast.Name)]
    consts = [x for x in [test.left, *test.comparators] if isinstance(x, ast.Constant)]
    return len(names) == 1 and names[0].id == name and len(consts) == len(test.comparators)


def _check_sides(chk: ast.If, lo: int, hi: int) -> tuple[int | None, int | None]:
    test = chk.test
    if isinstance(test, ast.UnaryOp):
        return lo, hi
    assert isinstance(test, ast.Compare)
    if isinstance(test.ops[0], ast.Gt):
        return None, hi
    return lo, None


# ---------------------------------------------------------------- the loop


def chunk_loop(
    body_lowerer: LoopHost,
    s: n.Loop,
    body: list[ast.stmt],
    times: ast.expr,
    promo: Promotion | None,
    slow_tail: ast.stmt,
) -> list[ast.stmt] | None:
    """The chunked form of a native `loop(n)` with pass `body`, or None if it does not apply."""
    if isinstance(s.count, n.IntConst) and 0 < (s.count.value & 0xFFFF) < MIN_COUNT:
        return None
    if _nested_loop(s) or not _budget_only(body):
        return None
    fast = clone(body)
    fixed = sum(x.value.value for x in fast if _is_charge(x))  # type: ignore[attr-defined]
    fast = [x for x in fast if not _is_charge(x)]
    _, extra = _costs(body)
    kmax = fixed + extra
    if kmax <= 0:
        return None
    lw = body_lowerer
    lw.counter += 1
    cn, ck = f"_n{lw.counter}", f"_k{lw.counter}"
    ints: dict[str, int] = {}
    if promo is not None:
        for (view, _i), local in promo.slots.items():
            if view in ("M", "H"):
                ints[local] = 32 if view == "M" else 16
    views: dict[tuple[str, int], str] = {}
    sizes = {base: size for base, (size, _) in promo.lists.items()} if promo is not None else {}
    an = _Ranges(ints, ck, views, sizes)
    an.classify(fast)
    checked = clone(fast)
    fast = an.block(fast, an.start_state())
    if an.retry:  # a split store the guard cannot prove may reload every scalar
        views.clear()
        an = _Ranges(ints, ck, views, sizes, trust=False)
        an.classify(checked)
        fast = an.block(clone(checked), an.start_state())
    if an.failed:
        an = _Ranges(ints, ck, {})
        an.vars = {}
        fast = checked
        views.clear()
    guard = [ast.Compare(nm(ck), [ast.Gt()], [const(0)])] + (an.guard() if not an.failed else [])
    test = guard[0] if len(guard) == 1 else ast.BoolOp(ast.And(), guard)

    def chunk(stmts: list[ast.stmt]) -> ast.stmt:
        rng = ast.Call(nm("range"), [nm(ck)], [])
        return ast.For(nm("_", True), rng, stmts or [ast.Pass()], [])

    run: list[ast.stmt] = [
        ast.AugAssign(nm(cn, True), ast.Sub(), nm(ck)),
        ast.AugAssign(
            nm("b", True),
            ast.Sub(),
            nm(ck) if fixed == 1 else binop(const(fixed), ast.Mult(), nm(ck)),
        ),
    ]
    flush = promo.flush_lists() if promo is not None else []
    listed = _list_variant(fast, views, promo) if not an.failed else None
    if listed is None:
        run += flush + [chunk(fast)]
    else:
        base, size, local, fast_list = listed
        # load the list when the chunk is long enough to pay for the copies
        load = ast.If(ast.BoolOp(ast.And(), [
                ast.Compare(nm(local), [ast.Is()], [const(None)]),
                ast.Compare(binop(nm(ck), ast.Mult(), const(4)), [ast.GtE()], [const(size)])]), [assign(nm(local, True), ast.Call(ast.Attribute(ast.Subscript(nm(views[("M", base)]), ast.Slice(lower=const(0), upper=const(size)), ast.Load()), "tolist", ast.Load()), [], []))], [])  # fmt: skip
        use = ast.If(
            ast.Compare(nm(local), [ast.IsNot()], [const(None)]), [chunk(fast_list)], [chunk(fast)]
        )
        run += [load, use]
    slow = [ast.AugAssign(nm(cn, True), ast.Sub(), const(1))] + flush + body + [slow_tail]
    size = binop(binop(nm("b"), ast.Sub(), const(1)), ast.FloorDiv(), const(kmax))
    loop_body: list[ast.stmt] = [
        assign(nm(ck, True), size),
        ast.If(ast.Compare(nm(ck), [ast.Gt()], [nm(cn)]), [assign(nm(ck, True), nm(cn))], []),
        ast.If(test, run, slow),
    ]
    out: list[ast.stmt] = []
    for (view, base), vname in sorted(views.items()):
        out.append(assign(nm(vname, True), nm("_" + vname)))
        lw.prog.views[vname] = (view, base, _VIEW_END[view])
    out.append(assign(nm(cn, True), times))
    out.append(ast.While(nm(cn), loop_body, []))
    return out


def _list_variant(
    fast: list[ast.stmt], views: dict[tuple[str, int], str], promo: Promotion | None
) -> tuple[int, int, str, list[ast.stmt]] | None:
    """(base, size, list local, chunk body on the list) if the region's list-backed array
    is reached here only through its view, else None."""
    if promo is None or not promo.lists:
        return None
    ((base, (size, local)),) = promo.lists.items()
    vname = views.get(("M", base))
    if vname is None:
        return None
    for s in fast:
        for node in ast.walk(s):
            if (
                isinstance(node, ast.Subscript)
                and isinstance(node.value, ast.Name)
                and node.value.id in ("M", "H", "F")
                and not isinstance(node.slice, ast.Constant)
            ):
                return None  # an access not proved: it might reach the array in memory
    out = clone(fast)
    for s in out:
        for node in ast.walk(s):
            if isinstance(node, ast.Name) and node.id == vname:
                node.id = local
    return base, size, local, _explicit_wraps(out, local)


def _explicit_wraps(body: list[ast.stmt], local: str) -> list[ast.stmt]:
    """A list does not refuse a value beyond 32 bits as memory does (ValueError): the
    `try: L[i] = v except ValueError: L[i] = _w32(v)` stores wrap explicitly instead."""
    out: list[ast.stmt] = []
    for s in body:
        if (
            isinstance(s, ast.Try)
            and len(s.body) == 1
            and isinstance(s.body[0], ast.Assign)
            and isinstance(s.body[0].targets[0], ast.Subscript)
            and isinstance(s.body[0].targets[0].value, ast.Name)
            and s.body[0].targets[0].value.id == local
        ):
            st = s.body[0]
            walrus = ast.NamedExpr(nm("_w", True), st.value)
            test = ast.Compare(const(-0x8000_0000), [ast.LtE(), ast.LtE()], [walrus, const(0x7FFF_FFFF)])  # fmt: skip
            value = ast.IfExp(test, nm("_w"), wrap_inline(nm("_w"), 32))
            out.append(ast.copy_location(assign(st.targets[0], value), st))
            continue
        if isinstance(s, ast.If):
            s.body = _explicit_wraps(s.body, local)
            s.orelse = _explicit_wraps(s.orelse, local)
        elif isinstance(s, ast.Try):
            s.body = _explicit_wraps(s.body, local)
        out.append(s)
    return out


__all__ = ["MIN_COUNT", "chunk_loop"]
