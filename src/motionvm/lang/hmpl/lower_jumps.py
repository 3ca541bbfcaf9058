"""Lower HMPL jumps: `break`, `continue`, `switch` with fall-through, `goto` and labels.

A `switch` becomes a one-pass `while True:` whose groups test `matched or value == case`,
so C fall-through and `break` keep their meaning; a `continue` inside it sets a flag, leaves
the switch and continues the enclosing loop. `goto` raises `_Goto(k)`, caught by a
dispatcher loop over the function's top-level label segments.
"""

from __future__ import annotations

import ast

from motionvm.lang.hmpl import ctypes_ as ct
from motionvm.lang.hmpl import nodes as n
from motionvm.lang.hmpl.lower_expr import SemanticError
from motionvm.lang.hmpl.lower_util import LoopCtx, at, backedge, countdown_init, placed_like
from motionvm.lang.hmpl.lvalues import call, const, name
from motionvm.lang.hmpl.symbols import Scope


class JumpLowering:
    """Mixin of the function lowerer: break, continue, switch, goto."""

    def _s_Break(self, s: n.Break) -> list[ast.stmt]:
        if not self.loops:
            raise self.fail(s.pos, "'break' outside a loop or switch")
        self.loops[-1].breaks += 1
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
                ast.Assign([name(sw.flag, True)], ast.Constant(True)),
                ast.Break(),
            ]
        if level < 0:
            raise self.fail(pos, "'continue' outside a loop")
        return [self._clone(x) for x in self.loops[level].cont]

    @staticmethod
    def _clone(node: ast.stmt) -> ast.stmt:
        return _copy_tree(node)

    def _s_Switch(self, s: n.Switch) -> list[ast.stmt]:
        v = self.expr(s.expr)
        if not v.type.is_integer:
            raise self.fail(s.expr.pos, f"switch quantity is not an integer (it is '{v.type}')")
        t = ct.promote(v.type)
        sw, matched, flag = self.temp(), self.temp(), self.temp()
        subject = self.convert(v, t, s.pos)
        out: list[ast.stmt] = [ast.Assign([name(sw, True)], subject)]
        items = s.body.items if isinstance(s.body, n.Block) else (s.body,)
        for it in items:
            nested = _nested_label(it) if type(it) in _NESTS else None
            if nested is not None:
                what = "case" if isinstance(nested, n.Case) else "default"
                raise self.fail(
                    nested.pos,
                    f"'{what}' label inside a nested statement of the switch is not supported"
                    " (a jump into a block, loop or 'if'); put it directly in the switch body",
                )
        groups: list[tuple[list, list]] = []  # (labels, statements)
        values: dict[int, object] = {}
        label_value: dict[int, int] = {}  # id(case label) -> its value, once lowered
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
                    label_value[id(it)] = cv
                    if cv in values:
                        self.sink.error(it.pos, f"duplicate case value {cv}")
                    values[cv] = it
            elif groups:
                groups[-1][1].append(it)
            elif not isinstance(it, n.Empty):
                self.sink.warning(it.pos, "statement before the first case label is never executed")
        ctx = LoopCtx("switch", flag=flag)
        ctx.split = self.nest(s.pos)
        self.loops.append(ctx)
        saved = self.scope
        self.scope = Scope(saved, "block")
        try:
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
                                cv = ct.wrap_int(self.const_int(lab.value), t)
                            except SemanticError:
                                continue
                        tests.append(ast.Compare(name(sw), [ast.Eq()], [const(cv)]))
                if not tests:
                    continue  # its labels failed (reported)
                inner: list[ast.stmt] = []
                if falls[g] and g + 1 < len(groups):
                    inner.append(ast.Assign([name(matched, True)], ast.Constant(True)))
                inner += self.stmts(stmts)
                test = tests[0] if len(tests) == 1 else ast.BoolOp(ast.Or(), tests)
                is_default = any(isinstance(lab, n.Default) for lab in labels)
                pos = labels[0].pos
                at([test], pos)
                chain.append((None if is_default else test, inner, pos))
                lowered.append((test, inner, pos))
                if inner and type(inner[-1]) is ast.Break:
                    stripped += 1
        finally:
            self.scope = saved
            self.loops.pop()
            self.unnest()
        if not (ctx.split or ctx.flag_used or any(falls[:-1]) or stripped != ctx.breaks):
            # no group falls into the next and every `break` ends a group: the groups'
            # tests exclude each other, so an if-chain without the loop does the same
            return self._switch_chain(out, subject, chain)
        # the loop form's groups (an empty one, `case 2: }`, gets a `pass` at its label)
        body = [
            at([ast.If(test, inner or [ast.Pass()], [])], pos)[0] for test, inner, pos in lowered
        ]
        body.append(ast.Break())
        loop = ast.While(ast.Constant(True), body, [])
        if uses_matched:
            out.append(ast.Assign([name(matched, True)], ast.Constant(False)))
        if ctx.flag_used:
            out.append(ast.Assign([name(flag, True)], ast.Constant(False)))
        out.extend(self.split_off(ctx, loop) if ctx.split else [loop])
        if ctx.flag_used:
            out.append(ast.If(name(flag), self._continue_from(len(self.loops) - 1, s.pos), []))
        return out

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

    def _s_Case(self, s: n.Case) -> list[ast.stmt]:
        raise self.fail(s.pos, "'case' label not directly inside a switch")

    def _s_Default(self, s: n.Default) -> list[ast.stmt]:
        raise self.fail(s.pos, "'default' label not directly inside a switch")

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
            test = ast.Compare(name(lbl), [ast.LtE()], [ast.Constant(k)])
            tries.append(ast.If(test, seg or [ast.Pass()], []))
        tries.append(ast.Break())
        handler = ast.ExceptHandler(
            name("_Goto"),
            g,
            [
                ast.Assign(
                    [name(lbl, True)],
                    ast.Subscript(
                        ast.Attribute(name(g), "args", ast.Load()), ast.Constant(0), ast.Load()
                    ),
                ),
            ]
            + backedge(b),
        )
        loop = ast.While(ast.Constant(True), [ast.Try(tries, [handler], [], [])], [])
        pre = [ast.Assign([name(lbl, True)], ast.Constant(0)), countdown_init(b)]
        return at(pre + [loop], body.pos)

    def _s_Goto(self, s: n.Goto) -> list[ast.stmt]:
        k = getattr(self, "labels", {}).get(s.label)
        if k is None:
            from motionvm.source.suggest import did_you_mean

            raise self.fail(
                s.pos,
                f"label '{s.label}' used but not defined{did_you_mean(s.label, list(getattr(self, 'labels', {})))}",
            )
        return [ast.Raise(call("_Goto", ast.Constant(k)), None)]

    def _s_Label(self, s: n.Label) -> list[ast.stmt]:
        raise self.fail(s.pos, f"label '{s.name}' must stand at the top level of the function body")


_NESTS = frozenset((n.Block, n.If, n.While, n.DoWhile, n.For))
"""Statements that `_nested_label` looks into (any other holds no label)."""


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


def _copy_tree(node: ast.AST) -> ast.AST:
    """A fresh copy of a generated subtree (what `copy.deepcopy` gives, several times faster):
    nodes that had a location keep it, the others get one where the copy is placed."""
    cls = type(node)
    new = cls.__new__(cls)
    d = new.__dict__
    for k, v in node.__dict__.items():
        if isinstance(v, ast.AST):
            v = _copy_tree(v)
        elif type(v) is list:
            v = [_copy_tree(x) if isinstance(x, ast.AST) else x for x in v]
        d[k] = v
    return new


_JUMP_STMTS = (n.Break, n.Continue, n.Return, n.Goto)


def _ends_in_jump(stmts) -> bool:
    """The statements end in a break, continue, return or goto (never fall off the end)."""
    while stmts:
        last = stmts[-1]
        if isinstance(last, _JUMP_STMTS):
            return True
        if not isinstance(last, n.Block):
            return False
        stmts = last.items
    return False
