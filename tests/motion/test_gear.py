"""Electronic gear (manual chapter 6): ratios, gear in/out, order of master and slave, errors."""

from __future__ import annotations

import itertools
import math
import os

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as hs

from motionvm.motion import axis_status as st
from motionvm.motion import gear
from motionvm.motion.axis_config import create
from motionvm.motion.gear import DISENGAGED, ENGAGED, ENGAGING, SyncError
from motionvm.motion.kernel import MotionKernel
from motionvm.motion.tolerances import P_TOL, limit_slack

DT = 0.001


def kernel(n: int = 5, **config) -> MotionKernel:
    k = MotionKernel([create(dict(config)) for _ in range(n)], DT)
    for a in k.axes:
        a.enable()
    run_until(k, lambda: all(a.enabled for a in k.axes))
    return k


def run_until(k: MotionKernel, cond, limit: int = 100_000) -> int:
    for n in range(limit):
        if cond():
            return n
        k.step()
    raise AssertionError("condition never held")


def geared(k: MotionKernel, master: int, slave: int, ratio: float):
    box = k.gears
    box.enable_gear(k.axes[master], k.axes[slave])
    box.gear_in(k.axes[master], k.axes[slave], ratio)
    return box.gear_of(slave)


@pytest.mark.parametrize("ratio", [1.0, 2.0, 4.0, -1.0, 0.5, -2.5])
def test_slave_follows_the_master_command_times_the_ratio_in_the_same_cycle(ratio):
    k = kernel()
    g = geared(k, 0, 1, ratio)
    assert g.in_gear and k.gears.lag_cycles(1) == 0
    m, s = k.axes[0], k.axes[1]
    m.move_abs(100.0)
    for _ in range(300):
        k.step()
        assert s.ref_pos == pytest.approx(ratio * m.ref_pos, abs=P_TOL)
        assert s.ref_vel == pytest.approx(ratio * m.ref_vel, rel=1e-6, abs=1e-6)
        assert g.gear_cmd_pos == s.ref_pos and g.master_pos_gear == m.ref_pos
    run_until(k, lambda: m.in_pos)
    for _ in range(5):
        k.step()
    assert s.pos_fb == pytest.approx(100.0 * ratio, abs=1e-4)


def test_gearing_is_relative_to_where_both_axes_stand():
    k = kernel()
    m, s = k.axes[0], k.axes[2]
    m.move_abs(10.0)
    s.move_abs(-30.0)
    run_until(k, lambda: m.in_pos and s.in_pos)
    geared(k, 0, 2, 3.0)
    m.move_abs(20.0)
    run_until(k, lambda: not m.moving)
    k.step()
    assert s.ref_pos == pytest.approx(-30.0 + 3.0 * 10.0, abs=P_TOL)


def test_a_master_with_a_higher_id_is_seen_late_only_if_it_steps_after_its_slave():
    k = kernel()
    geared(k, 3, 1, 2.0)
    lag = k.gears.lag_cycles(1)
    order = getattr(k, "step_order", k.axes)
    assert lag == (1 if order.index(k.axes[3]) > order.index(k.axes[1]) else 0)
    m, s = k.axes[3], k.axes[1]
    m.move_abs(50.0)
    refs = [(m.ref_pos, s.ref_pos)]
    for _ in range(200):
        k.step()
        refs.append((m.ref_pos, s.ref_pos))
    for (m_prev, _), (m_now, s_now) in itertools.pairwise(refs):
        assert s_now == pytest.approx(2.0 * (m_prev if lag else m_now), abs=P_TOL)


def test_a_kernel_with_a_step_order_steps_masters_first():
    k = kernel(4)
    k.step_order = list(k.axes)
    box = k.gears
    geared(k, 3, 1, 1.0)
    geared(k, 2, 0, 1.0)
    assert [a.axis_id for a in k.step_order] == [2, 3, 0, 1]
    assert box.lag_cycles(1) == 0 and box.lag_cycles(0) == 0
    box.gear_out(k.axes[1])
    box.disable_gear(k.axes[1])
    assert [a.axis_id for a in k.step_order] == [2, 0, 1, 3]


