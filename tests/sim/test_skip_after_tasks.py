"""A jump may open in the motion phase of a computed cycle: after the tasks that issued
a move, the axes are advanced in closed form from that very cycle on (sim/jumps.py,
`JumpPlanner.jump(..., after_tasks=True)`), with the same output as stepping."""

from __future__ import annotations

import pytest

from motionvm.api import Simulation

MOVER = """void main() {
    int k;
    Enable(0); Till(IsEnabled(0));
    for (k = 0; k < 10; k++) {
        MoveAbs(0, k % 2 ? 0.0 : 100.0);
        Till(IsInPos(0));
    }
    Print("%d %.6f", system_timeInMs, GetPosFb(0));
}"""


def _stepped_cycles(sim: Simulation) -> list[int]:
    """Run `sim`; return the cycles whose motion phase the controller stepped."""
    ctl = sim.controller
    motion = ctl.motion
    step = motion.step
    cycles = []

    def recording() -> None:
        cycles.append(ctl.clock.cycle)
        step()

    motion.step = recording  # an instance attribute: only this run records
    sim.run(timeout=10.0)
    return cycles


def test_the_cycle_that_starts_a_move_is_not_stepped():
    skipping = Simulation.from_source(MOVER)
    stepping = Simulation.from_source(MOVER, skip=False)
    stepped = _stepped_cycles(skipping)
    assert len(_stepped_cycles(stepping)) == 2030
    assert skipping.messages == stepping.messages == ["2029 0.000000"]
    # cycles 0-9 enable the axis and start the first move (the drive settles in them);
    # each of the nine moves after it coasts from the cycle that starts it, so no move
    # costs a stepped motion phase: only the last cycle (the Print, the task's end) is
    assert stepped == [*range(10), 2029]


def test_session_step_is_still_one_cycle():
    sim = Simulation.from_source(MOVER)
    sim.step(40)  # enabled, the first move under way
    assert sim.controller.cycle == 40
    assert sim.controller.motion.axes[0].moving


MACHINE = """axes = 1
[[slave]]
kind = "digital"
inputs = 2
outputs = 2
"""


@pytest.mark.parametrize("offset_ms", [0, 1, 2, 3, 5])
def test_an_input_in_the_cycle_after_a_move_starts_is_seen_in_it(write_file, offset_ms):
    """The move starts at 100 ms; the input comes `offset_ms` later, while the task waits
    for it or for the end of the move: the next cycle's events bound the jump."""
    m = write_file("m.toml", MACHINE)
    at = (100 + offset_ms) / 1000.0
    s = write_file("s.toml", f'[[event]]\nat = {at}\nset = "gpi2"\nvalue = 1\n')
    program = """void main() {
        Enable(0); Till(IsEnabled(0));
        Sleep(100 - system_timeInMs);
        MoveAbs(0, 50.0);
        Till(GetGPI(2) || IsInPos(0));
        Print("%d %d %.9f", system_timeInMs, GetGPI(2), GetPosFb(0));
        Till(IsInPos(0));
        Print("%d %.9f", system_timeInMs, GetPosFb(0));
    }"""
    runs = []
    for skip in (True, False):
        sim = Simulation.from_source(program, machine=m, scenario=s, skip=skip)
        sim.run(until=2.0)
        runs.append(list(sim.messages))
    assert runs[0] == runs[1]
    assert runs[1][0].startswith(f"{100 + offset_ms} 1 ")
