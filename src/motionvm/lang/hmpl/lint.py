"""gcc-like warnings that need only the syntax tree of a function: an assignment used as a
truth value (-Wparentheses), unused local variables (-Wunused-variable) and statements
after a return, break, continue or goto (unreachable code). Type-based warnings (formats
of Print and friends, built-ins that are not implemented) come from the lowering."""

from __future__ import annotations

from collections.abc import Callable

from motionvm.lang.hmpl import nodes as n
from motionvm.lang.hmpl.analysis import _GETTERS, _LITERALS, children_getter, walk
from motionvm.source.files import SourcePos

Warn = Callable[[SourcePos, str], None]

_JUMPS = (n.Return, n.Break, n.Continue, n.Goto)
_LABELS = (n.Label, n.Case, n.Default)


def lint_function(f: n.FuncDef, warn: Warn) -> None:
    """Every syntax-only warning of one function definition, in source order."""
    if f.body is None:
        return
    found: list[tuple[SourcePos, str]] = []

    def add(pos: SourcePos, message: str) -> None:
        found.append((pos, message))

    _Lint(add).function(f)
    for pos, message in sorted(found, key=lambda w: (w[0].file, w[0].line, w[0].col)):
        warn(pos, message)


def _check_tree(tree, warn: Warn) -> None:
    """-Wparentheses at each condition and unreachable code per block, in a subtree the
    statement walk of `_Lint` does not enter (a prototype, a struct spelled out in a
    declaration's type)."""
    for x in walk(tree):
        t = type(x)
        if t is n.Block:
            _check_unreachable(x, warn)
        elif t in _CONDITIONAL:
            _check_condition(x.cond, t, warn)
        elif t is n.Call:
            _check_till(x, warn)


def _check_condition(c, t: type, warn: Warn) -> None:
    """-Wparentheses: an unparenthesized `=` as the condition `c` of a node of class `t`."""
    if type(c) is n.Unary and c.op == "!" and t is n.While:
        c = c.operand  # `Till (cond) { ... }` is parsed as `while (!cond) { ... }`
    if type(c) is n.Assign and c.op == "=" and not c.parenthesized:
        warn(c.pos, "suggest parentheses around assignment used as truth value")


def _check_till(x: n.Call, warn: Warn) -> None:
    """-Wparentheses on the condition of a `Till(cond)` call."""
    if type(x.func) is n.Name and x.func.id == "Till" and x.args:
        _check_condition(x.args[0], n.Call, warn)


_CONDITIONAL = frozenset((n.If, n.While, n.DoWhile, n.For, n.Cond))


def _check_unreachable(blk: n.Block, warn: Warn) -> None:
    """The first statement after a jump in a block, up to the next label.

    A `break` right after a `return` or `goto` (`case 1: return 5; break;`) is a common
    defensive habit and is not reported, as clang's -Wunreachable-code does not.
    """
    jump = None  # the jump that ended the live code (None: live)
    for s in blk.items:
        if isinstance(s, _LABELS):
            jump = None
        elif jump is None:
            if isinstance(s, _JUMPS):
                jump = s
        elif jump is _REPORTED or type(s) is n.Empty:
            continue
        elif type(s) is n.Break and type(jump) in (n.Return, n.Goto):
            continue
        else:
            warn(s.pos, "unreachable code")
            jump = _REPORTED


_REPORTED = object()  # a stretch of dead code already reported


