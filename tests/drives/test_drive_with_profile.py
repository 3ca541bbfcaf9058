"""The profile generator driving a simulated servo drive in CSP, as the axis layer will."""

from __future__ import annotations

import math

from motionvm.drives.cia402 import Cia402Drive
from motionvm.drives.objects import (
    CONTROLWORD,
    FOLLOWING_ERROR_ACTUAL,
    MODES_OF_OPERATION,
    POSITION_ACTUAL,
    TARGET_POSITION,
    State,
    wrap_i32,
)
from motionvm.motion.profile import ProfileGenerator

DT = 0.001
COUNTS_PER_MM = 1000.0


def test_smoothed_move_through_a_servo_settles_on_target():
    bandwidth, damping = 30.0, 0.8
    drive = Cia402Drive.create(
        {"mechanics": {"model": "servo", "bandwidth": bandwidth, "damping": damping}}
    )
    gen = ProfileGenerator(DT, 100.0, 1000.0, 1000.0, 0.02)
    drive.write(MODES_OF_OPERATION, 0, 8)
    for controlword in (0x06, 0x0F):
        drive.write(CONTROLWORD, 0, controlword)
        for _ in range(10):
            drive.step(DT)
    assert drive.state is State.OPERATION_ENABLED
    gen.move_to(50.0)
    errors, cycles = [], 0
    while not gen.is_done:
        ref_pos, _, _ = gen.step()
        drive.write(TARGET_POSITION, 0, wrap_i32(round(ref_pos * COUNTS_PER_MM)))
        drive.step(DT)
        errors.append(drive.read(FOLLOWING_ERROR_ACTUAL))
        cycles += 1
    wn = 2 * math.pi * bandwidth
    # the ramp error 2 zeta v / wn at 100 mm/s, plus a little for the acceleration
    assert max(abs(e) for e in errors) <= 1.1 * 2 * damping * 100.0 * COUNTS_PER_MM / wn
    t_settle = 4.0 / (damping * wn) * 1.5
    for _ in range(int(t_settle / DT)):
        drive.step(DT)
    assert abs(drive.read(POSITION_ACTUAL) - 50_000) <= 1
