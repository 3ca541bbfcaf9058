"""-Wformat for HMPL: a literal format of Print, StringPrint, SendMsgEvent (any built-in
whose last fixed parameter is `char *format` followed by `...`) checked against the types
of the arguments, as gcc does for printf. The directives are those `cformat` runs, so
the check and the run agree on what a format means."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from functools import lru_cache

from motionvm.lang.hmpl import ctypes_ as ct
from motionvm.lang.hmpl.lib.cformat import compile_format
from motionvm.runtime.errors import RuntimeFault
from motionvm.source.files import SourcePos

Warn = Callable[[SourcePos, str], None]

# expected C type per length modifier (integer directives); HMPL's `l` is 32 bits wide
_SIGNED = {"": "int", "hh": "int", "h": "int", "l": "long int"}
_UNSIGNED = {
    "": "unsigned int",
    "hh": "unsigned int",
    "h": "unsigned int",
    "l": "long unsigned int",
}


@lru_cache(maxsize=256)
def _directives(fmt: bytes) -> list:
    """The parts of a format (read only), kept: a program passes the same few formats
    many times."""
    return compile_format(fmt)[0]


def is_printf_like(params: Sequence[tuple[str, ct.CType]], variadic: bool) -> bool:
    """A `char *format` as the last fixed parameter, then `...`."""
    return variadic and bool(params) and params[-1][0] == "format"


def check_format(
    fmt: bytes,
    fmt_pos: SourcePos,
    first_arg: int,
    args: Sequence[tuple[ct.CType, SourcePos]],
    warn: Warn,
) -> None:
    """Warn about the arguments `args` (numbered from `first_arg`, as gcc counts them:
    the format's own number plus one) that do not fit the directives of `fmt`."""
    try:
        parts = _directives(fmt)
    except RuntimeFault:
        return  # a field too wide: the run reports it
    k = 0
    for d in parts:
        if isinstance(d, bytes):
            continue
        text = _spelling(d)
        wanted: list[tuple[str, str, Callable[[ct.CType], bool]]] = []
        if _is_star(d.width):
            wanted.append(("field width specifier '*'", "int", _is_int32))
        if _is_star(d.prec):
            wanted.append(("field precision specifier '.*'", "int", _is_int32))
        wanted.append((f"format '{text}'", *_expected(d.conv, d.length)))
        for what, type_name, fits in wanted:
            if k >= len(args):
                warn(fmt_pos, f"{what} expects a matching '{type_name}' argument")
                return
            t, pos = args[k]
            shown = _promoted(t)
            if not fits(shown):
                warn(
                    pos,
                    f"{what} expects an argument of type '{type_name}', but argument "
                    f"{first_arg + k} has type '{shown}'",
                )
            k += 1
    if k < len(args):
        warn(fmt_pos, "too many arguments for format")


def _is_star(field: int | None) -> bool:
    return field is not None and field < 0  # cformat marks `*` with a negative number


def _spelling(d) -> str:
    """The directive as a program writes it (flags in cformat's canonical order)."""
    out = "%" + d.flags
    if d.width is not None:
        out += "*" if _is_star(d.width) else str(d.width)
    if d.prec is not None:
        out += "." + ("*" if _is_star(d.prec) else str(d.prec))
    return out + d.length + d.conv


def _expected(conv: str, length: str) -> tuple[str, Callable[[ct.CType], bool]]:
    if conv in "di":
        if length in _SIGNED:
            return _SIGNED[length], _is_int32
        return "long long int", _is_int64
    if conv in "uxXo":
        if length in _UNSIGNED:
            return _UNSIGNED[length], _is_int32
        return "long long unsigned int", _is_int64
    if conv in "fFeEgG":
        return ("long double" if length == "L" else "double"), _is_float
    if conv == "c":
        return "int", _is_int32
    if conv == "s":
        return "char *", _is_char_pointer
    return "void *", _is_pointer  # %p


def _promoted(t: ct.CType) -> ct.CType:
    """The type a variadic argument is passed as (default argument promotions)."""
    if isinstance(t, ct.ArrayT):
        return ct.pointer_to(t.elem)
    if t == ct.FLOAT:
        return ct.DOUBLE
    return ct.promote(t)


def _is_int32(t: ct.CType) -> bool:
    return isinstance(t, ct.IntT) and t.size == 4


def _is_int64(t: ct.CType) -> bool:
    return isinstance(t, ct.IntT) and t.size == 8


def _is_float(t: ct.CType) -> bool:
    return isinstance(t, ct.FloatT)


def _is_pointer(t: ct.CType) -> bool:
    return isinstance(t, ct.PtrT)


def _is_char_pointer(t: ct.CType) -> bool:
    return isinstance(t, ct.PtrT) and isinstance(t.target, ct.IntT) and t.target.size == 1
