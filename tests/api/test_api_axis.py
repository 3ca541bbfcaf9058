"""axis(n): a frozen snapshot with every axis variable of manual 5.1.1 and the status flags."""

from __future__ import annotations

import dataclasses

import pytest

from motionvm.api import AxisState, Simulation
from motionvm.motion.axis_status import VARIABLES

MOVE = "void main() { Enable(1); Till(IsEnabled(1)); MoveAbs(1, 20.0); Till(IsInPos(1)); }\n"
FLAGS = ("enabled", "moving", "in_pos", "error_stop", "stopping", "halted")


def test_the_snapshot_has_every_manual_variable_and_the_status_flags():
    fields = {f.name for f in dataclasses.fields(AxisState)}
    assert set(VARIABLES) <= fields
    assert set(FLAGS) <= fields


def test_a_snapshot_is_frozen_and_stays_as_taken():
    sim = Simulation.from_source(MOVE)
    before = sim.axis(1)
    with pytest.raises(dataclasses.FrozenInstanceError):
        before.pos_fb = 1.0  # type: ignore[misc]
    sim.run()
    after = sim.axis(1)
    assert before.pos_fb == 0.0 and not before.enabled
    assert after.enabled and after.in_pos and not after.moving and not after.error_stop
    assert after.pos_fb == pytest.approx(20.0) and after.ref_pos == pytest.approx(20.0)
    assert after.coe_pos_fb == pytest.approx(200000, abs=1)  # counts: 10000 per mm
    assert after.sim_time == sim.time and after.axis_id == 1


def test_a_snapshot_while_moving_shows_velocity_in_mm_per_s():
    sim = Simulation.from_source(MOVE)
    sim.run(until=0.05)
    moving = sim.axis(1)
    assert moving.moving and not moving.in_pos
    assert 0 < moving.ref_vel <= moving.max_vel
    assert moving.ref_vel == sim.read("axis1.ref_vel")


def test_an_axis_that_does_not_exist_is_an_index_error():
    sim = Simulation.from_source("void main() { }\n")
    with pytest.raises(IndexError, match="axes 0..7"):
        sim.axis(8)
