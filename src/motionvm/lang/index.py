"""What an editor sees inside one file: declarations, every use of a name, completions, calls.

A language builds a `SourceIndex` of a file's text (`Language.index`): its declarations
(`Symbol`) and every occurrence of a name, each resolved to the declaration it names (or to
none: a built-in, a keyword). Go to definition, references and rename are lookups in it;
hover and completion read it with the language's documented names. The text helpers at
the end (`word_at`, `call_at`, `param_spans`) serve every language whose syntax is
C-like enough: words, parentheses, commas.
"""

from __future__ import annotations

import bisect
import re
from dataclasses import dataclass, field

from motionvm.source.files import text_lines


def cut_inside(pattern: re.Pattern, text: str, offset: int, at_end: frozenset[str]) -> bool:
    """Whether character `offset` of `text` lies inside a comment or a literal, as the
    named groups of a language's `pattern` scan the text before it: a group named in
    `at_end` (a line comment, a string still open) holds the offset when its match ends
    there; a group named "unclosed" (a block comment's opening without its end before
    the offset, tried after the closed form) holds every offset after it."""
    last = None
    for m in pattern.finditer(text, 0, offset):
        g = m.lastgroup
        if g == "unclosed":
            return True
        if m.end() > m.start():  # (`\Z` and the like match where the text is cut)
            last = m
    return last is not None and last.end() == offset and last.lastgroup in at_end


@dataclass(frozen=True)
class Symbol:
    """A declaration in a source file (outline, go to definition, rename)."""

    name: str
    kind: str
    """"function", "variable", "constant", "macro", "struct", "member", "label", "task",
    "module", "object", "procedure", "parameter", "type"."""
    file: str
    line: int
    """1-based."""
    col: int
    """1-based column of the name."""
    container: str | None = None
    """The enclosing function, struct, module or task (None: file level)."""
    detail: str = ""
    """The declaration as written (`int count`, `AXIS$MOTOR fan`)."""
    end_line: int = 0
    """The last line of what it declares (a function's body), 0: its own line only."""


@dataclass(frozen=True)
class Occurrence:
    """One place where a name is written: a declaration or a use."""

    name: str
    line: int
    """1-based."""
    col: int
    """1-based column of its first character."""
    symbol: Symbol | None
    """The declaration it names (None: a built-in, a keyword, an unknown name)."""

    @property
    def end_col(self) -> int:
        """1-based column just after its last character."""
        return self.col + len(self.name)


@dataclass
class SourceIndex:
    """The names of one file's text (`Language.index`)."""

    path: str
    text: str
    symbols: list[Symbol] = field(default_factory=list)
    """Every declaration, in source order."""
    occurrences: list[Occurrence] = field(default_factory=list)
    """Every written name that a tool can point at, in source order."""

    def __post_init__(self) -> None:
        self.occurrences.sort(key=lambda o: (o.line, o.col))
        self._keys = [(o.line, o.col) for o in self.occurrences]
        self._lines: list[str] | None = None

    @property
    def lines(self) -> list[str]:
        if self._lines is None:
            self._lines = text_lines(self.text)
        return self._lines

    def line_text(self, line: int) -> str:
        """The text of 1-based `line` ("" past the end)."""
        return self.lines[line - 1] if 0 < line <= len(self.lines) else ""

    def offset(self, line: int, col: int) -> int:
        """The character offset in `text` of 1-based (line, col), lines ending at
        newlines (a column past its line's end: the line's end)."""
        text = self.text
        start = 0
        for _ in range(line - 1):
            start = text.find("\n", start) + 1
            if not start:
                return len(text)
        end = text.find("\n", start)
        return min(start + max(col, 1) - 1, len(text) if end < 0 else end)

    def at(self, line: int, col: int) -> Occurrence | None:
        """The occurrence under 1-based (line, col), or just before it (a cursor at a
        name's end still names it)."""
        i = bisect.bisect_right(self._keys, (line, col)) - 1
        if i >= 0:
            o = self.occurrences[i]
            if o.line == line and o.col <= col <= o.end_col:
                return o
        return None

    def uses(self, symbol: Symbol) -> list[Occurrence]:
        """Every occurrence naming `symbol`, its declaration included, in source order."""
        return [o for o in self.occurrences if o.symbol == symbol]

    def symbols_named(self, name: str) -> list[Symbol]:
        return [s for s in self.symbols if s.name == name]

    def enclosing(self, line: int, kinds: tuple[str, ...] = ("function",)) -> Symbol | None:
        """The innermost declaration of one of `kinds` whose lines hold `line`."""
        best = None
        for s in self.symbols:
            if s.kind in kinds and s.line <= line <= max(s.end_line, s.line):
                if best is None or s.line >= best.line:
                    best = s
        return best


