"""PDL lexer: source text to tokens with positions; comments and `\\`-newline splices removed.

Keywords and directives are case-insensitive (`Sleep`, `#Long`): a
keyword token's `value` is its lower-case spelling. Identifiers keep their case.
Typographic quotes from pasted PDF text are read as ASCII quotes.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from motionvm.lang.index import cut_inside
from motionvm.source.diagnostics import DiagnosticSink
from motionvm.source.files import SourcePos

BUILTIN_FUNCS = frozenset(
    [
        "max",
        "min",
        "abs",
        "unsign",
        "sign",
        "sin",
        "cos",
        "sqrt",
        "divi",
        "shift",
        "bitset",
        "bitclr",
        "bittog",
        "memcpy",
        "memset",
        "memmin",
        "memmax",
        "memsum",
    ]
)

# `run` is not reserved: the manual uses it as a parameter name (§2.4.2, `instate run`).
KEYWORDS = (
    frozenset(
        [
            "halt",
            "wait",
            "sleep",
            "goto",
            "call",
            "ret",
            "exitproc",
            "loop",
            "do",
            "end",
            "if",
            "else",
            "while",
            "till",
            "proc",
            "lock",
            "unlock",
            "kill",
            "seton",
            "setoff",
            "toggle",
            "sttovar",
            "sizeof",
            "tout",
            "printl",
            "prints",
            "retprintl",
            "long",
            "float",
            "short",
            "instate",
            "_ro",
            "_lp",
        ]
    )
    | BUILTIN_FUNCS
)

PUNCT2 = ("+=", "-=", "*=", "/=", "%=", "&=", "|=", "@=", "++", "--", "<=", ">=", "<>", "->")
PUNCT1 = frozenset("=+-*/%&|@~<>()[]{},;:")

_QUOTES = {"\u201c": '"', "\u201d": '"', "\u201e": '"', "\u2018": "'", "\u2019": "'"}
_FULL_WIDTH = {"\uff1b": ";", "\uff0c": ",", "\uff1a": ":", "\uff08": "(", "\uff09": ")"}


@dataclass(frozen=True, slots=True)
class MacroOrigin:
    """The macro whose body a token was copied from, and where that macro was defined."""

    name: str
    def_pos: SourcePos
    body_ends_with_semicolon: bool = False


@dataclass(slots=True, unsafe_hash=True)  # not frozen: a frozen init costs 8x (25,000 tokens)
class Token:
    """One token (never changed once made).

    kind: 'name' | 'keyword' | 'int' | 'float' | 'string' | 'punct' | 'directive' | 'eof'.
    value: int (signed 32-bit) for 'int', float for 'float', str for 'string', the
    lower-case word for 'keyword' and 'directive' (without '#'), None otherwise.
    `bol` marks the first token of a logical line (directives must start one).
    `end_col` is the column just after the token, for adjacency tests.
    A token produced by a macro expansion carries the position of the macro's use and
    the macro it came from in `origin`.
    """

    kind: str
    text: str
    pos: SourcePos
    value: object = None
    bol: bool = False
    end_col: int = 0
    origin: MacroOrigin | None = None


_DIGITS = frozenset("0123456789")
"""ASCII digits only: `str.isdigit` also accepts digits of other scripts and superscripts."""

_COMMON = re.compile(
    r"[ \t\r\f\v]*+(?:(?P<newline>\n)|(?P<word>[A-Za-z_][A-Za-z0-9_]*)"
    r"|(?P<int>[0-9]++(?![.xX]))"  # not a float, a hexadecimal constant or `1..`
    r"|(?P<punct>\+=|-=|\*=|/=|%=|&=|\|=|@=|\+\+|--|<=|>=|<>|->"
    r"|[=+\-*%&|@~<>()\[\]{},;:]|/(?![/*])))"
)
"""A common token after spaces, matched at once: what `run` reads one character at a
time otherwise (the same tokens; anything else, and every error, takes that way)."""


def _shown(text: str, limit: int = 24) -> str:
    """A constant's text for a message, shortened in the middle if long."""
    if len(text) <= limit:
        return text
    return f"{text[:10]}...{text[-6:]} ({len(text)} characters)"


def _wrap32(v: int) -> int:
    return ((v + 0x80000000) & 0xFFFFFFFF) - 0x80000000


