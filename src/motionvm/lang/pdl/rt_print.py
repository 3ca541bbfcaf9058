"""printl/prints/retprintl message formatting (manual §2.4).

A format is split once, at compile time, by `printfmt.parse_format`; at run time the
argument values are captured when the statement executes and formatted as C printf
would on the drive's 32-bit values:

* `%d`, `%ld`, `%i`: signed decimal; `%u`: the unsigned 32-bit pattern; `%x`: hex of the
  pattern; `%c`: the low byte as a character;
* `%g` (and `%f`, `%e`): a float; an integer argument is converted numerically;
* `%s`: takes consecutive arguments, 4 characters each, LSB first, up to and including
  the first one holding a NUL byte.

A float given to an integer conversion is rounded first (the checker warns).

Pointers. A pointer holds a word address (rt_memory), and the manual prints addresses
with `%x` (`"n address is %08x", &n`). A pointer variable or `&var` given to any of
`%d %ld %i %u %x %X` prints as that address: the non-negative hex of its 32-bit
pattern (two's complement if pointer arithmetic made it negative), keeping the width,
`0`, `-` and `#` flags (`%X`: upper case). So `"p=0x%ld", p` prints `p=0xfffffff8`,
never `p=0x-8`. `%c` and the float conversions treat a pointer as any integer.
"""

from __future__ import annotations

from dataclasses import dataclass

from motionvm.lang.pdl.printfmt import FLOAT_CONVERSIONS, Conversion, parse_format
from motionvm.lang.pdl.rt_memory import round_int

MASK32 = 0xFFFF_FFFF


@dataclass(frozen=True, slots=True)
class PrintFormat:
    """One compiled format: text pieces and conversions (with the C spec rewritten)."""

    parts: tuple[str | tuple[str, str, str], ...]
    """Literal text, or (conversion letter, Python %-spec, %-spec for a pointer) triples."""
    mode1: int
    mode2: int
    command: str
    pointers: frozenset[int] = frozenset()
    """Indices of the arguments that are pointers (a pointer variable or `&var`)."""


def _pointer_spec(spec: str, conv: str) -> str:
    """The %-spec printing a pointer for integer conversion `spec` (already without l/h)."""
    body = spec[1:-1].replace("+", "").replace(" ", "")
    return "%" + body + ("X" if conv == "X" else "x")


def compile_format(
    fmt: str, mode1: int, mode2: int, command: str, pointers: tuple[bool, ...] = ()
) -> PrintFormat:
    """Prepare a format string for `format_message` (the checker already validated it);
    `pointers[i]` tells whether argument i is a pointer."""
    parts, _issues = parse_format(fmt)
    out: list[str | tuple[str, str, str]] = []
    for p in parts:
        if isinstance(p, Conversion):
            spec = p.text.replace("l", "").replace("h", "")
            conv = p.conv
            if conv in ("i", "u"):
                spec = spec[:-1] + "d"
            out.append((conv, spec, _pointer_spec(spec, conv)))
        else:
            out.append(p)
    marked = frozenset(i for i, is_ptr in enumerate(pointers) if is_ptr)
    return PrintFormat(tuple(out), mode1, mode2, command, marked)


def _as_int(v: float) -> int:
    return round_int(v) if type(v) is float else int(v)


def format_message(pf: PrintFormat, args: tuple) -> str:
    """The message text for these argument values."""
    out: list[str] = []
    k = 0
    for part in pf.parts:
        if isinstance(part, str):
            out.append(part)
            continue
        conv, spec, ptr_spec = part
        if conv == "s":
            text = bytearray()
            while k < len(args):
                word = _as_int(args[k]) & MASK32
                k += 1
                chunk = word.to_bytes(4, "little")
                if 0 in chunk:
                    text += chunk[: chunk.index(0)]
                    break
                text += chunk
            out.append(spec % text.decode("latin-1"))
            continue
        v = args[k] if k < len(args) else 0
        is_pointer = k in pf.pointers
        k += 1
        if conv in FLOAT_CONVERSIONS:
            out.append(spec % float(v))
        elif is_pointer and conv != "c":
            out.append(ptr_spec % (_as_int(v) & MASK32))
        elif conv in ("x", "X", "u"):
            out.append(spec % (_as_int(v) & MASK32))
        elif conv == "c":
            out.append(chr(_as_int(v) & 0xFF))
        else:
            out.append(spec % _as_int(v))
    return "".join(out)
