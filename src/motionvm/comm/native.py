"""Native ASCII requests (manual 21.1): one line, parsed in the server thread.

    request  := call | read | write
    call     := NAME '(' [arg {',' arg}] ')' [';']
    read     := var
    write    := var '=' arg [';']
    var      := NAME ['[' INTEGER ']']       (an array element: table[3])
    arg      := ['-' | '+'] NUMBER | STRING | CHAR | NAME

NUMBER is a C integer (decimal, 0x hex, 0 octal, 0b binary; at most UINT64_MAX, as a
C constant must fit unsigned long long) or a C floating literal;
STRING a C string literal (`"a\\n"`), CHAR a C character literal (`'A'`, its code);
NAME an identifier (an HMPL named constant such as HMPL_ABS, resolved by the program's
side). Parsing touches no simulation state; `execute` runs a parsed request through the
hub's `NativeTable` at a cycle boundary. Reply format: `format_value`.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from motionvm.comm.hub import CommHub, RequestError

UINT64_MAX = 2**64 - 1
"""The largest integer constant (C's unsigned long long); a larger one is an error."""


@dataclass(frozen=True)
class Ident:
    """A name given as an argument (a named constant)."""

    name: str


@dataclass(frozen=True)
class Request:
    """A parsed request: `kind` is "call", "read" or "write"."""

    kind: str
    name: str
    args: tuple = ()


_TOKEN = re.compile(
    r"""\s*(?:
      (?P<float>(?:\d+\.\d*|\.\d+)(?:[eE][+-]?\d+)?|\d+[eE][+-]?\d+)
    | (?P<int>0[xX][0-9a-fA-F]+|0[bB][01]+|\d+)[uUlL]*
    | (?P<name>[A-Za-z_]\w*)
    | (?P<str>"(?:[^"\\]|\\.)*")
    | (?P<chr>'(?:[^'\\]|\\.)+')
    | (?P<punct>[(),=;+\[\]-])
    )""",
    re.VERBOSE,
)

_ESCAPES = {"n": 10, "t": 9, "r": 13, "\\": 92, '"': 34, "'": 39, "a": 7, "b": 8,
            "f": 12, "v": 11, "?": 63}  # fmt: skip


def _unescape(body: str) -> bytes:
    out = bytearray()
    i = 0
    while i < len(body):
        ch = body[i]
        if ch != "\\":
            out += ch.encode("latin-1", "replace")
            i += 1
            continue
        nxt = body[i + 1] if i + 1 < len(body) else ""
        if nxt == "x":
            m = re.match(r"[0-9a-fA-F]{1,2}", body[i + 2 :])
            if not m:
                raise RequestError("bad \\x escape in a string")
            out.append(int(m.group(), 16))
            i += 2 + len(m.group())
        elif nxt in "01234567":
            digits = re.match(r"[0-7]{1,3}", body[i + 1 :]).group()  # type: ignore[union-attr]
            if int(digits, 8) > 0xFF:
                raise RequestError(f"octal escape '\\{digits}' is out of range (at most \\377)")
            out.append(int(digits, 8))
            i += 1 + len(digits)
        elif nxt in _ESCAPES:
            out.append(_ESCAPES[nxt])
            i += 2
        else:
            raise RequestError(f"unknown escape '\\{nxt}' in a string")
    return bytes(out)


def _tokens(line: str) -> list[tuple[str, str]]:
    out: list[tuple[str, str]] = []
    pos = 0
    text = line.rstrip()
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if m is None or m.end() == pos:
            rest = text[pos:].strip()
            raise RequestError(f"unexpected '{rest[:20]}' at column {len(text) - len(rest) + 1}")
        kind = m.lastgroup or ""
        out.append((kind, m.group(kind)))
        pos = m.end()
    return out


def parse_request(line: str) -> Request:
    """The request of one line; RequestError says what is wrong with it."""
    toks = _tokens(line)
    if toks and toks[-1] == ("punct", ";"):
        toks.pop()
    if not toks:
        raise RequestError("empty request")
    kind, name = toks[0]
    if kind != "name":
        raise RequestError("a request starts with a function or variable name")
    if len(toks) > 1 and toks[1] == ("punct", "["):
        toks = [("name", _element(name, toks))] + toks[4:]
        name = toks[0][1]
        if len(toks) > 1 and toks[1] == ("punct", "("):
            raise RequestError(
                f"'{name}' is an array element: it can be read or written, not called"
            )
    if len(toks) == 1:
        return Request("read", name)
    if toks[1] == ("punct", "="):
        value, end = _arg(toks, 2)
        if end != len(toks):
            raise RequestError(f"unexpected '{toks[end][1]}' after the value")
        return Request("write", name, (value,))
    if toks[1] != ("punct", "("):
        raise RequestError(f"expected '(' or '=' after '{name}'")
    missing = RequestError(f"missing ')' at the end of the call of '{name}'")
    args: list[object] = []
    i = 2
    if i < len(toks) and toks[i] == ("punct", ")"):
        i += 1
    else:
        while True:
            if i >= len(toks):
                raise missing
            value, i = _arg(toks, i)
            args.append(value)
            if i >= len(toks):
                raise missing
            if toks[i] == ("punct", ")"):
                i += 1
                break
            if toks[i] != ("punct", ","):
                raise RequestError(f"expected ',' or ')' in the call of '{name}'")
            i += 1
    if i != len(toks):
        raise RequestError(f"unexpected '{toks[i][1]}' after the call of '{name}'")
    return Request("call", name, tuple(args))


def _element(name: str, toks: list[tuple[str, str]]) -> str:
    """`name[k]` of the tokens `NAME [ INTEGER ]` at the start of `toks`."""
    if len(toks) < 4 or toks[3] != ("punct", "]"):
        raise RequestError(f"expected '{name}[INDEX]' with an integer index")
    index, _ = _arg(toks, 2)
    if not isinstance(index, int) or index < 0:
        raise RequestError(f"expected '{name}[INDEX]' with an integer index >= 0")
    return f"{name}[{index}]"


def _arg(toks: list[tuple[str, str]], i: int) -> tuple[object, int]:
    """The literal argument at token `i` and the index after it."""
    sign, signed = 1, False
    if i < len(toks) and toks[i][0] == "punct" and toks[i][1] in "+-":
        sign, signed = (-1 if toks[i][1] == "-" else 1), True
        i += 1
    if i >= len(toks):
        raise RequestError("missing value")
    kind, text = toks[i]
    if kind == "int":
        t = text.rstrip("uUlL").lower()
        if t.startswith("0x"):
            v = int(t, 16)
        elif t.startswith("0b"):
            v = int(t[2:], 2)
        elif len(t) > 1 and t.startswith("0"):
            if not re.fullmatch(r"[0-7]+", t):
                raise RequestError(f"invalid octal number '{text}'")
            v = int(t, 8)
        else:
            v = int(t)
        if v > UINT64_MAX:  # no C type holds it: the compiler refuses it too
            raise RequestError(
                f"integer constant '{text}' is too large (the limit is {UINT64_MAX})"
            )
        return sign * v, i + 1
    if kind == "float":
        return sign * float(text), i + 1
    if signed:
        raise RequestError(f"a sign before '{text}': only numbers have one")
    if kind == "str":
        return _unescape(text[1:-1]), i + 1
    if kind == "chr":
        data = _unescape(text[1:-1])
        if len(data) != 1:
            raise RequestError(f"character literal {text} holds {len(data)} characters")
        return data[0], i + 1
    if kind == "name":
        return Ident(text), i + 1
    raise RequestError(f"expected a value, got '{text}'")


def format_value(value: object) -> str:
    """A value as a reply shows it: integers in decimal, doubles in the shortest form
    that reads back exactly (`0.1`, `1e-07`, `inf`, `nan`), strings in C quotes."""
    if isinstance(value, bool):
        return str(int(value))
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        return repr(value)
    if isinstance(value, (bytes, bytearray)):
        return '"' + _quote(bytes(value)) + '"'
    return str(value)


def _quote(data: bytes) -> str:
    out = []
    for b in data:
        ch = chr(b)
        if ch in '"\\':
            out.append("\\" + ch)
        elif 32 <= b < 127:
            out.append(ch)
        elif b == 10:
            out.append("\\n")
        elif b == 13:
            out.append("\\r")
        elif b == 9:
            out.append("\\t")
        else:
            out.append(f"\\x{b:02x}")
    return "".join(out)


def execute(hub: CommHub, request: Request, read_only: bool = False) -> str:
    """Run a parsed request (in the simulation thread): its reply line, `ERR ...` if it
    cannot run. A `read_only` server runs variable reads and the calls the table calls
    queries (`NativeTable.native_is_query`) and refuses the rest."""
    table = hub.native
    try:
        if table is None:
            raise RequestError("this run has no HMPL program: built-ins and variables need one")
        if read_only and request.kind == "write":
            raise RequestError(f"read-only server: '{request.name}' cannot be written")
        if (
            read_only
            and request.kind == "call"
            and not table.native_is_query(request.name, list(request.args))
        ):
            raise RequestError(
                f"read-only server: {request.name} may change the machine (only variable "
                "reads and queries such as Get..., Is..., ReadSDO are served)"
            )
        if request.kind == "call":
            return table.native_call(request.name, list(request.args))
        if request.kind == "read":
            return table.native_read(request.name)
        return table.native_write(request.name, request.args[0])
    except RequestError as exc:
        return f"ERR {exc}"
    except Exception as exc:  # noqa: BLE001 — a bug of ours; the client still gets a reply
        return f"ERR internal error of motionvm (a bug): {type(exc).__name__}: {exc}"


def handle_line(line: str) -> Request | str:
    """A parsed request, or the `ERR ...` reply of a line that does not parse."""
    try:
        return parse_request(line)
    except RequestError as exc:
        return f"ERR {exc}"
