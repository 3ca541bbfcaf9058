"""PDL built-in functions (manual §2.3) and the arithmetic helpers of `%`.

Each function takes Python numbers and returns the exact value the manual states;
the generated code then converts it to the target's type like any assignment
(a float into a long rounds, halves away from zero; an int wraps to the width).
Integer arguments arrive as signed 32-bit values; `unsign` also gets the width of
its argument's declared type (16 for a short).
"""

from __future__ import annotations

import math
import struct

from motionvm.lang.pdl.rt_memory import FLOAT, Memory, w32
from motionvm.runtime.errors import RuntimeFault

MASK32 = 0xFFFF_FFFF
_F32 = struct.Struct("f")


def f32(x: float) -> float:
    """Round to IEEE-754 single precision (every PDL float is 32-bit)."""
    try:
        return _F32.unpack(_F32.pack(x))[0]
    except OverflowError:
        return math.copysign(math.inf, x)


def c_mod(a: float, b: float) -> int:
    """`a % b` as C: the remainder takes the sign of the dividend."""
    if b == 0:
        raise RuntimeFault("division by zero (remainder '%')")
    r = abs(a) % abs(b)
    return -r if a < 0 else r


def divi(a: float, b: float) -> int:
    """The integer part of a / b, truncated toward zero (manual §2.3.7)."""
    if b == 0:
        raise RuntimeFault("division by zero in 'divi'")
    if type(a) is int and type(b) is int:
        q = abs(a) // abs(b)
        return q if (a < 0) == (b < 0) else -q
    return int(a / b)


def sign(a: float) -> int:
    """1, -1 or 0 (manual §2.3.4)."""
    return 1 if a > 0 else (-1 if a < 0 else 0)


def unsign(a: int, bits: int) -> int:
    """The unsigned value of a short (0..65535) or of a long's 32-bit pattern (§2.3.3)."""
    return a & (0xFFFF if bits == 16 else MASK32)


def f_sin(a: float) -> float:
    """sin of radians, in float32."""
    return f32(math.sin(a))


def f_cos(a: float) -> float:
    """cos of radians, in float32."""
    return f32(math.cos(a))


def f_sqrt(a: float) -> float:
    """Square root; a negative argument gives the negative root (manual §2.3.6)."""
    return f32(-math.sqrt(-a)) if a < 0 else f32(math.sqrt(a))


def shift(a: int, n: int) -> int:
    """Shift the 32-bit pattern left (n > 0) or right, zero-filled (n < 0)."""
    if n >= 32 or n <= -32:
        return 0
    u = a & MASK32
    return w32((u << n) & MASK32 if n >= 0 else u >> -n)


def bitset(a: int, n: int) -> int:
    """Set bit n (0..31); other n leave the value unchanged."""
    return w32(a | (1 << n)) if 0 <= n <= 31 else a


def bitclr(a: int, n: int) -> int:
    """Clear bit n (0..31)."""
    return w32(a & ~(1 << n)) if 0 <= n <= 31 else a


def bittog(a: int, n: int) -> int:
    """Toggle bit n (0..31)."""
    return w32(a ^ (1 << n)) if 0 <= n <= 31 else a


class MemFunctions:
    """memcpy, memset, memmin, memmax, memsum on one drive's memory (§2.3.10-13).

    Addresses are element addresses as `&var` gives them; `kind` is the declared
    element type of the array (FLOAT or not). n <= 0 does nothing: the min/max/sum
    functions then return None and the generated code leaves the target unchanged.
    """

    def __init__(self, mem: Memory) -> None:
        self.mem = mem

    def memcpy(self, dst: int, src: int, n: int, kind: int) -> None:
        if n > 0:
            self.mem.write_block(dst, self.mem.read_block(src, n, kind), kind)

    def memset(self, dst: int, value: float, n: int, kind: int) -> None:
        if n > 0:
            self.mem.check_block(dst, n, "memset")
            self.mem.write_block(dst, [value] * n, kind)

    def memmin(self, src: int, n: int, kind: int) -> int | float | None:
        return min(self.mem.read_block(src, n, kind)) if n > 0 else None

    def memmax(self, src: int, n: int, kind: int) -> int | float | None:
        return max(self.mem.read_block(src, n, kind)) if n > 0 else None

    def memsum(self, src: int, n: int, kind: int) -> int | float | None:
        if n <= 0:
            return None
        values = self.mem.read_block(src, n, kind)
        if kind == FLOAT:
            total = 0.0
            for v in values:
                total = f32(total + v)
            return total
        return w32(sum(values))