def test_gear_in_on_a_moving_master_ramps_the_ratio_at_the_slave_acceleration():
    k = kernel()
    m, s = k.axes[0], k.axes[1]
    box = k.gears
    box.enable_gear(m, s)
    m.move_vel(500.0)
    run_until(k, lambda: abs(m.ref_vel - 500.0) < 1e-6)
    box.gear_in(m, s, 2.0)
    g = box.gear_of(1)
    assert g.state == ENGAGING and not g.in_gear
    n = run_until(k, lambda: g.in_gear)
    assert n == math.ceil(2.0 * 500.0 / s.pg.a_max / DT)
    assert s.ref_vel == pytest.approx(1000.0)
    accs = []
    for _ in range(50):
        k.step()
        accs.append(s.ref_acc)
        assert s.ref_vel == pytest.approx(2.0 * m.ref_vel)
    assert max(abs(a) for a in accs) < 1e-3 * s.pg.a_max


def test_gear_out_brakes_the_slave_and_hands_it_back_to_its_profile_generator():
    k = kernel()
    m, s = k.axes[0], k.axes[1]
    geared(k, 0, 1, -1.0)
    m.move_vel(400.0)
    run_until(k, lambda: abs(m.ref_vel - 400.0) < 1e-6)
    k.step()
    assert s.ref_vel == pytest.approx(-400.0)
    k.gears.gear_out(s)
    assert not k.gears.is_in_gear(1)
    n = run_until(k, lambda: s.following is None)
    assert n == pytest.approx(400.0 / s.pg.d_max / DT, abs=1)
    assert s.ref_vel == 0.0
    run_until(k, lambda: s.in_pos)
    held = s.ref_pos
    for _ in range(20):
        k.step()
    assert s.ref_pos == held  # the master goes on, the slave stays
    s.move_rel(5.0)
    run_until(k, lambda: s.in_pos)
    assert s.pos_fb == pytest.approx(held + 5.0, abs=1e-4)


def test_gear_out_of_a_resting_slave_lets_go_at_once_and_disable_gear_uncouples():
    k = kernel()
    s = k.axes[1]
    box = k.gears
    geared(k, 0, 1, 2.0)
    assert s.motion_status & st.MS_GEAR and s.motion_status & st.MS_SYNC
    assert box.is_master(0) and box.is_slave(1) and box.ratio(1) == 2.0
    with pytest.raises(SyncError) as e:
        box.disable_gear(s)
    assert e.value.code == st.CMD_INVALID_IN_SYNC
    box.gear_out(s)
    assert s.following is None and box.gear_of(1).state == DISENGAGED
    box.disable_gear(s)
    assert not box.is_slave(1) and not box.is_master(0)
    assert not s.motion_status & (st.MS_GEAR | st.MS_SYNC)


def test_one_master_drives_many_slaves():
    k = kernel()
    ratios = {1: 1.0, 2: 2.0, 3: 4.0, 4: -1.0}
    for sid, r in ratios.items():
        geared(k, 0, sid, r)
    k.axes[0].move_abs(100.0)
    run_until(k, lambda: k.axes[0].in_pos)
    for sid, r in ratios.items():
        assert k.axes[sid].ref_pos == pytest.approx(100.0 * r, abs=P_TOL)


def test_changing_the_ratio_while_engaged_ramps_from_the_old_one():
    k = kernel()
    m, s = k.axes[0], k.axes[1]
    g = geared(k, 0, 1, 1.0)
    m.move_vel(200.0)
    run_until(k, lambda: abs(m.ref_vel - 200.0) < 1e-6)
    k.gears.gear_in(m, s, 3.0)
    assert g.state == ENGAGING
    run_until(k, lambda: g.in_gear)
    k.step()
    assert s.ref_vel == pytest.approx(600.0) and g.ratio == 3.0


