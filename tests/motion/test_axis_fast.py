"""The fast path of the axis cycle gives bit-identical results to the general path."""

from __future__ import annotations

import random

import pytest

from motionvm.motion.axis import Axis
from motionvm.motion.axis_config import create
from motionvm.motion.axis_status import VARIABLES, AxisCommandError

DT = 0.001
DRIVE_ATTRS = ("controlword", "statusword", "target_position", "position_actual", "position_demand",
               "velocity_actual", "torque_actual", "following_error", "digital_inputs", "error_code",
               "mode_display", "_r", "_target_prev", "_x_prev", "_enc")  # fmt: skip


class _Generic(Axis):
    fast_path = False


def _state(a: Axis) -> tuple:
    d, m = a.drive, a.drive.mechanics
    return (
        tuple(a.variable(n) for n in VARIABLES),
        tuple(getattr(d, n) for n in DRIVE_ATTRS),
        (m.position, m.velocity, m.torque, m._demand, tuple(m._line)),
        (a.enabled, a.moving, a.in_pos, a.error_stop, a.last_error, a.resting, d.state),
    )


def _script(seed: int):
    """A random sequence of (cycle, method, args) commands."""
    rnd = random.Random(seed)
    cmds, cycle = [], 0
    for _ in range(40):
        cycle += rnd.randrange(1, 120)
        kind = rnd.choice(["abs", "abs", "rel", "vel", "stop", "scale", "vel_limit", "setpos", "halt", "resume",
                           "reset", "enable", "swrl", "fault", "ignore_swl", "ignore_swl"])  # fmt: skip
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
        }[kind]
        cmds.append((cycle, *args))
    return cmds


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize(
    "config",
    [{}, {"smooth_time_ms": 20, "drive": {"mechanics": {"model": "ideal", "delay_cycles": 3}}}],
)
def test_fast_and_general_paths_agree_bit_for_bit(seed, config):
    fast, slow = Axis(0, create(config), DT), _Generic(0, create(config), DT)
    assert fast.fast_path and not slow.fast_path
    script = _script(seed)
    fast.enable()
    slow.enable()
    cycle = 0
    for at, method, args in script:
        while cycle < at:
            fast.step()
            slow.step()
            cycle += 1
            assert _state(fast) == _state(slow), f"cycle {cycle}"
        for a in (fast, slow):
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


def test_the_fast_path_is_taken_for_profile_moves():
    a = Axis(0, create({}), DT)
    a.enable()
    for _ in range(20):
        a.step()
    a.move_abs(50.0)
    a.step()
    assert callable(a._fast_ok)


LIMITS_SCRIPT = [
    (10, "move_vel", (1500.0,)),  # runs into the software right limit
    (1500, "reset", ()),
    (1510, "set_ignore", ("swl", 1)),
    (1520, "move_vel", (800.0,)),  # now into the hardware right limit switch
    (2500, "reset", ()),
    (2510, "move_abs", (0.0,)),  # back off the switch
    (4000, "inject", ()),  # drive fault: disable
    (4100, "reset", ()),
    (4200, "enable", ()),
    (4300, "move_abs", (-30.0,)),
]


def test_fast_and_general_paths_agree_through_limits_and_faults():
    fast, slow = Axis(0, create({}), DT), _Generic(0, create({}), DT)
    seen = set()
    for a in (fast, slow):
        a.enable()
    cycle = 0
    for at, method, args in LIMITS_SCRIPT + [(5000, "stop", ())]:
        while cycle < at:
            fast.step()
            slow.step()
            cycle += 1
            assert _state(fast) == _state(slow), f"cycle {cycle}"
            seen.add(fast.last_error & 0xFFFF)
        for a in (fast, slow):
            if method == "inject":
                a.drive.inject_fault(0x1234)
            else:
                getattr(a, method)(*args)
    assert {0x07DA, 0x07EE, 0x03F2} <= seen  # SWRL, HWRL, drive fault


def _bits(a: Axis) -> str:
    """Every compared value, and the mechanics' demand velocity, to the bit (repr)."""
    return repr((_state(a), a.drive.mechanics._demand_vel, a.vel_fb))


@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize(
    "config",
    [
        {"drive": {"following_error_window": 8000, "max_torque": 40}},
        {"drive": {"mechanics": {"model": "ideal", "delay_cycles": 0}, "max_torque": 1}},
        {"drive": {"mechanics": {"model": "ideal", "delay_cycles": 2}, "max_torque": 0}},
    ],
)
def test_fast_path_values_computed_on_demand_agree(seed, config):
    """Following error faults, the internal limit bit and the values the fast cycle
    leaves to be computed when read (velocity, torque, demand, following error)."""
    fast, slow = Axis(0, create(config), DT), _Generic(0, create(config), DT)
    fast.enable()
    slow.enable()
    cycle = 0
    for at, method, args in _script(100 + seed):
        while cycle < at:
            fast.step()
            slow.step()
            cycle += 1
            assert _bits(fast) == _bits(slow), f"cycle {cycle}"
        for a in (fast, slow):
            if a.error_stop or not a.enabled:
                a.reset()
                try:
                    a.enable()
                except AxisCommandError:
                    pass
            if method == "inject":
                continue
            try:
                getattr(a, method)(*args)
            except AxisCommandError:
                pass
