"""Deferred axes stay deferred while the run only asks whether it is busy.

Once a program's tasks end, the run loop asks the motion kernel every cycle whether an
axis still moves (`MotionKernel.busy`). For axes on a positioning move the status flags
answer that (motion/deferred.py, `Deferrals.one_busy`): the axes are not brought up to
date every cycle (which cost a closed-form advance of every axis each cycle, five times
a stepped cycle). A jog may reach its velocity inside a deferred stretch (`cruising`,
which ends a run): the kernel still brings it up to date to answer. A jog that can
never cruise (its software limits on, or a hardware limit switch ahead of it that is
checked: it ends on that limit) is answered by its flags too. Both runs end as stepping
ends.
"""

from __future__ import annotations

import pytest

from motionvm.api import Simulation
from motionvm.lang.hmpl.compiler import TaskFile
from motionvm.sim.machine import MachineConfig, default_axes

AXES = 4
MOVES = f"""
void main() {{
    int a;
    for (a = 0; a < {AXES}; a++) {{ SetVel(a, 100.0); Enable(a); }}
    for (a = 0; a < {AXES}; a++) Till(IsEnabled(a));
    for (a = 0; a < {AXES}; a++) MoveAbs(a, 150.0 + 10.0 * a);
}}
"""
JOG = """
void main() {
    SetRollover(0, 360.0);
    IgnoreHWL(0, 1);
    SetVel(0, 50.0); SetAcc(0, 200.0); SetDec(0, 200.0);
    Enable(0);
    Till(IsEnabled(0));
    MoveVel(0, 1);
}
"""

LIMITED_JOG = """
void main() {
    SetVel(0, 50.0); SetAcc(0, 200.0); SetDec(0, 200.0);
    Enable(0);
    Till(IsEnabled(0));
    MoveVel(0, 1);
}
"""

TOWARD_SWITCH = LIMITED_JOG.replace("Enable(0);", "IgnoreSWL(0, 1); Enable(0);")


def _run(
    program: str, defer: bool, axes: int = AXES, timeout: float = 10.0
) -> tuple[tuple, int, str, float]:
    sim = Simulation(
        [TaskFile(0, "p.hmpl", program)],
        machine=MachineConfig(axes=default_axes(axes)),
        skip=False,
    )
    sim.controller.defer_axes = defer
    result = sim.run(timeout=timeout)
    state = tuple(
        (a.pos_fb, a.ref_pos, a.ref_vel, a.in_pos, a.moving, a._cycle, a.move_time_ms)
        for a in sim.controller.motion.axes
    )
    return state, sim.controller.motion.deferred.batches, str(result), sim.time


def test_moves_after_the_tasks_end_stay_deferred_and_end_as_stepped():
    stepped = _run(MOVES, defer=False)
    deferred = _run(MOVES, defer=True)
    assert deferred[0] == stepped[0] and deferred[2:] == stepped[2:]
    cycles = round(deferred[3] * 1000)
    assert cycles > 1000  # (the moves take over a second)
    assert 0 < deferred[1] < cycles // 20  # not a catch-up per axis and cycle


def test_a_jog_after_the_tasks_end_runs_as_stepped():
    stepped = _run(JOG, defer=False, axes=1, timeout=2.0)
    deferred = _run(JOG, defer=True, axes=1, timeout=2.0)
    assert deferred[0] == stepped[0] and deferred[2:] == stepped[2:]
    assert "reason='finished'" in stepped[2] and stepped[3] < 1.0  # it cruises: the run ends


@pytest.mark.parametrize("program", [LIMITED_JOG, TOWARD_SWITCH], ids=["swl", "hw-switch"])
def test_a_jog_that_never_cruises_stays_deferred_and_ends_as_stepped(program):
    # it jogs toward a limit for the whole run: until then the axis stays deferred, where
    # a catch-up each cycle made the run slower than stepping
    stepped = _run(program, defer=False, axes=1, timeout=4.0)
    deferred = _run(program, defer=True, axes=1, timeout=4.0)
    assert deferred[0] == stepped[0] and deferred[2:] == stepped[2:]
    cycles = round(deferred[3] * 1000)
    assert stepped[0][0][4] and cycles >= 4000  # still jogging at the end
    assert 0 < deferred[1] < cycles // 100
