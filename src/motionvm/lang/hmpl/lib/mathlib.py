"""HMPL math built-ins (manual chapter 4) with C libm semantics: no exceptions, IEEE results.

Python's `math` raises where C returns a special value; each function here returns
what C99 Annex F specifies instead:
- domain errors (asin(2), sqrt(-1), log(-1), sin(inf), pow(-8, 1/3)) give NaN
  (always a positive NaN: the sign of such a NaN is unspecified in C);
- pole errors (log(0), pow(0, -1)) give -inf / +-inf;
- overflow of ldexp, exp, pow and hypot (4.12-4.14, 4.19: "if the result is too
  large, the largest representable double is returned") gives +-DBL_MAX
  (1.7976931348623157e308), with the sign of the true result: ldexp takes the sign
  of x, pow(x, y) is negative for a negative x and an odd integer y, exp and hypot
  are positive. Overflow means finite arguments with a result beyond DBL_MAX; an
  infinite argument (exp(inf), hypot(inf, 1)) still gives inf, as does a pole.
- ceil/floor return doubles and keep the sign of zero (ceil(-0.5) is -0.0).
`abs` is C's int abs: the argument and result wrap to 32 bits, so abs(INT_MIN) is INT_MIN.
The functions use the platform's libm through `math`, so results are those of C on
the same machine (e.g. cbrt(27.0) is 3.0000000000000004 with glibc, printed 3.000000).
"""

from __future__ import annotations

import math

from motionvm.lang.hmpl.lib.base import Library, builtin

_NAN = math.nan
_INF = math.inf
DBL_MAX = 1.7976931348623157e308
"""The largest double, what the manual's overflowing math functions return."""


def _clamp_overflow(r: float, *args: float) -> float:
    """`r`, or +-DBL_MAX if finite `args` gave an infinite `r` (an overflow)."""
    if r - r == 0.0 or r != r:  # finite or NaN
        return r
    for a in args:
        if a - a != 0.0:  # an infinite or NaN argument: an exact inf, not an overflow
            return r
    return math.copysign(DBL_MAX, r)


def _is_odd_integer(y: float) -> bool:
    return y - y == 0.0 and y == math.floor(y) and math.fmod(y, 2.0) != 0.0


def c_pow(x: float, y: float) -> float:
    """C's pow(x, y)."""
    try:
        return math.pow(x, y)
    except OverflowError:
        return -_INF if x < 0 and _is_odd_integer(y) else _INF
    except ValueError:
        if x == 0.0:  # pole: 0 to a negative power
            return math.copysign(_INF, x) if _is_odd_integer(y) else _INF
        return _NAN


def _guard(fn):
    """Wrap a one-argument math function: ValueError -> NaN (domain), OverflowError -> inf."""

    def call(x: float) -> float:
        try:
            return fn(x)
        except ValueError:
            return _NAN
        except OverflowError:
            return _INF

    return call


_sin = _guard(math.sin)
_cos = _guard(math.cos)
_tan = _guard(math.tan)
_asin = _guard(math.asin)
_acos = _guard(math.acos)
_exp = _guard(math.exp)  # only overflows upward: exp never goes below 0
_sqrt = _guard(math.sqrt)


def c_log(x: float, fn=math.log) -> float:
    """C's log/log10: log(+-0) is -inf, a negative argument gives NaN."""
    if x == 0.0:
        return -_INF
    try:
        return fn(x)
    except ValueError:
        return _NAN


class MathLib(Library):
    """Chapter 4: sin ... hypot. Arguments arrive as floats (ints for abs, ldexp's y)."""

    @builtin()
    def sin(self, x: float) -> float:
        return _sin(x)

    @builtin()
    def cos(self, x: float) -> float:
        return _cos(x)

    @builtin()
    def tan(self, x: float) -> float:
        return _tan(x)

    @builtin()
    def asin(self, x: float) -> float:
        return _asin(x)

    @builtin()
    def acos(self, x: float) -> float:
        return _acos(x)

    @builtin()
    def atan(self, x: float) -> float:
        return math.atan(x)

    @builtin()
    def atan2(self, y: float, x: float) -> float:
        return math.atan2(y, x)

    @builtin("abs")
    def int_abs(self, x: int) -> int:
        """|x| of a 32-bit int, wrapping as C does (abs(-2147483648) == -2147483648)."""
        x = (int(x) + 0x8000_0000) % 0x1_0000_0000 - 0x8000_0000
        return x if x >= 0 or x == -0x8000_0000 else -x

    @builtin()
    def fabs(self, x: float) -> float:
        return math.fabs(x)

    @builtin()
    def ceil(self, x: float) -> float:
        if x - x != 0.0 or x == 0.0:  # inf, nan, +-0 are their own ceiling
            return float(x)
        r = float(math.ceil(x))
        return -0.0 if r == 0.0 and x < 0.0 else r

    @builtin()
    def floor(self, x: float) -> float:
        if x - x != 0.0 or x == 0.0:
            return float(x)
        return float(math.floor(x))

    @builtin()
    def ldexp(self, x: float, y: int) -> float:
        """x * 2**y; overflow gives +-DBL_MAX (the sign of x)."""
        try:
            return math.ldexp(x, int(y))
        except OverflowError:
            return math.copysign(DBL_MAX, x)

    @builtin()
    def exp(self, x: float) -> float:
        return _clamp_overflow(_exp(x), x)

    @builtin()
    def pow(self, x: float, y: float) -> float:
        x, y = float(x), float(y)
        if x == 0.0:  # 0 to a negative power is a pole (inf), not an overflow
            return c_pow(x, y)
        return _clamp_overflow(c_pow(x, y), x, y)

    @builtin()
    def log(self, x: float) -> float:
        return c_log(x)

    @builtin()
    def log10(self, x: float) -> float:
        return c_log(x, math.log10)

    @builtin()
    def sqrt(self, x: float) -> float:
        return _sqrt(x)

    @builtin()
    def cbrt(self, x: float) -> float:
        return math.cbrt(x)

    @builtin()
    def hypot(self, x: float, y: float) -> float:
        try:
            return _clamp_overflow(math.hypot(x, y), x, y)
        except OverflowError:
            return DBL_MAX
