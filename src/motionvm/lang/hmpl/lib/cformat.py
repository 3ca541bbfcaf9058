"""C printf formatting for HMPL's Print, StringPrint and SendMsgEvent (manual 3.2).

`format_c(fmt, args, mem)` produces exactly the bytes glibc's printf produces for the
directives `d i u x X o c s f F e E g G p %`, the flags `- + space # 0`, a width and a
precision (each a number or `*`), and the length modifiers `hh h l ll z j t L`.

Choices where C leaves the behaviour undefined or the controller differs from glibc:
- Integer widths follow the controller's data types (manual 1.4): no modifier, `l` -> 32
  bits (HMPL has no 64-bit `long`, as on an LLP64 target), `h` -> 16, `hh` -> 8,
  `ll z j t L` -> 64. The value is wrapped to that width, so `%u`/`%x` of -1 print
  4294967295 / ffffffff, and 18446744073709551615 / ffffffffffffffff with `ll`.
- An argument of the wrong kind is converted as by a C cast: a double given to `%d`
  is truncated toward zero (NaN and infinities give 0), an int given to `%f` is
  widened. (On the controller this is undefined behaviour.)
- `%s` takes an address read with `Memory.read_cstr`; with a precision at most that
  many bytes are read and no terminator is needed. A null or dangling address is a
  RuntimeFault. `%c` takes an int and prints its low byte.
- `%p` prints as glibc does: `0x` and lower-case hex, `(nil)` for a null pointer.
- Infinities and NaNs print `inf`/`nan` (`INF`/`NAN` for F E G), with a `-` for a
  negative sign bit (so `-nan` is possible), and the `0` flag is ignored for them.
- An unknown directive such as `%k` (or a `%` at the end of the format) is copied
  to the output literally and consumes no argument; `%n` is not supported and is
  treated as unknown, because letting a message write memory is never wanted.
- Too few arguments is a RuntimeFault "<func>: format needs N arguments, got M";
  extra arguments are ignored (manual 3.2).
- A width or numeric precision above MAX_FIELD is a FieldTooWide fault (no HMPL
  string can hold such a field: HMPL_STR_MAX_LEN is 512); Print and StringPrint turn
  it into their error return -1, as any result over 512 characters.

A format is compiled once into a list of literal byte strings and `_Directive`s and
cached by its bytes, so a Print with a literal format costs one dict lookup plus the
conversions.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

from motionvm.runtime.errors import RuntimeFault

if TYPE_CHECKING:  # pragma: no cover
    from motionvm.lang.hmpl.cmemory import Memory

MAX_FIELD = 4096
"""Largest width or numeric precision accepted [characters]."""

_CACHE_LIMIT = 2048
_STAR = -1  # width/precision marker: taken from the argument list

_FLAG_CHARS = "-+ #0"
_LENGTHS = ("hh", "h", "ll", "l", "z", "j", "t", "L")
_INT_BITS = {"": 32, "hh": 8, "h": 16, "l": 32, "ll": 64, "z": 64, "j": 64, "t": 64, "L": 64}
_INT_CONVS = "diuxXo"
_FLOAT_CONVS = "fFeEgG"
_KNOWN_CONVS = _INT_CONVS + _FLOAT_CONVS + "csp"


class _Directive:
    """One compiled `%...` directive."""

    __slots__ = ("_left", "bits", "conv", "flags", "length", "prec", "pyfmt", "render", "width")

    def __init__(self, conv: str, flags: str, width: int | None, prec: int | None, length: str):
        self.conv = conv
        self.flags = flags
        self.width = width
        self.prec = prec
        self.length = length
        self.bits = _INT_BITS[length]
        self._left: _Directive | None = None
        self.pyfmt = b""
        if conv in _FLOAT_CONVS:
            self.render = self._render_float
            if width != _STAR and prec != _STAR:
                self.pyfmt = _float_pyfmt(flags, width, prec, conv)
            if not flags and width is None and prec is None:
                self.render = self._render_float_plain
        elif conv in _INT_CONVS:
            self.render = self._render_int
            if conv in "di" and not flags and width is None and prec is None:
                self.render = self._render_dec_plain
        elif conv == "c":
            self.render = self._render_char
        elif conv == "s":
            self.render = self._render_str
        else:
            self.render = self._render_ptr

    @property
    def n_args(self) -> int:
        return 1 + (self.width == _STAR) + (self.prec == _STAR)

    def left_justified(self) -> _Directive:
        """This directive with the '-' flag (for a negative `*` width)."""
        if self._left is None:
            flags = self.flags.replace("0", "") + ("" if "-" in self.flags else "-")
            self._left = _Directive(self.conv, flags, self.width, self.prec, self.length)
        return self._left

    # Each renderer takes (value, width, prec, mem) with `*` already resolved.

    def _render_dec_plain(self, v, width, prec, mem) -> bytes:
        if v.__class__ is not int:
            v = _to_int(v)
        bits = self.bits
        v &= (1 << bits) - 1
        if v >> (bits - 1):
            v -= 1 << bits
        return b"%d" % v

    def _render_float_plain(self, v, width, prec, mem) -> bytes:
        if v.__class__ is not float:
            v = _to_float(v)
        if v - v == 0.0:  # finite
            return self.pyfmt % v
        return _nonfinite(v, self.flags, width, self.conv)

    def _render_float(self, v, width, prec, mem) -> bytes:
        if v.__class__ is not float:
            v = _to_float(v)
        if v - v != 0.0:
            return _nonfinite(v, self.flags, width, self.conv)
        pyfmt = self.pyfmt or _float_pyfmt(self.flags, width, prec, self.conv)
        return pyfmt % v

    def _render_int(self, v, width, prec, mem) -> bytes:
        return _format_int(_to_int(v), self.conv, self.flags, width, prec, self.bits)

    def _render_ptr(self, v, width, prec, mem) -> bytes:
        v = _to_int(v) & 0xFFFF_FFFF_FFFF_FFFF
        if v == 0:
            return _pad(b"(nil)", self.flags, width)
        return _format_int(v, "p", self.flags, width, prec, 64)

    def _render_char(self, v, width, prec, mem) -> bytes:
        return _pad(bytes((_to_int(v) & 0xFF,)), self.flags, width)

    def _render_str(self, v, width, prec, mem) -> bytes:
        addr = _to_int(v)
        if prec is None:
            text = mem.read_cstr(addr, "%s argument")
        else:
            text = _read_bounded(mem, addr, prec)
        return _pad(text, self.flags, width)


def _to_int(v) -> int:
    if v.__class__ is int:
        return v
    if isinstance(v, float):
        return int(v) if v - v == 0.0 else 0
    return int(v)


def _to_float(v) -> float:
    try:
        return float(v)
    except OverflowError:  # an int beyond the double range
        return math.inf if v > 0 else -math.inf


def _float_pyfmt(flags: str, width: int | None, prec: int | None, conv: str) -> bytes:
    """A Python bytes %-format equivalent to the C directive (finite values only)."""
    spec = "%" + flags
    if width:
        spec += str(width)
    if prec is not None:
        spec += "." + str(prec)
    return (spec + conv).encode("ascii")


def _nonfinite(x: float, flags: str, width: int | None, conv: str) -> bytes:
    body = b"nan" if x != x else b"inf"
    if conv in "FEG":
        body = body.upper()
    if math.copysign(1.0, x) < 0:
        body = b"-" + body
    elif "+" in flags:
        body = b"+" + body
    elif " " in flags:
        body = b" " + body
    return _pad(body, flags, width)


def _pad(body: bytes, flags: str, width: int | None) -> bytes:
    if width and len(body) < width:
        fill = b" " * (width - len(body))
        return body + fill if "-" in flags else fill + body
    return body


def _format_int(v: int, conv: str, flags: str, width: int | None, prec: int | None, bits: int):
    v &= (1 << bits) - 1
    sign = b""
    if conv in "di":
        if v >> (bits - 1):
            v -= 1 << bits
        if v < 0:
            sign, v = b"-", -v
        elif "+" in flags:
            sign = b"+"
        elif " " in flags:
            sign = b" "
        digits = b"%d" % v
    elif conv == "u":
        digits = b"%d" % v
    elif conv == "p":  # glibc: like %#llx, but honouring '+' and ' '
        sign = b"+" if "+" in flags else b" " if " " in flags else b""
        digits = b"%x" % v
        flags += "#"
    elif conv == "x":
        digits = b"%x" % v
    elif conv == "X":
        digits = b"%X" % v
    else:
        digits = b"%o" % v
    if prec is not None:
        if prec == 0 and v == 0:
            digits = b""
        elif len(digits) < prec:
            digits = b"0" * (prec - len(digits)) + digits
    prefix = b""
    if "#" in flags:
        if conv == "o" and not digits.startswith(b"0"):
            digits = b"0" + digits
        elif conv in "xXp" and v != 0:
            prefix = b"0X" if conv == "X" else b"0x"
    head = sign + prefix
    n = len(head) + len(digits)
    if width and n < width:
        if "-" in flags:
            return head + digits + b" " * (width - n)
        if "0" in flags and prec is None:
            return head + b"0" * (width - n) + digits
        return b" " * (width - n) + head + digits
    return head + digits


def _read_bounded(mem: Memory, addr: int, limit: int) -> bytes:
    """At most `limit` bytes of the string at `addr`, stopping at a NUL (C's `%.Ns`)."""
    if limit == 0:
        return b""
    if addr == 0:
        raise RuntimeFault("null %s argument pointer")
    room = mem.extent(addr)
    if room == 0:
        raise RuntimeFault(f"%s argument pointer 0x{addr:x} points outside any object")
    n = min(room, limit)
    end = mem.buf.find(b"\0", addr, addr + n)
    if end >= 0:
        return bytes(mem.buf[addr:end])
    if n < limit:
        raise RuntimeFault(f"%s argument is not terminated by '\\0' within its {room} bytes")
    return bytes(mem.buf[addr : addr + n])


def _parse_number(fmt: bytes, i: int) -> tuple[int | None, int]:
    """A decimal number or `*` starting at fmt[i] -> (value or _STAR or None, next index)."""
    if i < len(fmt) and fmt[i] == 0x2A:  # '*'
        return _STAR, i + 1
    j = i
    while j < len(fmt) and 0x30 <= fmt[j] <= 0x39:
        j += 1
    if j == i:
        return None, i
    value = int(fmt[i:j])
    if value > MAX_FIELD:
        raise FieldTooWide(f"format field {value} exceeds the limit {MAX_FIELD}")
    return value, j


def compile_format(fmt: bytes) -> tuple[list, int]:
    """Split a format into literal bytes and _Directives; also return the arguments needed."""
    parts: list = []
    n_args = 0
    literal = bytearray()
    i, n = 0, len(fmt)
    while i < n:
        pct = fmt.find(b"%", i)
        if pct < 0:
            literal += fmt[i:]
            break
        literal += fmt[i:pct]
        j = pct + 1
        flags = ""
        while j < n and chr(fmt[j]) in _FLAG_CHARS:
            if chr(fmt[j]) not in flags:
                flags += chr(fmt[j])
            j += 1
        width, j = _parse_number(fmt, j)
        prec = None
        if j < n and fmt[j] == 0x2E:  # '.'
            prec, j = _parse_number(fmt, j + 1)
            if prec is None:
                prec = 0
        length = ""
        for cand in _LENGTHS:
            if fmt.startswith(cand.encode(), j):
                length, j = cand, j + len(cand)
                break
        conv = chr(fmt[j]) if j < n else ""
        if conv == "%":
            literal += b"%"
        elif conv and conv in _KNOWN_CONVS:
            if literal:
                parts.append(bytes(literal))
                literal.clear()
            if "-" in flags:  # '-' overrides '0', '+' overrides ' ' (C 7.21.6.1)
                flags = flags.replace("0", "")
            if "+" in flags:
                flags = flags.replace(" ", "")
            d = _Directive(conv, flags, width, prec, length)
            parts.append(d)
            n_args += d.n_args
        else:  # unknown directive: copied literally
            literal += fmt[pct : j + 1]
        i = j + 1
    if literal:
        parts.append(bytes(literal))
    return parts, n_args


ONE_INT = (True,)
"""`CFormat.kinds` of a format whose one directive is a plain int32 `%d`."""


class CFormat:
    """A compiled format: its parts, the arguments it needs and, when every directive is
    a plain `%d`/`%i`/`%ld` or a float directive with constant width and precision, one
    Python bytes %-format doing the whole job (`quick`) for arguments of the right
    class and range (int32 ints, finite floats)."""

    __slots__ = ("kinds", "n_args", "parts", "quick")

    def __init__(self, parts: list, n_args: int) -> None:
        self.parts = parts
        self.n_args = n_args
        kinds: list[bool] = []  # per argument: True for an int32 `%d`, False for a float
        quick = b""
        for part in parts:
            if part.__class__ is bytes:
                quick += part.replace(b"%", b"%%")
            elif part.render == part._render_dec_plain and part.bits == 32:
                quick += b"%d"
                kinds.append(True)
            elif part.conv in _FLOAT_CONVS and part.pyfmt:
                quick += part.pyfmt
                kinds.append(False)
            else:
                kinds = []
                quick = b""
                break
        self.kinds = ONE_INT if kinds == [True] else tuple(kinds)
        self.quick = quick if kinds else b""

    def render(self, args: Sequence, mem: Memory, func: str) -> bytes:
        """The formatted bytes of `args` (extra arguments are ignored)."""
        kinds = self.kinds
        if kinds is ONE_INT and len(args) == 1:  # the commonest case, checked in place
            v = args[0]
            if v.__class__ is int and -2147483648 <= v <= 2147483647:
                return self.quick % v
        elif kinds and len(args) >= len(kinds):
            if len(args) > len(kinds) or args.__class__ is not tuple:
                args = tuple(args[: len(kinds)])
            for is_int, v in zip(kinds, args):
                if is_int:
                    if v.__class__ is not int or not -2147483648 <= v <= 2147483647:
                        break
                elif v.__class__ is not float or v - v != 0.0:
                    break
            else:
                return self.quick % args
        return _render_parts(self.parts, self.n_args, args, mem, func)


_cache: dict[bytes, CFormat] = {}


class FieldTooWide(RuntimeFault):
    """A width or precision above MAX_FIELD: the result would exceed any HMPL string."""


def compiled_format(fmt: bytes, func: str = "Print") -> CFormat:
    """The compiled form of format `fmt` (cached by its bytes)."""
    prog = _cache.get(fmt)
    if prog is None:
        try:
            prog = CFormat(*compile_format(fmt))
        except RuntimeFault as exc:
            raise type(exc)(f"{func}: {exc}") from None
        if len(_cache) >= _CACHE_LIMIT:
            _cache.clear()
        _cache[fmt] = prog
    return prog


def format_c(fmt: bytes, args: Sequence, mem: Memory, func: str = "Print") -> bytes:
    """Format `args` by the C format `fmt` as printf does; `func` names the caller in faults."""
    return compiled_format(fmt, func).render(args, mem, func)


def _render_parts(parts: list, n_args: int, args: Sequence, mem: Memory, func: str) -> bytes:
    if len(args) < n_args:
        raise RuntimeFault(f"{func}: format needs {n_args} arguments, got {len(args)}")
    out = []
    k = 0
    for part in parts:
        if part.__class__ is bytes:
            out.append(part)
            continue
        width, prec = part.width, part.prec
        if width == _STAR:
            width = _to_int(args[k])
            k += 1
            if width < 0:  # a negative `*` width means the '-' flag and its magnitude
                width = -width
                part = part.left_justified()
        if prec == _STAR:
            prec = _to_int(args[k])
            k += 1
            if prec < 0:
                prec = None
        if (width is not None and width > MAX_FIELD) or (
            prec is not None and prec > MAX_FIELD and part.conv != "s"
        ):
            big = max(width or 0, prec or 0)
            raise FieldTooWide(f"{func}: format field {big} exceeds the limit {MAX_FIELD}")
        out.append(part.render(args[k], width, prec, mem))
        k += 1
    return b"".join(out)
