"""Scenarios of any run (sim/scenario.py): HMPL and machine names, fault events and
their reactions, errors at their keys, and one file shared with a GDL application."""

from __future__ import annotations

import pytest

from motionvm.api import Simulation
from motionvm.session import SessionError

MACHINE = """axes = 2
[[slave]]
kind = "digital"
inputs = 2
outputs = 2
[[slave]]
kind = "analog"
ai = 1
"""


def files(write_file, scenario: str, machine: str = MACHINE) -> tuple[str, str]:
    return write_file("m.toml", machine), write_file("s.toml", scenario)


def run(write_file, scenario: str, program: str, **kw) -> Simulation:
    m, s = files(write_file, scenario)
    sim = Simulation.from_source(program, machine=m, scenario=s, **kw)
    sim.run(until=kw.pop("until", 5.0))
    return sim


def test_inputs_and_variables_change_at_their_cycle(write_file):
    sim = run(
        write_file,
        """[initial]
gpi1 = 1
[[event]]
at = 0.050
set = "gpi3"
value = "ON"
[[event]]
at = 0.0605
set = "slv2.di1"
value = true
[[event]]
at = 0.070
set = "slv3.ai1"
value = 49152
[[event]]
at = 0.080
set = "system_dtest0"
value = 2.5
""",
        """void main() {
            Print("%d", GetGPI(1));
            Till(GetGPI(3)); Print("%d", system_timeInMs);
            Till(GetSlvGPI(2, 1)); Print("%d", system_timeInMs);
            SetSlvAIType(3, 1, HMPL_DAC_N10_P10);
            Till(GetSlvAIRaw(3, 1)); Print("%d %f", system_timeInMs, GetSlvAI(3, 1));
            Till(system_dtest0 > 2); Print("%d %f", system_timeInMs, system_dtest0);
        }""",
    )
    assert sim.messages == ["1", "50", "61", "70 5.000000", "80 2.500000"]


@pytest.mark.parametrize("skip", [True, False])
def test_events_wake_a_sleeping_program_the_same_with_or_without_skipping(write_file, skip):
    sim = run(
        write_file,
        '[[event]]\nat = 0.5\nset = "gpi2"\nvalue = 1\n',
        'void main() { Till(GetGPI(2)); Print("%d", system_timeInMs); }',
        skip=skip,
    )
    assert sim.messages == ["500"]


def test_the_run_lasts_until_the_last_event_and_until_is_read(write_file):
    m, s = files(write_file, 'until = 0.3\n[[event]]\nat = 0.2\nset = "gpi2"\nvalue = 1\n')
    sim = Simulation.from_source("void main() { }", machine=m, scenario=s)
    result = sim.run()
    assert result.sim_time == pytest.approx(0.201) and sim.read("gpi2") == 1


def test_drive_fault(write_file):
    sim = run(
        write_file,
        '[[event]]\nat = 0.2\nfault = "drive"\naxis = 1\ncode = 0x7500\n',
        """void main() {
            Enable(1); Till(IsEnabled(1)); MoveAbs(1, 500);
            Till(IsDriveErr(1));
            Print("%x %d %d", GetDriveErr(1), IsEnabled(1), IsErrorStop(1));
        }""",
    )
    assert sim.messages == ["7500 0 1"]
    assert not sim.axis(1).enabled and sim.axis(1).pos_fb < 500


def test_encoder_loss(write_file):
    sim = run(
        write_file,
        '[[event]]\nat = 0.1\nfault = "encoder_loss"\naxis = 0\n',
        """void main() {
            Enable(0); Till(IsEnabled(0)); MoveAbs(0, 500);
            Till(IsDriveErr(0)); Print("%x %d", GetDriveErr(0), IsEnabled(0));
        }""",
    )
    assert sim.messages == ["7305 0"]


def test_following_error(write_file):
    sim = run(
        write_file,
        '[[event]]\nat = 0.1\nfault = "following_error"\naxis = 0\n',
        """void main() {
            Enable(0); Till(IsEnabled(0)); MoveAbs(0, 500);
            Till(!IsEnabled(0)); Print("%x", GetAxisLastErr(0));
        }""",
    )
    assert sim.messages == ["8300083e"]


def test_hw_limit(write_file):
    sim = run(
        write_file,
        '[[event]]\nat = 0.1\nfault = "hw_limit"\naxis = 0\nside = "right"\n',
        """void main() {
            Enable(0); Till(IsEnabled(0)); MoveAbs(0, 500);
            Till(IsErrorStop(0)); Till(!IsMoving(0));
            Print("%d %d", IsHWRL(0), GetPosFb(0) < 500);
        }""",
    )
    assert sim.messages == ["1 1"]


def test_slave_lost(write_file):
    sim = run(
        write_file,
        """[[event]]
at = 0.1
fault = "slave_lost"
slave = 1
[[event]]
at = 0.1
fault = "slave_lost"
slave = 2
""",
        """void main() {
            Enable(1); Till(IsEnabled(1)); SetSlvGPO(2, 1, 1);
            Till(GetSlvECATSt(1) != 8);
            Print("%d %d %d %d", GetSlvECATSt(1), GetSlvECATSt(2), GetSlvECATSt(0), IsEnabled(1));
            Print("%d %d", SetSlvGPO(2, 1, 1), GetSlaveNum());
        }""",
    )
    assert sim.messages == ["1 1 8 0", "-1 4"]
    assert sim.read("slv1.state") == 1 and sim.axis(1).error_stop


def test_estop_event(write_file):
    sim = run(
        write_file,
        '[[event]]\nat = 0.1\nfault = "estop"\n',
        "void main() { Enable(0); while (1) Sleep(1); }",
    )
    assert not sim.axis(0).enabled and "E-stop at t=0.100 s" in sim.faults[0]


