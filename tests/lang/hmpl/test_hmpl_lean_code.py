"""The shorter forms the compiler generates keep C's meaning at their edges: `x + k`
without a temporary still wraps, a switch lowered as an if-chain keeps its breaks and
defaults, `%` and `/` of a value known not negative match C's truncation (and a value
that may be negative still gets C's), a counting loop in chunks runs every value, and a
function that always returns gets no trailing `return 0` (one that may fall off still
gets it)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from motionvm.lang.hmpl.compiler import TaskFile, compile_tasks
from motionvm.source.diagnostics import DiagnosticSink

sys.path.insert(0, str(Path(__file__).resolve().parent))
from hmpl_run import run_hmpl  # noqa: E402


def _python_of(src: str) -> str:
    sink = DiagnosticSink()
    prog, _ = compile_tasks([TaskFile(0, "lean.hmpl", src)], sink)
    assert prog is not None, [d.headline() for d in sink.items]
    return prog.python_source()


def _wrap(x: int, bits: int = 32) -> int:
    half = 1 << (bits - 1)
    return ((x + half) & ((1 << bits) - 1)) - half


def _c_div(x: int, y: int) -> int:
    q = abs(x) // abs(y)
    return q if (x >= 0) == (y >= 0) else -q


EDGES = [-2147483648, -2147483647, -2147483600, -1, 0, 1, 2147483600, 2147483646, 2147483647]
STEPS = [1, -1, 10, -10, 2147483647, -2147483647]


@pytest.mark.parametrize("k", STEPS)
def test_a_name_plus_a_constant_wraps_at_both_ends(k):
    # `y < 0` and `y / 3` see the Python int itself: an unreduced sum would show there
    lines = "\n".join(
        f'    x = {v}; y = x + ({k}); Print("%d %d %d", y, y < 0, y / 3);' for v in EDGES
    )
    src = f"void main() {{\n    int x; int y;\n{lines}\n}}\n"
    assert "_w :=" not in _python_of(src)  # the short form, not the general wrap
    expect = [_wrap(v + k) for v in EDGES]
    assert run_hmpl(src) == [f"{y} {int(y < 0)} {_c_div(y, 3)}" for y in expect]


def test_increments_and_compound_steps_wrap():
    src = """
void main() {
    int a = 2147483647; a++;
    int b = -2147483648; b--;
    int c = 2147483640; c += 10;
    int d = -2147483640; d -= 10;
    int e = 5; e = 7 + e;
    long long f = 9223372036854775807LL; f++;
    char g = 127; g++;
    int h = 3; h = h + 0;
    Print("%d %d %d %d %d %lld %d %d", a, b, c, d, e, f, g, h);
}
"""
    py = _python_of(src)
    assert py.count("_w :=") == 1  # only the char's: int to char reduces modulo 2**8
    assert run_hmpl(src) == [
        f"{-2147483648} {2147483647} {_wrap(2147483650)} {_wrap(-2147483650)} 12"
        f" {-(1 << 63)} -128 3"
    ]


SWITCHES = """
int plain(int v) {
    int s = 0;
    switch (v) { case 1: s = 10; break; case 2: s = 20; break; default: s = 99; }
    return s;
}
int default_first(int v) {
    int s = 0;
    switch (v) { default: s = 7; break; case 3: s = 30; break; case 4: s = 40; }
    return s;
}
int grouped(int v) {
    int s = 0;
    switch (v) { case 5: case 6: s = 56; break; case 1: default: s = -1; break; case 8: s = 8; }
    return s;
}
int inner_break(int v) {
    int s = 0;
    switch (v) { case 1: if (s == 0) break; s = 100; break; case 2: s = 2; break; }
    return s;
}
int changes_subject(int v) {
    switch (v) { case 1: v = 2; break; case 2: v = 200; break; default: v = v * 3; }
    return v;
}
int no_default(int v) {
    int s = 1;
    switch (v) { case 0: s = 0; break; case 9: s = 9; }
    return s;
}
int in_loop(int n) {
    int s = 0;
    for (int i = 0; i < n; i++) {
        switch (i % 4) { case 0: continue; case 1: s += 1; break; default: s += 100; break; }
        s += 1000;
    }
    return s;
}
int nested(int a, int b) {
    switch (a) {
    case 1:
        switch (b) { case 1: return 11; case 2: break; default: return 19; }
        return 12;
    default:
        return 0;
    }
}
void main() {
    int v;
    for (v = -1; v < 10; v++)
        Print("%d %d %d %d %d %d", plain(v), default_first(v), grouped(v), inner_break(v),
              changes_subject(v), no_default(v));
    Print("%d %d %d %d %d", in_loop(10), nested(1, 1), nested(1, 2), nested(1, 3), nested(2, 1));
}
"""


def _switches_model(v: int) -> str:
    plain = {1: 10, 2: 20}.get(v, 99)
    default_first = {3: 30, 4: 40}.get(v, 7)
    grouped = 56 if v in (5, 6) else 8 if v == 8 else -1
    inner_break = {2: 2}.get(v, 0)
    changes = {1: 2, 2: 200}.get(v, v * 3)
    no_default = {0: 0, 9: 9}.get(v, 1)
    return f"{plain} {default_first} {grouped} {inner_break} {changes} {no_default}"


def test_switches_as_if_chains_keep_c_meaning():
    py = _python_of(SWITCHES)
    assert py.count("while True") < 8  # most are if-chains now
    in_loop = sum(0 if i % 4 == 0 else (1 if i % 4 == 1 else 100) + 1000 for i in range(10))
    assert run_hmpl(SWITCHES) == [_switches_model(v) for v in range(-1, 10)] + [
        f"{in_loop} 11 12 19 0"
    ]


def test_an_empty_last_group_of_a_falling_switch_compiles():
    # `case 2: }` leaves the loop form's last group empty: it gets a placed `pass` (it was
    # a node without a line, and Python's compile() refused the module)
    src = """
