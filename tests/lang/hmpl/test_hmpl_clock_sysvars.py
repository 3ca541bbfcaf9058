"""system_timeInMs and system_fclk as each cycle's set-up writes them (manual 22.2):
the short path of the cycles before any wrap gives what the full arithmetic gives, for
every cycle time, at the edges where the values wrap."""

from __future__ import annotations

import pytest

from motionvm.api import Simulation
from motionvm.sim.machine import MachineConfig

EDGES = [0, 1, 999, 2**30 - 1, 2**30, 2**31 - 2, 2**31 - 1, 2**31, 2**32 + 5, 2**53 + 1]


@pytest.mark.parametrize("cycle_ms", [1.0, 0.125, 0.5, 1.5, 2.0, 100.0])
def test_the_clock_system_variables_at_the_wrap_edges(cycle_ms):
    sim = Simulation.from_source(
        "void main() { }", machine=MachineConfig(cycle_time=cycle_ms / 1000.0), skip=False
    )
    ctl = sim.controller
    rt = sim.runtime
    for cycle in EDGES:
        ctl.clock.cycle = cycle
        rt.begin_cycle()
        assert sim.read("system_timeInMs") == round(cycle * cycle_ms) & 0x7FFFFFFF
        assert sim.read("system_fclk") == ((cycle + 2**31) & 0xFFFFFFFF) - 2**31
    sim.close()
