"""Fault reactions of table 5.1.1.4, fault_status bits and last errors; property tests of
the fault reactions and of the in-position logic (Hypothesis, profiles `dev`/`ci`)."""

from __future__ import annotations

import itertools
import os

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as hs

from motionvm.drives.objects import State
from motionvm.motion import axis_status as st
from motionvm.motion.axis import Axis
from motionvm.motion.axis_config import create
from motionvm.motion.axis_status import AxisCommandError
from motionvm.motion.tolerances import limit_slack

DT = 0.001
settings.register_profile("axis-ci", max_examples=30, derandomize=True, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])  # fmt: skip
settings.register_profile("axis-thorough", max_examples=300, derandomize=True, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])  # fmt: skip
PROFILE = settings.get_profile("axis-" + os.environ.get("HYPOTHESIS_PROFILE", "ci"))


def enabled(**config) -> Axis:
    a = Axis(3, create(config), DT)
    a.enable()
    while not a.enabled:
        a.step()
    return a


def run(a: Axis, cycles: int) -> None:
    for _ in range(cycles):
        a.step()


def test_software_limit_stops_at_kill_deceleration_and_error_stops_until_reset():
    a = enabled(sw_right=100.0, kill_dec=50_000.0)
    a.move_vel(1000.0)
    vels = []
    while not a.error_stop:
        a.step()
    while a.moving:
        a.step()
        vels.append(a.ref_vel)
    decel = max(-(v1 - v0) / DT for v0, v1 in itertools.pairwise(vels))
    assert decel <= 50_000.0 * (1 + 1e-9) + limit_slack(50_000.0, 120.0, DT, 2)
    assert len(vels) <= 1000.0 / 50_000.0 / DT + 2
    assert a.enabled
    assert a.fault_status == st.FS_ERROR_STOP | st.FS_SW_RIGHT
    assert a.last_error == st.axis_error(st.SWRL, 3) and (a.last_error & 0xFFFFFFFF) == 0x830307DA
    with pytest.raises(AxisCommandError) as exc:
        a.move_abs(0.0)
    assert exc.value.code == st.CMD_INVALID_ERROR_STATE
    a.reset()
    assert not a.error_stop and a.fault_status == 0
    a.move_abs(0.0)  # back inside is allowed
    run(a, 600)
    assert a.in_pos and a.ref_pos == 0.0


def test_a_target_beyond_the_soft_limits_is_refused_unless_ignored():
    a = enabled()
    with pytest.raises(AxisCommandError) as exc:
        a.move_abs(1000.5)
    assert exc.value.code == st.CMD_INVALID_POS
    a.set_ignore("swl", 1)
    a.move_abs(1000.5)
    run(a, 3000)
    assert a.in_pos and not a.error_stop


def test_hardware_limit_switch_stops_the_axis_and_stays_set_while_pressed():
    a = enabled(sw_right=2000.0, hw_right=30.0)
    a.move_vel(500.0)
    run(a, 200)
    assert a.error_stop and not a.moving
    assert a.fault_status == st.FS_ERROR_STOP | st.FS_HW_RIGHT
    assert a.last_error == st.axis_error(st.HWRL, 3)
    assert a.variable("di_bit_HWRL") == 1
    a.reset()
    assert a.fault_status == st.FS_HW_RIGHT  # still on the switch
    a.move_rel(5.0)  # further in: stopped again
    run(a, 50)
    assert a.error_stop
    a.reset()
    a.move_abs(0.0)
    run(a, 500)
    assert a.in_pos and a.fault_status == 0


def test_ignore_hwl_suppresses_the_stop_but_still_reports_the_switch():
    a = enabled(sw_right=2000.0, hw_right=30.0)
    a.set_ignore("hwl", 1)
    a.move_abs(40.0)
    run(a, 500)
    # no limit stop, but IsHWRL (fault_status bit) still shows the switch (manual 5.4.9)
    assert a.in_pos and not a.error_stop and a.fault_status == st.FS_HW_RIGHT
    assert a.variable("di_bit_HWRL") == 1


def test_position_error_disables_the_axis():
    a = enabled(
        max_pos_err=0.5, drive={"mechanics": {"model": "servo", "bandwidth": 5.0, "damping": 0.7}}
    )
    a.move_abs(200.0)
    run(a, 300)
    assert a.error_stop and not a.enabled
    assert a.fault_status & st.FS_POSITION_ERROR and a.fault_status & st.FS_ERROR_STOP
    assert a.last_error == st.axis_error(st.PERR, 3)
    run(a, 2)
    assert a.drive.state is State.SWITCH_ON_DISABLED


