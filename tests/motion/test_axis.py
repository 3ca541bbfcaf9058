"""Axis (manual 5.1-5.3): enable through the drive, moves, in-position, modes, buffer, settings."""

from __future__ import annotations

import math

import pytest

from motionvm.drives.objects import State
from motionvm.motion import axis_status as st
from motionvm.motion.axis import Axis
from motionvm.motion.axis_config import create
from motionvm.motion.axis_status import AxisCommandError
from motionvm.motion.tcurve import rest_to_rest_time

DT = 0.001


def make(**config) -> Axis:
    return Axis(0, create(config), DT)


def enabled(**config) -> Axis:
    a = make(**config)
    a.enable()
    run_until(a, lambda: a.enabled)
    return a


def run_until(a: Axis, cond, limit: int = 100_000) -> int:
    """Step until cond() holds; the number of cycles it took."""
    for n in range(limit):
        if cond():
            return n
        a.step()
    raise AssertionError("condition never held")


def test_enable_walks_the_drive_state_machine_and_takes_its_cycles():
    a = make(drive={"boot_cycles": 2, "switch_on_cycles": 3, "enable_cycles": 5})
    a.enable()
    states = []
    while not a.enabled:
        a.step()
        states.append(a.drive.state)
    assert states[-1] is State.OPERATION_ENABLED
    assert State.READY_TO_SWITCH_ON in states and State.SWITCHED_ON in states
    assert len(states) >= 3 + 5
    assert a.motion_status & st.MS_ENABLED


def test_disable_powers_off_at_once_and_clears_the_plan():
    a = enabled()
    a.move_abs(200.0)
    for _ in range(50):
        a.step()
    a.disable()
    assert not a.enabled and not a.moving
    a.step()
    assert a.drive.state is State.SWITCH_ON_DISABLED


def test_a_move_reaches_its_target_in_the_closed_form_time():
    a = enabled()
    a.move_abs(123.456)
    cycles = run_until(a, lambda: not a.moving)
    t = rest_to_rest_time(123.456, 1000.0, 10000.0, 10000.0)
    assert abs(cycles * DT - t) <= 2 * DT
    run_until(a, lambda: a.in_pos)
    assert a.ref_pos == 123.456
    assert abs(a.pos_fb - 123.456) <= 1.0 / a.cpu
    assert a.move_time_ms == pytest.approx(t * 1000.0, abs=2.0)


@pytest.mark.parametrize("smooth_ms", [0, 1, 2, 50, 500])
def test_move_time_is_the_t_curve_time_plus_the_whole_smooth_time(smooth_ms):
    # Manual 5.1: total time T = T-curve time Ta + smooth time Ts (GetMoveTime, 5.3.17),
    # Ts as the axis has it (GetSMTime: whole cycles, 1 ms at a 1 ms cycle is none).
    a = enabled()
    a.set_smooth_time(smooth_ms)
    assert a.smooth_time_ms == (0 if smooth_ms == 1 else smooth_ms)
    a.move_abs(100.0)
    run_until(a, lambda: a.in_pos)
    t_a = math.ceil(rest_to_rest_time(100.0, 1000.0, 10000.0, 10000.0) / DT - 1e-9) * DT
    assert a.move_time_ms == pytest.approx(t_a * 1000.0 + a.smooth_time_ms)


@pytest.mark.parametrize("smooth_ms", [0, 20])
def test_set_smooth_time_is_accepted_in_the_cycle_the_axis_stops(smooth_ms):
    # Manual 5.3.16: SetSMTime is refused while the axis moves, so once IsMoving is 0.
    a = enabled()
    a.set_smooth_time(smooth_ms)
    a.move_abs(10.0)
    run_until(a, lambda: not a.moving)
    a.set_smooth_time(30)
    assert a.smooth_time_ms == 30 and a.ref_pos == 10.0
    a.move_abs(0.0)
    with pytest.raises(AxisCommandError):
        a.set_smooth_time(40)