@dataclass(frozen=True)
class Completion:
    """One proposal of a completion list."""

    label: str
    kind: str
    """"function", "variable", "constant", "keyword", "macro", "member", "label", "type",
    "module", "object", "procedure", "attribute", "class", "parameter"."""
    detail: str = ""
    """One line: a prototype, a declaration, a value."""
    snippet: str = ""
    """What to insert, with `${1:arg}` placeholders ("": the label)."""
    doc: str = ""
    """Markdown shown beside it."""


@dataclass(frozen=True)
class Signature:
    """A callable's prototype and where each of its parameters is written in it."""

    label: str
    params: tuple[tuple[int, int], ...]
    """(start, end) offsets of each parameter in `label`."""
    doc: str = ""


# ------------------------------------------------------------------ text helpers

WORD = re.compile(r"[A-Za-z_$][A-Za-z0-9_$]*")
_TOKEN = re.compile(
    r"[A-Za-z_$][A-Za-z0-9_$]*|0[xX][0-9A-Fa-f]+|\d+(?:\.\d*)?(?:[eE][-+]?\d+)?|\"[^\"]*\"?|'[^']*'?"
)


def word_at(line_text: str, col: int, pattern: re.Pattern[str] = WORD) -> tuple[str, int] | None:
    """The word of `pattern` under 1-based `col` (or ending just before it) and its
    1-based start column."""
    for m in pattern.finditer(line_text):
        if m.start() + 1 <= col <= m.end() + 1:
            return m.group(), m.start() + 1
        if m.start() + 1 > col:
            break
    return None


def token_end(line_text: str, col: int) -> int:
    """1-based column just after the token that starts at 1-based `col`: a word, a number,
    a string; one character otherwise."""
    m = _TOKEN.match(line_text, max(0, col - 1))
    if m is not None and m.end() > m.start():
        return m.end() + 1
    return min(col + 1, len(line_text) + 1) if col <= len(line_text) else col


_PAIRS = {")": "(", "]": "[", "}": "{"}


def call_at(lines: list[str], line: int, col: int, max_back: int = 50) -> tuple[str, int] | None:
    """The callee name and 0-based argument index of the innermost open call around
    1-based (line, col), looking back at most `max_back` lines: the name before the
    unclosed `(` and the commas at its level. Strings and `//` comments are skipped."""
    depth: list[str] = []
    commas = 0
    first = max(1, line - max_back)
    for ln in range(line, first - 1, -1):
        text = lines[ln - 1] if 0 < ln <= len(lines) else ""
        text = _blank_strings(text)
        end = col - 1 if ln == line else len(text)
        i = min(end, len(text)) - 1
        while i >= 0:
            ch = text[i]
            if ch in _PAIRS:
                depth.append(_PAIRS[ch])
            elif ch in "([{":
                if depth:
                    depth.pop()
                elif ch != "(":
                    return None
                else:
                    m = re.search(r"([A-Za-z_$][A-Za-z0-9_$]*)\s*$", text[:i])
                    return (m.group(1), commas) if m else None
            elif ch == ";" and not depth:
                return None
            elif ch == "," and not depth:
                commas += 1
            i -= 1
    return None


def _blank_strings(text: str) -> str:
    """`text` with string and char literals and a `//` comment blanked out (same length)."""
    out = []
    quote = ""
    i = 0
    while i < len(text):
        ch = text[i]
        if quote:
            if ch == "\\":
                out.append("  ")
                i += 2
                continue
            if ch == quote:
                quote = ""
            out.append(" ")
        elif ch in "\"'":
            quote = ch
            out.append(" ")
        elif text.startswith("//", i):
            out.append(" " * (len(text) - i))
            break
        else:
            out.append(ch)
        i += 1
    return "".join(out)[: len(text)]


