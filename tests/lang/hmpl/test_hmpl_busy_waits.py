"""Busy loops that only wait: `while (c);` and `while (c) RunScheduler();`.

Nothing else runs in a task's slice, so a condition that changes nothing is decided by
its first test in each cycle: spinning to the end of the slice shows a program nothing
more. Such a loop polls once per cycle, and if its condition waits on an event (axis
status flags, I/O, the task's variables) it is lowered as `Till(!c)`: the controller may
jump past it. Each case here is checked against the same wait written as a loop that
does something (`a = a;`), which keeps the budgeted spin of any other loop.
"""

from __future__ import annotations

import pytest
from hmpl_run import python_of

from motionvm.api import Simulation


@pytest.mark.parametrize("loop", [
    "while (!IsInPos(a));", "while (!IsInPos(a)) {}", "while (!IsInPos(a)) RunScheduler();",
    "while (!IsInPos(a)) { RunScheduler(); }", "while (IsMoving(0) || !IsInPos(a)) ;",
])  # fmt: skip
def test_a_loop_that_waits_on_axis_flags_is_a_status_wait(loop):
    text = python_of(loop)
    assert "yield -4" in text and "yield -3" in text
    assert "_budget -=" not in text  # no budgeted spin


@pytest.mark.parametrize("loop", ["while (g == 0);", "while (!HIMC_GPI(3)) RunScheduler();"])
def test_a_loop_that_waits_on_globals_or_inputs_is_an_event_wait(loop):
    text = python_of(loop)
    assert "yield -2" in text and "yield -1" in text


@pytest.mark.parametrize("loop", ["do ; while (!IsInPos(a));", "do {} while (!IsInPos(a));"])
def test_an_empty_do_loop_is_the_same_wait(loop):
    text = python_of(loop)
    assert "yield -4" in text and "yield -3" in text and "yield\n" not in text


def test_a_do_loop_that_yields_first_yields_then_waits():
    text = python_of("do RunScheduler(); while (!IsInPos(a));")
    body = text.split("def g_main")[1]
    assert body.index("yield\n") < body.index("yield -4") and "_budget -=" not in body


@pytest.mark.parametrize("loop", ["while (1);", "for (;;);", "for (;;) RunScheduler();"])
def test_a_loop_forever_waits_on_no_flag(loop):
    assert "yield -4" in python_of(loop)


def test_a_loop_on_a_group_flag_is_a_status_wait():
    assert "yield -4" in python_of("while (!IsGrpInPos(0)) RunScheduler();")
    assert "yield -4" in python_of("while (IsGrpMoving(a) || !IsGrpEnabled(1));")


def test_a_for_loop_that_only_waits_is_a_wait():
    assert "yield -4" in python_of("for (; !IsInPos(a);) {}")
    assert "_budget -=" in python_of("for (; !IsInPos(a); a = a) {}")


@pytest.mark.parametrize("loop", ["while (system_timeInMs < t);", "while (t > system_timeInMs) {}",
                                  "while (system_timeInMs <= t + 5) RunScheduler();"])  # fmt: skip
def test_a_loop_until_a_time_sleeps_until_that_time(loop):
    assert "yield _till_ms(" in python_of(loop)


@pytest.mark.parametrize("loop", ["while (GetPosFb(0) < 5.0);", "while (5.0 < GetPosFb(a)) {}"])
def test_a_loop_until_a_position_tells_the_controller_the_position(loop):
    text = python_of(loop)
    assert "yield _till_pos(" in text and "_budget -=" not in text


@pytest.mark.parametrize("loop", ["while (GetPosFb(0) < GetRefPos(0));", "while (system_fclk < t) {}",
                                  "while (GetVelFb(a) != 0.0 || !IsInPos(a));",
                                  "while (GetRefVel(0) != 0.0) RunScheduler();"])  # fmt: skip
def test_a_loop_on_other_reads_polls_once_per_cycle(loop):
    text = python_of(loop)
    assert "yield\n" in text and "yield -" not in text
    assert "_budget -=" not in text


@pytest.mark.parametrize("loop", [
    "while (a++ < 5);", "while (f());", "while (g < 5) g++;",
    "while (!IsInPos(0)) { RunScheduler(); g = 1; }", "while (!IsInPos(0)) Sleep(1);",
    "while ((g = IsInPos(0)) == 0);", "for (a = 0; !IsInPos(0);) {}", "do g++; while (!IsInPos(0));",
])  # fmt: skip
def test_a_loop_that_does_something_keeps_its_budgeted_spin(loop):
    assert "_budget -=" in python_of(loop)


PROGRAM = """
int g;
void main() {
    int i, a = 0;
    Enable(0); WAIT_ENABLED
    for (i = 0; i < 4; i++) {
        MoveAbs(0, i % 2 ? 0.0 : 60.0);
        WAIT_IN_POS
        Print("%d %.9f %d", system_timeInMs, GetPosFb(0), IsMoving(0));
    }
    g = system_timeInMs + 123;
    WAIT_TIME
    Print("%d", system_timeInMs);
}
"""
IDIOMS = {
    "empty": ("while (!IsEnabled(0));", "while (!IsInPos(a));", "while (system_timeInMs < g);"),
    "braces": ("while (!IsEnabled(0)) {}", "while (!IsInPos(a)) {}", "while (system_timeInMs < g) {}"),
    "yield": ("while (!IsEnabled(0)) RunScheduler();", "while (!IsInPos(a)) RunScheduler();",
              "while (system_timeInMs < g) RunScheduler();"),
    "do": ("do ; while (!IsEnabled(0));", "do {} while (!IsInPos(a));",
           "do RunScheduler(); while (system_timeInMs < g);"),
}  # fmt: skip
SPIN = ("while (!IsEnabled(0)) { a = a; }", "while (!IsInPos(a)) { a = a; }",
        "while (system_timeInMs < g) { a = a; }")  # fmt: skip
"""The same waits as loops that do something: the budgeted spin of any loop."""


def _program(waits: tuple[str, str, str]) -> str:
    text = PROGRAM
    for key, loop in zip(("WAIT_ENABLED", "WAIT_IN_POS", "WAIT_TIME"), waits):
        text = text.replace(key, loop)
    return text


def _run(src: str, skip: bool):
    sim = Simulation.from_source(src, skip=skip, stamp=True)
    sim.run(timeout=30.0)
    a = sim.controller.motion.axes[0]
    return (sim.messages, sim.time, a.pos_fb, a.in_pos), sim.controller.cycles_computed


@pytest.mark.parametrize("idiom", sorted(IDIOMS))
def test_a_waiting_loop_runs_as_the_spinning_one_and_skips(idiom):
    spun, spun_cycles = _run(_program(SPIN), False)
    assert spun_cycles == round(spun[1] / 0.001)
    assert len(spun[0]) == 5
    stepped, stepped_cycles = _run(_program(IDIOMS[idiom]), False)
    jumped, jumped_cycles = _run(_program(IDIOMS[idiom]), True)
    assert stepped == jumped == spun
    assert stepped_cycles == spun_cycles
    assert jumped_cycles < 0.05 * stepped_cycles  # waits on events: the clock jumps


def test_a_parked_task_lets_the_clock_jump():
    """`while (1);` at the end of a task, a common way to park it: nothing is polled."""
    src = 'void main() { Print("parked"); while (1); }'
    sim = Simulation.from_source(src, skip=True)
    sim.run(until=60.0)
    assert sim.messages == ["parked"]
    assert sim.time == pytest.approx(60.0)
    assert sim.controller.cycles_computed < 10
