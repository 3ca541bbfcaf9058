"""Scope channels of a GDL application: `OBJECT.STATE`, recorded on the controller's cycle."""

from __future__ import annotations

from pathlib import Path

import pytest

from motionvm.lang.gdl import compile_app
from motionvm.lang.gdl.client import GdlApplication
from motionvm.lang.gdl.scenario import load_scenario
from motionvm.runtime.scope import BIT_UNIT, RAW_UNIT
from motionvm.sim.controller import Controller
from motionvm.sim.scope import ChannelRegistry, ScopeError, ScopeRecorder
from motionvm.sim.scope_sources import AxisSource
from motionvm.source.diagnostics import DiagnosticSink

EXAMPLES = Path(__file__).resolve().parents[3] / "examples"
PACKER = EXAMPLES / "02_gdl_packer.gdl"


def _packer() -> tuple[Controller, GdlApplication]:
    app = compile_app([str(PACKER)], sink=DiagnosticSink())
    assert app is not None
    controller = Controller()
    scenario = load_scenario(str(PACKER.with_suffix(".toml")), app)
    client = GdlApplication(controller, app, scenario, emit=lambda s: None, report=print)
    controller.add_client(client)
    return controller, client


def test_gdl_scope_records_state_variables_each_cycle() -> None:
    controller, client = _packer()
    registry = ChannelRegistry([*client.scope_sources(), AxisSource(controller)])
    names = [
        "cooling_fan.VALUE",
        "photocell{2}.STATUS",
        "MAIN_MOTOR.operating$condition",
        "main_motor.CONSTANT$STATUS",
        "main_motor.SPEED",
        "axis0.ref_vel",
    ]
    channels = registry.resolve_all(names)
    assert [c.unit for c in channels[:5]] == [RAW_UNIT, BIT_UNIT, BIT_UNIT, BIT_UNIT, RAW_UNIT]
    recorder = ScopeRecorder(channels, controller.cycle_time)
    recorder.attach(controller)
    controller.run(client.run_until(1.0))
    at = {c: i for i, c in enumerate(recorder.cycles)}
    fan, cell2, running, disabled, speed, ref_vel = recorder.columns
    # Every cycle until the run ends (the motor cruises again after 0.8 s): no jumps.
    assert recorder.cycles == list(range(len(recorder.cycles))) and 800 < len(recorder.cycles)
    assert (fan[at[99]], fan[at[100]], fan[at[300]], fan[at[500]]) == (0, 500, 1000, 0)
    assert (cell2[at[299]], cell2[at[300]]) == (0, 1)
    assert (running[at[99]], running[at[100]], running[at[500]]) == (0, 1, 0)  # STOPPED 0
    assert (disabled[at[99]], disabled[at[100]], disabled[at[500]]) == (1, 0, 1)  # ENABLED 0
    # SPEED follows the main motor's machine axis (axis 0) after every motion step.
    assert speed[at[400]] == 1200 and speed[at[400]] == round(ref_vel[at[400]])
    assert speed[at[130]] == round(ref_vel[at[130]]) and 0 < speed[at[130]] < 1200


def test_gdl_scope_names_and_errors() -> None:
    _, client = _packer()
    registry = ChannelRegistry(client.scope_sources())
    names = registry.names()
    assert "cooling_fan.VALUE" in names and "photocell{1}.STATUS" in names
    (source,) = client.scope_sources()
    assert source.resolve("axis0.ref_pos") is None  # not a GDL object: another source's
    assert source.resolve("system_timeInMs") is None
    with pytest.raises(ScopeError, match=r"PWM\$OUTPUT has no state variable VALUES"):
        registry.resolve("cooling_fan.VALUES")
    with pytest.raises(ScopeError, match=r"photocell is an array of 4; record one element"):
        registry.resolve("photocell.STATUS")
    with pytest.raises(ScopeError, match=r"index 5 of photocell is outside 1\.\.4"):
        registry.resolve("photocell{5}.STATUS")
    with pytest.raises(ScopeError, match=r"cooling_fan is not an array"):
        registry.resolve("cooling_fan{1}.VALUE")
    with pytest.raises(ScopeError, match=r"did you mean cooling_fan\.VALUE"):
        registry.resolve("cooling_fn.VALUE")