def test_an_accepted_move_is_moving_and_not_in_position_in_the_same_cycle():
    a = enabled()
    run_until(a, lambda: a.in_pos)
    a.move_abs(10.0)
    assert a.moving and not a.in_pos  # before any motion cycle ran
    assert a.motion_status & st.MS_MOVING and not a.motion_status & st.MS_IN_POSITION
    a.move_rel(0.0)  # also a move that does not move
    assert a.moving and not a.in_pos


def test_in_position_needs_the_radius_for_the_debounce_time_region_ii_then_iii():
    # a slow servo lags: the plan ends (region II) before the feedback is in the radius
    a = enabled(inpos_radius=0.005, inpos_debounce_ms=5.0,
                drive={"mechanics": {"model": "servo", "bandwidth": 20.0, "damping": 0.7}})  # fmt: skip
    run_until(a, lambda: a.in_pos)
    a.move_abs(20.0)
    run_until(a, lambda: not a.moving)
    region_ii = 0
    inside = 0
    while not a.in_pos:
        assert not a.moving
        region_ii += 1
        a.step()
        inside = inside + 1 if abs(a.ref_pos - a.pos_fb) <= 0.005 else 0
    assert region_ii > 5
    assert inside == 6  # 5 ms of debounce after the first cycle inside
    assert a.settling_time_ms == pytest.approx(region_ii, abs=1.0)


def test_velocity_mode_jogs_and_stop_brakes_at_the_profile_deceleration():
    a = enabled()
    a.move_vel(-300.0)
    for _ in range(200):
        a.step()
    assert a.ref_vel == pytest.approx(-300.0)
    assert a.accelerating is False
    a.stop()
    n = run_until(a, lambda: not a.moving)
    assert n == pytest.approx(300.0 / 10000.0 / DT, abs=2)
    assert not a.error_stop


def test_moves_are_refused_while_stopping_with_the_manuals_code():
    a = enabled()
    a.move_vel(500.0)
    for _ in range(100):
        a.step()
    a.stop()
    with pytest.raises(AxisCommandError) as exc:
        a.move_abs(0.0)
    assert exc.value.code == st.CMD_INVALID_STOPPING


def test_halt_and_resume():
    a = enabled()
    a.move_abs(300.0)
    for _ in range(100):
        a.step()
    a.halt()
    run_until(a, lambda: a.ref_vel == 0.0 and a.pg.is_halted)
    held = a.ref_pos
    for _ in range(50):
        a.step()
    assert a.ref_pos == held and a.moving and not a.in_pos
    a.resume()
    run_until(a, lambda: a.in_pos)
    assert a.ref_pos == 300.0


def test_velocity_scale_zero_keeps_a_new_move_waiting():
    a = enabled()
    a.set_vel_scale(0.0)
    a.move_abs(5.0)
    for _ in range(20):
        a.step()
    assert a.moving and a.ref_pos == 0.0
    a.set_vel_scale(50.0)
    run_until(a, lambda: a.in_pos)
    assert a.ref_pos == 5.0
    assert max(abs(a.ref_vel), 0.0) <= 500.0


def test_on_the_fly_target_and_limit_changes():
    a = enabled()
    a.move_abs(500.0)
    peak = 0.0
    for k in range(150):
        a.step()
        peak = max(peak, abs(a.ref_vel))
        if k == 60:
            a.set_vel(400.0)
        if k == 100:
            a.move_abs(-50.0)
    run_until(a, lambda: a.in_pos)
    assert a.ref_pos == -50.0


