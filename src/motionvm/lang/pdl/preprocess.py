"""PDL preprocessor: #define/#undef, #ifdef family, #include, on the lexer's tokens.

Directives are line-oriented and start a line (manual §2.5.3-§2.5.6).
A `#define` body is every token to the end of the (spliced) line, a trailing `;`
included: `#define size 10;` makes `array[size]` read `array[10;]`, as the manual
warns. Tokens copied from a macro body carry the position of the macro's use and the
macro in `Token.origin`, so the parser can explain such mistakes. Expansion rescans
the result with the following input (as C does); a macro is not expanded inside its
own expansion. `#task`, `#long`, `#short` and `#float` are statements for the parser.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field

from motionvm.lang.pdl.lexer import MacroOrigin, Token, tokenize
from motionvm.source.diagnostics import DiagnosticSink
from motionvm.source.files import NOT_REGULAR, SourceFile, SourcePos
from motionvm.source.suggest import did_you_mean

MAX_INCLUDE_DEPTH = 20
MAX_EXPANSION_TOKENS = 250_000
"""Tokens a file's macro expansions may produce in total (stops runaway macros)."""
MAX_MACRO_NESTING = 200

PP_DIRECTIVES = (
    "define",
    "undef",
    "ifdef",
    "ifndef",
    "elifdef",
    "elifndef",
    "else",
    "endif",
    "include",
)
STATEMENT_DIRECTIVES = ("task", "long", "short", "float")


@dataclass(frozen=True, slots=True)
class Macro:
    """A `#define`: params None for an object-like macro."""

    name: str
    params: tuple[str, ...] | None
    body: tuple[Token, ...]
    pos: SourcePos


@dataclass(slots=True)
class _Cond:
    """One open #ifdef group."""

    pos: SourcePos
    directive: str
    parent_active: bool
    active: bool
    taken: bool
    else_seen: bool = False


@dataclass(slots=True)
class _Item:
    """A token waiting for expansion and the macros it may no longer expand."""

    tok: Token
    hide: frozenset[str] = field(default_factory=frozenset)


_NO_HIDE: frozenset[str] = frozenset()


class _ExpansionTooLarge(Exception):
    pass


def _copy(t: Token, pos: SourcePos, origin: MacroOrigin) -> Token:
    """A macro-body token placed at the macro's use."""
    return Token(t.kind, t.text, pos, t.value, False, pos.col + len(t.text), origin)


def _line_spans(toks: list[Token]) -> list[tuple[int, int]]:
    """[start, end) index pairs of the logical lines, the final eof excluded."""
    spans: list[tuple[int, int]] = []
    start = 0
    n = len(toks) - 1
    for i in range(1, n + 1):
        if i == n or toks[i].bol:
            if start < i:
                spans.append((start, i))
            start = i
    return spans


