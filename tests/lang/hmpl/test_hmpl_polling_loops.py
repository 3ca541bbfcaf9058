"""Polling loops end their task's slice at the first iteration that changes nothing.

A loop forever, or one that reads the machine (`READ_BUILTINS`), compares at its back-edge
the locals its body writes with those of the back-edge before; if they are the same and
no statement that may act ran, every further iteration of the slice would repeat this
one, so the task yields at once, with the loop's countdown as the spin leaves it. Each
program here runs against the same program looping on a call of its own function
(`while (yes())`: a condition that may act, so the loop keeps its plain spin), and must
print the same, cycle for cycle: the number of iterations a slice runs while the loop
works shows in the counts printed.
"""

from __future__ import annotations

import pytest
from hmpl_run import python_of

from motionvm.api import Simulation

SCAN = """
int yes() { return 1; }
void main() {
    int n = 0, last = 0, edges = 0;
    while (FOREVER) {
        int in = GetGPI(1);
        if (in) n++;
        if (in != last) {
            edges++;
            SetGPO(2, in);
            Print("%d edge %d n=%d gpo=%d", system_timeInMs, in, n, GetGPO(2));
            last = in;
        }
    }
}
"""
STATE_MACHINE = """
int yes() { return 1; }
void main() {
    int state = 0, count = 0;
    for (; FOREVER;) {
        switch (state) {
        case 0:
            if (GetGPI(1)) { state = 1; Print("%d start", system_timeInMs); }
            break;
        case 1:
            count++;
            if (count >= 3000) { state = 2; Print("%d counted", system_timeInMs); }
            break;
        default:
            if (!GetGPI(1)) { state = 0; count = 0; Print("%d reset", system_timeInMs); }
        }
    }
}
"""
GLOBAL_COUNT = """
int hits;
int yes() { return 1; }
void main() {
    int last = 0;
    while (FOREVER) {
        int in = GetGPI(1);
        if (in) hits++;
        if (in != last) { Print("%d edge %d hits=%d", system_timeInMs, in, hits); last = in; }
    }
}
"""
"""While the input is on, only a global changes: each iteration acts (the marker)."""
SKIP_ON_OFF = """
int yes() { return 1; }
void main() {
    int last = 0, n = 0;
    while (FOREVER) {
        int in = GetGPI(1);
        if (!in) { last = 0; continue; }
        n++;
        if (!last) Print("%d on n=%d", system_timeInMs, n);
        last = in;
    }
}
"""
"""A `continue` ends the quiet iterations: it checks for a fixed point as the back-edge."""
TOGGLES = [(0.0105, 1), (0.0123, 0), (0.0301, 1), (0.0302, 0), (0.0450, 1), (0.0702, 0)]


def _run(src: str, skip: bool) -> tuple[list[str], int]:
    sim = Simulation.from_source(src, skip=skip, stamp=True)
    for t, value in TOGGLES:
        sim.run(until=t)
        sim.set_input(1, bool(value))
    sim.run(until=0.1)
    return sim.messages, sim.controller.cycles_computed


@pytest.mark.parametrize(
    "program",
    [SCAN, STATE_MACHINE, GLOBAL_COUNT, SKIP_ON_OFF],
    ids=["scan", "state_machine", "global_count", "continue"],
)
@pytest.mark.parametrize("skip", [False, True])
def test_a_polling_loop_runs_as_the_spinning_one(program, skip):
    fast = _run(program.replace("FOREVER", "1"), skip)[0]
    spun = _run(program.replace("FOREVER", "yes()"), skip)[0]
    assert fast == spun
    assert len(fast) >= 2


def test_the_scan_counts_the_iterations_of_whole_slices():
    """While the input is on the loop works every iteration (n grows): the slice runs
    its whole budget, so the counts printed depend on where each slice ends."""
    lines = _run(SCAN.replace("FOREVER", "1"), False)[0]
    counts = [int(x.split("n=")[1].split()[0]) for x in lines]
    assert counts[1] > 2000  # two cycles with the input on: whole slices


def test_a_polling_loop_lowers_with_the_fixed_point_check():
    text = python_of(
        "int last = 0; while (1) { int in = GetGPI(4); if (in && !last) DisableAll(); last = in; }"
    )
    assert "!= (v_last,)" in text  # `in` is declared in the body: it lives one iteration
    assert text.count("= 1\n") >= 2  # the marker before the loop and before DisableAll


def test_a_continue_checks_for_a_fixed_point():
    text = python_of("while (1) { if (!GetGPI(1)) continue; DisableAll(); }")
    assert text.count("!= ()") == 2  # at the `continue` and at the back-edge


@pytest.mark.parametrize("loop", [
    "int i = 0; while (i < 100) i++;",  # a loop that reads nothing of the machine
    "int i; for (i = 0; GetGPI(1); i++) {}",  # a step: never the same locals
    "while (f()) {}",  # a condition that may act
])  # fmt: skip
def test_other_loops_keep_the_plain_back_edge(loop):
    assert " != (" not in python_of(loop)


SLAVE_MACHINE = """axes = 1
[[slave]]
kind = "digital"
inputs = 4
outputs = 4
"""
SLAVE_SCAN = """
int yes() { return 1; }
void main() {
    int last = 0, edges = 0;
    while (FOREVER) {
        int in = GetSlvGPI(1, 3);
        if ((in ^ last) && !in) {
            edges++;
            ToggleSlvGPO(1, 2);
            Print("%d falling %d: outputs %d", system_timeInMs, edges, GetSlvAllGPO(1));
        }
        last = in;
    }
}
"""


def test_a_loop_polling_a_slave_input_jumps_and_runs_as_its_spin(tmp_path):
    """The manual's 9.1.2 example 2: slave inputs are events of the jumps too."""
    machine = tmp_path / "machine.toml"
    machine.write_text(SLAVE_MACHINE, encoding="utf-8")
    runs = {}
    for forever, skip in (("1", True), ("1", False), ("yes()", False)):
        sim = Simulation.from_source(
            SLAVE_SCAN.replace("FOREVER", forever), skip=skip, stamp=True, machine=str(machine)
        )
        for t, value in TOGGLES:
            sim.run(until=t)
            sim.set_input("slv1.di3", bool(value))
        sim.run(until=0.1)
        runs[forever, skip] = (sim.messages, sim.controller.cycles_computed)
    assert runs["1", True][0] == runs["1", False][0] == runs["yes()", False][0]
    assert len(runs["1", True][0]) == 2
    assert runs["1", True][1] < 30  # of 100: the clock jumps between the input changes
