"""Tests of the simulated CiA 402 drive: state machine, modes, objects, faults, wrap."""

from __future__ import annotations

import itertools
import math

import pytest

from motionvm.drives.cia402 import Cia402Drive
from motionvm.drives.objects import (
    CONTROLWORD,
    DIGITAL_INPUTS,
    ERROR_CODE,
    FOLLOWING_ERROR_ACTUAL,
    MODES_DISPLAY,
    MODES_OF_OPERATION,
    POSITION_ACTUAL,
    STATUSWORD,
    SW_FAULT,
    SW_TARGET_REACHED,
    TARGET_POSITION,
    TARGET_TORQUE,
    TARGET_VELOCITY,
    TORQUE_ACTUAL,
    VELOCITY_ACTUAL,
    SdoAbort,
    State,
    state_of,
    wrap_i32,
)

DT = 0.001
SHUTDOWN, SWITCH_ON, ENABLE, DISABLE_VOLTAGE, QUICK_STOP = 0x06, 0x07, 0x0F, 0x00, 0x02
FAULT_RESET = 0x80


def make(**config) -> Cia402Drive:
    return Cia402Drive.create(config)


def command(drive: Cia402Drive, controlword: int, cycles: int = 1) -> State:
    drive.write(CONTROLWORD, 0, controlword)
    for _ in range(cycles):
        drive.step(DT)
    assert state_of(drive.read(STATUSWORD)) is drive.state
    return drive.state


def boot(drive: Cia402Drive) -> None:
    for _ in range(drive.boot_cycles):
        drive.step(DT)
    assert drive.state is State.SWITCH_ON_DISABLED


def enable(drive: Cia402Drive, mode: int = 8) -> None:
    drive.write(MODES_OF_OPERATION, 0, mode)
    drive.write(TARGET_POSITION, 0, drive.read(POSITION_ACTUAL))
    command(drive, SHUTDOWN)
    command(drive, ENABLE, drive.switch_on_cycles + drive.enable_cycles)
    assert drive.state is State.OPERATION_ENABLED


def test_boot_goes_from_not_ready_to_switch_on_disabled():
    drive = make(boot_cycles=3)
    assert drive.state is State.NOT_READY_TO_SWITCH_ON and drive.read(STATUSWORD) == 0
    drive.step(DT)
    drive.step(DT)
    assert drive.state is State.NOT_READY_TO_SWITCH_ON
    drive.step(DT)
    assert drive.state is State.SWITCH_ON_DISABLED
    assert drive.read(STATUSWORD) & 0x4F == 0x40


STATES = {
    "SOD": [],
    "RTSO": [(SHUTDOWN, 1)],
    "SO": [(SHUTDOWN, 1), (SWITCH_ON, 2)],
    "OE": [(SHUTDOWN, 1), (SWITCH_ON, 2), (ENABLE, 4)],
}


@pytest.mark.parametrize(
    "start, controlword, expected",
    [
        ("SOD", SHUTDOWN, State.READY_TO_SWITCH_ON),  # 2
        ("RTSO", SWITCH_ON, State.SWITCHED_ON),  # 3
        ("SO", ENABLE, State.OPERATION_ENABLED),  # 4
        ("OE", SWITCH_ON, State.SWITCHED_ON),  # 5 disable operation
        ("SO", SHUTDOWN, State.READY_TO_SWITCH_ON),  # 6
        ("RTSO", DISABLE_VOLTAGE, State.SWITCH_ON_DISABLED),  # 7
        ("RTSO", QUICK_STOP, State.SWITCH_ON_DISABLED),  # 7
        ("OE", SHUTDOWN, State.READY_TO_SWITCH_ON),  # 8
        ("OE", DISABLE_VOLTAGE, State.SWITCH_ON_DISABLED),  # 9
        ("SO", DISABLE_VOLTAGE, State.SWITCH_ON_DISABLED),  # 10
        ("SO", QUICK_STOP, State.SWITCH_ON_DISABLED),  # 10
        ("OE", QUICK_STOP, State.QUICK_STOP_ACTIVE),  # 11
        ("SOD", SWITCH_ON, State.SWITCH_ON_DISABLED),  # not a valid command here
        ("SOD", ENABLE, State.SWITCH_ON_DISABLED),
        ("RTSO", SHUTDOWN, State.READY_TO_SWITCH_ON),
    ],
)
def test_state_machine_transitions(start, controlword, expected):
    drive = make(mechanics={"model": "ideal"}, quick_stop_option=6)
    boot(drive)
    drive.write(MODES_OF_OPERATION, 0, 8)
    for cw, cycles in STATES[start]:
        command(drive, cw, cycles)
    cycles = {State.SWITCHED_ON: 2, State.OPERATION_ENABLED: 4}.get(expected, 1)
    assert command(drive, controlword, cycles) is expected


