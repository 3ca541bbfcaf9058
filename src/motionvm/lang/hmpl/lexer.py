"""HMPL lexer: C tokens from source text, with one compiled master regex.

`tokenize` is the public entry (errors go straight to the sink). `scan` is what the
preprocessor uses: it also returns where each `#` directive line starts and ends and
holds lexical errors back, so that text inside `#if 0` does not produce errors.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from motionvm.lang.gc_hold import gc_held
from motionvm.lang.hmpl.tokens import KEYWORDS, Token
from motionvm.lang.index import cut_inside
from motionvm.source.diagnostics import DiagnosticSink, TooManyErrors
from motionvm.source.files import SourceFile, SourcePos

PUNCTUATORS = [
    "...",
    "<<=",
    ">>=",
    "->",
    "++",
    "--",
    "<<",
    ">>",
    "<=",
    ">=",
    "==",
    "!=",
    "&&",
    "||",
    "*=",
    "/=",
    "%=",
    "+=",
    "-=",
    "&=",
    "^=",
    "|=",
    "##",
    "[",
    "]",
    "(",
    ")",
    "{",
    "}",
    ".",
    "&",
    "*",
    "+",
    "-",
    "~",
    "!",
    "/",
    "%",
    "<",
    ">",
    "^",
    "|",
    "?",
    ":",
    ";",
    "=",
    ",",
    "#",
]

# A C pp-number: anything that starts like a number and continues with digits,
# letters, '_', '.', or a sign after an exponent letter. Classified afterwards, so
# that `12abc` gives "invalid suffix 'abc'" instead of two tokens.
_PP_NUMBER = r"\.?[0-9](?:[eEpP][+-]|[0-9A-Za-z_.])*+"  # possessive: see the strings below

# Leading blanks are folded into each match: fewer iterations of the Python loop.
# No-break and ideographic spaces and a byte-order mark count as blanks: they come
# with code copied from the manual or written in Chinese editors.
# The common tokens come first (names, newlines, punctuators), so that their groups have
# the smallest numbers and a match tries few alternatives: the one-character punctuators
# are one character class, a `/` that starts a comment and a `.` that starts a number
# are left to the alternatives after them.
_SINGLE_PUNCT = "".join(re.escape(p) for p in PUNCTUATORS if len(p) == 1 and p not in "/.")
_MASTER = re.compile(
    "[ \t\f\v\r\u00a0\u3000\ufeff]*(?:"
    + "|".join(
        [
            r"(?P<name>[A-Za-z_][A-Za-z0-9_]*)",
            r"(?P<nl>\n)",
            "(?P<punct>"
            + "|".join(re.escape(p) for p in PUNCTUATORS if len(p) > 1)
            + f"|[{_SINGLE_PUNCT}]|/(?![/*])|\\.(?![0-9]))",
            r"(?P<dec>(?:0|[1-9][0-9]{0,18})(?![0-9A-Za-z_.]))",  # plain decimal < 2**64
            r"(?P<lcom>//[^\n]*)",
            r"(?P<bcom>/\*(?s:.*?)\*/)",
            r"(?P<ubcom>/\*)",
            r"(?P<num>" + _PP_NUMBER + ")",
            # possessive (`*+`): a backtracking repeat keeps the regex engine's state
            # for every repetition, ~400 bytes each (a 1 MB literal took 400 MB)
            r'(?P<str>"[^"\\\n]*+(?:\\(?s:.)[^"\\\n]*+)*+")',
            r'(?P<ustr>"[^"\\\n]*+(?:\\(?s:.)[^"\\\n]*+)*+)',
            r"(?P<chr>'[^'\\\n]*+(?:\\(?s:.)[^'\\\n]*+)*+')",
            r"(?P<uchr>'[^'\\\n]*+(?:\\(?s:.)[^'\\\n]*+)*+)",
            r"(?P<cont>\\\n)",
            r"(?P<tail>\Z)",  # blanks at the very end of a file without a final newline
            r"(?P<bad>(?s:.))",
        ]
    )
    + ")"
)
_NAME, _NL, _PUNCT, _DEC = (_MASTER.groupindex[g] for g in ("name", "nl", "punct", "dec"))
_UNCLOSED = _MASTER.pattern.replace("(?P<ubcom>", "(?P<unclosed>")
"""`_MASTER`'s pattern with its unclosed block comment named as `cut_inside` reads it
(compiled on first use, by an editor's question only: `re` keeps it)."""

_INT = re.compile(r"(0[xX][0-9a-fA-F]+|0[bB][01]+|[0-9]+)([A-Za-z_0-9.+-]*)")
_FLOAT = re.compile(r"((?:[0-9]*\.[0-9]+|[0-9]+\.)(?:[eE][+-]?[0-9]+)?|[0-9]+[eE][+-]?[0-9]+)(.*)")
_INT_SUFFIXES = {
    "": "",
    "u": "u",
    "l": "l",
    "ul": "ul",
    "lu": "ul",
    "ll": "ll",
    "ull": "ull",
    "llu": "ull",
}
_ESCAPE = re.compile(r"\\(x[0-9a-fA-F]+|[0-7]{1,3}|(?s:.))")
_SIMPLE_ESCAPES = {
    "n": 10,
    "t": 9,
    "r": 13,
    "a": 7,
    "b": 8,
    "f": 12,
    "v": 11,
    "\\": 92,
    "'": 39,
    '"': 34,
    "?": 63,
}
UINT64_MAX = (1 << 64) - 1

_set_file = SourcePos.file.__set__  # type: ignore[attr-defined]
_set_line = SourcePos.line.__set__  # type: ignore[attr-defined]
_set_col = SourcePos.col.__set__  # type: ignore[attr-defined]


@dataclass(slots=True)
class Scan:
    """What `scan` found in one file.

    `tokens` holds every token (no 'eof'); `directives` holds (start, end) index
    ranges of the `#` lines in `tokens` (the '#' included); `errors` holds
    (pos, message, always) in source order — `always` errors are reported even in
    skipped `#if` regions (an unterminated comment ends the file regardless);
    `names` holds the text of every name and keyword token (the preprocessor's test
    whether a region can hold a macro use, without a pass over its tokens).
    """

    tokens: list[Token] = field(default_factory=list)
    directives: list[tuple[int, int]] = field(default_factory=list)
    errors: list[tuple[SourcePos, str, bool]] = field(default_factory=list)
    names: set[str] = field(default_factory=set)


def tokenize(sf: SourceFile, sink: DiagnosticSink) -> list[Token]:
    """All tokens of a file, ending with an 'eof' token; lexical errors go to `sink`."""
    with gc_held(promote=False):
        sc = scan(sf)
    try:
        for pos, msg, _ in sc.errors:
            sink.error(pos, msg)
    except TooManyErrors:
        pass
    sc.tokens.append(Token("eof", "", end_pos(sf)))
    return sc.tokens


_OPEN_AT_END = frozenset(("lcom", "ustr", "uchr"))
"""Groups of `_MASTER` that, ending where the text is cut, hold the cut inside them."""


def inside_comment_or_literal(text: str, offset: int) -> bool:
    """Whether character `offset` of `text` lies inside a comment, a string or a
    character literal, as the lexer reads the text before it (`cut_inside`; `_MASTER`'s
    `ubcom` is the `/*` without its `*/`)."""
    return cut_inside(re.compile(_UNCLOSED), text, offset, _OPEN_AT_END)


def end_pos(sf: SourceFile) -> SourcePos:
    """The position just after the last character of a file."""
    if not sf.lines:
        return SourcePos(sf.path, 1, 1)
    return SourcePos(sf.path, len(sf.lines), len(sf.lines[-1]) + 1)


def scan(sf: SourceFile) -> Scan:
    """Tokens, directive-line ranges and held-back errors of one file."""
    text = sf.text
    path = sf.path
    out = Scan()
    toks = out.tokens
    append = toks.append
    errors = out.errors
    keywords = KEYWORDS
    add_name = out.names.add
    line = 1
    col_base = -1  # just before the line's first character: a column is an offset minus this
    bol = True  # no token yet on this logical line
    directive_start = -1
    new = object.__new__
    tnew = tuple.__new__
    set_file, set_line, set_col = _set_file, _set_line, _set_col
    NAME, NL, PUNCT, DEC = _NAME, _NL, _PUNCT, _DEC
    for m in _MASTER.finditer(text):
        k = m.lastindex  # the group's number: cheaper than its name
        if k == NAME or k == PUNCT or k == DEC:
            # the hot path: build the frozen SourcePos through its slot descriptors and
            # the Token as a plain tuple, about twice as fast as their constructors
            # (`m[k]`: a subscript, cheaper than the call `m.group(k)`)
            s = m[k]
            pos = new(SourcePos)
            set_file(pos, path)
            set_line(pos, line)
            set_col(pos, m.start(k) - col_base)
            if k == NAME:
                add_name(s)
                append(tnew(Token, ("keyword" if s in keywords else "name", s, pos, None, "")))
            elif k == PUNCT:
                if bol and s == "#":
                    directive_start = len(toks)
                append(tnew(Token, ("punct", s, pos, None, "")))
            else:
                append(tnew(Token, ("int", s, pos, int(s), "")))
            bol = False
            continue
        if k == NL:
            line += 1
            col_base = m.end() - 1
            bol = True
            if directive_start >= 0:
                out.directives.append((directive_start, len(toks)))
                directive_start = -1
            continue
        kind = m.lastgroup
        if kind == "tail":
            continue
        s = m.group(kind)
        start = m.start(kind)
        pos = SourcePos(path, line, start - col_base)
        if kind == "num":
            append(_number(s, pos, errors))
        elif kind == "lcom":
            continue
        elif kind == "bcom" or kind == "cont":
            n = s.count("\n")
            if n:
                line += n
                col_base = start + s.rindex("\n")
            continue
        elif kind == "str" or kind == "ustr":
            if kind == "ustr":
                errors.append((pos, "unterminated string literal", False))
                body = s[1:]
            else:
                body = s[1:-1]
            append(Token("string", s, pos, _decode(body, pos, errors)))
        elif kind == "chr" or kind == "uchr":
            append(_char(s, kind == "uchr", pos, errors))
        elif kind == "ubcom":
            errors.append((pos, "unterminated comment", True))
            break
        else:  # bad
            errors.append((pos, _stray_message(s), False))
            continue
        if kind in ("str", "ustr", "chr", "uchr"):
            n = s.count("\n")  # escaped newlines inside the literal
            if n:
                line += n
                col_base = start + s.rindex("\n")
        bol = False
    if directive_start >= 0:
        out.directives.append((directive_start, len(toks)))
    return out


_IDEOGRAPHIC_PUNCT = {
    "\u3001": ",",
    "\u3002": ".",
    "\u201c": '"',
    "\u201d": '"',
    "\u2018": "'",
    "\u2019": "'",
}


def _stray_message(ch: str) -> str:
    if "\uff01" <= ch <= "\uff5e":  # full-width ASCII, typed with a Chinese input method
        return f"stray '{ch}' in program (a full-width character; did you mean '{chr(ord(ch) - 0xFEE0)}'?)"
    if ch in _IDEOGRAPHIC_PUNCT:
        return f"stray '{ch}' in program (a full-width character; did you mean '{_IDEOGRAPHIC_PUNCT[ch]}'?)"
    if not ch.isprintable():  # a control character: gcc's octal escape, not the raw byte
        return f"stray '\\{ord(ch):o}' in program"
    return f"stray '{ch}' in program"


def lex_fragment(text: str, pos: SourcePos) -> list[Token] | None:
    """Tokens of a pasted or generated text, all placed at `pos`; None if it does not lex cleanly."""
    sf = SourceFile(pos.file, text)
    sc = scan(sf)
    if sc.errors:
        return None
    return [Token(t.kind, t.text, pos, t.value, t.suffix) for t in sc.tokens]


def _number(s: str, pos: SourcePos, errors: list) -> Token:
    """Classify a pp-number as an integer or floating constant."""
    m = _INT.fullmatch(s)
    if m and not (m.group(2)[:1] in (".", "e", "E") and m.group(1)[:2] not in ("0x", "0X")):
        digits, suffix = m.group(1), m.group(2)
        if digits[:2] in ("0x", "0X") or digits[:2] in ("0b", "0B"):
            value = int(digits, 0)
        elif digits[0] == "0" and len(digits) > 1:
            bad = next((c for c in digits if c in "89"), None)
            if bad is not None:
                errors.append((pos, f"invalid digit '{bad}' in octal constant", False))
                value = 0
            else:
                value = int(digits, 8)
        elif len(digits) > 20:  # above UINT64_MAX, and int() refuses over 4300 digits
            value = UINT64_MAX + 1
        else:
            value = int(digits)
        canon = _INT_SUFFIXES.get(suffix.lower())
        if canon is None or "lL" in suffix or "Ll" in suffix:
            errors.append((pos, f"invalid suffix '{suffix}' on integer constant", False))
            canon = ""
        if value > UINT64_MAX:
            shown = f"'{s}'" if len(s) <= 40 else f"'{s[:20]}...' ({len(s)} characters)"
            errors.append(
                (pos, f"integer constant {shown} is too large (the limit is {UINT64_MAX})", False)
            )
            value &= UINT64_MAX
        return Token("int", s, pos, value, canon)
    m = _FLOAT.fullmatch(s)
    if m:
        body, suffix = m.group(1), m.group(2)
        low = suffix.lower()
        if low not in ("", "f", "l"):
            errors.append((pos, f"invalid suffix '{suffix}' on floating constant", False))
            low = ""
        try:
            value = float(body)
        except ValueError:  # pragma: no cover - the regex admits only valid floats
            value = 0.0
        return Token("float", s, pos, value, "f" if low == "f" else "")
    errors.append((pos, f"invalid numeric constant '{s}'", False))
    return Token("int", s, pos, 0, "")


def _decode(body: str, pos: SourcePos, errors: list) -> bytes:
    """The bytes of a string or char literal body: UTF-8 text with C escapes decoded."""
    if "\\" not in body:
        return body.encode("utf-8")
    out = bytearray()
    last = 0
    for m in _ESCAPE.finditer(body):
        out += body[last : m.start()].encode("utf-8")
        last = m.end()
        e = m.group(1)
        c = e[0]
        if c == "x":
            if len(e) == 1:
                errors.append((pos, "\\x used with no following hex digits", False))
                out.append(0)  # one byte, so that '\x' gets no second error
                continue
            v = int(e[1:], 16)
            if v > 255:
                errors.append((pos, f"hex escape sequence '\\{e}' out of range", False))
            out.append(v & 255)
        elif c in "01234567":
            v = int(e, 8)
            if v > 255:
                errors.append((pos, f"octal escape sequence '\\{e}' out of range", False))
            out.append(v & 255)
        elif c == "\n":
            pass  # backslash-newline continues the literal on the next line
        elif c in _SIMPLE_ESCAPES:
            out.append(_SIMPLE_ESCAPES[c])
        else:
            errors.append((pos, f"unknown escape sequence '\\{c}'", False))
            out += c.encode("utf-8")
    out += body[last:].encode("utf-8")
    return bytes(out)


def _char(s: str, unterminated: bool, pos: SourcePos, errors: list) -> Token:
    """A character constant; its value is the signed char value of its one byte."""
    if unterminated:
        errors.append((pos, "unterminated character constant", False))
        body = s[1:]
    else:
        body = s[1:-1]
    data = _decode(body, pos, errors)
    if not data:
        if not unterminated:
            errors.append((pos, "empty character constant", False))
        value = 0
    else:
        if len(data) > 1 and not unterminated:
            errors.append((pos, f"character constant {s} holds more than one byte", False))
        value = data[0] - 256 if data[0] > 127 else data[0]
    return Token("char", s, pos, value)