def param_spans(prototype: str) -> tuple[tuple[int, int], ...]:
    """(start, end) offsets of each parameter between the outermost parentheses of a
    prototype (`int MoveAbs(int axis_id, double pos)`): split at commas of that level."""
    open_ = prototype.find("(")
    if open_ < 0:
        return ()
    spans = []
    depth = 0
    start = open_ + 1
    for i in range(open_ + 1, len(prototype)):
        ch = prototype[i]
        if ch in "([":
            depth += 1
        elif ch in ")]":
            if depth == 0:
                spans.append((start, i))
                break
            depth -= 1
        elif ch == "," and depth == 0:
            spans.append((start, i))
            start = i + 1
    out = []
    for a, b in spans:
        text = prototype[a:b]
        stripped = text.strip()
        if stripped and stripped != "void":
            lead = len(text) - len(text.lstrip())
            out.append((a + lead, a + lead + len(stripped)))
    return tuple(out)


def snippet_of(name: str, prototype: str) -> str:
    """A call of `name` with one placeholder per parameter of `prototype`, named after
    the parameter (its last word)."""
    names = []
    for a, b in param_spans(prototype):
        words = WORD.findall(prototype[a:b])
        names.append(words[-1] if words else "arg")
    args = ", ".join(f"${{{i + 1}:{p}}}" for i, p in enumerate(names))
    return f"{name}({args})"


def words(text: str, pattern: re.Pattern[str] = WORD) -> list[tuple[str, int, int]]:
    """(word, 1-based line, 1-based col) of every word of `text`."""
    out = []
    for ln, line in enumerate(text_lines(text), 1):
        for m in pattern.finditer(line):
            out.append((m.group(), ln, m.start() + 1))
    return out


SCOPES = ("function", "procedure")
"""Kinds of declaration whose lines are a scope of their own (their locals' container)."""


def resolve(
    path: str,
    text: str,
    symbols: list[Symbol],
    names: list[tuple[str, int, int]],
    *,
    fold: bool = False,
) -> SourceIndex:
    """The index of a file from its declarations and the (word, line, col) of every
    name token: each name resolved to the declaration it names.

    A declaration written at the name's own place is that declaration. Otherwise a
    local of the scope around the name (its container is that function or procedure)
    that is visible there (declared before it, within its `end_line`) wins, the latest
    declared first; then a file-level one. Members and names no declaration has are left
    unresolved. `fold`: names are case-insensitive."""
    key = str.lower if fold else (lambda s: s)
    at_place = {(s.line, s.col): s for s in symbols}
    named: set[str] = set()  # names some declaration (not a member) has
    scoped: dict[tuple[str, str], list[Symbol]] = {}  # (name, container) -> its locals
    wide: dict[str, list[Symbol]] = {}  # name -> its file-level declarations, in order
    for s in symbols:
        if s.kind != "member":
            k = key(s.name)
            named.add(k)
            if s.container is not None and s.kind not in SCOPES:
                scoped.setdefault((k, s.container), []).append(s)
            if s.container is None or s.kind in ("object", "procedure"):
                wide.setdefault(k, []).append(s)
    scopes = sorted((s for s in symbols if s.kind in SCOPES), key=lambda s: s.line)
    n_lines = text.count("\n") + 2
    scope_of_line: list[str | None] = [None] * (n_lines + 1)
    for s in scopes:
        for ln in range(s.line, min(max(s.end_line, s.line), n_lines) + 1):
            scope_of_line[ln] = s.name
    out: list[Occurrence] = []
    for word, line, col in names:
        found = at_place.get((line, col))
        if found is not None and key(found.name) == key(word):
            out.append(Occurrence(word, line, col, found))
            continue
        k = key(word)
        if k not in named:
            continue
        scope = scope_of_line[line] if line < len(scope_of_line) else None
        out.append(Occurrence(word, line, col, _pick(k, scope, line, col, scoped, wide)))
    return SourceIndex(path, text, list(symbols), out)


def _pick(
    k: str,
    scope: str | None,
    line: int,
    col: int,
    scoped: dict[tuple[str, str], list[Symbol]],
    wide: dict[str, list[Symbol]],
) -> Symbol | None:
    """What name `k` at (line, col) in `scope` names: the latest visible local of that
    scope, else the first file-level declaration that is not one of its locals."""
    best = None
    for s in scoped.get((k, scope), ()) if scope is not None else ():
        visible = s.kind in ("parameter", "label") or (
            (s.line, s.col) <= (line, col) and (not s.end_line or line <= s.end_line)
        )
        if visible and (best is None or (s.line, s.col) > (best.line, best.col)):
            best = s
    if best is not None:
        return best
    for s in wide.get(k, ()):
        if not (s.container is not None and s.container == scope and s.kind not in SCOPES):
            return s
    return None