def test_enable_takes_the_configured_cycles():
    drive = make(switch_on_cycles=3, enable_cycles=5)
    boot(drive)
    assert command(drive, SHUTDOWN) is State.READY_TO_SWITCH_ON  # at once
    drive.write(CONTROLWORD, 0, ENABLE)  # switch on + enable operation
    seen = []
    for _ in range(8):
        drive.step(DT)
        seen.append(drive.state)
    assert seen == [State.READY_TO_SWITCH_ON] * 2 + [State.SWITCHED_ON] * 5 + [
        State.OPERATION_ENABLED
    ]
    assert drive.read(STATUSWORD) & 0x6F == 0x27


def test_withdrawn_command_restarts_the_enable_delay():
    drive = make(enable_cycles=4)
    boot(drive)
    command(drive, SHUTDOWN)
    command(drive, SWITCH_ON, 2)
    command(drive, ENABLE, 3)
    command(drive, SWITCH_ON, 1)  # enable withdrawn before the 4th cycle
    assert command(drive, ENABLE, 3) is State.SWITCHED_ON
    assert command(drive, ENABLE, 1) is State.OPERATION_ENABLED


def test_quick_stop_ramps_down_then_switches_on_disabled():
    drive = make(quick_stop_decel=1_000_000, quick_stop_option=2)
    boot(drive)
    enable(drive, mode=9)
    drive.write(TARGET_VELOCITY, 0, 100_000)
    command(drive, ENABLE, 5)
    assert drive.read(VELOCITY_ACTUAL) == 100_000
    velocities = []
    drive.write(CONTROLWORD, 0, QUICK_STOP)
    while drive.state is not State.SWITCH_ON_DISABLED:
        drive.step(DT)
        velocities.append(drive.read(VELOCITY_ACTUAL))
        assert len(velocities) < 1000
    # 100000 counts/s at 1e6 counts/s^2: 100 cycles, 1000 counts/s less each
    assert len(velocities) == 100
    assert all(a - b == 1000 for a, b in itertools.pairwise(velocities))


@pytest.mark.parametrize("option", [5, 6])
def test_quick_stop_option_5_6_stays_and_can_be_re_enabled(option):
    drive = make(quick_stop_option=option)
    boot(drive)
    enable(drive)
    assert command(drive, QUICK_STOP, 3) is State.QUICK_STOP_ACTIVE
    assert drive.read(STATUSWORD) & 0x6F == 0x07
    assert drive.read(STATUSWORD) & SW_TARGET_REACHED
    assert command(drive, ENABLE) is State.OPERATION_ENABLED  # 16


def test_quick_stop_active_disable_voltage():
    drive = make(quick_stop_option=6)
    boot(drive)
    enable(drive)
    command(drive, QUICK_STOP)
    assert command(drive, DISABLE_VOLTAGE) is State.SWITCH_ON_DISABLED  # 12


def test_fault_needs_a_reset_edge():
    drive = make()
    boot(drive)
    enable(drive)
    drive.inject_fault(0x2310)
    drive.step(DT)
    assert drive.state is State.FAULT  # at rest: the fault reaction ends at once
    sw = drive.read(STATUSWORD)
    assert sw & SW_FAULT and state_of(sw) is State.FAULT
    assert drive.read(ERROR_CODE) == 0x2310
    assert command(drive, ENABLE, 3) is State.FAULT  # ignored
    assert command(drive, FAULT_RESET) is State.SWITCH_ON_DISABLED  # 15, rising edge
    assert drive.read(ERROR_CODE) == 0
    drive.inject_fault(0x2310)
    drive.step(DT)
    assert command(drive, FAULT_RESET, 3) is State.FAULT  # bit 7 held: no new edge
    command(drive, 0x00)
    assert command(drive, FAULT_RESET) is State.SWITCH_ON_DISABLED


def test_fault_reaction_while_moving_ramps_down_first():
    drive = make(quick_stop_decel=2_000_000)
    boot(drive)
    enable(drive, mode=9)
    drive.write(TARGET_VELOCITY, 0, 200_000)
    command(drive, ENABLE, 3)
    drive.inject_fault(0x5400)
    states = []
    for _ in range(200):
        drive.step(DT)
        states.append(drive.state)
    n_reaction = states.count(State.FAULT_REACTION_ACTIVE)
    assert n_reaction == 99  # 100 cycles of ramp, the last one ends in Fault
    assert drive.read(STATUSWORD) & 0x4F == 0x08
    assert drive.read(VELOCITY_ACTUAL) == 0


