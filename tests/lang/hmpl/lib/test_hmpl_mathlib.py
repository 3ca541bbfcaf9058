"""MathLib: the manual's chapter 4 examples, C special values, and agreement with the C libm."""

from __future__ import annotations

import ctypes
import ctypes.util
import itertools
import math

import pytest

from motionvm.lang.hmpl.cmemory import Memory
from motionvm.lang.hmpl.lib.cformat import format_c
from motionvm.lang.hmpl.lib.mathlib import MathLib

PI = math.pi
INF = math.inf
NAN = math.nan
DBL_MAX = 1.7976931348623157e308


class _Rt:
    mem = Memory(4096)


@pytest.fixture(scope="module")
def m() -> MathLib:
    return MathLib(_Rt())


def printf(fmt: str, *args) -> str:
    return format_c(fmt.encode(), list(args), _Rt.mem).decode()


def manual(r: float, *args: float) -> float:
    """C's result `r` as the manual's 4.12-4.14/4.19 want it: an overflow (finite
    arguments, infinite result) gives the largest double with the result's sign."""
    if math.isinf(r) and all(math.isfinite(a) for a in args):
        return math.copysign(DBL_MAX, r)
    return r


def same(a: float, b: float) -> bool:
    """Equal as C doubles: bit-identical, any NaN equals any NaN."""
    if a != a or b != b:
        return a != a and b != b
    return a == b and math.copysign(1.0, a) == math.copysign(1.0, b)


def test_registered_names():
    names = "sin cos tan asin acos atan atan2 abs fabs ceil floor ldexp exp pow log log10 sqrt cbrt"
    assert set(MathLib.builtin_methods()) == set(names.split()) | {"hypot"}


def test_manual_examples(m):
    assert printf("%f", m.sin(30.0 * PI / 180)) == "0.500000"
    assert printf("%f", m.cos(60.0 * PI / 180)) == "0.500000"
    assert printf("%f", m.tan(45.0 * PI / 180)) == "1.000000"
    assert printf("%f", m.asin(0.5) * 180.0 / PI) == "30.000000"
    assert printf("%f", m.acos(0.5) * 180.0 / PI) == "60.000000"
    assert printf("%f", m.atan(1.0) * 180.0 / PI) == "45.000000"
    assert printf("%f", m.atan2(10, -10) * 180.0 / PI) == "135.000000"
    assert (
        printf("absolute value of -3591 is %d.", m.int_abs(-3591))
        == "absolute value of -3591 is 3591."
    )
    assert printf("%f", m.fabs(-35.91)) == "35.910000"
    assert [printf("%g", m.ceil(x)) for x in (2.3, 3.8, -2.3, -3.8)] == ["3", "4", "-2", "-3"]
    assert [printf("%g", m.floor(x)) for x in (2.3, 3.8, -2.3, -3.8)] == ["2", "3", "-3", "-4"]
    assert printf("0.95 * 2^4 = %f", m.ldexp(0.95, 4)) == "0.95 * 2^4 = 15.200000"
    assert printf("%f", m.exp(5.0)) == "148.413159"
    assert printf("%f", m.pow(7.0, 3.0)) == "343.000000"
    assert printf("%f", m.pow(4.73, 12.0)) == "125410439.217423"
    assert printf("%f", m.pow(32.01, 1.54)) == "208.036691"
    assert printf("log(5.5) = %f", m.log(5.5)) == "log(5.5) = 1.704748"
    assert printf("%f", m.log10(1000.0)) == "3.000000"
    assert printf("%f", m.sqrt(1024.0)) == "32.000000"
    assert printf("%f", m.cbrt(27.0)) == "3.000000"
    assert printf("%f", m.hypot(3.0, 4.0)) == "5.000000"