def test_buffer_mode_queues_moves_and_counts_them():
    a = enabled()
    a.set_buffer_mode(1)
    a.move_abs(10.0)
    a.move_abs(20.0)
    a.move_rel(5.0)
    assert a.cmd_num == 2
    with pytest.raises(AxisCommandError) as exc:
        a.set_buffer_mode(0)
    assert exc.value.code == st.CMD_INVALID_SETBUFFERMODE
    targets = [a.pg.target]
    while a.moving:
        before = a.ref_pos
        a.step()
        if a.pg.target != targets[-1]:
            targets.append(a.pg.target)
            assert before == targets[-2]  # each started where the one before ended
    assert targets == [10.0, 20.0, 25.0]
    assert a.cmd_num == 0 and a.ref_pos == 25.0


def test_buffer_mode_0_aborts_the_move_in_progress():
    a = enabled()
    a.move_abs(100.0)
    for _ in range(30):
        a.step()
    a.move_abs(-10.0)
    run_until(a, lambda: a.in_pos)
    assert a.ref_pos == -10.0


def test_set_pos_changes_the_offset_not_the_motor():
    a = enabled()
    a.move_abs(40.0)
    run_until(a, lambda: a.in_pos)
    counts = a.drive.position_actual
    a.set_pos(0.0)
    assert a.pos_fb == 0.0 and a.pos_offset == pytest.approx(40.0)
    assert a.variable("pos_fb_raw") == pytest.approx(40.0)
    for _ in range(5):
        a.step()
    assert a.drive.position_actual == counts
    a.move_abs(10.0)
    run_until(a, lambda: a.in_pos)
    assert a.pos_fb == pytest.approx(10.0) and a.variable("offset_pos_out") == pytest.approx(50.0)


def test_set_pos_at_rest_on_a_target_makes_the_reference_read_exactly_the_position():
    # 0.1 * 3 is 0.30000000000000004: the reference, while the feedback is 3000 counts,
    # 0.3. Within half a count they are one position: after SetPos(a, 0) GetRefPos reads
    # exactly 0.0 (the homing example of manual 20.1.2 tests GetRefPos(axis) == 0.0).
    a = enabled()
    a.move_abs(0.1 * 3)
    run_until(a, lambda: a.in_pos)
    assert a.ref_pos != a.pos_fb
    a.set_pos(0.0)
    assert a.ref_pos == 0.0 and a.pos_fb == 0.0


def test_set_pos_is_refused_while_moving():
    a = enabled()
    a.move_abs(40.0)
    with pytest.raises(AxisCommandError) as exc:
        a.set_pos(0.0)
    assert exc.value.code == st.CMD_INVALID_MOVING


def test_rollover_wraps_positions_and_counts_turns():
    a = make(
        type="rotary", max_vel=3600.0, max_acc=36000.0, max_dec=36000.0, sw_left=-1e5, sw_right=1e5
    )
    a.set_rollover(360.0)
    a.enable()
    run_until(a, lambda: a.enabled)
    with pytest.raises(AxisCommandError) as exc:
        a.set_rollover(180.0)
    assert exc.value.code == st.CMD_INVALID_ENABLED
    a.move_vel(3600.0)
    for _ in range(1000):
        a.step()
    a.stop()
    run_until(a, lambda: a.in_pos)
    assert 0.0 <= a.variable("pos_fb") < 360.0
    assert a.rollover_turns == math.floor(a.pos_fb / 360.0) >= 5
    a.move_abs(350.0)  # the shortest way: at most half a turn
    start = a.pos_fb
    run_until(a, lambda: a.in_pos)
    assert abs(a.pos_fb - start) <= 180.0
    assert a.variable("pos_fb") == pytest.approx(350.0, abs=1e-3)


def test_csv_mode_moves_by_velocity_and_ends_on_target():
    a = enabled()
    a.set_op_mode(9)
    assert a.drive.mode == 9
    a.move_abs(50.0)
    run_until(a, lambda: a.in_pos)
    assert a.pos_fb == pytest.approx(50.0, abs=0.01)


