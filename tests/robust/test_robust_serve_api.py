"""`Simulation.serve` runs the simulation in its own thread: `run`, `step` and `write`
from the caller's thread while it serves are refused (they raced with it), and a closed
simulation cannot be served (the servers used to listen, then the run failed)."""

from __future__ import annotations

import pytest

from motionvm.api import SessionError, Simulation

PROGRAM = "void main() { while (1) Sleep(10); }\n"


@pytest.mark.parametrize(
    "call",
    [
        lambda sim: sim.run(until=0.01),
        lambda sim: sim.step(2),
        lambda sim: sim.write("system_ltest0", 1),
    ],
    ids=["run", "step", "write"],
)
def test_driving_a_served_simulation_from_outside_is_refused(call):
    with Simulation.from_source(PROGRAM) as sim:
        with sim.serve():
            with pytest.raises(SessionError, match="this simulation is being served"):
                call(sim)
        call(sim)  # once the serving stopped, it works again


def test_a_closed_simulation_cannot_be_served():
    sim = Simulation.from_source(PROGRAM)
    sim.close()
    with pytest.raises(SessionError, match="this run was closed"):
        sim.serve()
