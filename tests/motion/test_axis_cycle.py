"""The axis cycle: a profile move against a servo-free reference, moves as values, cruising.

The common cycle (a profile move in CSP on an ideal drive) is checked against a reference
written out here from the definitions: the profile generator's output, the target in
counts, the ideal drive's demand delayed by its delay line, the encoder's int32 counts and
their unwrapping. Every value must agree to the bit over many cycles. A second test runs a
script with limits, faults and resets twice, once with the sensors made to evaluate every
cycle, and compares everything.
"""

from __future__ import annotations

import dataclasses
import random
from collections import deque

import pytest

from motionvm.drives.objects import wrap_i32
from motionvm.motion.axis import Axis, MoveAbsolute, MovePvt, MoveRelative, MoveVelocity
from motionvm.motion.axis_config import create
from motionvm.motion.axis_status import VARIABLES, AxisCommandError
from motionvm.motion.profile import ProfileGenerator

DT = 0.001


def enabled(config: dict) -> Axis:
    a = Axis(0, create(config), DT)
    a.enable()
    for _ in range(30):
        a.step()
    assert a.enabled and a.in_pos
    return a


class Reference:
    """An axis in CSP on an ideal drive, from the definitions, without the drive model."""

    def __init__(self, a: Axis, delay: int):
        self.cpu, self.offset = a.cpu, a.pos_offset
        self.pg = ProfileGenerator(DT, a.pg.v_max, a.pg.a_max, a.pg.d_max, a.pg.t_smooth)
        self.pg.reset(a.ref_pos)
        self.target = a.drive.target_position
        self.demand = float(a.drive.position_demand)  # integral: no wrap near the start
        self.line = deque([self.demand] * (delay + 1), maxlen=delay + 1)
        self.x = self.demand
        self.position_actual = a.drive.position_actual
        self.counts = round(a.pos_fb_raw * self.cpu)

    def step(self) -> dict:
        p, v, acc = self.pg.step()
        target = wrap_i32(round((p + self.offset) * self.cpu))
        self.demand += wrap_i32(target - self.target)
        self.target = target
        self.line.append(self.demand)
        x_0, self.x = self.x, self.line[0]
        position_actual = wrap_i32(round(self.x))
        self.counts += wrap_i32(position_actual - self.position_actual)
        self.position_actual = position_actual
        return {
            "ref": (p, v, acc),
            "target_position": target,
            "position_actual": position_actual,
            "pos_fb": self.counts / self.cpu - self.offset,
            "vel_fb": wrap_i32(round((self.x - x_0) / DT)) / self.cpu,
        }


def observed(a: Axis) -> dict:
    d = a.drive
    return {
        "ref": (a.ref_pos, a.ref_vel, a.ref_acc),
        "target_position": d.target_position,
        "position_actual": d.position_actual,
        "pos_fb": a.pos_fb,
        "vel_fb": a.vel_fb,
    }


@pytest.mark.parametrize("delay", [0, 1, 3])
@pytest.mark.parametrize(
    "config",
    [
        {},
        {"smooth_time_ms": 20.0},
        # 1e7 counts/mm: the int32 counters wrap at +-214.7 mm, inside the travel
        {"counts_per_unit": 1e7, "max_pos_err": 1e3, "hw_left": False, "hw_right": False},
    ],
)
def test_profile_moves_match_a_servo_free_reference_bit_for_bit(delay, config):
    config = dict(config, drive={"mechanics": {"model": "ideal", "delay_cycles": delay}})
    a = enabled(config)
    a.set_pos(12.345)  # an offset between the axis and the slave
    ref = Reference(a, delay)
    rnd = random.Random(delay)
    for move in range(12):
        if move % 4 == 3:
            v = rnd.uniform(-900.0, 900.0)
            a.move_vel(v)
            ref.pg.move_velocity(v)
            cycles = 150
        else:
            target = rnd.uniform(-600.0, 600.0)
            a.move_abs(target)
            ref.pg.move_to(target)
            cycles = rnd.randrange(50, 900)
        for cycle in range(cycles):
            a.step()
            assert observed(a) == ref.step(), f"move {move}, cycle {cycle}"
        assert not a.error_stop


def _state(a: Axis) -> tuple:
    d, m = a.drive, a.drive.mechanics
    return (
        tuple(a.variable(n) for n in VARIABLES),
        (
            d.controlword,
            d.statusword,
            d.target_position,
            d.position_actual,
            d.position_demand,
            d.velocity_actual,
            d.torque_actual,
            d.following_error,
            d.digital_inputs,
            d.error_code,
            d.mode_display,
            d.state,
        ),  # fmt: skip
        (m.position, m.velocity, m.torque),
        (a.enabled, a.moving, a.in_pos, a.error_stop, a.last_error, a.resting, a.cruising),
    )