def test_encoder_loss_freezes_feedback_and_blocks_reset():
    drive = make()
    boot(drive)
    enable(drive, mode=9)
    drive.write(TARGET_VELOCITY, 0, 50_000)
    command(drive, ENABLE, 10)
    frozen = drive.read(POSITION_ACTUAL)
    drive.encoder_loss()
    drive.step(DT)
    assert drive.state is State.FAULT and drive.read(ERROR_CODE) == 0x7305
    assert drive.read(POSITION_ACTUAL) == frozen
    assert command(drive, FAULT_RESET) is State.FAULT
    drive.encoder_restore()
    command(drive, 0)
    assert command(drive, FAULT_RESET) is State.SWITCH_ON_DISABLED


@pytest.mark.parametrize("delay", [0, 1, 4])
def test_csp_ideal_tracks_with_exact_delay(delay):
    drive = make(mechanics={"model": "ideal", "delay_cycles": delay})
    boot(drive)
    enable(drive)
    targets = [round(50_000 * math.sin(k / 30.0)) for k in range(300)]
    actual = []
    for t in targets:
        drive.write(TARGET_POSITION, 0, t)
        drive.step(DT)
        actual.append(drive.read(POSITION_ACTUAL))
    assert actual[delay:] == targets[: len(targets) - delay]
    assert drive.read(FOLLOWING_ERROR_ACTUAL) == targets[-1] - actual[-1]
    assert drive.read(MODES_DISPLAY) == 8


def test_csp_servo_following_error_bounded_and_settles():
    bandwidth, damping = 40.0, 0.7
    drive = make(mechanics={"model": "servo", "bandwidth": bandwidth, "damping": damping})
    boot(drive)
    enable(drive)
    wn = 2 * math.pi * bandwidth
    v = 200_000.0  # [counts/s] for 0.5 s, then hold
    errors = []
    for k in range(1, 1001):
        target = round(v * min(k, 500) * DT)
        drive.write(TARGET_POSITION, 0, target)
        drive.step(DT)
        errors.append(drive.read(FOLLOWING_ERROR_ACTUAL))
    bound = 2 * damping * v / wn * 1.1  # ramp error 2 zeta v / wn plus its overshoot
    assert max(abs(e) for e in errors) <= bound
    assert errors[499] == pytest.approx(2 * damping * v / wn, abs=2)
    t_settle = 4.0 / (damping * wn) * 1.25  # 2 % band
    assert all(abs(e) <= 0.02 * bound for e in errors[500 + int(t_settle / DT) :])


def test_csv_and_cst_modes():
    drive = make(mechanics={"model": "servo", "bandwidth": 50.0, "inertia": 1e-4}, rated_torque=0.5)
    boot(drive)
    enable(drive, mode=9)
    drive.write(TARGET_VELOCITY, 0, -30_000)
    command(drive, ENABLE, 300)
    assert drive.read(VELOCITY_ACTUAL) == -30_000
    drive.write(MODES_OF_OPERATION, 0, 10)
    drive.write(TARGET_TORQUE, 0, 100)  # 10 % of 0.5 N*m
    v_0 = drive.mechanics.velocity
    command(drive, ENABLE, 100)
    assert drive.read(MODES_DISPLAY) == 10
    assert drive.read(TORQUE_ACTUAL) == 100
    alpha = 0.05 / 1e-4 * (1 << 17) / (2 * math.pi)  # [counts/s^2]
    assert drive.mechanics.velocity - v_0 == pytest.approx(alpha * 0.1, rel=1e-9)


def test_encoder_wraps_and_csp_crosses_the_wrap_point():
    start = 2**31 - 5_000
    drive = make(mechanics={"model": "ideal", "delay_cycles": 1}, position=start)
    boot(drive)
    assert drive.read(POSITION_ACTUAL) == start
    enable(drive)
    previous = drive.read(POSITION_ACTUAL)
    for k in range(1, 101):
        drive.write(TARGET_POSITION, 0, wrap_i32(start + 100 * k))
        drive.step(DT)
        actual = drive.read(POSITION_ACTUAL)
        assert wrap_i32(actual - previous) in (0, 100)
        assert -(2**31) <= actual < 2**31
        previous = actual
    assert previous == wrap_i32(start + 9_900) and previous < 0
    assert drive.read(FOLLOWING_ERROR_ACTUAL) == 100
    assert drive.read(VELOCITY_ACTUAL) == 100_000


