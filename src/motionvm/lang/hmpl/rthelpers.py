"""The run-time helpers generated HMPL code calls: C arithmetic, checked memory access.

These are the only non-built-in names generated code uses (besides memory views and
`_budget`/`_stack`); `make_helpers(mem)` binds them to one program's memory, as
closures over the typed views so each call costs one Python function call.
"""

from __future__ import annotations

import math

from motionvm.lang.hmpl.cmemory import (
    ADDRESS_SIGN_MASK,
    SCALAR_FORMATS,
    SHADOW_CAP,
    Memory,
    to_f32,
    wrap_scalar,
)
from motionvm.lang.hmpl.lower_util import CHUNK
from motionvm.lang.hmpl.lvalues import VIEW_NAMES
from motionvm.runtime.errors import RuntimeFault


def _idiv(a: int, b: int) -> int:
    """C integer division: truncates toward zero; division by zero is a fault."""
    if b == 0:
        raise RuntimeFault("integer division by zero")
    if (a >= 0) == (b > 0):
        return a // b if a >= 0 else (-a) // (-b)
    return -(abs(a) // abs(b))


def _imod(a: int, b: int) -> int:
    """C remainder: takes the sign of the dividend; modulo by zero is a fault."""
    if b == 0:
        raise RuntimeFault("integer modulo by zero")
    r = abs(a) % abs(b)
    return -r if a < 0 else r


def _shc(count: int, bits: int) -> int:
    """The shift count a shift by `count` of a `bits`-wide integer uses: modulo the width,
    as the controller's shifter does; a negative count (undefined in C) is a fault."""
    if count < 0:
        raise RuntimeFault(f"negative shift count {count}")
    return count % bits


def _fdiv(a: float, b: float) -> float:
    """IEEE division: x/0 gives inf (or nan for 0/0), as on the controller's FPU."""
    try:
        return a / b
    except ZeroDivisionError:
        if a == 0 or math.isnan(a):
            return math.nan
        return math.copysign(math.inf, a) * math.copysign(1.0, b)


def float_to_int(x: float, bits: int = 32, signed: bool = True) -> int:
    """Float to integer as the controller's FPU does: truncate, saturate, NaN gives 0.

    Generated code calls it as `_f2i`; the compiler folds constants with it too, so a
    conversion gives the same value at compile time and at run time."""
    if x != x:
        return 0
    lo, hi = (-(1 << (bits - 1)), (1 << (bits - 1)) - 1) if signed else (0, (1 << bits) - 1)
    if x >= hi:
        return hi
    if x <= lo:
        return lo
    return int(x)


def _wrapi(x: int, bits: int = 32) -> int:
    """Two's-complement reduction of x to a signed integer of `bits` bits (generated code
    leaves out the common 32, and `_f2i`'s 32 and True: fewer nodes to compile)."""
    half = 1 << (bits - 1)
    return ((x + half) & ((1 << bits) - 1)) - half


def _chunks(r: range):
    """The chunks of CHUNK values a counting loop runs between budget charges: nothing for
    an empty range, the range itself when it is one chunk (the common short loop)."""
    n = len(r)
    if n <= CHUNK:
        return (r,) if n else ()
    return (r[k : k + CHUNK] for k in range(0, n, CHUNK))


def _bad_step(step: int) -> int:
    """A counting loop whose run-time step is not positive would never reach its bound."""
    raise RuntimeFault(
        f"for loop step is {step}: counting up by a step <= 0 never reaches the bound"
    )


def _oob(i: int, n: int) -> int:
    raise RuntimeFault(f"array index {i} out of bounds (the array has {n} elements)")


def _ck(i: int, n: int) -> int:
    if 0 <= i < n:
        return i
    return _oob(i, n)


def _stv(view, idx: int, value):
    """Store into a typed view and give the stored value (assignment as an expression)."""
    view[idx] = value
    return view[idx]


class _Goto(Exception):
    """Raised by `goto L` (args[0] is L's segment); caught by the function's dispatcher."""


def _mklist(image: bytes, code: str) -> list:
    """The values of a constant array initializer, as a Python list."""
    return memoryview(bytearray(image)).cast(SCALAR_FORMATS[code][0]).tolist()


def _notimpl(name: str, *args):
    raise RuntimeFault(f"{name} is not implemented yet")


def make_helpers(mem: Memory) -> dict[str, object]:
    """All helper names for one program's namespace, bound to `mem`."""
    ns: dict[str, object] = {
        "_idiv": _idiv,
        "_imod": _imod,
        "_shc": _shc,
        "_fdiv": _fdiv,
        "_f2i": float_to_int,
        "_f32": to_f32,
        "_oob": _oob,
        "_wrapi": _wrapi,
        "_bad_step": _bad_step,
        "_chunks": _chunks,
        "_ck": _ck,
        "_stv": _stv,
        "_notimpl": _notimpl,
        "_mklist": _mklist,
        "_Goto": _Goto,
        "_budget": 0,
        "_stack": None,
    }
    for code, vname in VIEW_NAMES.items():
        ns[vname] = getattr(mem, code)
    sh = mem.shadow
    ns["_SH"] = sh

    def make_access(code: str):
        view = getattr(mem, code)
        size = SCALAR_FORMATS[code][1]
        shift = size.bit_length() - 1
        mask = ADDRESS_SIGN_MASK | (size - 1)

        def load(a):
            try:
                if not a & mask and sh[a] >= size:
                    return view[a >> shift]
            except (IndexError, TypeError):
                pass
            return mem.load(a, code)

        def store(a, v):
            try:
                if not a & mask and sh[a] >= size:
                    view[a >> shift] = v
                    return view[a >> shift]
            except (IndexError, TypeError):
                pass
            mem.store(a, code, v)
            return mem.load(a, code)

        return load, store

    for code in SCALAR_FORMATS:
        ld, st = make_access(code)
        ns["_ld_" + code] = ld
        ns["_st_" + code] = st

    def _chkp(p, n, align=1):
        """Check that a pointer designates n bytes of one live object, suitably aligned."""
        mem.check(p, n)
        if p % align:
            raise RuntimeFault(f"misaligned pointer 0x{p:x} (needs alignment {align})")
        return p

    def _fill(addr, image):
        mem.buf[addr : addr + len(image)] = image

    def _copy(dst, src, n):
        mem.check(src, n, "source")
        mem.check(dst, n, "destination")
        mem.buf[dst : dst + n] = mem.buf[src : src + n]
        return dst

    def _inobj(c, size):
        """True if the `size` bytes at each address of the range `c` (non-empty, its
        step a multiple of `size`) lie inside one live object, aligned for `size`."""
        a = c.start
        if a & (ADDRESS_SIGN_MASK | (size - 1)):
            return False
        left = c[-1] + size - a
        try:
            while left > SHADOW_CAP:
                if sh[a] != SHADOW_CAP:
                    return False
                # bytes a .. a + SHADOW_CAP - 1 are the object's: go on from the last
                a += SHADOW_CAP - 1
                left -= SHADOW_CAP - 1
            return sh[a] >= left
        except IndexError:
            return False

    ns["_chkp"] = _chkp
    ns["_inobj"] = _inobj
    ns["_fill"] = _fill
    ns["_copy"] = _copy
    ns["_wrap"] = wrap_scalar
    return ns