def _script(seed: int) -> list:
    """A random sequence of (cycle, method, args) commands, limits and faults included."""
    rnd = random.Random(seed)
    cmds, cycle = [], 0
    for _ in range(40):
        cycle += rnd.randrange(1, 120)
        kind = rnd.choice(["abs", "abs", "rel", "vel", "stop", "scale", "vel_limit", "setpos",
                           "halt", "resume", "reset", "enable", "swrl", "fault", "ignore_swl",
                           "ignore_hwl", "buffer"])  # fmt: skip
        args = {
            "abs": ("move_abs", (rnd.uniform(-1100, 1100),)),
            "rel": ("move_rel", (rnd.uniform(-50, 50),)),
            "vel": ("move_vel", (rnd.uniform(-1500, 1500),)),
            "stop": ("stop", ()),
            "scale": ("set_vel_scale", (rnd.uniform(0, 100),)),
            "vel_limit": ("set_vel", (rnd.uniform(10, 2000),)),
            "setpos": ("set_pos", (rnd.uniform(-100, 100),)),
            "halt": ("halt", ()),
            "resume": ("resume", ()),
            "reset": ("reset", ()),
            "enable": ("enable", ()),
            "swrl": ("set_sw_right", (rnd.uniform(100, 1000),)),
            "fault": ("inject", ()),
            "ignore_swl": ("set_ignore", ("swl", rnd.randrange(2))),
            "ignore_hwl": ("set_ignore", ("hwl", rnd.randrange(2))),
            "buffer": ("set_buffer_mode", (rnd.randrange(2),)),
        }[kind]
        cmds.append((cycle, *args))
    return cmds


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize(
    "config",
    [{}, {"smooth_time_ms": 20, "drive": {"mechanics": {"model": "ideal", "delay_cycles": 3}}}],
)
def test_sensors_skipped_in_their_quiet_interval_change_nothing(seed, config):
    """The same script twice; one axis's sensors evaluate every cycle (writing their
    inputs empties the quiet interval). Limit switches, index pulses and the home switch
    are crossed, faults raised and reset."""
    quiet, evaluating = Axis(0, create(config), DT), Axis(0, create(config), DT)
    for a in (quiet, evaluating):
        a.enable()
    cycle = 0
    for at, method, args in _script(seed) + [(cycle + 10_000, "stop", ())]:
        while cycle < at:
            sensors = evaluating.drive.sensors
            sensors.external = sensors.external
            quiet.step()
            evaluating.step()
            cycle += 1
            assert _state(quiet) == _state(evaluating), f"cycle {cycle}"
        for a in (quiet, evaluating):
            if a.error_stop or not a.enabled:  # recover, so that the script goes on moving
                a.reset()
                try:
                    a.enable()
                except AxisCommandError:
                    pass  # a drive fault is still being reset
            if method == "inject":
                if random.Random(at).random() < 0.3:
                    a.drive.inject_fault(0x1234)
                continue
            try:
                getattr(a, method)(*args)
            except AxisCommandError:
                pass


# ---- moves as values ---------------------------------------------------------------------


def test_moves_are_frozen_values_in_the_queue():
    a = enabled({})
    a.set_buffer_mode(1)
    a.move_abs(100.0)
    a.move_rel(-20.0)
    a.move_vel(50.0)
    a.move_pvt([100.0], [0.0], [0.0])
    queued = list(a._command_queue)
    assert queued[:3] == [MoveRelative(-20.0), MoveVelocity(50.0), queued[2]]
    assert isinstance(queued[2], MovePvt) and queued[2].trajectory.duration == 0.1
    with pytest.raises(dataclasses.FrozenInstanceError):
        queued[0].distance = 1.0  # type: ignore[misc]
    assert MoveAbsolute(1.0) == MoveAbsolute(1.0) != MoveAbsolute(2.0)


def test_a_move_at_zero_velocity_scale_waits_as_a_value():
    a = enabled({})
    a.set_vel_scale(0.0)
    a.move_abs(10.0)
    assert a.moving and a._deferred_move == MoveAbsolute(10.0)
    a.set_vel_scale(50.0)
    assert a._deferred_move is None
    while a.moving:
        a.step()
    assert abs(a.pos_fb - 10.0) < 1e-3


# ---- cruising ----------------------------------------------------------------------------

FREE = {"hw_left": False, "hw_right": False}  # no limit switch in the way


def cycles_until(a: Axis, cond, limit: int = 20_000) -> int:
    for n in range(limit):
        if cond():
            return n
        a.step()
    raise AssertionError("condition never held")


@pytest.mark.parametrize("smooth_ms", [0.0, 50.0])
def test_cruising_once_a_jog_holds_its_velocity(smooth_ms):
    a = enabled(dict(FREE, smooth_time_ms=smooth_ms, max_acc=1000.0))
    a.set_ignore("swl", 1)
    a.move_vel(-200.0)
    assert not a.cruising  # accelerating
    n = cycles_until(a, lambda: a.cruising)
    # the T-curve reaches 200 mm/s after 0.2 s; the smoothing window then fills
    assert n == pytest.approx(200 + smooth_ms, abs=3)
    for _ in range(100):
        assert a.ref_vel == pytest.approx(-200.0, rel=1e-9)
        assert abs(a.ref_acc) < 1e-3 and not a.accelerating
        a.step()
        assert a.cruising
    a.stop()
    assert not a.cruising
    cycles_until(a, lambda: not a.moving)
    assert not a.cruising


def test_not_cruising_where_something_will_change():
    a = enabled(FREE)
    a.move_vel(100.0)  # the software limit lies ahead
    for _ in range(500):
        a.step()
        assert not a.cruising
    b = enabled({})
    b.set_ignore("swl", 1)
    b.move_vel(100.0)  # a limit switch lies ahead
    for _ in range(500):
        b.step()
    assert not b.cruising
    b.set_ignore("hwl", 1)
    assert b.cruising
    b.halt()
    assert not b.cruising  # halting
    b.resume()
    cycles_until(b, lambda: b.cruising)
    b.move_abs(b.ref_pos + 500.0)
    assert not b.cruising  # a move to a target
    for _ in range(200):
        b.step()
        assert not b.cruising


def test_a_rotary_axis_jogs_forever():
    a = enabled({"type": "rotary"})
    a.disable()
    a.set_rollover(360.0)
    a.enable()
    cycles_until(a, lambda: a.enabled)
    a.move_vel(720.0)
    cycles_until(a, lambda: a.cruising)
    for _ in range(2000):
        a.step()
        assert a.cruising