def test_digital_inputs_and_index_touch_probe():
    drive = make(
        negative_limit=-1_000, positive_limit=10_000, home_low=4_000, home_high=4_500,
        index_spacing=2_500, index_offset=300,
    )  # fmt: skip
    boot(drive)
    enable(drive, mode=9)
    drive.write(0x60B8, 0, 0x0001 | 0x0004 | 0x0010)  # TP1 on, index source, rising edge
    drive.write(TARGET_VELOCITY, 0, 100_000)  # 100 counts per cycle
    seen, index_cycles = set(), []
    for _k in range(120):
        drive.step(DT)
        di = drive.read(DIGITAL_INPUTS)
        seen.add(di & 0x7)
        if di & (1 << 16):
            index_cycles.append(drive.read(POSITION_ACTUAL))
    assert seen >= {0, 0b100, 0b010}
    assert drive.read(0x60B9) & 0b11 == 0b11
    assert drive.read(0x60BA) == 300  # the first index passed: exact, not sampled
    assert len(index_cycles) == 5  # 300, 2800, 5300, 7800, 10300
    drive.write(0x60B8, 0, 0x0001 | 0x0004)  # re-arm: the edge bit off for one cycle
    drive.step(DT)
    assert drive.read(0x60B9) & 0b11 == 0b01
    drive.write(0x60B8, 0, 0x0001 | 0x0004 | 0x0010)
    for _ in range(30):
        drive.step(DT)
    assert drive.read(0x60BA) == 12_800


def test_home_switch_edges_latch_on_touch_probe_1():
    drive = make(home_low=1_000, home_high=1_600)
    boot(drive)
    enable(drive, mode=9)
    drive.write(0x60B8, 0, 0x0001 | 0x0010 | 0x0020)  # TP1 on, probe input, both edges
    drive.write(TARGET_VELOCITY, 0, 70_000)
    command(drive, ENABLE, 40)
    assert (drive.read(0x60BA), drive.read(0x60BB)) == (1_000, 1_600)
    assert drive.read(0x60B9) & 0b111 == 0b111


def test_following_error_window_faults():
    drive = make(mechanics={"model": "ideal", "delay_cycles": 2}, following_error_window=150)
    boot(drive)
    enable(drive)
    for k in range(1, 10):
        drive.write(TARGET_POSITION, 0, 100 * k)
        drive.step(DT)
    assert drive.state is State.FAULT and drive.read(ERROR_CODE) == 0x8611


def test_sdo_access_errors():
    drive = make()
    with pytest.raises(SdoAbort, match="0x06010002.*Statusword"):
        drive.write(STATUSWORD, 0, 1)
    with pytest.raises(SdoAbort, match="0x06020000.*0x1234"):
        drive.read(0x1234)
    with pytest.raises(SdoAbort, match="0x06090011"):
        drive.read(CONTROLWORD, 1)
    with pytest.raises(SdoAbort, match=r"0x06090030.*70000 is not in 0\.\.65535"):
        drive.write(CONTROLWORD, 0, 70_000)
    with pytest.raises(SdoAbort, match="mode of operation 1 is not supported"):
        drive.write(MODES_OF_OPERATION, 0, 1)
    drive.write(MODES_OF_OPERATION, 0, 6)
    assert drive.read(MODES_OF_OPERATION) == 6 and drive.read(0x6502) == 0x3A0


def test_homing_mode_is_accepted_and_holds():
    drive = make(mechanics={"model": "servo"}, position=1234)
    boot(drive)
    enable(drive, mode=6)
    command(drive, ENABLE, 50)
    assert drive.read(MODES_DISPLAY) == 6 and drive.read(POSITION_ACTUAL) == 1234


@pytest.mark.parametrize(
    "config, message",
    [
        ({"enable_cycles": 0}, "drive: enable_cycles = 0 is not an integer >= 1"),
        ({"enabel_cycles": 3}, "drive: unknown key 'enabel_cycles' = 3"),
        ({"rated_torque": -1}, "drive: rated_torque = -1.0 is not a finite number > 0"),
        ({"quick_stop_option": 9}, "quick_stop_option = 9 is not in 0..8"),
        ({"home_low": 5}, "home_low and home_high must be given together"),
        ({"home_low": 5, "home_high": 1}, "home_low = 5.0 is above home_high = 1.0"),
        ({"mechanics": {"model": "servo", "damping": 0}}, "mechanics 'servo': damping = 0.0"),
        ({"mechanics": "servo"}, "mechanics: the configuration must be a table"),
    ],
)
def test_bad_config_is_rejected_naming_key_and_value(config, message):
    with pytest.raises(ValueError, match=message):
        Cia402Drive.create(config)
