"""format_c against glibc printf (a table of cases compiled with gcc) and chosen cases."""

from __future__ import annotations

import itertools
import math
import shutil
import subprocess

import pytest

from motionvm.lang.hmpl.cmemory import Memory
from motionvm.lang.hmpl.lib import cformat
from motionvm.lang.hmpl.lib.cformat import format_c
from motionvm.runtime.errors import RuntimeFault

NAN = float("nan")
INF = float("inf")

# (C type, value): "int" and "ll" are C int / long long, "dbl" double, "str" a char *
# (bytes, written into memory for format_c), "ptr" a void *.
Arg = tuple[str, object]


def _flag_sets(allowed: str) -> list[str]:
    return ["".join(c) for r in range(len(allowed) + 1) for c in itertools.combinations(allowed, r)]


def _int_cases() -> list[tuple[str, list[Arg]]]:
    cases = []
    values = [0, 1, -42, 0x12345678, -1]
    for conv in "diuxXo":
        flags = _flag_sets("-+ 0" + ("" if conv in "diu" else "#"))
        for fl, w, p, v in itertools.product(flags, ["", "8"], ["", ".0", ".3"], values):
            cases.append((f"[%{fl}{w}{p}{conv}]", [("int", v)]))
    big = [0, 5, -5, 255, 256, 65535, 65536, -32769, 2**31 - 1, -(2**31), 2**63 - 1, -(2**63)]
    for conv, length, v in itertools.product("diuxXo", ["h", "hh", "ll", "z"], big):
        ctype = "ll" if length in ("ll", "z") else "int"
        cases.append((f"[%{length}{conv}|%#12{length}{conv}]", [(ctype, v), (ctype, v)]))
    return cases


def _float_cases() -> list[tuple[str, list[Arg]]]:
    cases = []
    values = [0.0, -0.0, 1428.57, -1.5, 1e-5, 0.5, 123456789.0, 1e300, INF, -INF, NAN, -NAN]
    for conv in "fFeEgG":
        for fl, w, p in itertools.product(_flag_sets("-+ #0"), ["", "12"], ["", ".0", ".3"]):
            cases.append((f"[%{fl}{w}{p}{conv}]", [("dbl", v) for v in values[:1]]))
        for fl, w, p, v in itertools.product(
            ["", "-", "+0", " #", "#0"], ["", "12"], ["", ".0", ".2", ".10"], values
        ):
            cases.append((f"[%{fl}{w}{p}{conv}]", [("dbl", v)]))
    for v in [
        2.5,
        3.5,
        0.125,
        1e15,
        1e16,
        9.9999995,
        0.0001,
        0.00001234,
        5e-324,
        1.7976931348623157e308,
    ]:
        cases.append(("%f %e %g %.1f %.2e %.15g %.17g %#g", [("dbl", v)] * 8))
    return cases


def _other_cases() -> list[tuple[str, list[Arg]]]:
    cases = []
    for fl, w in itertools.product(["", "-"], ["", "1", "4"]):
        for v in (65, 0x141, 32, 126):
            cases.append((f"[%{fl}{w}c]", [("int", v)]))
    for fl, w, p, s in itertools.product(
        ["", "-"], ["", "3", "15"], ["", ".0", ".2", ".20"], [b"", b"hello world"]
    ):
        cases.append((f"[%{fl}{w}{p}s]", [("str", s)]))
    for fl, w, v in itertools.product(
        ["", "-", "+", " ", "0", "-0"], ["", "20"], [0, 0x40, 0xDEADBEEF]
    ):
        cases.append((f"[%{fl}{w}p]", [("ptr", v)]))
    star = [("int", 6), ("int", -6), ("int", 0)]
    for (_, w), (_, p) in itertools.product(star, star):
        cases.append(
            (
                "[%*d][%-*.*f][%.*s][%*.*e]",
                [
                    ("int", w),
                    ("int", 42),
                    ("int", w),
                    ("int", p),
                    ("dbl", 3.14159),
                    ("int", p),
                    ("str", b"abcdefgh"),
                    ("int", w),
                    ("int", p),
                    ("dbl", -2.5),
                ],
            )
        )
    cases.append(("100%% done, %d%%", [("int", 5)]))
    cases.append(
        ("var1: %d, var2: %f, str: %s", [("int", 321), ("dbl", 1428.57), ("str", b"hello world")])
    )
    return cases


