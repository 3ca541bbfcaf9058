"""HMPL preprocessor: #define/#undef, #if family, #include, #error, #line, macro expansion.

Works on the tokens of `lexer.scan`: text between directive lines is macro-expanded
as one stream (so a macro call may span lines), directive lines are interpreted.
Macro expansion follows C's rescanning rules with hide sets (a macro is not expanded
again inside its own expansion). Tokens coming from a macro body carry the position
of the macro's use; tokens of macro arguments keep the position they were written at.
`_TASKID_` is predefined as the task id; `__LINE__` and `__FILE__` become the line and
file name of their use. `#line N ["FILE"]` renumbers the lines after it (C89 6.8.4): the
positions of later tokens, lexical errors and `__LINE__`/`__FILE__` follow it.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from operator import attrgetter

from motionvm.lang.gc_hold import gc_held
from motionvm.lang.hmpl.lexer import Scan, end_pos, lex_fragment, scan
from motionvm.lang.hmpl.tokens import BINARY_PREC, Token
from motionvm.source.diagnostics import DiagnosticSink, TooManyErrors
from motionvm.source.files import SourceFile, SourcePos
from motionvm.source.suggest import did_you_mean

DIRECTIVES = (
    "define",
    "undef",
    "include",
    "if",
    "ifdef",
    "ifndef",
    "elif",
    "else",
    "endif",
    "error",
    "line",
    "pragma",
)
LINE_MAX = 2147483647  # the largest line number `#line` may give (C99 6.10.4)
MAX_EXPANSIONS = 200_000  # macro expansions in one text region before we give up
MAX_TOKENS = 1_000_000  # tokens made by macro substitutions in one task file (and its includes)
MAX_NESTING = 200  # nested macro calls in arguments

_EMPTY: frozenset[str] = frozenset()
_LINE_FILE = frozenset(("__LINE__", "__FILE__"))
# Markers inside a substituted body: '##' to apply, and an empty argument next to it.
_PASTE = Token("punct", "##", SourcePos("<paste>", 0, 0))
_PLACEMARKER = Token("punct", "", SourcePos("<placemarker>", 0, 0))


@dataclass(slots=True)
class Macro:
    """One macro definition; `params` is None for an object-like macro."""

    name: str
    pos: SourcePos
    body: list[Token]
    params: list[str] | None = None
    variadic: bool = False


@dataclass(slots=True)
class _Cond:
    """One open #if: whether the enclosing region is live, and what was taken so far."""

    pos: SourcePos
    parent_active: bool
    taken: bool
    else_seen: bool = False


@dataclass(slots=True)
class _State:
    """Per-file state while scanning one file."""

    sf: SourceFile
    scan: Scan
    conds: list[_Cond] = field(default_factory=list)
    error_index: int = 0
    # set by `#line`: (physical line of the directive, number of the next line, file name)
    line_map: tuple[int, int, str] | None = None
    directive_line: int = 0  # physical line of the directive being interpreted

    def remap(self, pos: SourcePos) -> SourcePos:
        """Where `pos` (a physical place in this file) is after the `#line` directives."""
        m = self.line_map
        if m is None or pos.line <= m[0]:
            return pos
        return SourcePos(m[2], m[1] + pos.line - m[0] - 1, pos.col)

    def mapped(self, toks: list[Token]) -> list[Token]:
        if self.line_map is None:
            return toks
        return [_at(t, self.remap(t.pos)) for t in toks]


class _Abort(Exception):
    """Stop interpreting the current directive (its error is already reported)."""


def preprocess(
    path: str,
    *,
    task_id: int,
    sink: DiagnosticSink,
    text: str | None = None,
    include_depth_limit: int = 20,
    included: list[SourceFile] | None = None,
) -> list[Token]:
    """The preprocessed tokens of one HMPL task file, ending with an 'eof' token.

    Reads `path` (or takes `text` as its contents). Errors go to `sink`; on too many
    errors the tokens produced so far are returned. `included` receives every file that
    an `#include` read, in order (what the compile cache checks).
    """
    with gc_held(promote=False):
        return _preprocess(path, task_id, sink, text, include_depth_limit, included)


