"""GDL on the machine: motors are the controller's axes, the controller's clock, faults."""

from __future__ import annotations

import io
import re
from pathlib import Path

import pytest

from motionvm.api import Simulation
from motionvm.lang.gdl import compile_app
from motionvm.lang.gdl.app import App
from motionvm.lang.gdl.client import GdlApplication
from motionvm.lang.gdl.motors import GdlMachineError
from motionvm.lang.gdl.scenario import Scenario, load_scenario
from motionvm.motion.axis_config import create as axis_config
from motionvm.sim.controller import Controller
from motionvm.sim.machine import MachineConfig, default_axes
from motionvm.source.diagnostics import DiagnosticSink

CELL = """MODULE cell;
  IO$BOARD io [ SLOT = 1 ];
  DIGITAL$INPUT go [ BOARD$NAME = io, CHANNEL = 1 ];
  DIGITAL$INPUT halt [ BOARD$NAME = io, CHANNEL = 2 ];
  STEPPER$BOARD steppers [ SLOT = 2 ];
  STEPPER$MOTOR belt [ BOARD$NAME = steppers, CHANNEL = 1, ACCELERATION = 5000 ];
  DC$MOTOR$AXIS lift [ AXIS$NUMBER = 1, MAX$SPEED = 500, ACCELERATION = 4000 ];
  PROCEDURE start;
  DECLARE { STATUS OF go };
  BEGIN
    IF STATUS OF go THEN
      CONSTANT$STATUS OF lift = ENABLED;
      CONSTANT$STATUS OF belt = ENABLED;
      MOVE$TO OF lift (250);
      RUN$AT$SPEED OF belt (400);
    END$IF;
  END$PROCEDURE;
  PROCEDURE cut;
  DECLARE { STATUS OF halt };
  BEGIN
    CONSTANT$STATUS OF belt = DISABLED;
  END$PROCEDURE;
END$MODULE;
"""

GO_AT_0_1 = '[[event]]\nat = 0.1\nset = "STATUS OF go"\nvalue = "ON"\n'


def _gdl(tmp_path: Path, text: str = CELL) -> str:
    path = tmp_path / "cell.gdl"
    path.write_text(text)
    return str(path)


def _app(tmp_path: Path, text: str = CELL) -> App:
    sink = DiagnosticSink()
    app = compile_app([_gdl(tmp_path, text)], sink=sink)
    assert app is not None, [d.headline() for d in sink.items]
    return app


def _scenario(tmp_path: Path, text: str) -> str:
    path = tmp_path / "s.toml"
    path.write_text(text)
    return str(path)


def _run(tmp_path: Path, scenario: str | None, until: float | None, **kw) -> Simulation:
    """CELL run through the API until `until`; no fault, no warning."""
    sim = Simulation.from_files([_gdl(tmp_path)], scenario=scenario, **kw)
    sim.run(until)
    assert sim.faults == []
    return sim


def test_gdl_motors_are_machine_axes_in_declaration_order(tmp_path: Path) -> None:
    sim = _run(tmp_path, _scenario(tmp_path, GO_AT_0_1), 1.0)
    controller = sim.controller
    belt, lift = controller.axes[0], controller.axes[1]
    assert belt.enabled and lift.enabled
    # The move ended exactly on its target, and the drive's feedback followed it.
    assert lift.ref_pos == 250.0 and lift.pos_fb == 250.0 and not lift.moving
    assert lift.variable("max_vel") == 500.0 and lift.variable("max_acc") == 4000.0
    # The belt jogs at its commanded speed (the run ended once nothing but it moved):
    # commanded in cycle 100, it has moved n cycles at 400/s minus half its 0.08 s ramp.
    n = controller.cycle - 1 - 100
    assert belt.cruising and belt.ref_vel == pytest.approx(400.0)
    assert belt.ref_pos == pytest.approx(400.0 * (n / 1000 - 0.04), abs=1e-6)
    assert all(a.ref_pos == 0.0 and not a.enabled for a in controller.axes[2:])
    assert "t=0.100 set OPERATING$CONDITION OF lift = RUNNING" in sim.messages


def test_gdl_run_ends_when_motors_stand_still_or_cruise(tmp_path: Path) -> None:
    controller = _run(tmp_path, _scenario(tmp_path, GO_AT_0_1), None).controller
    # The lift arrives after ~0.6 s; the belt cruises from 0.18 s on: the run ends soon after.
    assert controller.axes[1].ref_pos == 250.0
    assert controller.axes[0].cruising
    assert 0.7 < controller.sim_time < 0.8