class _Lexer:
    def __init__(self, path: str, text: str, sink: DiagnosticSink) -> None:
        self.path = path
        self.text = text
        self.sink = sink
        self.i = 0
        self.line = 1
        self.col = 1
        self.bol = True
        self.out: list[Token] = []

    def pos(self) -> SourcePos:
        return SourcePos(self.path, self.line, self.col)

    def peek(self, k: int = 0) -> str:
        j = self.i + k
        if j >= len(self.text):
            return ""
        c = self.text[j]
        return _QUOTES.get(c, c)

    def advance(self, n: int = 1) -> None:
        for _ in range(n):
            if self.i >= len(self.text):
                return
            if self.text[self.i] == "\n":
                self.line += 1
                self.col = 1
            else:
                self.col += 1
            self.i += 1

    def emit(self, kind: str, text: str, pos: SourcePos, value: object = None) -> None:
        self.out.append(Token(kind, text, pos, value, self.bol, pos.col + len(text)))
        self.bol = False

    def run(self) -> list[Token]:
        text, path, out = self.text, self.path, self.out
        common = _COMMON.match
        while self.i < len(text):
            i, line, col, bol = self.i, self.line, self.col, self.bol
            while (m := common(text, i)) is not None:
                kind, end = m.lastgroup, m.end()
                if kind == "newline":
                    line, col, bol, i = line + 1, 1, True, end
                    continue
                word = m.group(kind)
                col += end - i - len(word)  # the spaces before it
                p = SourcePos(path, line, col)
                col += len(word)
                i = end
                if kind == "word":
                    low = word.lower()
                    if low in KEYWORDS:
                        out.append(Token("keyword", word, p, low, bol, col))
                    else:
                        out.append(Token("name", word, p, None, bol, col))
                elif kind == "int":
                    self.bol = bol
                    self._decimal(word, p)
                else:
                    out.append(Token("punct", word, p, None, bol, col))
                bol = False
            self.i, self.line, self.col, self.bol = i, line, col, bol
            if i >= len(text):
                break
            c = self.peek()
            if c == "\n":
                self.advance()
                self.bol = True
            elif c in " \t\r\f\v":
                self.advance()
            elif c == "\\" and self._splice():
                pass
            elif c == "/" and self.peek(1) == "/":
                while self.i < len(self.text) and self.text[self.i] != "\n":
                    self.advance()
            elif c == "/" and self.peek(1) == "*":
                self._block_comment()
            elif c.isascii() and (c.isalpha() or c == "_"):
                self._word()
            elif c.isascii() and c.isdigit() or (c == "." and self.peek(1).isdigit()):
                self._number()
            elif c == '"':
                self._string()
            elif c == "#":
                self._directive()
            else:
                self._punct(c)
        self.out.append(Token("eof", "", self.pos(), None, True, self.col))
        return self.out

    def _splice(self) -> bool:
        """`\\` then optional blanks then a newline joins two lines (whitespace tolerated)."""
        j = self.i + 1
        while j < len(self.text) and self.text[j] in " \t\r":
            j += 1
        if j < len(self.text) and self.text[j] == "\n":
            self.advance(j - self.i + 1)
            return True
        if j >= len(self.text):
            self.advance(j - self.i)
            return True
        return False

    def _block_comment(self) -> None:
        start = self.pos()
        self.advance(2)
        while self.i < len(self.text):
            if self.text[self.i] == "*" and self.peek(1) == "/":
                self.advance(2)
                return
            self.advance()
        self.sink.error(start, "unterminated comment: '/*' has no closing '*/'")

    def _word(self) -> None:
        start, p = self.i, self.pos()
        while self.i < len(self.text) and (
            self.text[self.i].isascii()
            and (self.text[self.i].isalnum() or self.text[self.i] == "_")
        ):
            self.advance()
        word = self.text[start : self.i]
        low = word.lower()
        if low in KEYWORDS:
            self.emit("keyword", word, p, low)
        else:
            self.emit("name", word, p)

    def _number(self) -> None:
        start, p = self.i, self.pos()
        t = self.text
        if t[self.i] == "0" and self.peek(1) in ("x", "X"):
            self.advance(2)
            while self.i < len(t) and t[self.i] in "0123456789abcdefABCDEF":
                self.advance()
            text = t[start : self.i]
            if len(text) == 2:
                self.sink.error(p, f"hexadecimal constant '{text}' has no digits")
                self.emit("int", text, p, 0)
                return
            if len(text[2:].lstrip("0")) > 8:
                self.sink.error(p, f"constant {_shown(text)} does not fit in 32 bits")
                self.emit("int", text, p, 0)
                return
            self.emit("int", text, p, _wrap32(int(text, 16)))
            return
        while self.i < len(t) and t[self.i] in _DIGITS:
            self.advance()
        if self.i < len(t) and t[self.i] == "." and self.peek(1) != ".":
            self.advance()
            while self.i < len(t) and t[self.i] in _DIGITS:
                self.advance()
            text = t[start : self.i]
            self.emit("float", text, p, float(text if text != "." else "0"))
            return
        self._decimal(t[start : self.i], p)

    def _decimal(self, text: str, p: SourcePos) -> None:
        """An integer constant written in decimal digits."""
        # compared as text first: Python refuses int() of a string of more than 4300
        # digits, and a constant of 11 digits is out of range anyway
        if len(text.lstrip("0")) > 10 or int(text) > 0xFFFFFFFF:
            self.sink.error(p, f"constant {_shown(text)} does not fit in 32 bits")
            self.emit("int", text, p, 0)
            return
        self.emit("int", text, p, _wrap32(int(text)))

    def _string(self) -> None:
        p = self.pos()
        self.advance()
        chars: list[str] = []
        while True:
            c = self.peek()
            if c == "" or c == "\n":
                self.sink.error(p, "unterminated string: missing closing '\"' on this line")
                break
            if c == "\\" and self.peek(1) in ('"', "\\"):
                chars.append(self.peek(1))
                self.advance(2)
                continue
            self.advance()
            if c == '"':
                break
            chars.append(c)
        value = "".join(chars)
        self.emit("string", '"' + value + '"', p, value)

    def _directive(self) -> None:
        p = self.pos()
        self.advance()
        start = self.i
        while (
            self.i < len(self.text)
            and self.text[self.i].isascii()
            and (self.text[self.i].isalnum() or self.text[self.i] == "_")
        ):
            self.advance()
        word = self.text[start : self.i]
        if not word:
            j = self.i
            while j < len(self.text) and self.text[j] in " \t":
                j += 1
            k = j
            while (
                k < len(self.text)
                and self.text[k].isascii()
                and (self.text[k].isalnum() or self.text[k] == "_")
            ):
                k += 1
            word = self.text[j:k]
            if not word:
                self.sink.error(p, "'#' must be followed by a directive name such as #long")
                return
            self.sink.error(p, f"no space is allowed between '#' and '{word}': write '#{word}'")
            self.advance(k - self.i)
        self.emit("directive", "#" + word, p, word.lower())
        if word.lower() == "include":
            self._angle_path()

    def _angle_path(self) -> None:
        """`#include <file>`: the path between `<` and `>` is read as one string token."""
        while self.peek() in (" ", "\t"):
            self.advance()
        if self.peek() != "<":
            return
        p = self.pos()
        end = self.text.find(">", self.i)
        newline = self.text.find("\n", self.i)
        if end < 0 or (0 <= newline < end):
            return
        value = self.text[self.i + 1 : end]
        self.advance(end + 1 - self.i)
        self.emit("string", f"<{value}>", p, value)

    def _punct(self, c: str) -> None:
        p = self.pos()
        two = c + self.peek(1)
        if two in PUNCT2:
            self.advance(2)
            self.emit("punct", two, p)
        elif c in PUNCT1:
            self.advance()
            self.emit("punct", c, p)
        elif c == "'":
            self.sink.error(p, f"unexpected character '{self.text[self.i]}' (did you mean ';'?)")
            self.advance()
            self.emit("punct", ";", p)
        elif c in _FULL_WIDTH:
            ascii_c = _FULL_WIDTH[c]
            self.sink.error(p, f"full-width character '{c}' (did you mean '{ascii_c}'?)")
            self.advance()
            self.emit("punct", ascii_c, p)
        else:
            shown = c if c.isprintable() else f"\\x{ord(c):02x}"
            self.sink.error(p, f"unexpected character '{shown}'")
            self.advance()


def tokenize(path: str, text: str, sink: DiagnosticSink) -> list[Token]:
    """All tokens of `text`, ending with one 'eof' token; lexical errors go to `sink`."""
    return _Lexer(path, text, sink).run()


_QUIET = (
    r"(?P<lcom>//[^\n]*)|/\*(?s:.*?)\*/|(?P<unclosed>/\*)"
    r'|"(?:\\["\\]|[^"\n])*+"|(?P<ustr>"(?:\\["\\]|[^"\n])*+)'
)
"""PDL's comments and strings as `cut_inside` reads them (a line comment, a block
comment, closed or not, a string closed on its line or not)."""


def inside_comment_or_literal(text: str, offset: int) -> bool:
    """Whether character `offset` of `text` lies inside a comment or a string."""
    return cut_inside(re.compile(_QUIET), text, offset, frozenset(("lcom", "ustr")))
