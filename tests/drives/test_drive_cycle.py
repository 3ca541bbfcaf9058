"""The drive's cycle against its definition: inputs, lazily computed objects, status bits.

A step skips work whose outcome it knows (the sensors inside their quiet interval, the
following error under a window no int32 error exceeds) and leaves four objects and the
statusword's internal limit bit to be computed when read. These tests drive random
motions and compare every cycle, bit for bit, with the objects' definitions written out
here from the motor position the mechanics report.
"""

from __future__ import annotations

import math
import os

from drive_util import DT, enabled_csp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as hs

from motionvm.drives.objects import (
    DI_HOME_SWITCH,
    DI_INDEX_PULSE,
    DI_NEGATIVE_LIMIT,
    DI_POSITIVE_LIMIT,
    SW_FOLLOWING_ERROR,
    SW_INTERNAL_LIMIT,
    State,
    wrap_i32,
)

settings.register_profile(
    "drive-ci", max_examples=30, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)  # fmt: skip
settings.register_profile(
    "drive-thorough", max_examples=300, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)  # fmt: skip
PROFILE = settings.get_profile("drive-" + os.environ.get("HYPOTHESIS_PROFILE", "ci"))


def expected_inputs(config: dict, external: int, x_0: float, x_1: float) -> int:
    """0x60FD from its definition: switches at x_1, an index pulse passed from x_0."""
    bits = external
    if "negative_limit" in config and x_1 <= config["negative_limit"]:
        bits |= DI_NEGATIVE_LIMIT
    if "positive_limit" in config and x_1 >= config["positive_limit"]:
        bits |= DI_POSITIVE_LIMIT
    if "home_low" in config and config["home_low"] <= x_1 <= config["home_high"]:
        bits |= DI_HOME_SWITCH
    spacing = config.get("index_spacing")
    if spacing:
        offset = config.get("index_offset", 0.0)
        if math.floor((x_0 - offset) / spacing) != math.floor((x_1 - offset) / spacing):
            bits |= DI_INDEX_PULSE
    return bits


switch_configs = hs.fixed_dictionaries(
    {},
    optional={
        "negative_limit": hs.floats(-3e5, 0.0),
        "positive_limit": hs.floats(1.0, 3e5),
        "index_spacing": hs.sampled_from([1.0, 7.5, 2500.0, 100_000.0]),
        "index_offset": hs.floats(-5e4, 5e4),
        "mechanics": hs.sampled_from([{}, {"delay_cycles": 0}, {"delay_cycles": 3}]),
    },
)
home_bands = hs.one_of(hs.none(), hs.tuples(hs.floats(-2e5, 2e5), hs.floats(0.0, 5e4)))
# a walk of target steps [counts]: creeping, fast, crossing everything, jumping
walks = hs.lists(
    hs.tuples(hs.integers(-40_000, 40_000), hs.integers(1, 40), hs.sampled_from([0, 0, 1 << 17])),
    min_size=1,
    max_size=12,
)


@PROFILE
@given(switch_configs, home_bands, walks)
def test_digital_inputs_follow_their_definition_every_cycle(config, home, walk):
    if home is not None:
        config["home_low"], config["home_high"] = home[0], home[0] + home[1]
    drive = enabled_csp(config)
    m, sensors = drive.mechanics, drive.sensors
    x_0 = m.position
    for step, cycles, external in walk:
        if external != sensors.external:
            sensors.external = external  # the plant wiring sets an input
        for _ in range(cycles):
            drive.target_position = wrap_i32(drive.target_position + step)
            drive.step(DT)
            x_1 = m.position
            assert drive.digital_inputs == expected_inputs(config, external, x_0, x_1)
            x_0 = x_1


_SWITCH_KEYS = ("negative_limit", "positive_limit", "home_low", "home_high", "index_spacing")


@PROFILE
@given(switch_configs, home_bands, switch_configs, home_bands, walks, walks)
def test_digital_inputs_follow_switches_moved_between_two_walks(
    config, home, moved, moved_home, walk, then
):
    """The sensors' switch map and bands are rebuilt when a switch or the index is set:
    the inputs follow the new switches from the next cycle on, also where the motor
    stays inside a band found with the old ones (or had no switch at all before)."""
    for c, h in ((config, home), (moved, moved_home)):
        if h is not None:
            c["home_low"], c["home_high"] = h[0], h[0] + h[1]
    drive = enabled_csp(config)
    m, sensors = drive.mechanics, drive.sensors
    x_0 = m.position
    for part, switches in ((walk, config), (then, moved)):
        if switches is moved:  # the switches move while the motor stands
            for key in _SWITCH_KEYS:
                setattr(sensors, key, moved.get(key))
            sensors.index_offset = moved.get("index_offset", 0.0)
        for step, cycles, _ in part:
            for _ in range(cycles):
                drive.target_position = wrap_i32(drive.target_position + step)
                drive.step(DT)
                x_1 = m.position
                assert drive.digital_inputs == expected_inputs(switches, 0, x_0, x_1)
                x_0 = x_1


@PROFILE
@given(
    hs.sampled_from([0, 1, 2]),
    hs.floats(1e-6, 1e-3),
    hs.lists(hs.integers(-3_000_000, 3_000_000), min_size=1, max_size=60),
)
def test_objects_computed_when_read_equal_their_definition(delay, inertia, targets):
    """Velocity, torque, demand and following error in Operation enabled, read after
    every step, and the encoder wrap (the targets run through the int32 limit)."""
    drive = enabled_csp({"mechanics": {"delay_cycles": delay, "inertia": inertia},
                         "position": 2**31 - 2_000_000.0})  # fmt: skip
    m = drive.mechanics
    demand = float(drive.target_position)
    unwrapped = drive.target_position
    for target in targets:
        new = wrap_i32(unwrapped + target)
        demand += wrap_i32(new - drive.target_position)
        unwrapped += target
        drive.target_position = new
        drive.step(DT)
        enc = round(m.position)
        assert drive.position_actual == wrap_i32(enc)
        assert drive.velocity_actual == wrap_i32(round(m.velocity))
        torque = round(m.torque * 1000.0 / drive.rated_torque_nm)
        assert drive.torque_actual == max(-32768, min(32767, torque))
        assert drive.position_demand == wrap_i32(round(demand))
        assert drive.following_error == wrap_i32(round(demand) - enc)


