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
