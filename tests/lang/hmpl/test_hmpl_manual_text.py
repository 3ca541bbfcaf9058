"""HMPL behaviour that follows the letter of the manual, at cycle times other than 1 ms."""

from __future__ import annotations

import pytest

from motionvm.api import Simulation
from motionvm.sim.machine import MachineConfig


@pytest.mark.parametrize("cycle_time", [0.00025, 0.001, 0.002])
def test_system_fclk_counts_controller_cycles(cycle_time):
    # Manual 22.2: system_fclk "increases by 1 every controller cycle".
    sim = Simulation.from_source(
        """
void main() {
    int f0 = system_fclk; int t0 = system_timeInMs;
    Sleep(20);
    Print("%d %d", system_fclk - f0, system_timeInMs - t0);
}
""",
        machine=MachineConfig(cycle_time=cycle_time),
    )
    sim.run()
    cycles = round(0.020 / cycle_time)
    assert sim.messages == [f"{cycles} 20"]