def test_a_disabled_master_gears_its_slaves_out():
    k = kernel()
    m, s = k.axes[0], k.axes[1]
    g = geared(k, 0, 1, 1.0)
    m.move_vel(100.0)
    run_until(k, lambda: abs(m.ref_vel - 100.0) < 1e-6)
    k.step()
    m.disable()
    run_until(k, lambda: s.following is None)
    assert g.state == DISENGAGED and s.ref_vel == 0.0 and s.enabled


def test_a_slave_that_faults_leaves_its_gear():
    k = kernel()
    s = k.axes[1]
    g = geared(k, 0, 1, 1.0)
    s.disable()
    assert not g.in_gear and g.state == DISENGAGED
    assert k.gears.is_slave(1)


@pytest.mark.parametrize(
    ("call", "code", "axis"),
    [
        (lambda b, a: b.enable_gear(a[0], a[0]), gear.CMD_INVALID_MASTER_SLAVE_CONNECTION, 0),
        (lambda b, a: b.gear_in(a[0], a[1], 1.0), gear.CMD_GEAR_DISABLED, 1),
        (lambda b, a: b.gear_out(a[1]), gear.CMD_GEAR_DISABLED, 1),
        (lambda b, a: b.disable_gear(a[1]), gear.CMD_GEAR_DISABLED, 1),
    ],
)
def test_commands_refused_with_the_manual_codes(call, code, axis):
    k = kernel(2)
    with pytest.raises(SyncError) as e:
        call(k.gears, k.axes)
    assert (e.value.code, e.value.axis_id) == (code, axis)


def test_bad_ratios_states_and_chains_are_refused():
    k = kernel(4)
    a = k.axes
    box = k.gears
    box.enable_gear(a[0], a[1])
    for ratio in (0.0, math.nan, math.inf, 1001.0):
        with pytest.raises(SyncError) as e:
            box.gear_in(a[0], a[1], ratio)
        assert e.value.code == gear.CMD_INVALID_GEAR_RATIO
    with pytest.raises(SyncError) as e:
        box.gear_in(a[2], a[1], 1.0)
    assert e.value.code == gear.CMD_INVALID_MASTER_SLAVE_CONNECTION
    with pytest.raises(SyncError) as e:
        box.enable_gear(a[2], a[1])
    assert e.value.code == st.CMD_INVALID_IN_SYNC
    with pytest.raises(SyncError) as e:
        box.enable_gear(a[1], a[2])  # a slave cannot be a master
    assert (e.value.code, e.value.axis_id) == (st.CMD_INVALID_IN_SYNC, 1)
    with pytest.raises(SyncError) as e:
        box.enable_gear(a[2], a[0])  # a master cannot be a slave
    assert (e.value.code, e.value.axis_id) == (gear.CMD_INVALID_GEAR_MASTER, 0)
    a[3].disable()
    k.step()
    with pytest.raises(SyncError) as e:
        box.enable_gear(a[0], a[3])
    assert (e.value.code, e.value.axis_id) == (st.CMD_INVALID_DISABLED, 3)
    a[1].move_abs(10.0)
    with pytest.raises(SyncError) as e:
        box.gear_in(a[0], a[1], 1.0)
    assert e.value.code == st.CMD_INVALID_MOVING
    box.enable_gear(a[0], a[1])  # the same coupling again: nothing to do
    assert box.gear_of(1).state == DISENGAGED


def test_two_runs_give_identical_traces():
    def trace():
        k = kernel(3)
        geared(k, 0, 1, -1.5)
        geared(k, 0, 2, 0.25)
        k.axes[0].move_abs(80.0)
        rows = []
        for i in range(400):
            if i == 150:
                k.gears.gear_out(k.axes[1])
            k.step()
            rows.append(tuple((a.ref_pos, a.pos_fb, a.motion_status) for a in k.axes))
        return rows

    assert trace() == trace()