def _preprocess(
    path: str,
    task_id: int,
    sink: DiagnosticSink,
    text: str | None,
    include_depth_limit: int,
    included: list[SourceFile] | None,
) -> list[Token]:
    pp = Preprocessor(task_id=task_id, sink=sink, include_depth_limit=include_depth_limit)
    if included is not None:
        pp.included = included
    if text is None:
        try:
            sf = SourceFile.read(path)
        except OSError as e:
            sink.error(SourcePos(path, 1, 1), f"cannot read '{path}': {e.strerror or e}")
            return [Token("eof", "", SourcePos(path, 1, 1))]
    else:
        if "\r" in text:  # as SourceFile.read does: CRLF and CR line ends become LF
            text = text.replace("\r\n", "\n").replace("\r", "\n")
        sf = SourceFile.register(path, text)
    end = end_pos(sf)
    try:
        end = pp.run_file(sf).remap(end)
    except TooManyErrors:
        pass
    pp.out.append(Token("eof", "", end))
    return pp.out


class Preprocessor:
    """Macro table and output of one preprocessing run (one task)."""

    def __init__(self, *, task_id: int, sink: DiagnosticSink, include_depth_limit: int = 20):
        self.sink = sink
        self.task_id = task_id
        self.include_depth_limit = include_depth_limit
        self.out: list[Token] = []
        self.files: list[str] = []  # real paths of the files being read, outermost first
        self.included: list[SourceFile] = []  # every file an #include read, in order
        here = SourcePos("<built-in>", 1, 1)
        self.macros: dict[str, Macro] = {
            "_TASKID_": Macro("_TASKID_", here, [Token("int", str(task_id), here, task_id)])
        }
        self._expansions = 0
        self._tokens_made = 0  # for the whole run: what expansion adds stays bounded
        self._nesting = 0
        self._use: Token | None = None  # the macro use being expanded in the file's text

    # ------------------------------------------------------------ files

    def run_file(self, sf: SourceFile) -> _State:
        """Preprocess one file, appending its tokens to `self.out`."""
        self.files.append(os.path.realpath(sf.path))
        st = _State(sf, scan(sf))
        toks = st.scan.tokens
        active = True
        prev = 0
        for ds, de in st.scan.directives:
            line = toks[ds].pos.line
            self._flush_errors(st, line - 1, active)
            if active and ds > prev:
                self._expansions = 0
                self.out.extend(self._text(st, toks[prev:ds]))
            end_line = toks[de - 1].pos.line
            self._flush_errors(st, end_line, active)
            st.directive_line = end_line
            active = self._directive(st, st.mapped(toks[ds:de]), active)
            prev = de
        self._flush_errors(st, 1 << 60, active)
        if active and prev < len(toks):
            self._expansions = 0
            self.out.extend(self._text(st, toks[prev:]))
        for c in st.conds:
            self.sink.error(c.pos, "unterminated #if (no matching #endif)")
        self.files.pop()
        return st

    def _text(self, st: _State, toks: list[Token]) -> list[Token]:
        """A region of program text: renumbered, expanded, `__LINE__`/`__FILE__` replaced.

        When no name in the whole file is a macro, `__LINE__` or `__FILE__` (the
        common case), the region is only renumbered: no pass over its tokens."""
        names = st.scan.names
        if self.macros.keys().isdisjoint(names) and _LINE_FILE.isdisjoint(names):
            return st.mapped(toks)
        return _line_and_file(self.expand(st.mapped(toks)))

    def _flush_errors(self, st: _State, last_line: int, active: bool) -> None:
        """Report (when `active`) or drop the lexical errors up to `last_line`."""
        errs = st.scan.errors
        i = st.error_index
        while i < len(errs) and errs[i][0].line <= last_line:
            pos, msg, always = errs[i]
            if active or always:
                self.sink.error(st.remap(pos), msg)
            i += 1
        st.error_index = i

    # ------------------------------------------------------------ directives

    def _directive(self, st: _State, line: list[Token], active: bool) -> bool:
        """Interpret one directive line (line[0] is '#'); returns whether text is live after it."""
        if len(line) == 1:
            return active  # the null directive
        word = line[1]
        name = word.text
        args = line[2:]
        sink = self.sink
        if name in ("if", "ifdef", "ifndef"):
            if not active:
                st.conds.append(_Cond(line[0].pos, False, True))
                return False
            if name == "if":
                value = self._eval_if(args, word)
            else:
                value = self._defined(self._ifdef_name(args, word))
                if name == "ifndef":
                    value = not value
            st.conds.append(_Cond(line[0].pos, True, value))
            return value
        if name in ("elif", "else", "endif"):
            if not st.conds:
                sink.error(line[0].pos, f"#{name} without #if")
                return active
            c = st.conds[-1]
            if name == "endif":
                self._no_extra(args, name, c.parent_active)
                st.conds.pop()
                return c.parent_active
            if c.else_seen:
                sink.error(line[0].pos, f"#{name} after #else")
            if name == "else":
                self._no_extra(args, name, c.parent_active)
                c.else_seen = True
                live = c.parent_active and not c.taken
                c.taken = True
                return live
            if c.parent_active and not c.taken:
                live = self._eval_if(args, word)
                c.taken = live
                return live
            return False
        if not active:
            return False
        try:
            if name == "define":
                self._define(args, word)
            elif name == "undef":
                n = self._ifdef_name(args, word)
                if n is not None:
                    self.macros.pop(n, None)
            elif name == "include":
                self._include(st, args, word)
            elif name == "error":
                msg = _spell(args) if args else ""
                sink.error(line[0].pos, f"#error {msg}".rstrip())
            elif name == "line":
                self._line(st, args, word)
            elif name == "pragma":
                pass  # no pragma means anything to HMPL; accepted for C compatibility
            else:
                sink.error(
                    word.pos,
                    f"invalid preprocessing directive '#{name}'" + did_you_mean(name, DIRECTIVES),
                )
        except _Abort:
            pass
        return True

    def _line(self, st: _State, args: list[Token], word: Token) -> None:
        """`#line N` or `#line N "FILE"` (macros expanded first, as C allows)."""
        toks = self.expand(args)
        sink = self.sink
        if not toks:
            sink.error(word.pos, '#line expects a line number (#line N or #line N "FILE")')
            raise _Abort
        num = toks[0]
        if num.kind != "int" or not num.text.isdigit():
            sink.error(num.pos, f"#line expects a line number, not '{num.text}'")
            raise _Abort
        value = int(num.text)
        if not 1 <= value <= LINE_MAX:
            sink.error(num.pos, f"#line number {num.text} is outside [1, {LINE_MAX}]")
            raise _Abort
        fname = st.line_map[2] if st.line_map is not None else st.sf.path
        if len(toks) > 1:
            ft = toks[1]
            if ft.kind != "string":
                sink.error(ft.pos, f"#line expects a file name in quotes, not '{ft.text}'")
                raise _Abort
            fname = bytes(ft.value).decode("utf-8", "replace")  # type: ignore[arg-type]
            if not fname:
                sink.error(ft.pos, "#line file name is empty")
                raise _Abort
            if len(toks) > 2:
                sink.error(toks[2].pos, "extra tokens at end of #line directive")
                raise _Abort
        st.line_map = (st.directive_line, value, fname)

    def _defined(self, name: str | None) -> bool:
        return name in self.macros or name in _LINE_FILE

    def _no_extra(self, args: list[Token], name: str, live: bool) -> None:
        if args and live:
            self.sink.warning(args[0].pos, f"extra tokens at end of #{name} directive")

    def _ifdef_name(self, args: list[Token], word: Token) -> str | None:
        if not args or args[0].kind not in ("name", "keyword"):
            self.sink.error(args[0].pos if args else word.pos, f"#{word.text} expects a macro name")
            return None
        self._no_extra(args[1:], word.text, True)
        return args[0].text

    def _define(self, args: list[Token], word: Token) -> None:
        sink = self.sink
        if not args:
            sink.error(word.pos, "macro name missing in #define")
            raise _Abort
        name_tok = args[0]
        if name_tok.kind not in ("name", "keyword"):
            sink.error(name_tok.pos, f"macro names must be identifiers, not '{name_tok.text}'")
            raise _Abort
        name = name_tok.text
        if name == "defined":
            sink.error(name_tok.pos, "'defined' cannot be used as a macro name")
            raise _Abort
        params: list[str] | None = None
        variadic = False
        body_start = 1
        if len(args) > 1 and args[1].text == "(" and _adjacent(name_tok, args[1]):
            params = []
            i = 2
            while True:
                if i >= len(args):
                    sink.error(args[-1].pos, "missing ')' in macro parameter list")
                    raise _Abort
                t = args[i]
                if t.text == ")" and not params and not variadic:
                    i += 1
                    break
                if t.text == "...":
                    variadic = True
                    params.append("__VA_ARGS__")
                    i += 1
                elif t.kind in ("name", "keyword"):
                    if t.text in params:
                        sink.error(t.pos, f"duplicate macro parameter '{t.text}'")
                        raise _Abort
                    params.append(t.text)
                    i += 1
                else:
                    sink.error(t.pos, f"expected parameter name, found '{t.text}'")
                    raise _Abort
                if i < len(args) and args[i].text == ")":
                    i += 1
                    break
                if i < len(args) and args[i].text == "," and not variadic:
                    i += 1
                    continue
                if i >= len(args):
                    sink.error(args[-1].pos, "missing ')' in macro parameter list")
                else:
                    sink.error(args[i].pos, "expected ',' or ')' in macro parameter list")
                raise _Abort
            body_start = i
        body = args[body_start:]
        if body and (body[0].text == "##" or body[-1].text == "##"):
            t = body[0] if body[0].text == "##" else body[-1]
            sink.error(t.pos, "'##' cannot appear at either end of a macro expansion")
            raise _Abort
        if params is not None:
            for k, t in enumerate(body):
                if (
                    t.text == "#"
                    and t.kind == "punct"
                    and (k + 1 >= len(body) or body[k + 1].text not in params)
                ):
                    sink.error(t.pos, "'#' is not followed by a macro parameter")
                    raise _Abort
        old = self.macros.get(name)
        new = Macro(name, name_tok.pos, body, params, variadic)
        if old is not None and not _same_definition(old, new):
            sink.warning(name_tok.pos, f"'{name}' redefined")
        self.macros[name] = new

    def _include(self, st: _State, args: list[Token], word: Token) -> None:
        sink = self.sink
        if args and args[0].kind not in ("string",) and args[0].text != "<":
            args = self.expand(args)
        if not args:
            sink.error(word.pos, '#include expects "FILENAME"')
            raise _Abort
        if args[0].kind == "string":
            fname = bytes(args[0].value).decode("utf-8", "replace")  # type: ignore[arg-type]
            rest = args[1:]
        elif args[0].text == "<":
            k = next((k for k, t in enumerate(args) if t.text == ">"), None)
            if k is None:
                sink.error(args[0].pos, "missing '>' in #include <FILENAME>")
                raise _Abort
            fname = "".join(t.text for t in args[1:k])
            rest = args[k + 1 :]
        else:
            sink.error(args[0].pos, '#include expects "FILENAME"')
            raise _Abort
        self._no_extra(rest, "include", True)
        base = os.path.dirname(st.sf.path)
        full = os.path.normpath(os.path.join(base, fname))
        if len(self.files) >= self.include_depth_limit:
            sink.error(
                word.pos,
                f"#include nested {len(self.files)} deep exceeds the limit "
                f"{self.include_depth_limit}",
            )
            raise _Abort
        real = os.path.realpath(full)
        if real in self.files:
            sink.error(args[0].pos, f"recursive #include of '{fname}' (an include cycle)")
            raise _Abort
        try:
            sf = SourceFile.read(full)
        except OSError as e:
            sink.error(
                args[0].pos, f"cannot open include file '{fname}': {e.strerror or 'unreadable'}"
            )
            raise _Abort from None
        self.included.append(sf)
        self.run_file(sf)

    # ------------------------------------------------------------ #if expressions

    def _eval_if(self, args: list[Token], word: Token) -> bool:
        """Evaluate a #if/#elif condition; errors count as false."""
        if not args:
            self.sink.error(word.pos, f"#{word.text} with no expression")
            return False
        pre: list[Token] = []
        i = 0
        n = len(args)
        while i < n:
            t = args[i]
            if t.text == "defined" and t.kind == "name":
                j = i + 1
                paren = j < n and args[j].text == "("
                if paren:
                    j += 1
                if j >= n or args[j].kind not in ("name", "keyword"):
                    self.sink.error(t.pos, "operator 'defined' requires an identifier")
                    return False
                val = 1 if self._defined(args[j].text) else 0
                j += 1
                if paren:
                    if j >= n or args[j].text != ")":
                        self.sink.error(t.pos, "missing ')' after 'defined'")
                        return False
                    j += 1
                pre.append(Token("int", str(val), t.pos, val))
                i = j
                continue
            pre.append(t)
            i += 1
        toks = _line_and_file(self.expand(pre))
        ev = _IfEval(toks, word.pos)
        try:
            value = ev.run()
        except _IfError as e:
            self.sink.error(e.pos, e.message)
            return False
        return value != 0

    # ------------------------------------------------------------ macro expansion

    def expand(self, toks: list[Token], hs_map: dict | None = None) -> list[Token]:
        """Macro-expand a token list (C rescanning with hide sets).

        Runs of tokens that cannot start an expansion are copied as slices; only
        macro names and what their expansions rescan go through the token loop.
        """
        macros = self.macros
        if macros.keys().isdisjoint(map(_text, toks)):  # the common case, at C speed
            return list(toks)
        starts = [i for i, s in enumerate(map(_text, toks)) if s in macros]
        if self._tokens_made > MAX_TOKENS:
            return list(toks)  # over the budget (reported): the rest stays unexpanded
        top = hs_map is None
        if hs_map is None:
            hs_map = {}
        src = _Source(toks)
        out: list[Token] = []
        append = out.append
        stack = src.stack
        k = 0
        while True:
            if not stack:
                # nothing pushed back: copy up to the next possible macro name
                while k < len(starts) and starts[k] < src.next:
                    k += 1
                if k == len(starts):
                    out.extend(toks[src.next :])
                    return out
                out.extend(toks[src.next : starts[k]])
                src.next = starts[k]
            written = not stack
            t = src.pop()
            if t is None:
                return out
            m = macros.get(t.text)
            if m is None or t.kind not in ("name", "keyword"):
                append(t)
                continue
            entry = hs_map.get(id(t))
            hs = entry[1] if entry is not None and entry[0] is t else _EMPTY
            if t.text in hs:
                append(t)
                continue
            if top and written:
                self._use = t  # a use written in the text: errors name it
            self._expansions += 1
            if self._expansions >= MAX_EXPANSIONS:
                if self._expansions == MAX_EXPANSIONS:
                    use = self._use or t
                    self.sink.error(
                        use.pos,
                        f"macro expansion of '{use.text}' needs more than "
                        f"{MAX_EXPANSIONS} macro expansions",
                    )
                # give up expanding: the rest goes to the parser as it is
                out.append(t)
                out.extend(reversed(stack))
                out.extend(toks[src.next :])
                return out
            if m.params is None:
                body = self._subst(m, None, hs | {m.name}, t.pos, hs_map)
                if not body and self._tokens_made > MAX_TOKENS:
                    body = [_placeholder(t)]
                _end_at(body, t, t, hs_map)
                stack.extend(reversed(body))
                continue
            nxt = src.peek()
            if nxt is None or nxt.text != "(" or nxt.kind != "punct":
                append(t)  # a function-like macro name without arguments stays a name
                continue
            src.pop()
            collected = self._collect_args(src, m)
            if collected is None:
                self.sink.error(t.pos, f"unterminated argument list invoking macro '{m.name}'")
                return out
            args, rparen = collected
            if not m.params and len(args) == 1 and not args[0]:
                args = []
            if len(args) != len(m.params) and not (m.variadic and len(args) == len(m.params) - 1):
                want = len(m.params) - (1 if m.variadic else 0)
                few = "only" if len(args) < want else "but"
                self.sink.error(
                    t.pos,
                    f"macro '{m.name}' requires {want} argument{'s' if want != 1 else ''}, "
                    f"{few} {len(args)} given",
                )
                continue
            if len(args) < len(m.params):
                args.append([])
            r_entry = hs_map.get(id(rparen))
            r_hs = r_entry[1] if r_entry is not None and r_entry[0] is rparen else _EMPTY
            body = self._subst(m, args, (hs & r_hs) | {m.name}, t.pos, hs_map)
            if not body and self._tokens_made > MAX_TOKENS:
                body = [_placeholder(t)]  # the use stays an operand: no follow-on errors
            _end_at(body, t, rparen, hs_map)
            stack.extend(reversed(body))

    def _collect_args(self, src: _Source, m: Macro) -> tuple[list[list[Token]], Token] | None:
        """Take a macro call's arguments from `src` (after its '('); None if unterminated."""
        assert m.params is not None
        args: list[list[Token]] = [[]]
        depth = 0
        nparams = len(m.params)
        while True:
            t = src.pop()
            if t is None:
                return None
            if t.kind == "punct":
                s = t.text
                if s == "(":
                    depth += 1
                elif s == ")":
                    if depth == 0:
                        return args, t
                    depth -= 1
                elif s == "," and depth == 0 and not (m.variadic and len(args) >= nparams):
                    args.append([])
                    continue
            args[-1].append(t)

    def _subst(
        self,
        m: Macro,
        args: list[list[Token]] | None,
        hs: frozenset[str],
        pos: SourcePos,
        hs_map: dict,
    ) -> list[Token]:
        """The body of `m` with arguments substituted, `#` and `##` applied, tokens at `pos`."""
        res: list[Token] = []
        if args is None:
            for b in m.body:
                res.append(_PASTE if b.text == "##" and b.kind == "punct" else _at(b, pos))
        else:
            assert m.params is not None
            index = {p: k for k, p in enumerate(m.params)}
            expanded: dict[int, list[Token]] = {}
            body = m.body
            n = len(body)
            i = 0
            while i < n:
                b = body[i]
                if b.kind == "punct" and b.text == "#" and i + 1 < n:
                    res.append(_stringize(args[index[body[i + 1].text]], pos))
                    i += 2
                    continue
                if b.kind == "punct" and b.text == "##":
                    res.append(_PASTE)
                    i += 1
                    continue
                k = index.get(b.text) if b.kind in ("name", "keyword") else None
                if k is None:
                    res.append(_at(b, pos))
                    i += 1
                    continue
                pasted = (i + 1 < n and body[i + 1].text == "##") or (
                    i > 0 and body[i - 1].text == "##"
                )
                if pasted:
                    arg = args[k]
                    piece = arg if arg else [_PLACEMARKER]
                else:
                    if k not in expanded:
                        expanded[k] = self._expand_argument(m, args[k], pos, hs_map)
                    piece = expanded[k]
                if self._tokens_made + len(res) + len(piece) > MAX_TOKENS:
                    return self._over_budget(m, pos)  # checked before the copy is made
                res.extend(piece)
                i += 1
        if self._tokens_made + len(res) > MAX_TOKENS:
            return self._over_budget(m, pos)
        self._tokens_made += len(res)
        if any(t is _PASTE for t in res):
            res = self._apply_pastes(res, pos)
        out: list[Token] = []
        # hide sets are shared: one union per distinct hide set of the argument tokens
        unions: dict[frozenset[str], frozenset[str]] = {}
        for t in res:
            if t is _PLACEMARKER:
                continue
            old = hs_map.get(id(t))
            nt = Token(t.kind, t.text, t.pos, t.value, t.suffix)
            if old is not None and old[0] is t:
                u = unions.get(old[1])
                if u is None:
                    u = unions[old[1]] = old[1] | hs
                hs_map[id(nt)] = (nt, u)
            else:
                hs_map[id(nt)] = (nt, hs)
            out.append(nt)
        return out

    def _over_budget(self, m: Macro, pos: SourcePos) -> list[Token]:
        """Report (once) that expansion made too many tokens; stop expanding."""
        if self._tokens_made <= MAX_TOKENS:
            use = self._use
            name, where = (use.text, use.pos) if use is not None else (m.name, pos)
            self.sink.error(
                where, f"macro expansion of '{name}' produces more than {MAX_TOKENS} tokens"
            )
        self._tokens_made = MAX_TOKENS + 1
        self._expansions = MAX_EXPANSIONS + 1
        return []

    def _expand_argument(
        self, m: Macro, arg: list[Token], pos: SourcePos, hs_map: dict
    ) -> list[Token]:
        if self._nesting >= MAX_NESTING:
            self.sink.error(pos, f"macro calls nested more than {MAX_NESTING} deep in '{m.name}'")
            return list(arg)
        self._nesting += 1
        try:
            return self.expand(arg, hs_map)
        finally:
            self._nesting -= 1

    def _apply_pastes(self, res: list[Token], pos: SourcePos) -> list[Token]:
        out: list[Token] = []
        i = 0
        n = len(res)
        while i < n:
            t = res[i]
            if t is not _PASTE:
                out.append(t)
                i += 1
                continue
            left = out.pop() if out else _PLACEMARKER
            right = res[i + 1] if i + 1 < n else _PLACEMARKER
            i += 2
            if left is _PLACEMARKER:
                out.append(right)
            elif right is _PLACEMARKER:
                out.append(left)
            else:
                glued = lex_fragment(left.text + right.text, pos)
                if glued is None or len(glued) != 1:
                    self.sink.error(
                        pos,
                        f"pasting '{left.text}' and '{right.text}' does not give a valid token",
                    )
                    out.extend((left, right))
                else:
                    out.append(glued[0])
        return out


