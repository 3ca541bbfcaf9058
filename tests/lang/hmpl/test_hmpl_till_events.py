"""Till on an event: which conditions wait (the controller may jump past them), which poll.

A Till over axis status flags, digital I/O and the task's variables waits on an event;
a Till on `system_timeInMs >= X` sleeps until that time; anything else polls each
cycle. Whatever the lowering, the program's output is the same as stepping.
"""

from __future__ import annotations

import pytest
from hmpl_run import python_of

from motionvm.api import Simulation


@pytest.mark.parametrize("cond", [
    "IsInPos(a)", "IsInPos(0) && !IsMoving(1)", "IsEnabled(g + 1) == 1", "IsHomed(a) || IsErrorStop(2)",
    "HIMC_GPI(3) == 1", "!HIMC_GPO(0)", "g > 3 ? IsInPos(0) : IsInPos(1)",
])  # fmt: skip
def test_conditions_on_status_flags_wait_on_an_event(cond):
    text = python_of(f"Till({cond});")
    assert ("yield -2" in text and "yield -1" in text) or (
        "yield -4" in text and "yield -3" in text
    )


@pytest.mark.parametrize("cond", [
    "IsInPos(a)", "IsInPos(0) && !IsMoving(1)", "IsHomed(a) || IsErrorStop(2)",
    "IsEnabled(a + 1) == 1", "a > 3 ? IsInPos(0) : IsHomed(1)",
])  # fmt: skip
def test_conditions_on_axis_flags_and_locals_wait_on_the_flags_alone(cond):
    text = python_of(f"Till({cond});")
    assert "yield -4" in text and "yield -3" in text and "yield -2" not in text


@pytest.mark.parametrize("cond", [
    "IsEnabled(g + 1) == 1", "HIMC_GPI(3) == 1", "!HIMC_GPO(0)", "g > 3 ? IsInPos(0) : IsInPos(1)",
    "IsHoming(a)", "IsInPos(0) && !IsHoming(0)",
])  # fmt: skip
def test_conditions_on_globals_or_io_wait_on_an_event_of_any_status(cond):
    text = python_of(f"Till({cond});")
    assert "yield -2" in text and "yield -1" in text and "yield -4" not in text


@pytest.mark.parametrize("cond", [
    "GetPosFb(0) > GetRefPos(0)", "f()", "IsInPos(a++)", "system_timeInMs > 5 && IsInPos(0)",
    "system_fclk > 10", "IsInPos(0) && GetVelFb(0) == 0.0",
])  # fmt: skip
def test_other_conditions_poll(cond):
    text = python_of(f"Till({cond});")
    assert "yield -" not in text and "_till_ms" not in text and "yield\n" in text


@pytest.mark.parametrize("cond", ["system_timeInMs >= t", "t + 5 < system_timeInMs"])
def test_a_time_comparison_sleeps_until_that_time(cond):
    assert "yield _till_ms(" in python_of(f"Till({cond});")


@pytest.mark.parametrize("cond", ["GetPosFb(0) > 5.0", "g <= GetPosFb(a)", "GetPosFb(a + 1) < -t"])
def test_a_position_comparison_tells_the_controller_the_position(cond):
    text = python_of(f"Till({cond});")
    assert "yield _till_pos(" in text and "yield\n" not in text


def _run(src: str, skip: bool):
    sim = Simulation.from_source(src, skip=skip, stamp=True)
    sim.run(timeout=30.0)
    return sim.messages, sim.time, sim.controller.cycles_computed


WAIT_PROGRAM = """
void main() {
    int i;
    Enable(0); Till(IsEnabled(0));
    for (i = 0; i < 6; i++) {
        MoveAbs(0, i % 2 ? 0.0 : 100.0);
        Till(IsInPos(0));
        Print("%d %.9f", system_timeInMs, GetPosFb(0));
    }
}
"""


def test_a_wait_on_in_position_computes_few_cycles_and_prints_the_same():
    jumped, stepped = _run(WAIT_PROGRAM, True), _run(WAIT_PROGRAM, False)
    assert jumped[:2] == stepped[:2]
    assert stepped[2] == round(stepped[1] / 0.001)
    assert jumped[2] < 0.05 * stepped[2]


def test_time_waits_wake_at_the_cycle_the_time_passes():
    src = """int t;
void main() {
    t = system_timeInMs + 250; Till(system_timeInMs >= t); Print("%d", system_timeInMs);
    Till(700 < system_timeInMs); Print("%d", system_timeInMs);
    Till(system_timeInMs >= -5); Print("%d", system_timeInMs);
    Till(system_timeInMs > 2147483647); Print("never");
}
"""
    sim = Simulation.from_source(src)
    sim.run(until=1.5)
    assert sim.messages == ["250", "701", "701"]
    assert (
        _run(src.replace('Print("never");', ""), True)[:2]
        == _run(src.replace('Print("never");', ""), False)[:2]
    )


SHARED_FLAG = """
int go;
void main() {
    StartTask(1);
    Enable(0); Till(IsEnabled(0));
    Till(IsInPos(0) && go == 1);
    Print("%d released", system_timeInMs);
    MoveAbs(0, 50.0);
    Till(!IsMoving(0) || go == 2);
    Print("%d %d moving %d", system_timeInMs, go, IsMoving(0));
}
"""
SHARED_FLAG_1 = """
void main() {
    Sleep(30); go = 1; Sleep(1); Till(IsMoving(0)); Sleep(7); go = 2;
}
"""


def test_a_variable_set_by_another_task_ends_a_wait_on_an_event_at_once(tmp_path):
    paths = []
    for i, text in enumerate((SHARED_FLAG, SHARED_FLAG_1)):
        p = tmp_path / f"t{i}.hmpl"
        p.write_text(text, encoding="utf-8")
        paths.append(p)
    runs = []
    for skip in (True, False):
        sim = Simulation.from_files(paths, skip=skip, stamp=True)
        sim.run(timeout=10.0)
        runs.append(sim.messages)
    assert runs[0] == runs[1]
    assert runs[0][0].endswith(" 32 released")  # task 1 runs from cycle 1, sets go at 31


def test_a_variable_the_host_writes_between_runs_is_seen(tmp_path):
    src = 'int go;\nvoid main() { Till(IsInPos(0) || go); Print("%d go", system_timeInMs); }\n'
    outs = []
    for skip in (True, False):
        sim = Simulation.from_source(src, skip=skip)
        sim.run(until=0.2)
        sim.write("go", 1)
        sim.run(until=0.5)
        outs.append(sim.messages)
    assert outs[0] == outs[1] == ["200 go"]


def test_no_client_of_a_plain_program_keeps_moving_axes_from_jumping():
    """A program without sensors, bound outputs, servers or armed triggers has only
    clients that do not read moving axes: the controller may coast them."""
    sim = Simulation.from_source(WAIT_PROGRAM, skip=True)
    observing = [
        type(c).__name__ for c in sim.controller.clients if getattr(c, "observes_motion", True)
    ]
    assert observing == []