def test_a_resting_master_engages_its_slave_at_once():
    k = kernel(2)
    assert geared(k, 0, 1, 1.0).state == ENGAGED


# ---- properties (Hypothesis; profiles as in test_profile_properties.py) -------------

PROFILE = settings(
    max_examples=400 if os.environ.get("HYPOTHESIS_PROFILE") == "thorough" else 30,
    derandomize=True,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)
LOOSE = {"sw_left": -1e7, "sw_right": 1e7, "hw_left": -2e7, "hw_right": 2e7, "max_pos_err": 1e9}
ratios = hs.floats(-10.0, 10.0).filter(lambda r: abs(r) >= 1e-3)


@PROFILE
@given(ratios, hs.floats(-500.0, 500.0), hs.floats(-500.0, 500.0), hs.floats(-90.0, 90.0))
def test_property_an_engaged_slave_tracks_every_master_move(ratio, s_0, target_1, target_2):
    k = MotionKernel([create(dict(LOOSE)), create(dict(LOOSE, start_position=s_0))], DT)
    for a in k.axes:
        a.enable()
    run_until(k, lambda: all(a.enabled for a in k.axes))
    m, s = k.axes
    m_0, s_0 = m.ref_pos, s.ref_pos
    geared(k, 0, 1, ratio)
    m.move_abs(target_1)
    for i in range(2000):
        if i == 40:
            m.move_abs(target_2)  # on the fly
        k.step()
        assert math.isfinite(s.ref_pos) and math.isfinite(s.ref_vel)
        assert s.ref_pos == pytest.approx(
            s_0 + ratio * (m.ref_pos - m_0), abs=1e-9 * (1 + abs(s_0))
        )
        if i > 40 and not m.moving:
            break
    assert not m.moving
    assert s.ref_pos == pytest.approx(s_0 + ratio * (target_2 - m_0), abs=1e-9 * (1 + abs(s_0)))


@PROFILE
@given(ratios, hs.floats(-800.0, 800.0).filter(lambda v: abs(v) > 1.0))
def test_property_gear_in_on_a_cruising_master_keeps_the_slave_acceleration(ratio, v_m):
    k = MotionKernel([create(dict(LOOSE)), create(dict(LOOSE))], DT)
    for a in k.axes:
        a.enable()
    run_until(k, lambda: all(a.enabled for a in k.axes))
    m, s = k.axes
    box = k.gears
    box.enable_gear(m, s)
    m.move_vel(v_m)
    run_until(k, lambda: not m.pg.is_done and m.ref_acc == 0.0 and abs(m.ref_vel - v_m) < 1e-6)
    box.gear_in(m, s, ratio)
    g = box.gear_of(1)
    slack = limit_slack(s.pg.a_max, 1e4, DT, 2)
    while not g.in_gear:
        k.step()
        assert abs(s.ref_acc) <= s.pg.a_max + slack
    k.step()
    assert s.ref_vel == pytest.approx(ratio * m.ref_vel, rel=1e-6, abs=1e-6)


def test_a_slave_driven_into_its_software_limit_stops_and_leaves_its_gear():
    k = kernel(2)
    m, s = k.axes
    g = geared(k, 0, 1, 4.0)
    m.move_abs(300.0)  # the slave would go to 1200 mm, beyond its limit at 1000 mm
    run_until(k, lambda: s.error_stop)
    assert s.fault_status & st.FS_SW_RIGHT and not g.in_gear
    p_0, v_0 = s.ref_pos, s.ref_vel  # from here: a kill stop
    run_until(k, lambda: not m.moving and not s.moving)
    assert m.ref_pos == 300.0
    assert s.ref_pos == pytest.approx(p_0 + v_0**2 / (2 * s.kill_dec), abs=v_0 * DT)