class _Source:
    """Tokens to expand: a pushback stack (rescanned expansions) over a list."""

    __slots__ = ("next", "stack", "toks")

    def __init__(self, toks: list[Token]) -> None:
        self.toks = toks
        self.next = 0
        self.stack: list[Token] = []

    def pop(self) -> Token | None:
        if self.stack:
            return self.stack.pop()
        if self.next < len(self.toks):
            self.next += 1
            return self.toks[self.next - 1]
        return None

    def peek(self) -> Token | None:
        if self.stack:
            return self.stack[-1]
        return self.toks[self.next] if self.next < len(self.toks) else None


_text = attrgetter("text")


def _end_at(body: list[Token], use: Token, last: Token, hs_map: dict) -> None:
    """Make the expansion end where the macro use ends (its name or its ')').

    Its last token is placed so that "just after it" (where a missing ';' is
    reported) is just after the use, not inside the macro name.
    """
    if not body or body[-1].pos is not use.pos or last.pos.file != use.pos.file:
        return  # the expansion ends with an argument: that token keeps its own place
    end = body[-1]
    col = max(1, last.pos.col + len(last.text) - len(end.text))
    if last.pos.line == use.pos.line and col < use.pos.col:
        col = use.pos.col
    nt = Token(
        end.kind, end.text, SourcePos(last.pos.file, last.pos.line, col), end.value, end.suffix
    )
    old = hs_map.get(id(end))
    hs_map[id(nt)] = (nt, old[1] if old is not None and old[0] is end else _EMPTY)
    body[-1] = nt


