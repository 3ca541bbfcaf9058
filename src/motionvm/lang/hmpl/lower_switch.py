"""Lower HMPL `switch` with C's fall-through.

A `switch` becomes a one-pass `while True:` whose groups test `matched or value == case`,
so C fall-through and `break` keep their meaning; a `continue` inside it sets a flag,
leaves the switch and continues the enclosing loop. A block of the body that holds a
label of the switch is opened into the body (`_open_blocks`), its scope kept; the
Python locals a label may jump past get their zero before the groups. When no group
falls into the next and every `break` ends a group, it is an if-chain instead:

    switch (a) { case 1: s++; break; case 2: t = 0;   default: s = 0; }
becomes
    _t1 = v_a
    _t2 = False
    while True:
        if _t1 == 1:
            v_s = v_s + 1 if v_s != 2147483647 else -2147483648
            break
        if _t1 == 2:
            _t2 = True
            v_t = 0
        if _t2 or _t1 not in (1, 2):
            v_s = 0
        break
"""

from __future__ import annotations

import ast

from motionvm.lang.hmpl import ctypes_ as ct
from motionvm.lang.hmpl import nodes as n
from motionvm.lang.hmpl.lower_context import FunctionContext, SemanticError
from motionvm.lang.hmpl.lower_decl import DeclLowerer
from motionvm.lang.hmpl.lower_expr import ExprLowerer
from motionvm.lang.hmpl.lower_jumps import JumpLowerer
from motionvm.lang.hmpl.lower_split import Nesting
from motionvm.lang.hmpl.lower_stmt import StatementLowerer
from motionvm.lang.hmpl.lower_util import LoopCtx
from motionvm.lang.hmpl.lvalues import const, name
from motionvm.lang.hmpl.symbols import Scope, VarSym
from motionvm.lang.placing import placed_like