@PROFILE
@given(
    hs.one_of(hs.integers(0, 3), hs.integers(4, 40_000)),
    hs.floats(1e-7, 1e-3),
    hs.lists(hs.integers(-20_000, 20_000), min_size=1, max_size=40),
)
def test_internal_limit_bit_is_the_torque_actual_at_max_torque(max_torque, inertia, targets):
    drive = enabled_csp({"mechanics": {"delay_cycles": 1, "inertia": inertia},
                         "max_torque": max_torque})  # fmt: skip
    for step in targets:
        drive.target_position = wrap_i32(drive.target_position + step)
        drive.step(DT)
        at_limit = abs(drive.torque_actual) >= drive.max_torque > 0
        assert bool(drive.statusword & SW_INTERNAL_LIMIT) == at_limit


@PROFILE
@given(
    hs.one_of(hs.integers(0, 50_000), hs.just(0x7FFFFFFF), hs.just(0xFFFFFFFF)),
    hs.sampled_from([0, 2, 5]),
    hs.lists(hs.integers(-30_000, 30_000), min_size=1, max_size=30),
)
def test_following_error_faults_exactly_beyond_its_window(window, delay, targets):
    drive = enabled_csp({"mechanics": {"delay_cycles": delay},
                         "following_error_window": window})  # fmt: skip
    for step in targets:
        drive.target_position = wrap_i32(drive.target_position + step)
        drive.step(DT)
        beyond = abs(drive.following_error) > window
        assert bool(drive.statusword & SW_FOLLOWING_ERROR) == beyond
        if beyond:
            assert drive.pending_fault is not None
            drive.step(DT)
            assert drive.state in (State.FAULT_REACTION_ACTIVE, State.FAULT)
            return
        assert drive.state is State.OPERATION_ENABLED


def test_a_probe_switched_on_makes_the_sensors_evaluate_again():
    """The quiet interval empties when the probe function or the inputs are written."""
    config = {"home_low": 5_000.0, "home_high": 6_000.0}
    drive = enabled_csp(config)
    for _ in range(3):
        drive.step(DT)
    sensors = drive.sensors
    assert sensors.quiet_low < drive.mechanics.position < sensors.quiet_high
    drive.tp_function = 0x0001 | 0x0010
    assert not sensors.quiet_low < drive.mechanics.position < sensors.quiet_high
    drive.tp_function = 0
    drive.step(DT)
    sensors.external = 1 << 17
    assert not sensors.quiet_low < drive.mechanics.position < sensors.quiet_high
    drive.step(DT)
    assert drive.digital_inputs == 1 << 17


@PROFILE
@given(
    hs.integers(1, 3000),
    hs.lists(
        hs.tuples(hs.integers(-200_000, 200_000), hs.sampled_from([None, 0, 1, 2])),
        min_size=1, max_size=40,
    ),
)  # fmt: skip
def test_the_internal_limit_bit_is_the_last_steps_until_the_next(max_torque, moves):
    """The statusword's internal limit bit is computed when read: it stays what the last
    step's torque and max_torque give, also when max_torque is written before the next
    step (to the torque actual itself or just above it); the base is the statusword but
    for that bit."""
    drive = enabled_csp({"mechanics": {"delay_cycles": 1, "inertia": 1e-5},
                         "max_torque": max_torque})  # fmt: skip
    for step, new_limit in moves:
        drive.target_position = wrap_i32(drive.target_position + step)
        drive.step(DT)
        at_limit = abs(drive.torque_actual) >= drive.max_torque > 0
        assert bool(drive.statusword & SW_INTERNAL_LIMIT) == at_limit
        if new_limit is not None:  # 0: no limit bit; 1: at the torque; 2: just above it
            drive.max_torque = new_limit and abs(drive.torque_actual) + new_limit - 1
        assert bool(drive.statusword & SW_INTERNAL_LIMIT) == at_limit
        assert drive.statusword & ~SW_INTERNAL_LIMIT == drive.statusword_base & ~SW_INTERNAL_LIMIT


def test_a_state_change_between_steps_shows_no_internal_limit_bit():
    """Local control taken and given back between steps: the statusword is the one set
    then, without a bit of the last step's torque, until the next step."""
    drive = enabled_csp({"mechanics": {"delay_cycles": 0}, "max_torque": 1})
    drive.target_position += 100_000
    drive.step(DT)
    assert drive.statusword & SW_INTERNAL_LIMIT and drive.mechanics.torque != 0.0
    drive.follow_local_demand(None)  # not under local control: no change
    assert drive.statusword & SW_INTERNAL_LIMIT
    drive.follow_local_demand(drive.mechanics.position)
    drive.follow_local_demand(None)
    assert drive.state is State.SWITCH_ON_DISABLED
    assert not drive.statusword & SW_INTERNAL_LIMIT
    drive.follow_local_demand(drive.mechanics.position)  # Operation enabled at once
    assert drive.state is State.OPERATION_ENABLED and drive.mechanics.torque != 0.0
    assert drive.statusword == drive.statusword_base
    assert not drive.statusword & SW_INTERNAL_LIMIT
