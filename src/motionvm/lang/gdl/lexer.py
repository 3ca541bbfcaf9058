"""GDL lexer: the description's lexical rules (the GDL description, 3.1).

- accepted characters: letters, digits, `& = + - * / ( ) , ; < > $ [ ] { } ' _ |`,
  SP, CR, LF, HT; anything else outside strings and comments is an error;
- words: a letter or `_`, then letters, digits, `_`, `$`; a word with `$` must be a
  reserved word; identifiers are 1..40 characters; keywords are case-insensitive;
- delimiters: single, and `<>`, `<=`, `>=` only when written together;
- integers: values up to 999999999, the GDL integer range (9 digits; leading zeros do
  not count: `0000000007` is 7), no reals, the minus sign is a separate delimiter; a
  larger constant, however many digits, is an error naming it;
- strings: `'...'`, at most 40 characters, HT becomes one space, a string continues
  on the next line after an opening quote preceded only by spaces;
- comments: `|...|`, not nestable, anywhere between words, acting as a space.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from motionvm.lang.gdl.objects import CATALOG_WORDS
from motionvm.lang.index import cut_inside
from motionvm.source.diagnostics import DiagnosticSink
from motionvm.source.files import SourcePos
from motionvm.source.suggest import did_you_mean

MAX_IDENT = 40
MAX_DIGITS = 9
MAX_INT = 10**MAX_DIGITS - 1
"""The largest integer constant: the GDL integer range is -999999999..999999999."""
MAX_STRING = 40

INSTRUCTION_WORDS = frozenset(
    {
        "MODULE",
        "END$MODULE",
        "USE",
        "PROCEDURE",
        "DECLARE",
        "BEGIN",
        "END$PROCEDURE",
        "IF",
        "THEN",
        "ELSE",
        "END$IF",
        "WHILE",
        "DO",
        "END$WHILE",
        "RETURN",
        "OF",
        "AND",
        "OR",
        "NOT",
    }
)
RESERVED_WORDS: frozenset[str] = INSTRUCTION_WORDS | CATALOG_WORDS

SINGLE_DELIMITERS = "=+-*/(),;<>[]{}&"
_SPACES = re.compile(r"[ \t\r\n]*")
_WORD_CHARS = re.compile(r"[A-Za-z0-9_$]*")
_DIGITS = re.compile(r"[0-9]*")
_WORD_START = frozenset("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz_")
_DIGIT_CHARS = frozenset("0123456789")


@dataclass(frozen=True, slots=True)
class Token:
    """One word. kind: 'ident', 'keyword', 'int', 'string', 'delim' or 'eof'.

    `text` is the keyword upper case, the identifier as written, or the delimiter;
    `value` is the integer or the joined string.
    """

    kind: str
    text: str
    pos: SourcePos
    value: object = None

    def describe(self) -> str:
        if self.kind == "eof":
            return "end of file"
        if self.kind == "string":
            return "a string"
        return f"'{self.text}'"


class Lexer:
    """Turns one file's text into tokens, reporting lexical errors to a sink."""

    def __init__(self, path: str, text: str, sink: DiagnosticSink) -> None:
        self.path = path
        self.text = text
        self.sink = sink
        self.i = 0
        self.line = 1
        self.line_start = 0

    def pos(self, i: int | None = None) -> SourcePos:
        i = self.i if i is None else i
        return SourcePos(self.path, self.line, i - self.line_start + 1)

    def _newline(self, i_after: int) -> None:
        self.line += 1
        self.line_start = i_after

    def tokens(self) -> list[Token]:
        """Every token of the file, ending with one 'eof' token."""
        out: list[Token] = []
        while True:
            self._skip_space_and_comments()
            if self.i >= len(self.text):
                out.append(Token("eof", "", self.pos()))
                return out
            tok = self._next()
            if tok is not None:
                out.append(tok)

    def _lines_to(self, end: int) -> None:
        """Count the line ends in text[i:end] (`i` itself is not moved)."""
        text = self.text
        ends = text.count("\n", self.i, end)
        if ends:
            self.line += ends
            self.line_start = text.rindex("\n", self.i, end) + 1

    def _skip_space_and_comments(self) -> None:
        text = self.text
        while True:
            end = _SPACES.match(text, self.i).end()
            if end > self.i:
                self._lines_to(end)
                self.i = end
            if end >= len(text) or text[end] != "|":
                return
            start = self.pos()
            j = text.find("|", end + 1)
            if j < 0:
                self._lines_to(len(text))
                self.sink.error(start, "unterminated comment: no closing vertical bar")
                self.i = len(text)
                return
            self._lines_to(j)
            self.i = j + 1

    def _next(self) -> Token | None:
        c = self.text[self.i]
        if c in _WORD_START:
            return self._word()
        if c in _DIGIT_CHARS:
            return self._number()
        if c == "'":
            return self._string()
        pos = self.pos()
        if c in "<>":
            nxt = self.text[self.i + 1 : self.i + 2]
            if (c == "<" and nxt in (">", "=")) or (c == ">" and nxt == "="):
                self.i += 2
                return Token("delim", c + nxt, pos)
        if c in SINGLE_DELIMITERS:
            self.i += 1
            return Token("delim", c, pos)
        self.i += 1
        if c == "$":
            self.sink.error(pos, "'$' cannot start a word: only reserved words contain '$'")
        elif c == "." and self._digit_around():
            self.sink.error(
                pos, "character '.' not accepted: GDL has no real numbers, only integers"
            )
        else:
            shown = c if c.isprintable() else f"U+{ord(c):04X}"
            self.sink.error(pos, f"character '{shown}' not accepted outside strings and comments")
        return None

    def _digit_around(self) -> bool:
        before = self.text[self.i - 2 : self.i - 1]
        after = self.text[self.i : self.i + 1]
        return before in _DIGIT_CHARS or after in _DIGIT_CHARS

    def _word(self) -> Token | None:
        start = self.i
        pos = self.pos()
        self.i = _WORD_CHARS.match(self.text, start).end()
        word = self.text[start : self.i]
        upper = word.upper()
        if upper in RESERVED_WORDS:
            return Token("keyword", upper, pos)
        if "$" in word:
            hint = did_you_mean(upper, sorted(RESERVED_WORDS))
            self.sink.error(
                pos, f"unknown reserved word '{word}': only reserved words contain '$'{hint}"
            )
            return Token("keyword", upper, pos)
        if len(word) > MAX_IDENT:
            self.sink.error(
                pos,
                f"identifier '{word[:12]}...' has {len(word)} characters, "
                f"more than the limit {MAX_IDENT}",
            )
        return Token("ident", word, pos)

    def _number(self) -> Token:
        start = self.i
        pos = self.pos()
        self.i = _DIGITS.match(self.text, start).end()
        digits = self.text[start : self.i]
        significant = digits.lstrip("0")
        value = int(significant or "0") if len(significant) <= MAX_DIGITS else 0
        if len(significant) > MAX_DIGITS:  # not converted: thousands of digits would fail
            shown = digits if len(digits) <= 24 else f"{digits[:12]}... ({len(digits)} digits)"
            self.sink.error(
                pos,
                f"integer constant {shown} is beyond the GDL integer range: at most "
                f"{MAX_INT} ({MAX_DIGITS} digits)",
            )
        end = _WORD_CHARS.match(self.text, self.i).end()
        if end > self.i:
            self.sink.error(
                pos,
                f"'{self.text[start:end]}': a number cannot be followed by "
                "letters, and a name cannot start with a digit",
            )
            self.i = end
        return Token("int", digits, pos, value)

    def _string(self) -> Token | None:
        text = self.text
        pos = self.pos()
        self.i += 1
        pieces: list[str] = []
        while True:
            if self.i >= len(text):
                self.sink.error(pos, "unterminated string: no closing quote")
                return None
            c = text[self.i]
            if c == "'":
                self.i += 1
                break
            if c == "\n":
                self.i += 1
                self._newline(self.i)
                j = self.i
                while j < len(text) and text[j] in " \t":
                    j += 1
                if j < len(text) and text[j] == "'":
                    self.i = j + 1
                    continue
                self.sink.error(
                    pos,
                    "unterminated string: a string continued on the next "
                    "line must repeat the opening quote there (only spaces before "
                    "it)",
                )
                return None
            pieces.append(" " if c == "\t" else c)
            self.i += 1
        value = "".join(pieces)
        if len(value) > MAX_STRING:
            self.sink.error(
                pos, f"string has {len(value)} characters, more than the limit {MAX_STRING}"
            )
        return Token("string", value, pos, value)


def tokenize(path: str, text: str, sink: DiagnosticSink) -> list[Token]:
    """The tokens of `text` (file `path`), ending with 'eof'; errors go to `sink`."""
    return Lexer(path, text, sink).tokens()


_QUIET = r"\|[^|]*+\||(?P<unclosed>\|)|'[^'\n]*+'|(?P<ustr>'[^'\n]*+)"
"""GDL's comments (`|...|`, closed or not) and strings (`'...'`, a line's piece of one
closed or not) as `cut_inside` reads them."""


def inside_comment_or_literal(text: str, offset: int) -> bool:
    """Whether character `offset` of `text` lies inside a comment or a string."""
    return cut_inside(re.compile(_QUIET), text, offset, frozenset(("ustr",)))