CASES = _int_cases() + _float_cases() + _other_cases()


def _c_string(data: bytes) -> str:
    return '"' + "".join(f"\\{b:03o}" for b in data) + '"'


def _c_arg(ctype: str, v) -> str:
    if ctype == "int":
        return f"(int)0x{v & 0xFFFFFFFF:08x}U"
    if ctype == "ll":
        return f"(long long)0x{v & 0xFFFFFFFFFFFFFFFF:016x}ULL"
    if ctype == "ptr":
        return f"(void *)0x{v:x}UL"
    if ctype == "str":
        return _c_string(v)
    if math.isnan(v):
        return "-NAN" if math.copysign(1.0, v) < 0 else "NAN"
    if math.isinf(v):
        return "-INFINITY" if v < 0 else "INFINITY"
    return v.hex()


@pytest.fixture(scope="module")
def glibc_outputs(tmp_path_factory) -> list[bytes]:
    """printf output of every case, from a C program built with gcc."""
    gcc = shutil.which("gcc")
    if gcc is None:
        pytest.skip("gcc is not installed")
    lines = [
        "#include <stdio.h>",
        "#include <math.h>",
        "static char buf[8192];",
        "int main(void) {",
        "int n;",
    ]
    for fmt, args in CASES:
        cargs = "".join(", " + _c_arg(t, v) for t, v in args)
        lines.append(f"n = snprintf(buf, sizeof buf, {_c_string(fmt.encode())}{cargs});")
        lines.append('printf("%d:", n); fwrite(buf, 1, n, stdout);')
    lines += ["return 0;", "}"]
    folder = tmp_path_factory.mktemp("cformat")
    src, exe = folder / "cases.c", folder / "cases"
    src.write_text("\n".join(lines))
    subprocess.run([gcc, "-w", "-O0", str(src), "-o", str(exe), "-lm"], check=True)
    raw = subprocess.run([str(exe)], check=True, capture_output=True).stdout
    outs, i = [], 0
    while i < len(raw):
        colon = raw.index(b":", i)
        n = int(raw[i:colon])
        outs.append(raw[colon + 1 : colon + 1 + n])
        i = colon + 1 + n
    assert len(outs) == len(CASES)
    return outs


def _run(fmt: bytes, args: list[Arg], mem: Memory) -> bytes:
    values = []
    for ctype, v in args:
        if ctype == "str":
            addr = mem.alloc_static(len(v) + 1)
            mem.write_cstr(addr, v)
            values.append(addr)
        else:
            values.append(v)
    return format_c(fmt, values, mem)


def test_every_case_matches_glibc(glibc_outputs):
    mem = Memory(1 << 22)
    bad = []
    for (fmt, args), want in zip(CASES, glibc_outputs, strict=True):
        got = _run(fmt.encode(), args, mem)
        if got != want:
            bad.append(f"{fmt!r} {args!r}: got {got!r}, C prints {want!r}")
    assert not bad, f"{len(bad)} of {len(CASES)} cases differ:\n" + "\n".join(bad[:30])


@pytest.fixture
def mem() -> Memory:
    return Memory(1 << 16)


def _cstr(mem: Memory, text: bytes) -> int:
    addr = mem.alloc_static(len(text) + 1)
    mem.write_cstr(addr, text)
    return addr