def test_torque_mode_clamps_to_the_continuous_torque():
    a = enabled(drive={"rated_torque": 2.0})
    with pytest.raises(AxisCommandError) as exc:
        a.move_trq(1.0)
    assert exc.value.code == st.CMD_INVALID_CONTROL_MODE
    a.set_op_mode(10)
    with pytest.raises(AxisCommandError):
        a.move_abs(1.0)
    a.move_trq(5.0)
    assert a.drive.rated_torque_nm == 2.0 and a._torque_per_mille == 1000
    for _ in range(20):
        a.step()
    assert a.drive.target_torque == 1000
    assert a.moving and a.vel_fb > 0.0
    assert a.current_fb == pytest.approx(2.0 / 0.5, rel=0.01)
    a.stop()
    run_until(a, lambda: not a.moving)
    assert a.op_mode == 8


def test_pvt_passes_its_points_with_their_velocities():
    a = enabled()
    times = [0.0, 200.0, 500.0]
    pos = [0.0, 30.0, 10.0]
    vel = [0.0, 50.0, 0.0]
    a.move_pvt(times, pos, vel)
    assert a.moving
    samples = []
    while a.moving:
        a.step()
        samples.append((a.ref_pos, a.ref_vel))
    assert samples[199][0] == pytest.approx(30.0, abs=1e-9)
    assert samples[199][1] == pytest.approx(50.0, abs=1e-6)
    assert a.ref_pos == 10.0


def test_pvt_errors_use_the_manuals_codes():
    a = enabled()
    with pytest.raises(AxisCommandError) as exc:
        a.move_pvt([0.0, 100.0, 50.0], [0.0, 1.0, 2.0], [0.0, 0.0, 0.0])
    assert exc.value.code == st.PVT_INVALID_TIME
    with pytest.raises(AxisCommandError) as exc:
        a.move_pvt([0.0, 10.0], [0.0, 500.0], [0.0, 0.0])
    assert exc.value.code == st.PVT_VEL_LIMIT
    with pytest.raises(AxisCommandError) as exc:
        a.move_pvt([0.0, 10.0], [7.0, 8.0], [0.0, 0.0])
    assert exc.value.code == st.CMD_INVALID_POS


@pytest.mark.parametrize(
    ("method", "value", "code"),
    [
        ("set_vel", 0.0, st.CMD_INVALID_VEL),
        ("set_vel", 5e-324, st.CMD_INVALID_VEL),  # a move would never end
        ("set_vel", 1e308, st.CMD_INVALID_VEL),  # the machine file caps it at 1e12
        ("set_acc", 5e-324, st.CMD_INVALID_ACC),
        ("set_acc", 1e13, st.CMD_INVALID_ACC),
        ("set_dec", 1e308, st.CMD_INVALID_DEC),
        ("set_dec", 1e-300, st.CMD_INVALID_DEC),
        ("set_kill_dec", 1e308, st.CMD_INVALID_KILL_DEC),
        ("set_kill_dec", 5e-324, st.CMD_INVALID_KILL_DEC),
        ("set_acc_time", 5e-324, st.CMD_INVALID_ACC),  # ms / 1000 used to divide by 0
        ("set_dec_time", 5e-324, st.CMD_INVALID_DEC),
        ("set_acc_time", 1e308, st.CMD_INVALID_ACC),  # an acceleration below 1e-6
        ("set_acc", -1.0, st.CMD_INVALID_ACC),
        ("set_dec", math.nan, st.CMD_INVALID_DEC),
        ("set_acc_time", 0.0, st.CMD_INVALID_ACC),
        ("set_kill_dec", 0.0, st.CMD_INVALID_KILL_DEC),
        ("set_smooth_time", 501.0, st.CMD_INVALID_SM_TIME),
        ("set_vel_scale", 101.0, st.CMD_INVALID_VEL_SCALE),
        ("set_op_mode", 6, st.CMD_INVALID_OP_MODE),
        ("set_buffer_mode", 2, st.CMD_INVALID_BUFFER_MODE),
        ("set_rollover", -1.0, st.CMD_INVALID_ROLLOVER_POS),
        ("set_rollover", 1e-320, st.CMD_INVALID_ROLLOVER_POS),  # below one encoder count
        ("set_rollover", 0.99e-4, st.CMD_INVALID_ROLLOVER_POS),  # 10000 counts per mm
        ("set_rollover", math.inf, st.CMD_INVALID_ROLLOVER_POS),
        ("set_sw_right", -2000.0, st.CMD_INVALID_POS),
        ("move_abs", 1500.0, st.CMD_INVALID_DISABLED),
    ],
)
def test_out_of_range_settings_are_refused(method, value, code):
    a = make()
    with pytest.raises(AxisCommandError) as exc:
        getattr(a, method)(value)
    assert exc.value.code == code