class _Lint:
    """One walk over a function: block-scoped use tracking of its local variables, and
    at the same time -Wparentheses at each condition and unreachable code per block."""

    def __init__(self, warn: Warn) -> None:
        self.warn = warn
        self.scopes: list[dict[str, list]] = []  # name -> [pos, used], one per open block
        # name -> the entries of the open blocks that declare it, innermost last: a use
        # finds its variable with one look-up
        self.live: dict[str, list[list]] = {}

    def function(self, f: n.FuncDef) -> None:
        self.enter({p.name: [p.pos, True] for p in f.params if p.name})
        _check_unreachable(f.body, self.warn)  # type: ignore[arg-type]
        self.block(f.body.items)  # type: ignore[union-attr]
        self.leave()

    def enter(self, scope: dict[str, list]) -> None:
        self.scopes.append(scope)
        live = self.live
        for name, entry in scope.items():
            live.setdefault(name, []).append(entry)

    def leave(self) -> dict[str, list]:
        scope = self.scopes.pop()
        live = self.live
        for name in scope:
            live[name].pop()
        return scope

    def block(self, items) -> None:
        self.enter({})
        for s in items:
            self.stmt(s)
        self.report(self.leave())

    def report(self, scope: dict[str, list]) -> None:
        for name, (pos, used) in scope.items():
            if not used:
                self.warn(pos, f"unused variable '{name}'")

    def sub(self, s) -> None:
        """A statement that is a scope of its own (a loop's or an if's body)."""
        if type(s) is n.Block:
            _check_unreachable(s, self.warn)
            self.block(s.items)
        else:
            self.block((s,))

    def uses(self, e) -> None:
        """Mark every variable named in expression `e` used (one walk); check the
        conditions of `?:` and `Till` on the way."""
        t = type(e)
        if t is n.Name:  # the common expressions first, without the walk's set-up
            entries = self.live.get(e.id)
            if entries:
                entries[-1][1] = True
            return
        if t in _LITERALS or e is None:
            return
        live = self.live
        Name, Cond, Call, getters, literals = n.Name, n.Cond, n.Call, _GETTERS, _LITERALS
        stack = [e]
        pop, push, extend = stack.pop, stack.append, stack.extend
        while stack:
            x = pop()
            t = type(x)
            if t is Name:
                entries = live.get(x.id)
                if entries:
                    entries[-1][1] = True
                continue
            if t is tuple or t is list:
                extend(x)
                continue
            if x is None or t in literals:
                continue
            if t is Cond:
                _check_condition(x.cond, t, self.warn)
            elif t is Call:
                _check_till(x, self.warn)
            kids = (getters.get(t) or children_getter(t))(x)
            if type(kids) is tuple:
                extend(kids)
            else:
                push(kids)

    def declare(self, d: n.VarDecl) -> None:
        if type(d) is n.FuncDef:  # a prototype: no variable
            _check_tree(d, self.warn)
            return
        if d.type.struct_def is not None:
            _check_tree(d.type.struct_def, self.warn)
        if type(d) is n.Typedef:  # a type name, not a variable
            self.uses(d.dims)
            return
        self.uses((d.dims, d.init))
        if d.name and d.name not in self.scopes[-1]:  # a redefinition is an error already
            entry = [d.pos, False]
            self.scopes[-1][d.name] = entry
            self.live.setdefault(d.name, []).append(entry)

    def stmt(self, s) -> None:
        t = type(s)
        if t is n.Block:
            _check_unreachable(s, self.warn)
            self.block(s.items)
        elif t is n.DeclStmt:
            for d in s.decls:
                self.declare(d)
        elif t is n.VarDecl:
            self.declare(s)
        elif t is n.ExprStmt:
            self.uses(s.expr)
        elif t is n.If:
            _check_condition(s.cond, t, self.warn)
            self.uses(s.cond)
            self.sub(s.then)
            if s.else_ is not None:
                self.sub(s.else_)
        elif t is n.While or t is n.DoWhile:
            _check_condition(s.cond, t, self.warn)
            self.uses(s.cond)
            self.sub(s.body)
        elif t is n.For:
            _check_condition(s.cond, t, self.warn)
            self.enter({})
            if s.init is not None:
                self.stmt(s.init)
            self.uses((s.cond, s.step))
            self.sub(s.body)
            self.report(self.leave())
        elif t is n.Switch:
            self.uses(s.expr)
            self.sub(s.body)
        elif t is n.Return:
            self.uses(s.value)
        else:  # case labels; statements without names (break, goto, ...)
            self.uses(s)
