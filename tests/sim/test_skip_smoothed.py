"""Smoothed moves (`SetSMTime`) coast through the end of their T-curve and the flush of
the moving average in closed form, as stepping computes them.

Moves of several lengths (short ones end within the window) with smoothing of 3 to 60
cycles, on ideal drives with 0 to 3 cycles of delay, run skipping and stepping: the same
output with `--stamp` times (the reference, feedback and move time printed at each
status change and in between), the same final state of every axis; and the skipping run
jumps a few times per move, not once per cycle of the flush.
"""

from __future__ import annotations

import pytest
from skip_util import machine_file, outcome

PROGRAM = """
void main() {
    int k;
    Enable(0); Till(IsEnabled(0));
    SetSMTime(0, SMOOTH_MS);
    for (k = 0; k < 6; k++) {
        MoveAbs(0, k % 2 ? 0.0 : (k < 3 ? 100.0 : 0.4));
        Till(!IsMoving(0));
        Print("%d end %.12f %.12f %.3f", system_timeInMs, GetRefPos(0), GetPosFb(0), GetMoveTime(0));
        Till(IsInPos(0));
        Print("%d in %.12f %.12f", system_timeInMs, GetRefPos(0), GetPosFb(0));
    }
}
"""


def _outcome(tmp_path, sources, skip: bool, machine: str):
    """`outcome`, with the generator's own state: every field exactly as stepping
    leaves it (the flush count, the filter's ring, the segment)."""
    out = outcome(tmp_path, sources, skip, machine)
    from motionvm.api import Simulation

    paths = [tmp_path / f"t{i}.hmpl" for i in range(len(sources))]
    sim = Simulation.from_files(paths, skip=skip, machine=machine)
    sim.run(until=out[2])
    pg = sim.controller.motion.axes[0].pg
    fields = (pg._n, pg._flush, pg._tc_done, pg._idle, pg._seg_i, pg._seg_t_0, pg._seg_t_1,
              pg._seg_p_0, pg._seg_v_0, pg._seg_half_a, pg._j, pg._sum, tuple(pg._buf),
              pg.output, pg.mode)  # fmt: skip
    return out, fields


TICKER = "void main() { for (;;) Sleep(TICK); }"
"""A second task that wakes every TICK ms: jumps end inside the moves and their flush."""


@pytest.mark.parametrize("cycle_ms", [1.0, 0.5])
@pytest.mark.parametrize("delay", [0, 1, 3])
@pytest.mark.parametrize("sm", [3.0, 20.0, 60.0])
@pytest.mark.parametrize("tick", [0, 7, 13])
def test_smoothed_moves_coast_as_they_step(tmp_path, cycle_ms, delay, sm, tick):
    spec = (cycle_ms, [{"counts_per_unit": 10000.0, "delay": delay}])
    machine = machine_file(tmp_path, spec, 1)
    program = PROGRAM.replace("SMOOTH_MS", str(sm))
    if tick:
        program = program.replace("int k;", "int k;\n    StartTask(1);")
    src = [program] + ([TICKER.replace("TICK", str(tick))] if tick else [])
    jumped, stepped = (
        _outcome(tmp_path, src, True, machine),
        _outcome(tmp_path, src, False, machine),
    )
    assert jumped == stepped
    assert len(stepped[0][1]) == 12


def test_the_flush_of_a_smoothed_move_is_one_jump():
    from motionvm.api import Simulation

    sim = Simulation.from_source(PROGRAM.replace("SMOOTH_MS", "50.0"), skip=True)
    sim.run(timeout=10.0)
    assert len(sim.messages) == 12
    assert sim.controller.jumps.jumps < 12 * 8  # before: a jump per cycle of each flush