def test_gdl_disabled_stops_the_motor_at_once(tmp_path: Path) -> None:
    s = _scenario(
        tmp_path, GO_AT_0_1 + '[[event]]\nat = 0.5\nset = "STATUS OF halt"\nvalue = "ON"\n'
    )
    sim = _run(tmp_path, s, 0.6)
    belt = sim.controller.axes[0]
    # At 0.5 s the belt had jogged 0.4 s minus half its 0.08 s ramp at 400/s: it holds there.
    assert belt.ref_pos == pytest.approx(400.0 * (0.4 - 0.04), abs=1e-6)
    assert belt.enabled and not belt.moving and belt.ref_vel == 0.0
    assert sim.messages[-3:] == [
        "t=0.500 set CONSTANT$STATUS OF belt = DISABLED",
        "t=0.500 set SPEED OF belt = 0",
        "t=0.500 set OPERATING$CONDITION OF belt = STOPPED",
    ]


def test_gdl_too_few_machine_axes_is_an_error(tmp_path: Path, cli) -> None:
    app = _app(tmp_path)
    controller = Controller(0.001, MachineConfig(axes=default_axes(1)))
    with pytest.raises(
        GdlMachineError,
        match=r"motor lift has no machine axis: the machine's 1 axes are all taken",
    ):
        GdlApplication(controller, app, Scenario((), (), None), emit=print, report=print)
    machine = tmp_path / "m.toml"
    machine.write_text("axes = 1\n")
    rc, out, err = cli("run", _gdl(tmp_path), "--machine", machine)
    assert rc == 3 and out == ""
    assert re.match(r"\S+cell\.gdl:\d+:\d+: error: motor lift has no machine axis", err), err
    assert "give a machine file with 2 [[axis]] tables" in err


def test_gdl_time_comes_from_the_controller_cycle(tmp_path: Path) -> None:
    s = _scenario(tmp_path, '[[event]]\nat = 0.00149\nset = "STATUS OF go"\nvalue = "ON"\n')
    machine = tmp_path / "m.toml"
    machine.write_text("[controller]\ncycle_time_ms = 0.5\n")
    sim = _run(tmp_path, s, 0.01, machine=machine)
    assert sim.messages[:2] == ["t=0.0015 input STATUS OF go = ON", "t=0.0015 run start"]
    assert sim.controller.cycle == 21  # until 0.01 s is inclusive: cycles 0..20


def test_gdl_motion_before_the_drive_is_enabled_waits_for_it(tmp_path: Path) -> None:
    s = _scenario(tmp_path, GO_AT_0_1.replace("0.1", "0"))
    sim = _run(tmp_path, s, 0.005)
    assert "t=0.000 set OPERATING$CONDITION OF lift = RUNNING" in sim.messages
    lift = sim.controller.axes[1]
    assert not lift.enabled and lift.ref_pos == 0.0
    assert _run(tmp_path, s, None).controller.axes[1].ref_pos == 250.0


def test_gdl_axis_fault_sets_diagn_status(tmp_path: Path) -> None:
    tight = axis_config({"max_pos_err": 0.01})  # the ideal drive lags one cycle: 0.4/cycle
    sim = _run(
        tmp_path,
        _scenario(tmp_path, GO_AT_0_1),
        0.2,
        machine=MachineConfig(0.001, axes=(tight, tight)),
    )
    faults = [line for line in sim.messages if "DIAGN$STATUS" in line]
    assert faults and faults[0].endswith("update DIAGN$STATUS OF belt = FAULT")
    assert not sim.controller.axes[0].enabled


def test_gdl_scenario_times_round_up_to_the_cycle(tmp_path: Path) -> None:
    app = _app(tmp_path)
    scenario = load_scenario(_scenario(tmp_path, GO_AT_0_1.replace("0.1", "0.0101")), app)
    assert scenario.events[0].at == 0.0101
    out = io.StringIO()
    controller = Controller()
    client = GdlApplication(
        controller, app, scenario, emit=lambda s: out.write(s + "\n"), report=print
    )
    controller.add_client(client)
    controller.run(client.run_until(0.02))
    assert out.getvalue().startswith("t=0.011 input STATUS OF go = ON\n")