def _at(t: Token, pos: SourcePos) -> Token:
    return Token(t.kind, t.text, pos, t.value, t.suffix)


def _line_and_file(toks: list[Token]) -> list[Token]:
    """`__LINE__` and `__FILE__` replaced by the line number and file name of their place
    (a macro body's tokens carry the place of the macro's use, as in C)."""
    if _LINE_FILE.isdisjoint(map(_text, toks)):
        return toks
    for i, t in enumerate(toks):
        if t.kind == "name" and (t.text == "__LINE__" or t.text == "__FILE__"):
            pos = t.pos
            if t.text == "__LINE__":
                toks[i] = Token("int", str(pos.line), pos, pos.line)
            else:
                data = pos.file.encode("utf-8")
                toks[i] = Token("string", _quote(data), pos, data)
    return toks


def _quote(data: bytes) -> str:
    text = data.decode("utf-8", "replace").replace("\\", "\\\\").replace('"', '\\"')
    return f'"{text}"'


def _adjacent(a: Token, b: Token) -> bool:
    """True when `b` follows `a` with no white space in between."""
    return (
        a.pos.file == b.pos.file
        and a.pos.line == b.pos.line
        and a.pos.col + len(a.text) == b.pos.col
    )


def _spell(toks: list[Token]) -> str:
    """Tokens written back as text, with a space wherever the source had white space."""
    parts: list[str] = []
    prev: Token | None = None
    for t in toks:
        if prev is not None and not _adjacent(prev, t):
            parts.append(" ")
        parts.append(t.text)
        prev = t
    return "".join(parts)