class SwitchLowerer:
    """Lowers the `switch` statements of one function."""

    def __init__(
        self,
        ctx: FunctionContext,
        x: ExprLowerer,
        stmts: StatementLowerer,
        nesting: Nesting,
        jumps: JumpLowerer,
        decls: DeclLowerer,
    ) -> None:
        self.ctx = ctx
        self.x = x
        self.stmts = stmts
        self.nesting = nesting
        self.jumps = jumps
        self.decls = decls
        self.fail = ctx.fail

    def handlers(self) -> dict[type, object]:
        """The statements this part lowers: node class -> method."""
        return {n.Switch: self.s_Switch}

    def s_Switch(self, s: n.Switch) -> list[ast.stmt]:
        v = self.x.expr(s.expr)
        if not v.type.is_integer:
            raise self.fail(s.expr.pos, f"switch quantity is not an integer (it is '{v.type}')")
        t = ct.promote(v.type)
        ctx = self.ctx
        sw, matched, flag = ctx.temp(), ctx.temp(), ctx.temp()
        subject = self.x.convert(v, t, s.pos)
        out: list[ast.stmt] = [ast.Assign([name(sw, True)], subject)]
        items = _open_blocks(s.body.items if isinstance(s.body, n.Block) else (s.body,))
        for it in items:
            nested = _nested_label(it) if type(it) in _LOOPS_AND_IFS else None
            if nested is not None:
                what = "case" if isinstance(nested, n.Case) else "default"
                raise self.fail(
                    nested.pos,
                    f"'{what}' label inside a nested statement of the switch is not supported"
                    " (a jump into a loop or 'if'); put it in the switch body or a block of it",
                )
        groups: list[tuple[list, list]] = []  # (labels, statements)
        prelude: list = []  # before the first label: declared, never executed
        values: dict[int, object] = {}
        label_value: dict[int, int] = {}  # id(case label) -> its value, once lowered
        jumped_decl = False  # a declaration a label lies after: it may be jumped over
        for it in items:
            if isinstance(it, (n.Case, n.Default)):
                jumped_decl = jumped_decl or any(
                    type(x) is n.DeclStmt for x in (groups[-1][1] if groups else prelude)
                )
                if groups and not groups[-1][1]:
                    groups[-1][0].append(it)
                else:
                    groups.append(([it], []))
                if isinstance(it, n.Case):
                    try:
                        cv = ct.wrap_int(self.x.const_int(it.value), t)
                    except SemanticError:
                        continue
                    label_value[id(it)] = cv
                    if cv in values:
                        ctx.sink.error(it.pos, f"duplicate case value {cv}")
                    values[cv] = it
            elif groups:
                groups[-1][1].append(it)
            else:
                prelude.append(it)
                if not isinstance(it, (n.Empty, n.DeclStmt, n.Label, _Open, _Close)):
                    ctx.sink.warning(
                        it.pos, "statement before the first case label is never executed"
                    )
        here = LoopCtx("switch", flag=flag)
        nesting = self.nesting
        here.split = nesting.nest(s.pos)
        nesting.loops.append(here)
        saved = ctx.scope
        ctx.scope = Scope(saved, "block")
        scopes = [ctx.scope]  # the body's and its opened blocks': a label may enter them
        try:
            self._group_stmts(prelude, scopes)  # declares; its code never runs
            lowered: list[tuple[ast.expr, list[ast.stmt], object]] = []  # each group's
            chain: list[tuple[ast.expr | None, list[ast.stmt], object]] = []  # the if-chain
            stripped = 0  # groups whose final `break` the if-chain form leaves out
            # `matched` carries a fall-through into the next group; a group after one that
            # ends in a jump is entered only by its own labels
            falls = [not _ends_in_jump(stmts) for _, stmts in groups]
            uses_matched = any(falls[:-1])
            for g, (labels, stmts) in enumerate(groups):
                entered = g > 0 and falls[g - 1]
                tests: list[ast.expr] = [name(matched)] if entered else []
                for lab in labels:
                    if isinstance(lab, n.Default):
                        others = ast.Tuple([const(k) for k in values], ast.Load())
                        tests.append(ast.Compare(name(sw), [ast.NotIn()], [others]))
                    else:
                        cv = label_value.get(id(lab))
                        if cv is None:
                            try:
                                cv = ct.wrap_int(self.x.const_int(lab.value), t)
                            except SemanticError:
                                continue
                        tests.append(ast.Compare(name(sw), [ast.Eq()], [const(cv)]))
                if not tests:  # its labels failed (reported); its blocks still open
                    self._group_stmts(stmts, scopes)
                    continue
                inner: list[ast.stmt] = []
                if falls[g] and g + 1 < len(groups):
                    inner.append(ast.Assign([name(matched, True)], ast.Constant(True)))
                inner += self._group_stmts(stmts, scopes)
                test = tests[0] if len(tests) == 1 else ast.BoolOp(ast.Or(), tests)
                is_default = any(isinstance(lab, n.Default) for lab in labels)
                pos = labels[0].pos
                ctx.at([test], pos)
                chain.append((None if is_default else test, inner, pos))
                lowered.append((test, inner, pos))
                if inner and type(inner[-1]) is ast.Break:
                    stripped += 1
            # a variable whose declaration a label jumps over exists all the same (C: its
            # value is indeterminate): a Python local or list gets its zero before the groups
            pre = self._jumped_locals(scopes, s.pos) if jumped_decl else []
        finally:
            ctx.scope = saved
            nesting.loops.pop()
            nesting.unnest()
        if not (here.split or here.flag_used or any(falls[:-1]) or stripped != here.breaks):
            # no group falls into the next and every `break` ends a group: the groups'
            # tests exclude each other, so an if-chain without the loop does the same
            return pre + self._switch_chain(out, subject, chain)
        # the loop form's groups (an empty one, `case 2: }`, gets a `pass` at its label)
        body = pre + [
            ctx.at([ast.If(test, inner or [ast.Pass()], [])], pos)[0]
            for test, inner, pos in lowered
        ]
        body.append(ast.Break())
        loop = ast.While(ast.Constant(True), body, [])
        if uses_matched:
            out.append(ast.Assign([name(matched, True)], ast.Constant(False)))
        if here.flag_used:
            out.append(ast.Assign([name(flag, True)], ast.Constant(False)))
        out.extend(nesting.placed(here, loop))
        if here.flag_used:
            out.append(
                ast.If(name(flag), self.jumps.continue_from(len(nesting.loops) - 1, s.pos), [])
            )
        return out

    def _group_stmts(self, items: list, scopes: list[Scope]) -> list[ast.stmt]:
        """The statements of a switch group; an opened block's marks open and close its
        scope (kept in `scopes`), each run between them lowered as a statement list."""
        ctx = self.ctx
        out: list[ast.stmt] = []
        run: list = []
        for it in items:
            if type(it) is _Open or type(it) is _Close:
                out += self.stmts.stmts(run)
                run = []
                if type(it) is _Open:
                    ctx.scope = Scope(ctx.scope, "block")
                    scopes.append(ctx.scope)
                else:
                    ctx.scope = ctx.scope.parent  # type: ignore[assignment]
            else:
                run.append(it)
        return out + self.stmts.stmts(run)

    def _jumped_locals(self, scopes: list[Scope], pos) -> list[ast.stmt]:
        """`v = 0` or `v = [0] * N` for each Python local or list the switch's body and
        its opened blocks declare (frame and static objects exist from the call on)."""
        out: list[ast.stmt] = []
        for sc in scopes:
            for sym in sc.names.values():
                if isinstance(sym, VarSym) and sym.storage in ("local", "pylist"):
                    out += self.decls.init_var(sym, None, pos)
        return self.ctx.at(out, pos)

    def _switch_chain(self, out: list[ast.stmt], subject: ast.expr, chain) -> list[ast.stmt]:
        """`if sw == 1: ... elif sw == 2: ... else: <default>` without the groups' final
        `break`s; a subject that is a plain name is tested without the temporary.

        before: `switch (a) { case 1: s++; break; default: s = 0; }`
        after:  `if v_a == 1: v_s = ... else: v_s = 0`
        """
        if type(subject) is ast.Name:
            out = []
            for test, _, _ in chain:
                if test is not None:
                    for cmp in test.values if type(test) is ast.BoolOp else [test]:
                        cmp.left = placed_like(name(subject.id), cmp)
        rest: list[ast.stmt] = []
        for test, inner, _ in chain:
            if test is None:  # the default group, exclusive of the others: the last `else`
                if inner and type(inner[-1]) is ast.Break:
                    inner.pop()
                rest = inner
        for test, inner, pos in reversed(chain):
            if test is not None:
                if inner and type(inner[-1]) is ast.Break:
                    inner.pop()
                rest = [_restamped(ast.If(test, inner or [_restamped(ast.Pass(), pos)], rest), pos)]
        return out + rest


