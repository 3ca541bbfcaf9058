"""Simulation.call (any HMPL built-in from Python), advance (relative time), one clock
(`system_timeInMs` shows `time` at every stop) and what each waiting task waits for."""

from __future__ import annotations

from pathlib import Path

import pytest

from motionvm.api import CallError, Simulation
from motionvm.session import Source

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
IDLE = "void main() { while (1) Sleep(7); }\n"
BAD_AXIS = 0x8300_0000  # an axis code: 0x83XXCCCC


def test_call_runs_a_builtin_with_the_manuals_checks():
    sim = Simulation.from_source(IDLE)
    assert sim.call("Enable", 0) == 0
    sim.advance(0.05)
    assert sim.call("IsEnabled", 0) == 1
    assert sim.call("MoveAbs", 0, 5) == 0  # an int converted to the double parameter
    sim.advance(2.0)
    assert sim.call("GetPosFb", 0) == pytest.approx(5.0)
    assert sim.read("axis0.pos_fb") == pytest.approx(5.0)
    assert sim.call("sqrt", 2) == pytest.approx(2**0.5)


def test_an_invalid_call_returns_the_manuals_error_code_as_in_hmpl():
    program = """
int code;
void main() { code = MoveAbs(99, 1.0); }
"""
    sim = Simulation.from_source(program)
    sim.run()
    from_hmpl = sim.read("code")
    assert from_hmpl != 0
    assert sim.call("MoveAbs", 99, 1.0) == from_hmpl


def test_out_parameters_come_back_after_the_value():
    sim = Simulation.from_source(IDLE)
    assert sim.call("StringPrint", "x=%d", 5) == (3, "x=5")
    status, version = sim.call("GetFirmwareVer")
    assert status == 0 and "motionvm" in version


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (("MovAbs", 0, 1.0), "did you mean 'MoveAbs'"),
        (("MoveAbs", 0), "takes 2 arguments, got 1"),
        (("MoveAbs", "zero", 1.0), "is an integer"),
        (("Sleep", 3), "only makes sense inside a task"),
    ],
)
def test_a_call_that_cannot_be_made_is_a_call_error(args, message):
    sim = Simulation.from_source(IDLE)
    with pytest.raises(CallError, match=message):
        sim.call(*args)
    assert issubclass(CallError, ValueError)


def test_call_needs_a_program_with_builtins():
    sim = Simulation.from_files([EXAMPLES / "02_gdl_packer.gdl"])
    with pytest.raises(CallError, match="HMPL"):
        sim.call("MoveAbs", 0, 1.0)


def test_advance_is_relative_and_counts_whole_cycles():
    sim = Simulation.from_source(IDLE)
    sim.run(until=0.25)
    for _ in range(10):
        result = sim.advance(0.1)
    assert result.reason == "until"
    assert sim.time == pytest.approx(1.25) and sim.controller.cycle == 1250
    with pytest.raises(ValueError, match="non-negative"):
        sim.advance(-1)


@pytest.mark.parametrize("skip", [True, False])
def test_system_time_shows_the_clock_at_every_stop(skip):
    sim = Simulation.from_source(IDLE, skip=skip)
    sim.run(until=0.2)
    assert sim.read("system_timeInMs") == round(sim.time * 1000) == 200
    sim.step(3)
    assert sim.read("system_timeInMs") == 203
    sim.advance(0.0305)
    assert sim.read("system_timeInMs") == round(sim.time * 1000)
    assert sim.read("system_fclk") == sim.controller.cycle


def test_every_waiting_task_says_what_it_waits_for():
    program = """
int flag;
void main() {
#if _TASKID_ == 0
    StartTask(1);
    Till(flag == 1);
#else
    Sleep(500);
#endif
}
"""
    sim = Simulation([Source("p.hmpl", program, 0), Source("p.hmpl", program, 1)])
    result = sim.run(until=0.2)
    why = {w.who: w.why for w in result.still_running}
    assert why == {"task 0": "in Till", "task 1": "sleeping until t=0.501 s"}  # started at 1 ms
    assert all(w.why for w in result.still_running)