class Preprocessor:
    """Runs the directives of a main file and its includes; collects the token stream."""

    def __init__(self, sink: DiagnosticSink) -> None:
        self.sink = sink
        self.macros: dict[str, Macro] = {}
        self.include_stack: list[str] = []
        self.out: list[Token] = []
        self.included: list[SourceFile] = []
        """Every file an `#include` read, in order (the compile cache checks them)."""
        self._budget = MAX_EXPANSION_TOKENS

    # ------------------------------------------------------------ files

    def run(self, path: str, text: str) -> list[Token]:
        """The preprocessed tokens of `path` (whose text is given), ending with 'eof'."""
        toks = tokenize(path, text, self.sink)
        self._file(path, toks)
        self.out.append(toks[-1])
        return self.out

    def _file(self, path: str, toks: list[Token]) -> None:
        self.include_stack.append(os.path.normpath(path))
        conds: list[_Cond] = []
        pending: list[Token] = []
        for start, end in _line_spans(toks):
            line = toks[start:end]
            head = line[0]
            active = not conds or conds[-1].active
            if head.kind == "directive" and head.value in PP_DIRECTIVES:
                if active:
                    self._flush(pending)
                    pending = []
                self._directive(head, line[1:], conds, active)
            elif head.kind == "directive" and head.value not in STATEMENT_DIRECTIVES:
                if active:
                    known = [f"#{d}" for d in PP_DIRECTIVES + STATEMENT_DIRECTIVES]
                    self.sink.error(
                        head.pos,
                        f"unknown directive '{head.text}'" + did_you_mean(head.text.lower(), known),
                    )
            elif active:
                pending.extend(line)
        self._flush(pending)
        for c in conds:
            self.sink.error(c.pos, f"'#{c.directive}' has no matching '#endif'")
        self.include_stack.pop()

    # ------------------------------------------------------------ directives

    def _directive(self, head: Token, args: list[Token], conds: list[_Cond], active: bool) -> None:
        d = str(head.value)
        if d in ("ifdef", "ifndef"):
            name = self._one_name(head, args) if active else None
            defined = name is not None and name in self.macros
            now = active and (defined if d == "ifdef" else not defined)
            conds.append(_Cond(head.pos, d, active, now, now))
            return
        if d in ("elifdef", "elifndef", "else", "endif"):
            if not conds:
                self.sink.error(head.pos, f"'#{d}' without a matching '#ifdef' or '#ifndef'")
                return
            top = conds[-1]
            if d == "endif":
                self._no_extra(head, args, 0)
                conds.pop()
                return
            if top.else_seen:
                self.sink.error(head.pos, f"'#{d}' after '#else' (the #else must come last)")
                return
            if d == "else":
                self._no_extra(head, args, 0)
                top.else_seen = True
                top.active = top.parent_active and not top.taken
            else:
                name = self._one_name(head, args) if top.parent_active else None
                defined = name is not None and name in self.macros
                hit = defined if d == "elifdef" else (name is not None and not defined)
                top.active = top.parent_active and not top.taken and hit
            top.taken = top.taken or top.active
            return
        if not active:
            return
        if d == "define":
            self._define(head, args)
        elif d == "undef":
            name = self._one_name(head, args)
            if name is not None:
                self.macros.pop(name, None)
        elif d == "include":
            self._include(head, args)

    def _one_name(self, head: Token, args: list[Token]) -> str | None:
        if not args or args[0].kind not in ("name", "keyword"):
            self.sink.error(head.pos, f"'{head.text}' needs a macro name")
            return None
        self._no_extra(head, args, 1)
        return args[0].text

    def _no_extra(self, head: Token, args: list[Token], n: int) -> None:
        if len(args) > n:
            self.sink.error(args[n].pos, f"unexpected '{args[n].text}' after '{head.text}'")

    def _define(self, head: Token, args: list[Token]) -> None:
        if not args or args[0].kind not in ("name", "keyword"):
            self.sink.error(head.pos, "'#define' needs a macro name")
            return
        name_tok = args[0]
        if name_tok.kind == "keyword":
            self.sink.error(name_tok.pos, f"cannot define '{name_tok.text}': it is a PDL keyword")
            return
        params: tuple[str, ...] | None = None
        body_start = 1
        if (
            len(args) > 1
            and args[1].text == "("
            and args[1].kind == "punct"
            and args[1].pos.line == name_tok.pos.line
            and args[1].pos.col == name_tok.end_col
        ):
            names: list[str] = []
            j = 2
            ok = False
            while j < len(args):
                t = args[j]
                if t.text == ")" and not names:
                    ok = True
                    j += 1
                    break
                if t.kind != "name":
                    break
                if t.text in names:
                    self.sink.error(t.pos, f"macro parameter '{t.text}' appears twice")
                    return
                names.append(t.text)
                j += 1
                if j < len(args) and args[j].text == ",":
                    j += 1
                    continue
                if j < len(args) and args[j].text == ")":
                    ok = True
                    j += 1
                break
            if not ok:
                where = args[j].pos if j < len(args) else head.pos
                self.sink.error(
                    where,
                    f"bad parameter list in the definition of macro "
                    f"'{name_tok.text}': expected names separated by ',' and ')'",
                )
                return
            params = tuple(names)
            body_start = j
        body = tuple(args[body_start:])
        old = self.macros.get(name_tok.text)
        if old is not None and (
            old.params != params or [t.text for t in old.body] != [t.text for t in body]
        ):
            self.sink.error(
                name_tok.pos,
                f"macro '{name_tok.text}' is already defined at "
                f"{old.pos.line}:{old.pos.col}; '#undef {name_tok.text}' first",
            )
            return
        self.macros[name_tok.text] = Macro(name_tok.text, params, body, name_tok.pos)

    def _include(self, head: Token, args: list[Token]) -> None:
        if args and args[0].kind == "string":
            rel = str(args[0].value)
            self._no_extra(head, args, 1)
        else:
            self.sink.error(head.pos, "'#include' needs a file name: #include \"file\"")
            return
        base = os.path.dirname(head.pos.file)
        path = os.path.normpath(os.path.join(base, rel.replace("\\", "/")))
        if len(self.include_stack) > MAX_INCLUDE_DEPTH:
            self.sink.error(
                head.pos,
                f"'#include' nested more than {MAX_INCLUDE_DEPTH} levels deep (including '{rel}')",
            )
            return
        if path in self.include_stack:
            self.sink.error(head.pos, f"'{rel}' includes itself (recursive #include)")
            return
        try:
            sf = SourceFile.read(path)
        except OSError as exc:
            why = (
                f": {NOT_REGULAR}"
                if exc.strerror == NOT_REGULAR
                else " (a relative path starts at the including file's folder)"
            )
            self.sink.error(head.pos, f"cannot open include file '{rel}'{why}")
            return
        self.included.append(sf)
        self._file(sf.path, tokenize(sf.path, sf.text, self.sink)[:])

    # ------------------------------------------------------------ expansion

    def _flush(self, toks: list[Token]) -> None:
        if not toks:
            return
        try:
            self.out.extend(self.expand(toks, 0))
        except _ExpansionTooLarge:
            self.sink.error(toks[0].pos, "macro expansion too large (recursive macros?)")

    def expand(self, toks: list[Token], depth: int) -> list[Token]:
        """Expand every macro use in `toks`, rescanning results with the following tokens."""
        macros = self.macros
        if not any(
            t.kind == "name"
            and t.text in macros
            or t.kind == "directive"
            and t.value in PP_DIRECTIVES
            for t in toks
        ):
            return list(toks)  # what the loop below gives: nothing to expand or report
        stack = [_Item(t, _NO_HIDE) for t in reversed(toks)]
        out: list[Token] = []
        while stack:
            item = stack.pop()
            t = item.tok
            m = self.macros.get(t.text) if t.kind == "name" else None
            if m is None or t.text in item.hide:
                if t.kind == "directive" and t.value in PP_DIRECTIVES:
                    self.sink.error(t.pos, f"'{t.text}' must start a line")
                    while (
                        stack
                        and not stack[-1].tok.bol
                        and stack[-1].tok.pos.line == t.pos.line
                        and stack[-1].tok.pos.file == t.pos.file
                    ):
                        stack.pop()
                    continue
                out.append(t)
                continue
            hide = item.hide | {m.name}
            origin = MacroOrigin(m.name, m.pos, bool(m.body) and m.body[-1].text == ";")
            if m.params is None:
                body = [_copy(b, t.pos, origin) for b in m.body]
                self._push(stack, [_Item(b, hide) for b in body])
                continue
            if not stack or stack[-1].tok.text != "(" or stack[-1].tok.kind != "punct":
                out.append(t)  # a function-like macro name without '(' is left alone
                continue
            args = self._collect_args(stack, t, m)
            if args is None:
                continue
            if depth >= MAX_MACRO_NESTING:
                self.sink.error(t.pos, f"macro calls nested more than {MAX_MACRO_NESTING} deep")
                return out
            expanded = [self.expand([a.tok for a in arg], depth + 1) for arg in args]
            body_items: list[_Item] = []
            for b in m.body:
                if b.kind == "name" and b.text in m.params:
                    body_items.extend(_Item(a, hide) for a in expanded[m.params.index(b.text)])
                else:
                    body_items.append(_Item(_copy(b, t.pos, origin), hide))
            self._push(stack, body_items)
        return out

    def _push(self, stack: list[_Item], items: list[_Item]) -> None:
        self._budget -= len(items)
        if self._budget < 0:
            raise _ExpansionTooLarge()
        stack.extend(reversed(items))

    def _collect_args(self, stack: list[_Item], name: Token, m: Macro) -> list[list[_Item]] | None:
        """Pop `( a, b, ... )` from the stack; None (after an error) if malformed."""
        stack.pop()  # '('
        args: list[list[_Item]] = [[]]
        depth = 0
        while stack:
            it = stack.pop()
            tx = it.tok.text if it.tok.kind == "punct" else ""
            if tx == "(":
                depth += 1
            elif tx == ")":
                if depth == 0:
                    break
                depth -= 1
            elif tx == "," and depth == 0:
                args.append([])
                continue
            args[-1].append(it)
        else:
            self.sink.error(name.pos, f"unterminated argument list in the use of macro '{m.name}'")
            return None
        assert m.params is not None
        if len(m.params) == 0 and args == [[]]:
            args = []
        if len(args) != len(m.params):
            self.sink.error(
                name.pos,
                f"macro '{m.name}' takes {len(m.params)} argument"
                f"{'' if len(m.params) == 1 else 's'}, got {len(args)}",
            )
            return None
        return args


def preprocess(
    path: str,
    sink: DiagnosticSink,
    text: str | None = None,
    included: list[SourceFile] | None = None,
) -> list[Token]:
    """Preprocess the file at `path` (or `text` registered under that name); `included`
    receives every file an `#include` read."""
    if text is None:
        sf = SourceFile.read(path)
    else:
        sf = SourceFile.register(path, text)
    pp = Preprocessor(sink)
    if included is not None:
        pp.included = included
    return pp.run(sf.path, sf.text)
