"""Lower HMPL jumps: `break`, `continue`, `goto` and labels (and a function body with them).

`break` and `continue` consult the enclosing loops and switches (`lower_split.Nesting`):
a `continue` runs its loop's back-edge, copied where it stands; inside a switch it sets
the switch's flag and leaves it (lower_switch.py). `goto` raises `_Goto(k)`, caught by a
dispatcher loop over the function's top-level label segments:

    L: x++; if (x < 3) goto L;
becomes
    _t1 = 0
    while True:
        try:
            if _t1 <= 0:
                pass
            if _t1 <= 1:
                v_x = v_x + 1 if v_x != 2147483647 else -2147483648
                if v_x < 3:
                    raise _Goto(1)
            break
        except _Goto as _t2:
            _t1 = _t2.args[0]   # plus a budgeted back-edge
"""

from __future__ import annotations

import ast

from motionvm.lang.hmpl import nodes as n
from motionvm.lang.hmpl.analysis import walk
from motionvm.lang.hmpl.lower_context import FunctionContext
from motionvm.lang.hmpl.lower_decl import DeclLowerer
from motionvm.lang.hmpl.lower_split import Nesting
from motionvm.lang.hmpl.lower_stmt import StatementLowerer
from motionvm.lang.hmpl.lower_util import backedge, countdown_init
from motionvm.lang.hmpl.lvalues import call, name
from motionvm.lang.hmpl.symbols import Scope, VarSym
from motionvm.source.suggest import did_you_mean


class JumpLowerer:
    """Lowers the jumps of one function: `break`, `continue`, `goto` and its labels."""

    def __init__(
        self, ctx: FunctionContext, stmts: StatementLowerer, nesting: Nesting, decls: DeclLowerer
    ) -> None:
        self.ctx = ctx
        self.stmts = stmts
        self.decls = decls
        self.nesting = nesting
        self.fail = ctx.fail
        self.labels: dict[str, int] = {}
        """Label name -> the index of the segment it starts (`function_body`)."""
        self.body: n.Block | None = None
        """The function body (`function_body`), where `s_Label` looks for a `goto`."""

    def handlers(self) -> dict[type, object]:
        """The statements this part lowers: node class -> method."""
        return {
            n.Break: self.s_Break,
            n.Continue: self.s_Continue,
            n.Goto: self.s_Goto,
            n.Label: self.s_Label,
            n.Case: self.s_Case,
            n.Default: self.s_Default,
        }

    def s_Break(self, s: n.Break) -> list[ast.stmt]:
        if not self.nesting.loops:
            raise self.fail(s.pos, "'break' outside a loop or switch")
        self.nesting.loops[-1].breaks += 1
        return [ast.Break()]

    def s_Continue(self, s: n.Continue) -> list[ast.stmt]:
        if not any(c.kind == "loop" for c in self.nesting.loops):
            raise self.fail(s.pos, "'continue' outside a loop")
        return self.continue_from(len(self.nesting.loops) - 1, s.pos)

    def continue_from(self, level: int, pos) -> list[ast.stmt]:
        while level >= 0 and self.nesting.loops[level].kind == "switch":
            sw = self.nesting.loops[level]
            sw.flag_used = True
            return [
                ast.Assign([name(sw.flag, True)], ast.Constant(True)),
                ast.Break(),
            ]
        if level < 0:
            raise self.fail(pos, "'continue' outside a loop")
        return [self._clone(x) for x in self.nesting.loops[level].cont]

    @staticmethod
    def _clone(node: ast.stmt) -> ast.stmt:
        return _copy_tree(node)

    def s_Case(self, s: n.Case) -> list[ast.stmt]:
        raise self.fail(s.pos, "'case' label not directly inside a switch")

    def s_Default(self, s: n.Default) -> list[ast.stmt]:
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
        A `goto` targets labels at the top level of the function body only.
        """
        labels = [it for it in body.items if isinstance(it, n.Label)]
        self.body = body
        self.labels = {}
        ctx = self.ctx
        for lab in labels:
            if lab.name in self.labels:
                self.ctx.sink.error(lab.pos, f"duplicate label '{lab.name}'")
            self.labels[lab.name] = len(self.labels) + 1
        if not labels:
            return self.stmts.block(body, "function")
        saved = ctx.scope
        ctx.scope = scope = Scope(saved, "function")
        try:
            segments: list[list[ast.stmt]] = [[]]
            for it in body.items:
                if isinstance(it, n.Label):
                    segments.append([])
                    continue
                segments[-1].extend(self.stmts.stmts([it]))
        finally:
            ctx.scope = saved
        lbl, g, b = ctx.temp(), ctx.temp(), ctx.temp()
        ctx.has_yield = True
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
        return self.ctx.at(self._declared_at_entry(body, scope) + pre + [loop], body.pos)

    def _declared_at_entry(self, body: n.Block, scope: Scope) -> list[ast.stmt]:
        """C lets a `goto` jump past a declaration at the top level of the body: the
        variable exists where the jump lands, its value indeterminate. Each one kept in a
        Python local (a scalar, an array in a list) gets a zero value before the
        dispatcher, so code after the label finds it (its declaration still initializes
        it where it stands)."""
        out: list[ast.stmt] = []
        for it in body.items:
            decls = it.decls if isinstance(it, n.DeclStmt) else (it,)
            for d in decls:
                if not isinstance(d, n.VarDecl) or d.is_static:
                    continue
                sym = scope.names.get(d.name)
                if isinstance(sym, VarSym) and sym.storage in ("local", "pylist"):
                    out.extend(self.decls.init_var(sym, None, d.pos))
        return out

    def s_Goto(self, s: n.Goto) -> list[ast.stmt]:
        k = self.labels.get(s.label)
        if k is None:
            raise self.fail(
                s.pos,
                f"label '{s.label}' used but not defined{did_you_mean(s.label, list(self.labels))}",
            )
        return [ast.Raise(call("_Goto", ast.Constant(k)), None)]

    def s_Label(self, s: n.Label) -> list[ast.stmt]:
        """A label inside a nested statement: nothing, if no `goto` names it."""
        body = self.body
        if body is None or any(type(x) is n.Goto and x.label == s.name for x in walk(body)):
            raise self.fail(
                s.pos, f"label '{s.name}' must stand at the top level of the function body"
            )
        return []


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