def test_inject_fault_from_python():
    sim = Simulation.from_source("void main() { Enable(0); while (1) Sleep(1); }")
    sim.step(20)
    sim.inject_fault("drive", axis=0, code=0x2310)
    sim.step(2)
    assert sim.read("axis0.fault_status") & 2 and not sim.axis(0).enabled
    with pytest.raises(ValueError, match="axis = 9"):
        sim.inject_fault("encoder_loss", axis=9)
    with pytest.raises(ValueError, match="must be one of"):
        sim.inject_fault("smoke")


@pytest.mark.parametrize(
    ("text", "where", "message"),
    [
        ('[[event]]\nat = 0.1\nset = "gpi9"\nvalue = 1\n', "3:1", "set = 'gpi9': unknown input"),
        ('[[event]]\nat = 0.1\nset = "gpi1"\n', "1:1", "missing 'value'"),
        ('[[event]]\nat = -1\nset = "gpi1"\nvalue = 1\n', "2:1", "'at' must be a number"),
        ('[[event]]\nat = 0.1\nset = "gpi1"\nvalue = "HIGH"\n', "4:1", "value = 'HIGH'"),
        ('[[event]]\nat = 0.1\nfault = "smoke"\n', "3:1", "fault = 'smoke'"),
        ('[[event]]\nat = 0.1\nfault = "drive"\n', "1:1", "needs 'axis'"),
        ('[[event]]\nat = 0.1\nfault = "drive"\naxis = 7\n', "4:1", "axis = 7"),
        ('[[event]]\nat = 0.1\nfault = "hw_limit"\naxis = 0\nside = "up"\n', "5:1", "side = 'up'"),
        ('[[event]]\nat = 0.1\nfault = "slave_lost"\nslave = 4\n', "4:1", "slave = 4"),
        ('[[event]]\nat = 0.1\nfault = "estop"\naxis = 0\n', "4:1", "'axis' does not apply"),
        (
            '[[event]]\nat = 0.1\nset = "gpi1"\nvalue = 1\nduring = "p"\n',
            "5:1",
            "apply to GDL objects",
        ),
        ("colour = 1\n", "1:1", "unknown key 'colour'"),
    ],
)
def test_bad_scenarios_are_errors_at_their_keys(write_file, error_at, text, where, message):
    m, s = files(write_file, text)
    with pytest.raises(SessionError) as err:
        Simulation.from_source("void main() { }", machine=m, scenario=s)
    error_at(err.value.messages[:1], s, where, message)


GDL = """MODULE m;
  IO$BOARD io [ SLOT = 1 ];
  DIGITAL$INPUT go_button [ BOARD$NAME = io, CHANNEL = 1 ];
  INTEGER$VARIABLE presses [ ];

  PROCEDURE pressed;
  DECLARE { STATUS OF go_button };
  BEGIN
    IF STATUS OF go_button THEN
      VALUE OF presses = VALUE OF presses + 1;
    END$IF;
  END$PROCEDURE;
END$MODULE;
"""


def test_one_scenario_shared_by_hmpl_and_gdl(tmp_path, write_file):
    m, s = files(
        write_file,
        """until = 0.5
[[event]]
at = 0.1
set = "STATUS OF go_button"
value = "ON"
[[event]]
at = 0.2
set = "gpi2"
value = 1
""",
    )
    (tmp_path / "app.gdl").write_text(GDL)
    (tmp_path / "main.hmpl").write_text(
        'void main() { Till(GetGPI(2)); Print("gpi2 at %d", system_timeInMs); }'
    )
    sim = Simulation.from_files(
        [tmp_path / "main.hmpl", tmp_path / "app.gdl"], machine=m, scenario=s
    )
    sim.run()
    assert "t=0.100 input STATUS OF go_button = ON" in sim.messages
    assert sim.messages[-1] == "gpi2 at 200"
    assert sim.read("presses.VALUE") == 1


def test_the_cli_runs_an_hmpl_scenario(tmp_path, write_file, capsys):
    from motionvm.cli import main

    m, s = files(write_file, '[[event]]\nat = 0.03\nset = "gpi5"\nvalue = 1\n')
    p = tmp_path / "p.hmpl"
    p.write_text('void main() { Till(GetGPI(5)); Print("%d", system_timeInMs); }')
    assert main(["run", "--machine", m, "--scenario", s, str(p)]) == 0
    assert capsys.readouterr().out == "30\n"
    (tmp_path / "bad.toml").write_text('[[event]]\nat = 0.1\nset = "gpi0"\nvalue = 1\n')
    assert main(["run", "--machine", m, "--scenario", str(tmp_path / "bad.toml"), str(p)]) == 3
    assert "bad.toml:3:1: error: event 1: set = 'gpi0'" in capsys.readouterr().err


def test_read_only_names_are_errors_and_refused_values_faults(write_file):
    m, s = files(write_file, '[[event]]\nat = 0.1\nset = "himc_gpi_bits"\nvalue = 1\n')
    with pytest.raises(SessionError, match="'himc_gpi_bits' is read-only"):
        Simulation.from_source("void main() { }", machine=m, scenario=s)
    m, s = files(write_file, '[[event]]\nat = 0.1\nset = "axis0.max_vel"\nvalue = -5\n')
    sim = Simulation.from_source("void main() { }", machine=m, scenario=s)
    sim.run()
    assert sim.fault_count == 1
    assert sim.faults[0].startswith(f"{s}:3:1: error: event 1: SetVel(0, -5) refused")
