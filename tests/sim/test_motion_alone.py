"""Cycles of the motion kernel alone (`Controller._motion_alone`) give the stepped run.

While stepping, a cycle in which no task is due and no client has anything to do but
write the clock's values runs as the motion kernel's phase alone, many in a row
(`MotionKernel.step_alone`). The random programs of test_skip_random.py (moves, jogs,
sleeps, waits of every kind, on random machines) run stepping with and without that:
outputs, end time, every axis's state and the cycles computed must be identical, with
deferred axes and without. Runs that end by a time, by their tasks and axes coming to
rest, or with a progress callback end at the same cycle; the HMPL system time shows
the same value after a run that ended inside such a stretch.
"""

from __future__ import annotations

from pathlib import Path

from hypothesis import given
from hypothesis import strategies as st
from skip_util import axis_states, machine_file, task_files
from test_skip_random import AXES, PROFILE, _task, machine, statement

from motionvm.api import Simulation
from motionvm.lang.hmpl.compiler import TaskFile
from motionvm.sim.machine import MachineConfig, default_axes


def _axes(sim: Simulation) -> list:
    """`axis_states` and the cycle each axis counts."""
    axes = sim.controller.motion.axes
    return [s + (a._cycle,) for s, a in zip(axis_states(sim), axes, strict=True)]


def _outcome(tmp: Path, sources: list[str], alone: bool, defer: bool, machine=None) -> tuple:
    sim = Simulation.from_files(task_files(tmp, sources), skip=False, stamp=True, machine=machine)
    ctl = sim.controller
    ctl.alone_cycles, ctl.defer_axes = alone, defer
    result = sim.run(timeout=60.0)
    alone_cycles = ctl.cycles_alone
    assert alone or alone_cycles == 0
    return (
        str(result),
        list(sim.messages),
        sim.time,
        _axes(sim),
        ctl.cycles_computed,
    ), alone_cycles


@PROFILE
@given(st.lists(statement, min_size=1, max_size=12), st.lists(statement, max_size=8), st.booleans())
def test_motion_alone_gives_the_stepped_run(tmp_path_factory, body_0, body_1, defer):
    tmp = tmp_path_factory.mktemp("alone")
    sources = [_task(body_0, True), _task(body_1, False)]
    alone, _ = _outcome(tmp, sources, True, defer)
    stepped, _ = _outcome(tmp, sources, False, defer)
    assert alone == stepped


@PROFILE
@given(machine, st.lists(statement, min_size=1, max_size=10), st.lists(statement, max_size=6))
def test_motion_alone_gives_the_stepped_run_on_random_machines(tmp_path_factory, spec, body_0,
                                                               body_1):  # fmt: skip
    tmp = tmp_path_factory.mktemp("alone-machine")
    m = machine_file(tmp, spec, AXES)
    sources = [_task(body_0, True), _task(body_1, False)]
    assert _outcome(tmp, sources, True, False, m)[0] == _outcome(tmp, sources, False, False, m)[0]


MOVES = """
int t;
void main() {
    int a;
    for (a = 0; a < 4; a++) { SetVel(a, 100.0 + 20.0 * a); Enable(a); }
    for (a = 0; a < 4; a++) Till(IsEnabled(a));
    for (a = 0; a < 4; a++) MoveAbs(a, 150.0 + 10.0 * a);
    Sleep(700);
    t = system_timeInMs;
    MoveAbs(0, 0.0);
}
"""


def _moves(alone: bool, defer: bool = False, **run) -> tuple:
    sim = Simulation(
        [TaskFile(0, "p.hmpl", MOVES)], machine=MachineConfig(axes=default_axes(4)), skip=False
    )
    ctl = sim.controller
    ctl.alone_cycles, ctl.defer_axes = alone, defer
    reports: list[float] = []
    if run.pop("report", False):  # (the controller's own run: the API has no progress)
        sim.run(until=0.002)
        result = ctl.run(until=run["until"], progress=reports.append, progress_every=50)
    else:
        result = sim.run(**run)
    clock = (sim.read("system_timeInMs"), sim.read("system_fclk"), sim.read("t"))
    passed = ctl.motion.deferred.passed
    assert defer or passed == 0
    return (getattr(result, "reason", result), sim.time, _axes(sim), ctl.cycles_computed, clock,
            reports, ctl.cycles_alone, passed)  # fmt: skip


def test_a_sleeping_task_and_moving_axes_step_alone_until_it_wakes_and_the_axes_rest():
    for defer in (False, True):
        alone, stepped = _moves(True, defer, timeout=10.0), _moves(False, defer, timeout=10.0)
        assert alone[:6] == stepped[:6]
        assert alone[0] == "finished"
        cycles = alone[3]
        assert cycles > 1400 and alone[6] > 0.9 * cycles  # the sleep and the last move
        assert stepped[6] == stepped[7] == 0
        if defer:  # most of them only counted (`Deferrals.pass_idle`)
            assert alone[7] > 0.8 * cycles


def test_a_run_ending_inside_a_stretch_ends_at_its_time_with_the_clock_shown():
    for until in (0.3, 0.9, 1.3):  # (asleep, axes moving; after the wake; one moving)
        alone, stepped = _moves(True, until=until), _moves(False, until=until)
        assert alone[:6] == stepped[:6]
        assert alone[1] == until and alone[6] > 0
        assert alone[4][0] == round(until * 1000)  # (`show_clock`: the clock as it is)


def test_progress_reports_come_at_the_same_cycles():
    alone = _moves(True, until=2.5, report=True)
    stepped = _moves(False, until=2.5, report=True)
    assert alone[:6] == stepped[:6] and len(alone[5]) > 10 and alone[6] > 0
