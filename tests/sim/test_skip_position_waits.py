"""Waits on an axis's position feedback let the clock jump to the cycle it is reached.

`Till(GetPosFb(a) >= x)` (and >, <=, <, the operands either way, `|| <event>`, and
the busy loop `while (GetPosFb(a) < x);`) polls once per cycle as any `Till`; a jump
over cycles nobody computes ends after the cycle in which the feedback reaches x, so
the task sees it in the same cycle as stepping. The same program runs skipping and
stepping and must print the same, with `--stamp` times; the random programs of
test_skip_random.py wait on positions too.
"""

from __future__ import annotations

import pytest

from motionvm.api import Simulation

PROGRAM = """
void main() {
    int i;
    Enable(0); Till(IsEnabled(0));
    for (i = 0; i < 3; i++) {
        MoveAbs(0, 100.0);
        WAIT_UP_10 Print("a %d %.9f", system_timeInMs, GetPosFb(0));
        Till(GetPosFb(0) > 50.0); Print("b %d %.9f", system_timeInMs, GetPosFb(0));
        Till(99.99 <= GetPosFb(0)); Print("c %d %.9f", system_timeInMs, GetPosFb(0));
        Till(IsInPos(0));
        MoveAbs(0, -20.0);
        Till(GetPosFb(0) <= 30.0 || IsInPos(1)); Print("d %d %.9f", system_timeInMs, GetPosFb(0));
        Till(GetPosFb(0) < -19.999999); Print("e %d %.9f", system_timeInMs, GetPosFb(0));
        Till(IsInPos(0));
        MoveAbs(0, 0.0);
        Till(GetPosFb(0) >= 0.0); Print("f %d %.9f", system_timeInMs, GetPosFb(0));
        Till(GetPosFb(0) >= 200.0 || !IsMoving(0)); Print("g %d %.9f", system_timeInMs, GetPosFb(0));
    }
}
"""


def _run(src: str, skip: bool):
    sim = Simulation.from_source(src, skip=skip, stamp=True)
    sim.run(timeout=30.0)
    return sim.messages, sim.time, sim.faults, sim.controller.cycles_computed


@pytest.mark.parametrize("wait", ["Till(GetPosFb(0) >= 10.0);", "while (GetPosFb(0) < 10.0);",
                                  "while (10.0 > GetPosFb(0)) RunScheduler();"])  # fmt: skip
def test_position_waits_print_the_same_and_jump(wait):
    src = PROGRAM.replace("WAIT_UP_10", wait)
    jumped, stepped = _run(src, True), _run(src, False)
    assert jumped[:3] == stepped[:3]
    assert len(stepped[0]) == 21 and not stepped[2]
    assert jumped[3] < 0.05 * stepped[3]


def test_a_position_never_reached_keeps_the_clock_jumping():
    src = """void main() {
    Enable(0); Till(IsEnabled(0)); MoveAbs(0, 10.0);
    Till(GetPosFb(0) >= 10.5); Print("never");
}"""
    jumped, stepped = _run(src, True), _run(src, False)
    assert jumped[:3] == stepped[:3]
    assert jumped[3] < 100