void main() {
    for (int v = 0; v < 4; v++) {
        int x = v;
        switch (v) { case 1: x += 10; case 2: }
        switch (v) { case 3: x += 100; default: }
        Print("%d", x);
    }
}
"""
    assert "while True" in _python_of(src)
    assert run_hmpl(src) == ["0", "11", "2", "103"]


def test_modulo_and_division_of_a_counter():
    src = """
void main() {
    int n = 7;
    for (int i = 0; i < n; i++) Print("%d %d", i % 3, i / 2);
    for (int j = -7; j < n; j += 3) Print("%d %d", j % 3, j / 2);
    for (int k = 4294967295LL; k < 2; k++) Print("%d %d", k % 3, k / 2);
    unsigned int u = 4294967295u;
    Print("%u %u", u % 10u, u / 10u);
}
"""
    py = _python_of(src)
    assert "v_i % 3" in py and "v_i // 2" in py  # proved: i runs from 0 up
    assert "_imod(v_j, 3)" in py and "_imod(v_k, 3)" in py  # may be negative
    expect = [f"{i % 3} {i // 2}" for i in range(7)]
    expect += [f"{j - _c_div(j, 3) * 3} {_c_div(j, 2)}" for j in range(-7, 7, 3)]
    expect += [f"{k - _c_div(k, 3) * 3} {_c_div(k, 2)}" for k in range(-1, 2)]
    expect += [f"{4294967295 % 10} {4294967295 // 10}"]
    assert run_hmpl(src) == expect


def test_a_counter_near_the_top_still_wraps_its_sum():
    # the counter's bounds come from its start and, the bound being unknown, its type:
    # i + 10 may pass INT_MAX, so it must keep its wrap
    src = """
void main() {
    int n = 2147483647;
    for (int i = 2147483640; i < n; i++) { int j = i + 10; Print("%d %d", j, j < 0); }
}
"""
    expect = [_wrap(i + 10) for i in range(2147483640, 2147483647)]
    assert run_hmpl(src) == [f"{j} {int(j < 0)}" for j in expect]


def test_a_quotient_by_minus_one_still_wraps():
    # any constant divisor but -1 keeps the quotient in range; INT_MIN / -1 does not
    src = """
void main() {
    int m = -2147483648; int d = -1;
    int q = m / -1;
    Print("%d %d %d %d %d", q, q < 0, m / d, m / 3, m / -2);
}
"""
    assert run_hmpl(src) == [f"-2147483648 1 -2147483648 {_c_div(-(2**31), 3)} 1073741824"]


@pytest.mark.parametrize("n", [0, 1, 63, 64, 65, 128, 129, 300])
def test_counting_loops_in_chunks_run_every_value(n):
    src = f"""
int g[400];
void main() {{
    int s = 0;
    for (int i = 0; i < {n}; i++) {{ g[i] = i; s += i; }}
    int t = 0;
    for (int j = 1; j <= {n}; j++) t += g[j - 1];
    int u = 0;
    for (int r = 0; r < 3; r++)
        for (int k = r; k < {n}; k++) u += g[k];   // a loop in a loop: chunks inline
    Print("%d %d %d", s, t, u);
}}
"""
    tri = n * (n - 1) // 2
    u = sum(sum(range(r, n)) for r in range(3))
    assert run_hmpl(src) == [f"{tri} {tri} {u}"]


def test_a_trailing_return_only_where_the_end_is_reachable():
    src = """
int both(int x) { if (x) return 5; else return 6; }
int maybe(int x) { if (x) return 5; }
void main() { Print("%d %d %d %d", both(1), both(0), maybe(1), maybe(0)); }
"""
    py = _python_of(src)
    both = py.split("def g_both")[1].split("def ")[0]
    maybe = py.split("def g_maybe")[1].split("def ")[0]
    assert "return 0" not in both and "return 0" in maybe
    assert run_hmpl(src) == ["5 6 5 0"]


def test_an_int_operand_of_a_double_operation_converts_as_float_does():
    # Python converts the int of `int * float` as float() does (to nearest, ties to even)
    src = """
void main() {
    long long big = 9007199254740993LL; int m = -2147483648; int i = 3;
    double h = 0.5;
    Print("%.1f %.1f %.1f %.3f %.3f", big * 1.0, big + h, m * h, h - i, i * h);
}
"""
    assert "float(" not in _python_of(src)
    big = 9007199254740993
    assert run_hmpl(src) == [
        f"{float(big) * 1.0:.1f} {float(big) + 0.5:.1f} {-(2.0**31) * 0.5:.1f} {0.5 - 3:.3f}"
        f" {3 * 0.5:.3f}"
    ]