def test_ignore_pe_lets_the_servo_lag():
    a = enabled(
        max_pos_err=0.5, drive={"mechanics": {"model": "servo", "bandwidth": 5.0, "damping": 0.7}}
    )
    a.set_ignore("pe", 1)
    a.move_abs(200.0)
    run(a, 300)
    assert not a.error_stop and a.enabled


def test_drive_fault_disables_and_reset_clears_it():
    a = enabled()
    a.move_vel(100.0)
    run(a, 10)
    a.drive.inject_fault(0x2310)
    run(a, 3)
    assert not a.enabled and a.error_stop
    assert a.fault_status & st.FS_DRIVE_FAULT
    assert a.last_error == st.axis_error(st.DRIVE_FAULT, 3)
    assert a.drive.error_code == 0x2310
    with pytest.raises(AxisCommandError):
        a.enable()
    a.reset()
    run(a, 2)
    assert a.error_stop  # the drive's fault reaction is still braking
    run(a, 200)
    assert not a.error_stop and a.fault_status == 0 and a.drive.error_code == 0
    a.enable()
    run(a, 20)
    assert a.enabled


def test_encoder_loss_keeps_the_fault_until_the_encoder_is_back():
    a = enabled()
    a.drive.encoder_loss()
    run(a, 3)
    assert a.error_stop
    a.reset()
    run(a, 3)
    assert a.error_stop and a.fault_status & st.FS_DRIVE_FAULT
    run(a, 1000)
    assert a.error_stop and a.last_error == st.axis_error(st.DRIVE_CLEAR_ERROR_TOUT, 3)
    a.drive.encoder_restore()
    a.reset()
    run(a, 3)
    assert not a.error_stop


def test_enable_times_out_with_the_manuals_error():
    a = Axis(0, create({"enable_timeout_ms": 20, "drive": {"enable_cycles": 500}}), DT)
    a.enable()
    run(a, 60)
    assert not a.enabled
    assert a.last_error == st.axis_error(st.DRIVE_ENABLE_TOUT, 0)


# ---- properties -------------------------------------------------------------------


@PROFILE
@given(
    hs.floats(50.0, 2000.0),  # jog velocity
    hs.floats(2_000.0, 500_000.0),  # kill deceleration
    hs.floats(5.0, 900.0),  # software right limit
    hs.sampled_from([0.0, 10.0, 50.0]),  # smooth time [ms]
)
def test_software_limit_reaction_never_exceeds_the_kill_deceleration(v, kill, limit, ts):
    a = enabled(sw_right=limit, kill_dec=kill, max_vel=2000.0, max_acc=50_000.0, smooth_time_ms=ts)
    a.move_vel(v)
    while not a.error_stop:
        a.step()
    trigger = a.ref_pos
    v_0 = a.ref_vel
    prev = v_0
    while a.moving:
        a.step()
        assert -(a.ref_vel - prev) / DT <= kill + limit_slack(kill, 1000.0, DT, 2) + 1e-6 * kill
        prev = a.ref_vel
    assert a.fault_status & st.FS_SW_RIGHT and a.fault_status & st.FS_ERROR_STOP and a.enabled
    # the T-curve (ahead of the smoothed output by up to Ts) runs at most at v
    assert a.ref_pos - trigger <= v * v / (2 * kill) + v * (DT + ts / 1000.0) + 1e-6


@PROFILE
@given(
    hs.floats(-300.0, 300.0),  # target
    hs.floats(0.001, 0.1),  # in-position radius
    hs.integers(0, 20),  # debounce [ms]
    hs.floats(5.0, 80.0),  # servo bandwidth
    hs.floats(0.3, 1.2),  # damping
)
def test_in_position_means_not_moving_and_inside_the_radius_for_the_debounce_time(
    target, radius, debounce, bandwidth, damping
):
    a = enabled(inpos_radius=radius, inpos_debounce_ms=debounce, max_pos_err=1000.0,
                drive={"mechanics": {"model": "servo", "bandwidth": bandwidth, "damping": damping}})  # fmt: skip
    a.move_abs(target)
    assert a.moving and not a.in_pos
    inside = 0
    for _ in range(3000):
        a.step()
        ok = not a.moving and abs(a.ref_pos - a.pos_fb) <= radius
        inside = inside + 1 if ok else 0
        assert a.in_pos == (inside > debounce), (inside, debounce)
        if a.in_pos:
            break
    assert a.in_pos and a.ref_pos == target