def test_manual_examples(mem):
    s = _cstr(mem, b"hello world")
    assert format_c(b"var1: %d, var2: %f, str: %s", [321, 1428.57, s], mem) == (
        b"var1: 321, var2: 1428.570000, str: hello world"
    )
    assert format_c(b"var2: %e", [1428.57], mem) == b"var2: 1.428570e+03"
    assert format_c(b"var2: %g", [1428.57], mem) == b"var2: 1428.57"
    # the directive table of 3.2
    assert format_c(b"%d %i %u %x %c", [589, 589, 589, 589, ord("M")], mem) == b"589 589 589 24d M"
    assert format_c(b"%f %e %g %%", [589.0, 589.0, 589.0], mem) == b"589.000000 5.890000e+02 589 %"


def test_unsigned_of_negative_is_twos_complement(mem):
    assert (
        format_c(b"%u %x %X %o", [-1, -1, -2, -1], mem)
        == b"4294967295 ffffffff FFFFFFFE 37777777777"
    )
    assert format_c(b"%llu %llx", [-1, -1], mem) == b"18446744073709551615 ffffffffffffffff"
    # `l` is 32 bits on the controller (LLP64), `z` 64
    assert (
        format_c(b"%lx %ld %zx", [-1, 2**31, -1], mem) == b"ffffffff -2147483648 ffffffffffffffff"
    )


def test_wrong_kind_of_argument_is_cast(mem):
    assert format_c(b"%d|%x|%d", [3.99, -1.5, NAN], mem) == b"3|ffffffff|0"
    assert format_c(b"%f|%g", [5, 2**2000], mem) == b"5.000000|inf"


def test_unknown_directive_is_literal_and_takes_no_argument(mem):
    assert format_c(b"%k|%5.2y|%d|%n|100%", [7], mem) == b"%k|%5.2y|7|%n|100%"


def test_extra_arguments_are_ignored(mem):
    assert format_c(b"%d", [1, 2, 3], mem) == b"1"
    assert format_c(b"no directives", [1.5], mem) == b"no directives"


def test_missing_arguments_fault(mem):
    with pytest.raises(RuntimeFault, match=r"^Print: format needs 3 arguments, got 1$"):
        format_c(b"%d %*d", [1], mem)
    with pytest.raises(RuntimeFault, match=r"^StringPrint: format needs 1 arguments, got 0$"):
        format_c(b"%s", [], mem, func="StringPrint")


def test_string_argument_faults(mem):
    with pytest.raises(RuntimeFault, match="null"):
        format_c(b"%s", [0], mem)
    with pytest.raises(RuntimeFault, match="outside"):
        format_c(b"%s", [mem.size - 8], mem)
    raw = mem.alloc_static(4)
    mem.write_bytes(raw, b"abcd")  # no terminator
    with pytest.raises(RuntimeFault, match="not terminated"):
        format_c(b"%s", [raw], mem)
    # a precision bounds the read: no terminator needed within it
    assert format_c(b"%.3s|%.4s", [raw, raw], mem) == b"abc|abcd"
    with pytest.raises(RuntimeFault, match="not terminated"):
        format_c(b"%.5s", [raw], mem)


def test_huge_field_faults(mem):
    with pytest.raises(RuntimeFault, match="exceeds the limit 4096"):
        format_c(b"%100000d", [1], mem)
    with pytest.raises(RuntimeFault, match="exceeds the limit 4096"):
        format_c(b"%*d", [5000, 1], mem)


def test_bytes_pass_through_unchanged(mem):
    s = _cstr(mem, bytes(range(1, 256)))
    assert format_c(b"\xe4%s\xff", [s], mem) == b"\xe4" + bytes(range(1, 256)) + b"\xff"


def test_compiled_formats_are_cached(mem):
    fmt = b"cache test %d"
    format_c(fmt, [1], mem)
    prog = cformat._cache[fmt]
    assert format_c(fmt, [2], mem) == b"cache test 2"
    assert cformat._cache[fmt] is prog