def _stringize(toks: list[Token], pos: SourcePos) -> Token:
    parts: list[str] = []
    prev: Token | None = None
    for t in toks:
        if prev is not None and not _adjacent(prev, t):
            parts.append(" ")
        if t.kind in ("string", "char"):
            parts.append(t.text.replace("\\", "\\\\").replace('"', '\\"'))
        else:
            parts.append(t.text)
        prev = t
    spelled = "".join(parts)
    raw = "".join(
        t.text if i == 0 or _adjacent(toks[i - 1], t) else " " + t.text for i, t in enumerate(toks)
    )
    return Token("string", '"' + spelled + '"', pos, raw.encode("utf-8"))


def _same_definition(a: Macro, b: Macro) -> bool:
    return (
        a.params == b.params
        and a.variadic == b.variadic
        and [t.text for t in a.body] == [t.text for t in b.body]
    )


# ---------------------------------------------------------------- #if evaluation


def _placeholder(use: Token) -> Token:
    """`0` in place of a macro use whose expansion ran over the budget (reported)."""
    return Token("int", "0", use.pos, 0)


class _IfError(Exception):
    def __init__(self, pos: SourcePos, message: str) -> None:
        super().__init__(message)
        self.pos = pos
        self.message = message


def _wrap64(v: int) -> int:
    v &= (1 << 64) - 1
    return v - (1 << 64) if v >= 1 << 63 else v


