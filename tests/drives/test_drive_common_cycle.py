"""The drive's common cycle (CSP in Operation enabled, the controlword repeated) against
the full one: a flag set by the cycle before lets the step take it without the state
machine; every event that could change that cycle must clear the flag.

The reference drive has the flag cleared before each step, so it goes through the
state machine and the mode dispatch every cycle. Random sequences of master writes,
faults, local control and window changes must leave both drives in the same state,
object by object, after every step.
"""

from __future__ import annotations

import os

from drive_util import DT, enabled_csp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as hs

from motionvm.drives.cia402 import Cia402Drive
from motionvm.drives.mechanics import IdealMechanics, ServoMechanics
from motionvm.drives.objects import (
    CONTROLWORD,
    FOLLOWING_ERROR_WINDOW,
    MODES_OF_OPERATION,
    SW_FOLLOWING_ERROR,
    State,
    wrap_i32,
)

settings.register_profile(
    "common-cycle-ci", max_examples=60, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)  # fmt: skip
settings.register_profile(
    "common-cycle-thorough", max_examples=600, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)  # fmt: skip
PROFILE = settings.get_profile("common-cycle-" + os.environ.get("HYPOTHESIS_PROFILE", "ci"))

CONFIG = {"mechanics": {"model": "ideal", "delay_cycles": 1}, "index_spacing": 5_000.0,
          "positive_limit": 200_000.0}  # fmt: skip


def observed(drive: Cia402Drive) -> tuple:
    m = drive.mechanics
    return (drive.state, drive.statusword, drive.position_actual, drive.digital_inputs,
            drive.mode_display, drive.velocity_actual, drive.torque_actual,
            drive.position_demand, drive.following_error, drive.error_code,
            drive.pending_fault, m.position, m.velocity, m.torque)  # fmt: skip


events = hs.one_of(
    hs.tuples(hs.just("target"), hs.integers(-60_000, 60_000)),
    hs.tuples(hs.just("controlword"), hs.sampled_from([0x00, 0x02, 0x06, 0x07, 0x0F, 0x8F])),
    hs.tuples(hs.just("mode"), hs.sampled_from([6, 8, 8, 9, 10])),
    hs.tuples(hs.just("fault"), hs.just(0)),
    hs.tuples(hs.just("window"), hs.sampled_from([0, 3_000, 60_000, 0x7FFFFFFF, 0xFFFFFFFF])),
    hs.tuples(hs.just("local"), hs.one_of(hs.none(), hs.integers(-50_000, 50_000))),
    hs.tuples(hs.just("encoder"), hs.booleans()),
)


def apply(drive: Cia402Drive, event: tuple) -> None:
    kind, value = event
    if kind == "target":
        drive.target_position = wrap_i32(drive.target_position + value)
    elif kind == "controlword":
        drive.write(CONTROLWORD, 0, value)
    elif kind == "mode":
        drive.write(MODES_OF_OPERATION, 0, value)
    elif kind == "fault":
        drive.inject_fault()
    elif kind == "window":
        drive.write(FOLLOWING_ERROR_WINDOW, 0, value)
    elif kind == "local":
        drive.follow_local_demand(value)
    elif value:
        drive.encoder_loss()
    else:
        drive.encoder_restore()


@PROFILE
@given(hs.lists(hs.tuples(events, hs.integers(1, 6)), min_size=1, max_size=25))
def test_the_common_cycle_ends_as_the_full_cycle_would(script):
    drive, reference = enabled_csp(CONFIG), enabled_csp(CONFIG)
    for event, cycles in script:
        apply(drive, event)
        apply(reference, event)
        for _ in range(cycles):
            drive.step(DT)
            reference._csp_ready = False  # through the state machine and mode dispatch
            reference.step(DT)
            assert observed(drive) == observed(reference)


def test_a_repeated_csp_cycle_is_known_from_the_flag_and_a_fault_clears_it():
    drive = enabled_csp(CONFIG)
    drive.step(DT)
    assert drive._csp_ready
    drive.inject_fault()
    assert not drive._csp_ready  # the next step runs the state machine
    drive.step(DT)  # at rest, the fault reaction ends at once
    assert drive.state in (State.FAULT_REACTION_ACTIVE, State.FAULT)


def test_a_window_written_while_the_drive_runs_is_checked_at_the_next_step():
    drive = enabled_csp(CONFIG)
    drive.step(DT)
    drive.write(FOLLOWING_ERROR_WINDOW, 0, 10)
    assert drive.following_error_window == drive.read(FOLLOWING_ERROR_WINDOW) == 10
    drive.target_position = wrap_i32(drive.target_position + 1_000)
    drive.step(DT)  # the motor is a cycle behind: 1000 counts of following error
    assert drive.statusword & SW_FOLLOWING_ERROR
    assert drive.pending_fault is not None


def test_step_position_returns_the_new_position_for_every_model():
    for m in (IdealMechanics(delay_cycles=0), IdealMechanics(delay_cycles=1),
              IdealMechanics(delay_cycles=3), ServoMechanics(),
              ServoMechanics(max_torque=1e-6)):  # fmt: skip
        for r in (10.0, 250.0, -40.0, -40.0):
            assert m.step_position(r, DT) == m.position
