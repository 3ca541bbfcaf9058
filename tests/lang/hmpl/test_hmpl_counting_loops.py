"""Counting loops (`for (i = a; i < b; i += s)` as Python ranges in chunks): an empty
range, a range of one chunk and longer ones leave the counter at C's value; a run-time
step is checked to be positive unless range analysis proves it is."""

from __future__ import annotations

import pytest

from motionvm.api import Simulation
from motionvm.lang.hmpl.compiler import TaskFile, compile_tasks
from motionvm.source.diagnostics import DiagnosticSink


def _python_of(src: str) -> str:
    sink = DiagnosticSink()
    prog, _ = compile_tasks([TaskFile(0, "loops.hmpl", src)], sink)
    assert prog is not None, [d.headline() for d in sink.items]
    return prog.python_source()


def _run(src: str):
    with Simulation.from_source(src) as sim:
        sim.run(until=1.0)
        return list(sim.messages), sim.fault_records


@pytest.mark.parametrize("stop", [0, 5, 6, 68, 69, 70, 200])
def test_the_counter_after_the_loop(stop):
    src = f"""
void main() {{
    int n = {stop};
    int i;
    int s = 0;
    for (i = 5; i < n; i++) s += i;
    int j;
    for (j = 5; j <= n; j += 3) s += j;
    Print("%d %d %d", i, j, s);
}}
"""
    i = max(5, stop)
    js = list(range(5, stop + 1, 3))
    j = 5 + 3 * len(js)
    assert _run(src) == ([f"{i} {j} {sum(range(5, stop)) + sum(js)}"], [])


def test_a_step_known_positive_is_not_checked():
    src = """
void main() {
    int n = 0;
    for (int i = 1; i < 5; i++) {
        for (int k = 0; k < 100; k += i) n++;
    }
    Print("%d", n);
}
"""
    assert "_bad_step" not in _python_of(src)
    assert _run(src) == ([str(sum(len(range(0, 100, i)) for i in range(1, 5)))], [])


def test_a_step_that_may_be_zero_faults():
    src = """
void main() {
    int n = 0;
    for (int i = 0; i < 5; i++) {
        for (int k = 0; k < 100; k += i) n++;
    }
    Print("not reached");
}
"""
    assert "_bad_step" in _python_of(src)
    messages, faults = _run(src)
    assert messages == []
    assert len(faults) == 1 and "step is 0" in faults[0].message, faults
    assert faults[0].line == 5


ONE_CHUNK = [(5, "<", 9, 1), (5, "<=", 20, 3), (10, ">", 0, -4), (0, "<", 64, 1),
             (-3, ">=", -9, -1)]  # fmt: skip
"""(start, comparison, bound, step) of counting loops of 1 .. 64 values."""


def _c_loop(start: int, op: str, bound: int, inc: int) -> tuple[int, int]:
    """(the counter after the loop, the sum of its values), as C runs the loop."""
    i, s = start, 0
    holds = {"<": int.__lt__, "<=": int.__le__, ">": int.__gt__, ">=": int.__ge__}[op]
    while holds(i, bound):
        s += i
        i += inc
    return i, s


@pytest.mark.parametrize("start,op,bound,inc", ONE_CHUNK)
def test_a_loop_of_one_chunk_known_when_compiling_runs_without_chunks(start, op, bound, inc):
    step = f"i += {inc}" if inc > 0 else f"i -= {-inc}"
    loop = f"for (i = {start}; i {op} {bound}; {step}) s += i;"
    src = f"""
void main() {{
    int i;
    int s = 0;
    int k;
    {loop}
    Print("%d %d", i, s);
    for (k = 0; k < 3; k++) {{ {loop} }}
    Print("%d %d", i, s);
}}
"""
    py = _python_of(src)
    assert "_chunks" not in py and "len(" not in py
    i, s = _c_loop(start, op, bound, inc)
    assert _run(src) == ([f"{i} {s}", f"{i} {4 * s}"], [])


def test_a_loop_of_more_than_one_chunk_keeps_its_chunks():
    src = "void main() { int i; int s = 0; for (i = 0; i < 65; i++) s += i; }"
    assert "_chunks" in _python_of(src)


def test_a_constant_start_outside_the_counters_type_is_not_taken_as_known():
    # the unsigned counter starts at 4294967295: the loop runs no time and leaves it so
    src = 'void main() { unsigned int i; int s = 0; for (i = -1; i < 5; i++) s++; Print("%u %d", i, s); }'  # noqa: E501
    assert _run(src) == (["4294967295 0"], [])
