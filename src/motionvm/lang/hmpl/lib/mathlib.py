"""HMPL math built-ins (manual chapter 4) with C libm semantics: no exceptions, IEEE results.

Python's `math` raises where C returns a special value; each function here returns
what C99 Annex F specifies instead:
- domain errors (asin(2), sqrt(-1), log(-1), sin(inf), pow(-8, 1/3)) give NaN
  (always a positive NaN: the sign of such a NaN is unspecified in C);
- pole errors (log(0), pow(0, -1)) give -inf / +-inf;
- overflow (exp(1000), ldexp(1, 5000), pow(10, 400), hypot(1.5e308, 1.5e308)) gives
  +-HUGE_VAL, which is +-inf. The manual's "largest representable double value" is
  its wording for HUGE_VAL, so inf it is (Print shows "inf").
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
        """x * 2**y; overflow gives +-inf (HUGE_VAL)."""
        try:
            return math.ldexp(x, int(y))
        except OverflowError:
            return math.copysign(_INF, x)

    @builtin()
    def exp(self, x: float) -> float:
        return _exp(x)

    @builtin()
    def pow(self, x: float, y: float) -> float:
        return c_pow(float(x), float(y))

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
            return math.hypot(x, y)
        except OverflowError:
            return _INF
