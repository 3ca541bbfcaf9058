"""HMPL tokens: what the lexer produces and the preprocessor and parser consume."""

from __future__ import annotations

from typing import NamedTuple

from motionvm.source.files import SourcePos

KEYWORDS = frozenset(
    [
        "void",
        "char",
        "short",
        "int",
        "long",
        "float",
        "double",
        "signed",
        "unsigned",
        "const",
        "volatile",
        "static",
        "extern",
        "struct",
        "union",
        "enum",
        "typedef",
        "sizeof",
        "if",
        "else",
        "while",
        "do",
        "for",
        "switch",
        "case",
        "default",
        "break",
        "continue",
        "return",
        "goto",
        "_AUTORUN_",
        "int8_t",
        "uint8_t",
        "int16_t",
        "uint16_t",
        "int32_t",
        "uint32_t",
        "int64_t",
        "uint64_t",
    ]
)

# C binary operator precedence (higher binds tighter): the parser and `#if` expressions
BINARY_PREC = {
    "||": 1,
    "&&": 2,
    "|": 3,
    "^": 4,
    "&": 5,
    "==": 6,
    "!=": 6,
    "<": 7,
    ">": 7,
    "<=": 7,
    ">=": 7,
    "<<": 8,
    ">>": 8,
    "+": 9,
    "-": 9,
    "*": 10,
    "/": 10,
    "%": 10,
}


class Token(NamedTuple):
    """One token (a named tuple: the lexer makes one per token, and a tuple is the
    cheapest object to make).

    kind: 'name' | 'keyword' | 'int' | 'float' | 'char' | 'string' | 'punct' | 'eof'.
    value: int for 'int' (and 'char', already the signed char value), float for 'float',
    bytes (escapes decoded, no NUL) for 'string', None otherwise.
    For 'int', `suffix` is the lower-cased suffix ('', 'u', 'l', 'ul', 'll', 'ull');
    for 'float', 'f' marks a float constant.
    `pos` is where the token was written; a token produced by a macro expansion
    carries the position of the macro's use, so errors point at the user's line.
    """

    kind: str
    text: str
    pos: SourcePos
    value: object = None
    suffix: str = ""