def test_a_rollover_of_one_encoder_count_is_the_smallest_taken():
    a = make(counts_per_unit=1000.0)
    a.set_rollover(0.001)
    assert a.rollover == 0.001
    with pytest.raises(AxisCommandError) as exc:
        a.set_rollover(0.000999)
    assert exc.value.code == st.CMD_INVALID_ROLLOVER_POS and a.rollover == 0.001
    a.set_rollover(0.0)  # off
    assert a.rollover == 0.0


def test_the_setters_take_the_machine_file_range_edges():
    a = make()
    a.set_vel(1e12)
    a.set_vel(1e-6)
    a.set_acc(1e-6)
    a.set_dec(1e12)
    a.set_kill_dec(1e12)
    assert (a.pg.v_max, a.pg.a_max, a.pg.d_max, a.kill_dec) == (1e-6, 1e-6, 1e12, 1e12)


def test_acc_time_sets_the_acceleration_from_the_maximum_velocity():
    a = make()
    a.set_acc_time(50.0)
    a.set_dec_time(200.0)
    assert a.pg.a_max == pytest.approx(1000.0 / 0.05)
    assert a.pg.d_max == pytest.approx(1000.0 / 0.2)


def test_every_variable_of_5_1_1_is_readable():
    a = enabled()
    a.move_abs(3.0)
    a.step()
    for name in st.VARIABLES:
        value = a.variable(name)
        assert isinstance(value, (int, float)) and math.isfinite(value), name
    with pytest.raises(KeyError):
        a.variable("ref_poss")


def test_an_idle_axis_rests_and_any_command_wakes_it():
    a = enabled()
    run_until(a, lambda: a.resting)
    before = a.drive.position_actual
    a.step()
    a.move_abs(1.0)
    assert not a.resting
    run_until(a, lambda: a.in_pos)
    assert a.drive.position_actual == before + 10000


def test_move_abs_target_checks_on_its_short_path():
    """MoveAbs checks its target inline: not a number, outside the software limits
    (inclusive), IgnoreSWL, and a move of a halted axis that ends the Halt."""
    a = enabled(sw_left=-10.0, sw_right=10.0)
    for bad in (math.nan, math.inf, -math.inf, 10.5, -10.000001):
        with pytest.raises(AxisCommandError) as exc:
            a.move_abs(bad)
        assert exc.value.code == st.CMD_INVALID_POS
        assert not a.moving
    a.move_abs(10.0)  # on the limit: accepted
    assert a.moving and a.pg.target == 10.0
    a.move_abs(5.0)  # on the fly, before the limit stop could trip
    run_until(a, lambda: a.in_pos)
    a.set_ignore("swl", 1)
    with pytest.raises(AxisCommandError) as exc:
        a.move_abs(math.inf)  # ignored limits still need a number
    assert exc.value.code == st.CMD_INVALID_POS
    a.move_abs(12.0)
    for _ in range(20):
        a.step()
    a.halt()
    run_until(a, lambda: a.pg.is_halted)
    a.move_abs(-3.0)  # a new move ends the Halt
    assert not a.halted
    run_until(a, lambda: a.in_pos)
    assert a.ref_pos == -3.0