class _IfEval:
    """Integer constant expression of #if, in 64-bit signed arithmetic."""

    def __init__(self, toks: list[Token], pos: SourcePos) -> None:
        self.toks = toks
        self.i = 0
        self.pos = pos
        self.unevaluated = 0  # > 0 inside the skipped operand of && || ?:

    def run(self) -> int:
        v = self.cond()
        if self.i < len(self.toks):
            t = self.toks[self.i]
            raise _IfError(t.pos, f"missing binary operator before '{t.text}' in #if")
        return v

    def _peek(self) -> Token | None:
        return self.toks[self.i] if self.i < len(self.toks) else None

    def cond(self) -> int:
        c = self.binary(1)
        t = self._peek()
        if t is not None and t.text == "?":
            self.i += 1
            self.unevaluated += not c
            a = self.cond()
            self.unevaluated -= not c
            t2 = self._peek()
            if t2 is None or t2.text != ":":
                raise _IfError(t.pos, "expected ':' in #if conditional expression")
            self.i += 1
            self.unevaluated += bool(c)
            b = self.cond()
            self.unevaluated -= bool(c)
            return a if c else b
        return c

    def binary(self, min_prec: int) -> int:
        left = self.unary()
        while True:
            t = self._peek()
            if t is None or t.kind != "punct":
                return left
            prec = BINARY_PREC.get(t.text)
            if prec is None or prec < min_prec:
                return left
            self.i += 1
            op = t.text
            if (op == "&&" and not left) or (op == "||" and left):
                self.unevaluated += 1
                self.binary(prec + 1)
                self.unevaluated -= 1
                left = int(op == "||")
                continue
            right = self.binary(prec + 1)
            if op in ("/", "%") and right == 0 and self.unevaluated:
                left = 0
                continue
            left = _wrap64(self._apply(op, left, right, t.pos))

    @staticmethod
    def _apply(op: str, a: int, b: int, pos: SourcePos) -> int:
        if op in ("/", "%"):
            if b == 0:
                raise _IfError(pos, "division by zero in #if")
            q = abs(a) // abs(b)
            q = q if (a < 0) == (b < 0) else -q
            return q if op == "/" else a - q * b
        if op in ("<<", ">>"):
            if b < 0:
                raise _IfError(pos, f"negative shift count {b} in #if")
            b %= 64  # as HMPL shifts at run time: the count modulo the width
            return a << b if op == "<<" else a >> b
        return {
            "||": lambda: int(bool(a or b)),
            "&&": lambda: int(bool(a and b)),
            "|": lambda: a | b,
            "^": lambda: a ^ b,
            "&": lambda: a & b,
            "==": lambda: int(a == b),
            "!=": lambda: int(a != b),
            "<": lambda: int(a < b),
            ">": lambda: int(a > b),
            "<=": lambda: int(a <= b),
            ">=": lambda: int(a >= b),
            "+": lambda: a + b,
            "-": lambda: a - b,
            "*": lambda: a * b,
        }[op]()

    def unary(self) -> int:
        t = self._peek()
        if t is None:
            last = self.toks[-1].pos if self.toks else self.pos
            raise _IfError(last, "expected value in #if expression")
        self.i += 1
        if t.kind == "punct":
            if t.text == "(":
                v = self.cond()
                t2 = self._peek()
                if t2 is None or t2.text != ")":
                    raise _IfError(t.pos, "missing ')' in #if expression")
                self.i += 1
                return v
            if t.text == "-":
                return _wrap64(-self.unary())
            if t.text == "+":
                return self.unary()
            if t.text == "!":
                return int(not self.unary())
            if t.text == "~":
                return _wrap64(~self.unary())
        if t.kind in ("int", "char"):
            return _wrap64(t.value)  # type: ignore[arg-type]
        if t.kind in ("name", "keyword"):
            return 0  # an identifier that is no macro counts as 0
        if t.kind == "float":
            raise _IfError(t.pos, "floating constant in preprocessor expression")
        raise _IfError(t.pos, f"token '{t.text}' is not valid in #if expressions")
