"""Deferred axis cycles (motion/deferred.py) give the run every axis stepped gives.

The random programs of test_skip_random.py (moves, jogs, stops, speed changes,
smoothing, SetPos, rollover, limits, waits, prints of the feedback) run stepping, with
and without deferring the axes: the outputs and every axis's final
state must be identical. The stepping benchmark's program (tasks polling IsInPos
every cycle and moving the axes on) defers, and ends as stepping every axis does.
"""

from __future__ import annotations

import sys
from pathlib import Path

from hypothesis import given
from hypothesis import strategies as st
from skip_util import task_files
from test_skip_random import PROFILE, _task, statement

from motionvm.api import Simulation

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "bench"))
import motion as bench_motion  # noqa: E402


def _outcome(tmp: Path, sources: list[str], skip: bool, defer: bool) -> tuple:
    sim = Simulation.from_files(task_files(tmp, sources), skip=skip, stamp=True)
    sim.controller.defer_axes = defer
    result = sim.run(timeout=60.0)
    axes = [(a.pos_fb, a.ref_pos, a.ref_vel, a.ref_acc, a.in_pos, a.moving, a.move_time_ms,
             a.settling_time_ms, a.last_error, a.resting, a._cycle, a.drive.position_actual,
             a.drive.digital_inputs, a.drive.mechanics.velocity, a.drive.mechanics.torque)
            for a in sim.controller.motion.axes]  # fmt: skip
    return str(result), list(sim.messages), sim.time, axes, sim.controller.motion.deferred.lagging


@PROFILE
@given(st.lists(statement, min_size=1, max_size=12), st.lists(statement, max_size=8))
def test_deferring_gives_the_stepped_run(tmp_path_factory, body_0, body_1):
    tmp = tmp_path_factory.mktemp("defer")
    sources = [_task(body_0, True), _task(body_1, False)]
    # (skipping with deferral against stepping with it: test_skip_random.py)
    assert _outcome(tmp, sources, False, True) == _outcome(tmp, sources, False, False)


def _bench_end(defer: bool) -> tuple:
    sim = bench_motion.simulation(8)
    sim.controller.defer_axes = defer
    sim.run(until=0.6)
    deferred = sim.controller.motion.deferred
    axes = sim.controller.motion.axes
    end = tuple((a.pos_fb, a.ref_pos, a.in_pos, a.moving, a._cycle, a.pg._n) for a in axes)
    return end, deferred.lagging, deferred.batches


def test_the_polling_benchmark_defers_and_ends_as_stepped():
    stepped, _, none = _bench_end(False)
    deferred, lagging, batches = _bench_end(True)
    assert deferred == stepped
    assert none == 0 and batches > 8
    assert lagging == {}  # (the run's end brought them up to date)


def test_a_program_reading_axes_otherwise_does_not_defer(tmp_path):
    body = ["MoveAbs(0, 200.0);", "p_1 = 100.0; Till(GetPosFb(0) >= p_1);"]
    sim = Simulation.from_files(
        [_write(tmp_path, _task(body, True)), _write(tmp_path, _task([], False), 1)]
    )
    assert sim.controller.kernel.reads_axes  # (a Till on a position)
    sim2 = bench_motion.simulation(2)
    assert not sim2.controller.kernel.reads_axes


def _write(tmp: Path, text: str, i: int = 0) -> Path:
    p = tmp / f"p{i}.hmpl"
    p.write_text(text, encoding="utf-8")
    return p


POLLING = """
int n;
void main() {
    int i;
    for (i = 0; i < 3; i++) Enable(i);
    for (i = 0; i < 3; i++) Till(IsEnabled(i));
    SetSMTime(2, 20.0);
    for (n = 0; n < 900; n++) {
        for (i = 0; i < 3; i++) {
            if (IsInPos(i)) MoveRel(i, i == 1 ? -37.5 : 120.25);
        }
        if (n % 97 == 13) Print("%d %.9f %.9f %d", n, GetPosFb(n % 3), GetRefVel(1), IsMoving(2));
        if (n == 300) SetVel(0, 55.0);
        if (n == 420) Stop(1);
        RunScheduler();
    }
}
"""


def test_getters_and_commands_mid_move_see_the_stepped_axis(tmp_path):
    """A task polling every cycle that reads positions and changes moves now and then:
    each read and command catches its axis up; the run is the stepped one."""
    runs = [_outcome(tmp_path, [POLLING], skip, defer) for skip, defer in
            ((False, False), (False, True), (True, True))]  # fmt: skip
    assert runs[1] == runs[0]
    assert runs[2][:4] == runs[0][:4]
    assert len(runs[0][1]) == 10
