"""A run that can never end ends at once ("forever"), exactly: a wait that anything left in
the run (a scenario event, a sleeping task, a moving axis, a listening server, a paused
debugger's input) could still end runs on."""

from __future__ import annotations

import pytest

from motionvm.api import Simulation
from motionvm.debug import BreakpointSpec, DebugEngine, Position
from motionvm.session import RunSpec, Source

WAIT_INPUT = """void main(void)
{
    Print("start");
    Till(GetGPI(5));
    Print("got 5");
}
"""


def _run(write_file, text: str, scenario: str | None = None, **kw):
    path = write_file("prog.hmpl", text)
    if scenario is not None:
        kw["scenario"] = write_file("prog.scenario.toml", scenario)
    with Simulation.from_files([path], **kw) as sim:
        return sim.run(), sim.messages


@pytest.mark.parametrize("skip", [True, False])
def test_an_input_nothing_sets_waits_forever(write_file, skip):
    result, messages = _run(write_file, WAIT_INPUT, skip=skip)
    assert result.reason == "forever" and not result.finished
    assert messages == ["start"]
    (w,) = result.still_running
    assert (w.who, w.line, w.col, w.why) == ("task 0", 4, 5, "in Till")
    assert w.forever().endswith("prog.hmpl:4:5: error: task 0 waits forever: in Till")
    assert result.sim_time < 0.05


def test_skipping_and_stepping_end_at_the_same_cycle(write_file):
    program = 'void main(void) { Sleep(30); Print("a"); Till(IsMoving(1) || GetGPI(2)); }\n'
    ends = {_run(write_file, program, skip=skip)[0].sim_time for skip in (True, False)}
    assert len(ends) == 1 and ends.pop() >= 0.03


def test_a_scenario_event_that_sets_the_input_ends_the_wait(write_file):
    scenario = '[[event]]\nat = 2.5\nset = "gpi5"\nvalue = 1\n'
    result, messages = _run(write_file, WAIT_INPUT, scenario)
    assert result.reason == "finished" and messages == ["start", "got 5"]
    assert result.sim_time >= 2.5


def test_a_scenario_event_of_another_input_keeps_the_run_going_until_it(write_file):
    scenario = '[[event]]\nat = 1.0\nset = "gpi6"\nvalue = 1\n'
    result, _ = _run(write_file, WAIT_INPUT, scenario)
    assert result.reason == "forever" and 1.0 <= result.sim_time < 1.05


def test_a_sleeping_task_runs_on(write_file):
    program = WAIT_INPUT.replace('Print("start");', 'Sleep(2000); Print("start");')
    result, messages = _run(write_file, program)
    assert result.reason == "forever" and messages == ["start"]
    assert 2.0 <= result.sim_time < 2.05


def test_a_task_that_sleeps_in_a_loop_is_no_wait_forever(write_file):
    path = write_file("two.hmpl", "void main(void) { Till(GetGPI(5)); }\n")
    other = write_file("two.task1.hmpl", "_AUTORUN_ void main() { while (1) Sleep(100); }\n")
    with Simulation.from_files([path, other]) as sim:
        result = sim.run(timeout=1.0)
    assert result.reason == "timeout" and result.sim_time == 1.0


def test_a_moving_axis_runs_on(write_file):
    program = """void main(void)
{
    Enable(0);
    Till(IsEnabled(0));
    MoveAbs(0, 100.0);
    Till(IsInPos(0));
    Print("in position");
    Till(IsInPos(0) && GetGPI(5));
}
"""
    result, messages = _run(write_file, program)
    assert messages == ["in position"]
    assert result.reason == "forever"
    (w,) = result.still_running
    assert w.line == 8


def test_till_is_in_pos_of_an_axis_that_never_moves(write_file):
    result, _ = _run(write_file, "void main(void)\n{\n    Till(IsMoving(1));\n}\n")
    assert result.reason == "forever" and result.still_running[0].line == 3


def test_until_is_a_time_to_reach_and_a_timeout_a_deadline(write_file):
    path = write_file("prog.hmpl", WAIT_INPUT)
    with Simulation.from_files([path]) as sim:
        assert sim.run(until=3.0).reason == "until"  # meant to last that long
        assert sim.time == 3.0
        result = sim.run(timeout=10.0)  # should have finished: it never can
        assert result.reason == "forever" and sim.time < 3.05


def test_a_listening_server_runs_on(write_file):
    path = write_file("prog.hmpl", WAIT_INPUT)
    with Simulation.from_files([path]) as sim:
        serving = sim.serve(until=0.2)
        result = serving.wait(timeout=30)
    assert result is not None and result.reason == "until"


def test_the_debugger_stops_with_a_reason_instead_of_spinning(write_file):
    path = write_file("prog.hmpl", WAIT_INPUT)
    with Simulation.from_files([path], debug=True) as sim:
        result = sim.run()
        assert result.reason == "forever" and result.still_running[0].line == 4
        assert sim.pause_reason.reason == "waits forever"
        assert "task 0 waits forever: in Till" in sim.pause_reason.text
        sim.write("gpi5", 1)  # an input of the paused run: the wait can end now
        assert sim.run().reason == "finished"
        assert sim.messages == ["start", "got 5"]


def test_the_debugger_with_a_breakpoint_set_stops_too(write_file):
    # with a breakpoint set every cycle is stepped (its statements are seen): the same
    # test at each boundary stops it where a free run stops (the target only paces:
    # without the test the resume would go on to it)
    path = write_file("prog.hmpl", WAIT_INPUT)
    stops = []
    for breakpoint in (False, True):
        engine = DebugEngine(RunSpec([Source(path)]), emit=lambda s: None, report=lambda s: None)
        engine.start()
        if breakpoint:  # Print("got 5"): never reached
            assert engine.set_breakpoints(path, [BreakpointSpec(5)])[0].verified
        stop = engine.resume_to(Position(5000), True)
        assert stop.reason == "waits forever" and "task 0 waits forever: in Till" in stop.text
        stops.append((stop.position, stop.text))
        engine.close()
    assert stops[0] == stops[1]
