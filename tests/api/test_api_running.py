"""step(n) and run(until=, timeout=): exact cycles, and why a run stopped."""

from __future__ import annotations

from api_programs import COUNTER

from motionvm.api import Simulation


def test_step_runs_exactly_n_cycles():
    sim = Simulation.from_source(COUNTER)
    sim.step(4)
    assert sim.time == 0.004
    assert sim.read("count") == 4


def test_run_says_why_it_stopped():
    sim = Simulation.from_source(COUNTER)
    early = sim.run(until=0.005)
    assert (early.reason, early.finished, early.sim_time, early.end) == (
        "until",
        False,
        0.005,
        0.005,
    )
    assert [w.who for w in early.still_running] == ["task 0"]
    done = sim.run()
    assert (done.reason, done.finished, done.still_running) == ("finished", True, [])


def test_a_run_past_its_timeout_says_timeout():
    sim = Simulation.from_source("void main() { while (1) Sleep(10); }\n")
    result = sim.run(timeout=0.05)
    assert result.reason == "timeout" and result.sim_time == 0.05