_NESTS = frozenset((n.Block, n.If, n.While, n.DoWhile, n.For))
"""Statements that `_nested_label` looks into (any other holds no label)."""
_LOOPS_AND_IFS = _NESTS - {n.Block}


class _Open:
    """In a switch body's items: a block holding a label of the switch opens here."""

    __slots__ = ("pos",)

    def __init__(self, pos) -> None:
        self.pos = pos


class _Close(_Open):
    """... and closes here (its scope ends)."""

    __slots__ = ()


def _open_blocks(items) -> list:
    """The switch body's items with each block that holds a `case` or `default` label of
    the switch (not in a loop or `if` of it) opened: its items between `_Open` and
    `_Close` marks, so that its labels are labels of the body and its scope still ends.

    before: `switch (x) { { x = 2; case 1: return 1; } }`
    after:  `_Open, x = 2;, case 1:, return 1;, _Close`
    """
    out: list = []
    for it in items:
        if type(it) is n.Block and _nested_label(it) is not None:
            out.append(_Open(it.pos))
            out += _open_blocks(it.items)
            out.append(_Close(it.pos))
        else:
            out.append(it)
    return out


def _nested_label(s) -> n.Case | n.Default | None:
    """The first `case`/`default` label nested inside statement `s` (not in an inner switch)."""
    t = type(s)
    if t is n.Block:
        for it in s.items:
            if isinstance(it, (n.Case, n.Default)):
                return it
            found = _nested_label(it)
            if found is not None:
                return found
        return None
    if t is n.If:
        for sub in (s.then, s.else_):
            if isinstance(sub, (n.Case, n.Default)):
                return sub
            found = _nested_label(sub) if sub is not None else None
            if found is not None:
                return found
        return None
    if t in (n.While, n.DoWhile, n.For):
        if isinstance(s.body, (n.Case, n.Default)):
            return s.body
        return _nested_label(s.body)
    return None


def _restamped(stmt: ast.stmt, pos) -> ast.stmt:
    """The statement placed at `pos` (its parts already were)."""
    stmt.lineno, stmt.col_offset = pos.line, max(pos.col - 1, 0)
    return stmt


_JUMP_STMTS = (n.Break, n.Continue, n.Return, n.Goto)


def _ends_in_jump(stmts) -> bool:
    """The statements end in a break, continue, return or goto (never fall off the end)."""
    while stmts and type(stmts[-1]) is _Close:
        stmts = stmts[:-1]
    while stmts:
        last = stmts[-1]
        if isinstance(last, _JUMP_STMTS):
            return True
        if not isinstance(last, n.Block):
            return False
        stmts = last.items
    return False
