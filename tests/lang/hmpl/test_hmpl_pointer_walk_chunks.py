"""Pointer walks (`while (p < end) { ...; p++; }`) run in chunks whose accesses are
checked once per chunk: the chunk must still fault at the access, line and iteration
where the element-by-element check faults, whatever object lies behind the red zone,
and a misaligned walk must still read its bytes; a sum wrapped once per chunk must equal
C's 32-bit sum; the loop must yield to other tasks at the back-edges the plain loop
does; the pointer must hold C's value after the loop."""

from __future__ import annotations

import pytest

from motionvm.api import Simulation
from motionvm.lang.hmpl.compiler import TaskFile, compile_tasks
from motionvm.source.diagnostics import DiagnosticSink


def _i32(v: int) -> int:
    v &= 0xFFFFFFFF
    return v - (1 << 32) if v >= 1 << 31 else v


def _cdiv3(v: int) -> int:
    return -(-v // 3) if v < 0 else v // 3


def _python_of(src: str) -> str:
    sink = DiagnosticSink()
    prog, _ = compile_tasks([TaskFile(0, "walk.hmpl", src)], sink)
    assert prog is not None, [d.headline() for d in sink.items]
    return prog.python_source()


def _line_of(src: str, text: str) -> int:
    return next(i for i, line in enumerate(src.splitlines(), 1) if text in line)


SUM = """
int data[100];
int Sum(int *p, int n) {
    int s = 0;
    int *end = p + n;
    while (p < end) { s += *p; p++; }
    return s;
}
int SumFor(int *a, int n) {
    int s = 0;
    for (int *q = a; q < a + n; q++) s += *q;
    return s;
}
void main() { for (int i = 0; i < 100; i++) data[i] = i; Print("%d %d", Sum(data, 100), SumFor(data, 100)); }
"""


def test_while_and_for_walks_take_the_chunked_form():
    py = _python_of(SUM)
    assert py.count("_inobj(") == 2, py
    with Simulation.from_source(SUM) as sim:
        sim.run(until=0.1)
        assert sim.messages == ["4950 4950"]


@pytest.mark.parametrize("ctype", ["char", "short", "int", "double"])
@pytest.mark.parametrize("n", [1, 64, 65, 66, 130, 300])
@pytest.mark.parametrize("start", [0, 5])
def test_a_walk_past_the_end_faults_at_the_first_element_past_it(ctype, n, start):
    start = min(start, n - 1)
    src = f"""
{ctype} a[{n}];
{ctype} b[400];
int seen;
void main() {{
    {ctype} *p = a + {start};
    {ctype} *end = a + {n} + 70;
    int s = 0;
    while (p < end) {{
        s += (int)*p;
        seen++;
        p++;
    }}
    Print("not reached");
}}
"""
    assert "_inobj(" in _python_of(src)
    with Simulation.from_source(src) as sim:
        sim.run(until=1.0)
        faults = sim.fault_records
        assert sim.messages == []
        assert len(faults) == 1 and "points outside its object" in faults[0].message, faults
        assert faults[0].line == _line_of(src, "s += (int)*p;")
        # every element of `a` was read, none of the red zone or of `b` behind it
        assert sim.read("seen") == n - start


def test_a_misaligned_walk_reads_its_bytes_and_faults_past_the_end():
    src = """
char buf[400];
int seen;
int total;
void main() {
    for (int i = 0; i < 400; i++) buf[i] = (char)(i * 7);
    int *p = (int *)(buf + 1);
    int *end = p + 100;
    int s = 0;
    while (p < end) {
        s += *p;
        total = s;
        seen++;
        p++;
    }
}
"""
    raw = bytes((i * 7) & 0xFF for i in range(400))
    words = [int.from_bytes(raw[1 + 4 * k : 5 + 4 * k], "little", signed=True) for k in range(99)]
    with Simulation.from_source(src) as sim:
        sim.run(until=1.0)
        faults = sim.fault_records
        # 100 ints from buf + 1 end at buf + 401: the last one ends one byte past buf
        assert len(faults) == 1 and "points outside its object" in faults[0].message, faults
        assert faults[0].line == _line_of(src, "s += *p;")
        assert sim.read("seen") == 99
        assert sim.read("total") == _i32(sum(words[:99]))


def test_sums_wrapped_once_per_chunk_equal_the_32_bit_sums():
    src = """
int a[1000];
void main() {
    for (int i = 0; i < 1000; i++) a[i] = 2000000000 - i * 7919;
    int s = 0, t = 5, u = 0;
    int *p = a;
    int *end = a + 1000;
    while (p < end) {
        s += *p;
        t -= *p * 3;
        if (*p & 1) u += *p; else u -= 12345;
        p++;
    }
    long long wide = 0;
    for (int *q = a; q < end; q++) { wide += *q; }
    Print("%d %d %d %lld", s, t, u, wide);
    Print("%d %d %d", (s < 0) + 2 * (t < 0) + 4 * (u < 0), s / 3, t / 3);
}
"""
    vals = [_i32(2000000000 - i * 7919) for i in range(1000)]
    s = _i32(sum(vals))
    t = _i32(5 - sum(_i32(v * 3) for v in vals))
    u = _i32(sum(v if v & 1 else -12345 for v in vals))
    assert "v_s = v_s + " in _python_of(src)  # the sum is wrapped per chunk, not per element
    with Simulation.from_source(src) as sim:
        sim.run(until=1.0)
        assert sim.fault_records == []
        signs = (s < 0) + 2 * (t < 0) + 4 * (u < 0)
        assert sim.messages == [f"{s} {t} {u} {sum(vals)}", f"{signs} {_cdiv3(s)} {_cdiv3(t)}"]


@pytest.mark.parametrize("step", ["p++", "p += 3"])
@pytest.mark.parametrize("cmp", ["<", "<="])
def test_the_pointer_after_the_walk_and_stores_through_it(step, cmp):
    src = f"""
char a[200];
void main() {{
    for (int i = 0; i < 200; i++) a[i] = (char)i;
    char *p = a + 1;
    char *end = a + 198;
    int k = 0;
    while (p {cmp} end) {{ *p = *p + 100; k++; {step}; }}
    int s = 0;
    for (int i = 0; i < 200; i++) s += a[i];
    Print("%d %d %d", (int)(p - a), k, s);
}}
"""
    stride = 1 if step == "p++" else 3
    last = 198 if cmp == "<=" else 197
    touched = list(range(1, last + 1, stride))
    a = [_i32(i << 24) >> 24 for i in range(200)]  # char: signed bytes
    for i in touched:
        a[i] = ((a[i] + 100 + 128) & 0xFF) - 128
    expect = f"{1 + len(touched) * stride} {len(touched)} {sum(a)}"
    assert "_inobj(" in _python_of(src)
    with Simulation.from_source(src) as sim:
        sim.run(until=1.0)
        assert sim.fault_records == []
        assert sim.messages == [expect]


def _progress(body_extra: str) -> list[int]:
    """`seen` after each of the cycles a 20,000-element walk takes, and at its end."""
    src = f"""
int big[20000];
int seen;
void Nop() {{ }}
void main() {{
    int *p = big;
    int *end = big + 20000;
    while (p < end) {{ *p = seen; seen++; {body_extra} p++; }}
    seen = -1;
}}
"""
    with Simulation.from_source(src) as sim:
        out = []
        while not out or out[-1] != -1:
            sim.step(1)
            out.append(sim.read("seen"))
            assert len(out) < 1000
        return out


def test_a_walk_yields_at_the_back_edges_of_the_plain_loop():
    walk = _progress("")
    plain = _progress("if (seen < 0) Nop();")  # a call: not a walk, the plain loop
    assert len(walk) > 5  # the loop spans several cycles
    assert walk == plain