@pytest.mark.parametrize(
    "name, args, want",
    [
        ("sin", (INF,), NAN),
        ("cos", (-INF,), NAN),
        ("tan", (INF,), NAN),
        ("asin", (2.0,), NAN),
        ("acos", (-1.5,), NAN),
        ("atan", (INF,), PI / 2),
        ("atan2", (0.0, -0.0), PI),
        ("atan2", (-0.0, -1.0), -PI),
        ("sqrt", (-1.0,), NAN),
        ("sqrt", (-0.0,), -0.0),
        ("sqrt", (INF,), INF),
        ("log", (0.0,), -INF),
        ("log", (-0.0,), -INF),
        ("log", (-1.0,), NAN),
        ("log", (INF,), INF),
        ("log10", (0.0,), -INF),
        ("log10", (-5.0,), NAN),
        ("exp", (1000.0,), DBL_MAX),
        ("exp", (INF,), INF),
        ("exp", (-INF,), 0.0),
        ("exp", (-1000.0,), 0.0),
        ("pow", (-8.0, 1 / 3), NAN),
        ("pow", (0.0, -1.0), INF),
        ("pow", (-0.0, -1.0), -INF),
        ("pow", (-0.0, -2.0), INF),
        ("pow", (0.0, 0.0), 1.0),
        ("pow", (NAN, 0.0), 1.0),
        ("pow", (10.0, 400.0), DBL_MAX),
        ("pow", (-10.0, 401.0), -DBL_MAX),
        ("pow", (-10.0, 400.0), DBL_MAX),
        ("pow", (1e-300, -2.0), DBL_MAX),
        ("pow", (INF, 2.0), INF),
        ("pow", (-INF, 3.0), -INF),
        ("pow", (0.0, -INF), INF),
        ("pow", (-1.0, INF), 1.0),
        ("ldexp", (1.0, 5000), DBL_MAX),
        ("ldexp", (INF, 1), INF),
        ("ldexp", (-1.0, 5000), -DBL_MAX),
        ("ldexp", (-1e308, 1), -DBL_MAX),
        ("ldexp", (1.0, -5000), 0.0),
        ("hypot", (1.5e308, 1.5e308), DBL_MAX),
        ("hypot", (-1.5e308, 1.5e308), DBL_MAX),
        ("hypot", (-INF, 1.0), INF),
        ("hypot", (INF, NAN), INF),
        ("ceil", (-0.5,), -0.0),
        ("ceil", (-0.0,), -0.0),
        ("ceil", (INF,), INF),
        ("ceil", (NAN,), NAN),
        ("floor", (0.5,), 0.0),
        ("floor", (-0.0,), -0.0),
        ("floor", (-INF,), -INF),
        ("ceil", (4503599627370497.0,), 4503599627370497.0),
        ("floor", (-1e300,), -1e300),
        ("fabs", (-0.0,), 0.0),
        ("cbrt", (-8.0,), -2.0),
    ],
)
def test_c_special_values(m, name, args, want):
    got = getattr(m, name)(*args)
    assert isinstance(got, float)
    assert same(got, want), f"{name}{args} = {got!r}, C gives {want!r}"


def test_abs_is_32_bit_int(m):
    assert m.int_abs(-5) == 5
    assert m.int_abs(7) == 7
    assert m.int_abs(-(2**31)) == -(2**31)
    assert m.int_abs(2**31 - 1) == 2**31 - 1


def _libm():
    name = ctypes.util.find_library("m")
    if name is None:
        pytest.skip("no C math library found")
    return ctypes.CDLL(name)


VALUES = [
    0.0,
    -0.0,
    0.5,
    -0.5,
    1.0,
    -1.0,
    2.0,
    3.7,
    -3.7,
    1e-300,
    1e300,
    710.0,
    -745.5,
    1024.0,
    27.0,
    INF,
    -INF,
    NAN,
]


@pytest.mark.parametrize(
    "name",
    [
        "sin",
        "cos",
        "tan",
        "asin",
        "acos",
        "atan",
        "exp",
        "log",
        "log10",
        "sqrt",
        "cbrt",
        "fabs",
        "ceil",
        "floor",
    ],
)
def test_unary_matches_libm(m, name):
    fn = getattr(_libm(), name)
    fn.restype, fn.argtypes = ctypes.c_double, [ctypes.c_double]
    for x in VALUES:
        want = manual(fn(x), x) if name == "exp" else fn(x)
        assert same(getattr(m, name)(x), want), f"{name}({x!r})"


@pytest.mark.parametrize("name", ["atan2", "pow", "hypot"])
def test_binary_matches_libm(m, name):
    fn = getattr(_libm(), name)
    fn.restype, fn.argtypes = ctypes.c_double, [ctypes.c_double, ctypes.c_double]
    ys = VALUES + [3.0, -3.0, 1 / 3, 400.0, -401.0]
    for x, y in itertools.product(VALUES, ys):
        want = fn(x, y)
        if name == "hypot" or (name == "pow" and x != 0.0):  # pow(0, y < 0) is a pole
            want = manual(want, x, y)
        assert same(getattr(m, name)(x, y), want), f"{name}({x!r}, {y!r})"


def test_ldexp_matches_libm(m):
    fn = _libm().ldexp
    fn.restype, fn.argtypes = ctypes.c_double, [ctypes.c_double, ctypes.c_int]
    for x, e in itertools.product(VALUES, [0, 1, -1, 4, 1023, 1024, -1074, -1075, 5000, -5000]):
        assert same(m.ldexp(x, e), manual(fn(x, e), x)), f"ldexp({x!r}, {e})"
