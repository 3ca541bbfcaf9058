"""`motionvm test -k EXPR`: pytest's keyword expressions over case ids.

    expr     := and_expr ('or' and_expr)*
    and_expr := not_expr ('and' not_expr)*
    not_expr := 'not' not_expr | '(' expr ')' | WORD

A WORD matches a case whose id contains it, ignoring case. An expression that does not
parse is a usage error naming the place, never a selection of nothing.
"""

from __future__ import annotations

import re
from collections.abc import Callable

_TOKEN = re.compile(r"\s*(?:(\()|(\))|([^\s()]+))")
_KEYWORDS = {"and", "or", "not"}

Matcher = Callable[[str], bool]


class KeywordError(ValueError):
    """An expression that does not parse (the message names what and where)."""


def compile_keywords(expr: str) -> Matcher:
    """A predicate over case ids for `expr`; KeywordError if it does not parse."""
    tokens: list[tuple[str, int]] = []
    pos = 0
    text = expr.rstrip()
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if m is None:  # pragma: no cover — every character is one of the three kinds
            raise KeywordError(f"unexpected character at column {pos + 1}")
        tokens.append((m.group(m.lastindex or 0), m.start(m.lastindex or 0) + 1))
        pos = m.end()
    parser = _Parser(tokens, expr)
    if not tokens:
        raise KeywordError("empty expression")
    match = parser.expr()
    if parser.i < len(tokens):
        word, col = tokens[parser.i]
        raise KeywordError(f"unexpected '{word}' at column {col}")
    return match


class _Parser:
    def __init__(self, tokens: list[tuple[str, int]], text: str) -> None:
        self.tokens = tokens
        self.text = text
        self.i = 0

    def _peek(self) -> str | None:
        return self.tokens[self.i][0] if self.i < len(self.tokens) else None

    def _fail(self, wanted: str) -> KeywordError:
        if self.i < len(self.tokens):
            word, col = self.tokens[self.i]
            return KeywordError(f"expected {wanted} at column {col}, got '{word}'")
        return KeywordError(f"expected {wanted} at the end")

    def expr(self) -> Matcher:
        parts = [self.and_expr()]
        while self._peek() == "or":
            self.i += 1
            parts.append(self.and_expr())
        return parts[0] if len(parts) == 1 else (lambda s: any(p(s) for p in parts))

    def and_expr(self) -> Matcher:
        parts = [self.not_expr()]
        while self._peek() == "and":
            self.i += 1
            parts.append(self.not_expr())
        return parts[0] if len(parts) == 1 else (lambda s: all(p(s) for p in parts))

    def not_expr(self) -> Matcher:
        token = self._peek()
        if token == "not":
            self.i += 1
            inner = self.not_expr()
            return lambda s: not inner(s)
        if token == "(":
            self.i += 1
            inner = self.expr()
            if self._peek() != ")":
                raise self._fail("')'")
            self.i += 1
            return inner
        if token is None or token == ")" or token in _KEYWORDS:
            raise self._fail("a word, 'not' or '('")
        self.i += 1
        word = token.lower()
        return lambda s: word in s.lower()
