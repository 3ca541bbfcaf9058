"""The debug engine from Python: `Simulation(debug=True)`."""

from __future__ import annotations

import pytest

from motionvm.api import SessionError, Simulation

PROGRAM = """\
int count = 0;

void main()
{
    int i;
    for (i = 0; i < 3; i++) {
        count = count + 10;
        Sleep(5);
    }
    Print("count=%d", count);
}
"""


@pytest.fixture
def program(tmp_path):
    path = tmp_path / "p.hmpl"
    path.write_text(PROGRAM)
    return str(path)


def test_breakpoints_inspection_and_time_travel(program):
    with Simulation.from_files([program], debug=True) as sim:
        assert sim.pause_reason.reason == "entry"
        bp = sim.break_at(program, 6, condition="i == 1")
        assert bp.verified and bp.line == 6
        result = sim.run()
        assert result.reason == "paused" and sim.pause_reason.reason == "breakpoint"
        # a line's event comes before the line runs: the loop's `i++` of the second
        # round has not run yet (cycle 10, after two Sleep(5))
        assert sim.locals() == {"i": 1}
        assert sim.evaluate("count") == 20 and sim.time == pytest.approx(0.010)
        assert [name for _key, name in sim.threads()] == ["task 0"]
        frames = sim.stack()
        assert (frames[0].name, frames[0].line) == ("main", 6)
        when = sim.time
        sim.clear_breakpoints(program)
        assert sim.run(until=0.012).reason == "until"
        assert sim.evaluate("count") == 30
        sim.go_to(when)
        assert sim.time == pytest.approx(when) and sim.evaluate("count") == 20
        sim.write("count", 100)
        assert sim.run().reason == "finished"
        assert sim.messages == ["count=110"]


def test_step_back_returns_to_the_statement_before(program):
    with Simulation.from_files([program], debug=True) as sim:
        sim.break_at(program, 7)
        sim.run()
        first = sim.pause_reason.position
        sim.run()
        assert sim.evaluate("count") == 10 and sim.time == pytest.approx(0.005)
        stop = sim.step_back()  # the loop's line of the second round, in the same cycle
        assert stop.reason == "step" and stop.position.cycle == 5
        assert sim.stack()[0].line == 6 and sim.evaluate("count") == 10
        sim.step_back()  # the Sleep(5) of the first round, in cycle 0
        assert sim.stack()[0].line == 8 and sim.pause_reason.position > first


def test_debug_methods_need_a_debugged_simulation(program):
    with Simulation.from_files([program]) as sim, pytest.raises(SessionError, match="debug=True"):
        sim.break_at(program, 6)
