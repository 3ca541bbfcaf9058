"""Host calls with values a user may well pass by mistake: each is the documented
exception with a clear message, never a wrong answer or an error from deep inside."""

from __future__ import annotations

import math

import pytest
from api_programs import COUNTER

from motionvm.api import SessionError, Simulation, WriteError

FOREVER = "void main() { while (1) Sleep(1); }"


@pytest.mark.parametrize(
    "call",
    [
        lambda sim: sim.read("count"),
        lambda sim: sim.write("count", 1),
        lambda sim: sim.variables,
        lambda sim: sim.set_input(3, 1),
        lambda sim: sim.set_input("gpi3", 1),
        lambda sim: sim.output(3),
        lambda sim: sim.scope(["count"]),
        lambda sim: sim.inject_fault("estop"),
    ],
)
def test_the_state_of_a_closed_simulation_is_gone_not_zero(call):
    with Simulation.from_source(COUNTER) as sim:
        sim.run()
        assert sim.read("count") == 10
    with pytest.raises(SessionError, match="this simulation was closed"):
        call(sim)
    assert sim.messages == ["count 10 table[3] 0"]  # what it recorded stays readable


@pytest.mark.parametrize("value", ["OFF", "off", False, 0, 0.0])
def test_a_digital_input_written_off_reads_0(value):
    with Simulation.from_source(FOREVER) as sim:
        sim.set_input(3, 1)
        sim.write("gpi3", value)
        assert sim.read("gpi3") == 0
        sim.set_input(4, 1)
        sim.set_input(4, value)
        assert sim.read("gpi4") == 0
        sim.set_input("gpi5", 1)
        sim.set_input("gpi5", value)
        assert sim.read("gpi5") == 0


@pytest.mark.parametrize("value", ["0", "1", "x", None, math.nan])
def test_a_digital_input_refuses_what_is_not_0_or_1(value):
    with Simulation.from_source(FOREVER) as sim:
        with pytest.raises(WriteError, match=r"a digital value is 0 or 1, true/false or ON/OFF"):
            sim.write("gpi3", value)
        with pytest.raises(ValueError, match=r"a digital value is 0 or 1"):
            sim.set_input(3, value)
        assert sim.read("gpi3") == 0


def test_advance_past_any_cycle_count_or_with_a_bad_timeout():
    with Simulation.from_source(FOREVER) as sim:
        result = sim.advance(1e308, timeout=0.01)  # 1e308 / 0.001 s overflowed
        assert (result.reason, result.sim_time) == ("timeout", 0.01)
        for kw in ({"timeout": math.nan}, {"timeout": -1.0}):
            with pytest.raises(ValueError, match="advance takes a finite, non-negative timeout"):
                sim.advance(0.01, **kw)
        with pytest.raises(ValueError, match="non-negative duration"):
            sim.advance("1")


def test_step_refuses_a_negative_count():
    with Simulation.from_source(FOREVER) as sim:
        with pytest.raises(ValueError, match="step takes a number of cycles >= 0, got -1"):
            sim.step(-1)


def test_scope_of_one_name_as_a_string_says_so():
    with Simulation.from_source(COUNTER) as sim:
        with pytest.raises(TypeError, match="a list of channel names, got the string 'count'"):
            sim.scope("count")


@pytest.mark.parametrize("n", ["0", 1.0])
def test_axis_takes_an_integer(n):
    with Simulation.from_source(FOREVER) as sim:
        with pytest.raises(TypeError, match="cannot be interpreted as an integer"):
            sim.axis(n)


def test_a_debugged_run_keeps_to_its_timeout():
    with Simulation.from_source(FOREVER, debug=True) as sim:
        result = sim.run(timeout=0.05)  # ran on forever: the timeout was dropped
        assert (result.reason, result.sim_time, result.end) == ("timeout", 0.05, 0.05)
        assert [w.who for w in result.still_running] == ["task 0"]
        assert sim.run(until=0.08, timeout=0.5).reason == "until"


@pytest.mark.parametrize("until", [math.inf, math.nan, -1.0, "1"])
def test_a_debugged_run_checks_its_end_time(until):
    with Simulation.from_source(FOREVER, debug=True) as sim:
        with pytest.raises(SessionError, match="until must be a finite, non-negative"):
            sim.run(until=until)


def test_going_to_a_time_that_is_not_finite_is_a_value_error():
    with Simulation.from_source('void main() { Sleep(5); Print("done"); }', debug=True) as sim:
        for t in (math.nan, math.inf):
            with pytest.raises(ValueError, match="a finite number of seconds"):
                sim.go_to(t)
        assert sim.go_to(1e308).reason == "exited"  # past the end of the run
        assert sim.messages == ["done"]


def test_a_breakpoint_in_gdl_nested_400_deep_is_verified(tmp_path):
    # the line table parsed the file with Python's default recursion limit: the
    # RecursionError left every line "no statement"
    deep = "(" * 400 + "1" + ")" * 400
    path = tmp_path / "cell.gdl"
    path.write_text(
        "MODULE cell;\n  IO$BOARD io [ SLOT = 1 ];\n"
        "  DIGITAL$INPUT start [ BOARD$NAME = io, CHANNEL = 1 ];\n"
        "  INTEGER$VARIABLE runs [ ];\n\n  PROCEDURE counter;\n"
        "  DECLARE { STATUS OF start };\n  BEGIN\n"
        f"    VALUE OF runs = {deep};\n  END$PROCEDURE;\nEND$MODULE;\n",
        encoding="utf-8",
    )
    with Simulation.from_files([path], debug=True) as sim:
        bp = sim.break_at(path, 9)
        assert (bp.line, bp.verified, bp.message) == (9, True, "")


@pytest.mark.parametrize("name", [5, None, ("count",)])
def test_a_variable_is_named_by_a_string(name):
    with Simulation.from_source("int count; void main() { count = 1; }") as sim:
        with pytest.raises(TypeError, match="a variable is named by a string"):
            sim.read(name)
        with pytest.raises(TypeError, match="a variable is named by a string"):
            sim.write(name, 1)


def test_the_api_names_its_own_parameters_in_time_errors():
    with Simulation.from_source("void main() { }") as sim:
        with pytest.raises(SessionError, match="^timeout must be"):
            sim.run(timeout=-1.0)
