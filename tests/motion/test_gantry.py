"""Gantry pairs (manual chapter 7): the linear/yaw transform, the enable sequence, errors."""

from __future__ import annotations

import os

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as hs

from motionvm.motion import axis_status as st
from motionvm.motion import gear
from motionvm.motion.axis_config import create
from motionvm.motion.gantry import ENABLING, OFF, STOPPING, from_axes, to_axes
from motionvm.motion.gear import SyncError
from motionvm.motion.kernel import MotionKernel
from motionvm.motion.tolerances import P_TOL

DT = 0.001
finite = hs.floats(-1e6, 1e6, allow_nan=False)


def kernel(n: int = 4, **config) -> MotionKernel:
    return MotionKernel([create(dict(config)) for _ in range(n)], DT)


def cycle(k: MotionKernel) -> None:
    """One cycle: the gantry step (before the tasks), then the motion phase."""
    k.gantries.step()
    k.step()


def run_until(k: MotionKernel, cond, limit: int = 100_000) -> int:
    for n in range(limit):
        if cond():
            return n
        cycle(k)
    raise AssertionError("condition never held")


def paired(k: MotionKernel, rhs: int = 0, lhs: int = 1):
    g = k.gantries.enable_pair(k.axes[rhs], k.axes[lhs])
    k.axes[rhs].enable()
    run_until(k, lambda: g.engaged)
    return g


# ---- the transform of manual 7.1 ------------------------------------------------------


@given(finite, finite)
def test_transform_round_trips(rhs, lhs):
    lin, yaw = from_axes(rhs, lhs)
    r, l = to_axes(lin, yaw)
    assert r == pytest.approx(rhs, abs=1e-9 * max(1.0, abs(rhs), abs(lhs)))
    assert l == pytest.approx(lhs, abs=1e-9 * max(1.0, abs(rhs), abs(lhs)))


def test_transform_of_the_manual():
    assert from_axes(12.0, 8.0) == (10.0, 2.0)
    assert to_axes(10.0, 2.0) == (12.0, 8.0)
    assert from_axes(5.0, 5.0) == (5.0, 0.0)


# ---- enable sequence ------------------------------------------------------------------


def test_enabling_one_axis_enables_the_pair_and_engages_without_a_jump():
    k = kernel(start_position=0.0)
    k.axes[1].drive.mechanics.position = 0.0
    g = k.gantries.enable_pair(k.axes[0], k.axes[1])
    assert g.pair_id == 0 and g.state == OFF
    assert all(a.motion_status & st.MS_GANTRY for a in g.axes)
    k.axes[0].enable()
    run_until(k, lambda: k.axes[0].enabled)
    cycle(k)
    assert g.state == ENABLING
    run_until(k, lambda: g.engaged)
    assert k.axes[1].enabled
    assert k.axes[0].following is g and k.axes[1].following is g
    before = [a.ref_pos for a in g.axes]
    cycle(k)
    assert [a.ref_pos for a in g.axes] == before


def test_engaging_with_the_axes_apart_keeps_them_where_they_are():
    k = kernel(2)
    r, l = k.axes
    for a, p in ((r, 3.0), (l, 1.0)):
        a.enable()
        run_until(k, lambda a=a: a.enabled)
        a.move_abs(p)
        run_until(k, lambda a=a: a.in_pos)
        a.disable()
        cycle(k)
    g = paired(k)
    assert g.linear_ref[0] == 2.0 and g.yaw_ref[0] == 1.0
    assert (g.linear_fb, g.yaw_fb) == pytest.approx((2.0, 1.0), abs=1e-4)
    r.move_abs(10.0)  # the linear axis: both motors move by 8
    run_until(k, lambda: r.pg.is_done and g.linear_ref[1] == 0.0)
    for _ in range(5):
        cycle(k)
    assert (r.ref_pos, l.ref_pos) == pytest.approx((11.0, 9.0), abs=P_TOL)
    assert (g.linear_fb, g.yaw_fb) == pytest.approx((10.0, 1.0), abs=1e-4)


def test_linear_and_yaw_commands_drive_both_motors():
    k = kernel()
    g = paired(k)
    r, l = g.axes
    r.move_abs(50.0)
    l.move_abs(0.5)
    for _ in range(200):
        cycle(k)
        lin, yaw = g.linear_ref, g.yaw_ref
        assert (r.ref_pos, l.ref_pos) == pytest.approx(to_axes(lin[0], yaw[0]), abs=P_TOL)
        assert (r.ref_vel, l.ref_vel) == pytest.approx(to_axes(lin[1], yaw[1]))
    run_until(k, lambda: not g.moving(r))
    for _ in range(5):
        cycle(k)
    assert (r.pos_fb, l.pos_fb) == pytest.approx((50.5, 49.5), abs=1e-4)
    assert (g.linear_fb, g.yaw_fb) == pytest.approx((50.0, 0.5), abs=1e-4)


def test_disabling_either_axis_disables_both():
    k = kernel()
    g = paired(k)
    k.axes[1].disable()
    cycle(k)
    assert not k.axes[0].enabled and g.state == OFF
    k.axes[1].enable()  # either axis powers the pair
    run_until(k, lambda: g.engaged)
    assert k.axes[0].enabled


def test_a_stop_of_one_axis_stops_both_and_the_pair_re_engages():
    k = kernel()
    g = paired(k)
    r, l = g.axes
    r.move_vel(200.0)
    run_until(k, lambda: abs(g.linear_ref[1] - 200.0) < 1e-6)
    r.stop()
    run_until(k, lambda: g.engaged and not r.stopping and not l.stopping)
    assert r.ref_vel == 0.0 and l.ref_vel == 0.0
    assert r.ref_pos == pytest.approx(l.ref_pos, abs=P_TOL)
    assert r.following is g and l.following is g


def test_pair_ids_and_queries():
    k = kernel(6)
    gs = k.gantries
    a = k.axes
    assert gs.enable_pair(a[2], a[3]).pair_id == 0
    assert gs.enable_pair(a[4], a[0]).pair_id == 1
    assert [gs.pair_id(i) for i in range(6)] == [1, -1, 0, 0, 1, -1]
    assert gs.is_pair(2, 3) and gs.is_pair(3, 2) and gs.is_pair(0, 4)
    assert not gs.is_pair(2, 4) and not gs.is_pair(1, 5) and not gs.is_pair(2, 2)
    gs.disable_pair(a[3])
    assert gs.pair_id(2) == -1 and not a[2].motion_status & st.MS_GANTRY
    assert gs.enable_pair(a[1], a[5]).pair_id == 0
    gs.disable_pair(a[2])  # in no pair: nothing to do


def test_commands_refused_with_the_manual_codes():
    k = kernel(4)
    gs = k.gantries
    a = k.axes
    with pytest.raises(SyncError) as e:
        gs.enable_pair(a[0], a[0])
    assert e.value.code == st.CMD_INVALID_PARAMETER
    a[1].enable()
    run_until(k, lambda: a[1].enabled)
    with pytest.raises(SyncError) as e:
        gs.enable_pair(a[0], a[1])
    assert (e.value.code, e.value.axis_id) == (st.CMD_INVALID_ENABLED, 1)
    a[2].enable()
    run_until(k, lambda: a[2].enabled)
    k.gears.enable_gear(a[1], a[2])
    a[1].disable()
    a[2].disable()
    cycle(k)
    with pytest.raises(SyncError) as e:
        gs.enable_pair(a[0], a[2])
    assert (e.value.code, e.value.axis_id) == (st.CMD_INVALID_IN_SYNC, 2)
    gs.enable_pair(a[0], a[3])
    with pytest.raises(SyncError) as e:
        gs.enable_pair(a[3], a[1])
    assert (e.value.code, e.value.axis_id) == (gear.CMD_INVALID_GANTRY_MODE, 3)
    a[0].enable()
    run_until(k, lambda: gs.pair_of(0).engaged)
    with pytest.raises(SyncError) as e:
        gs.disable_pair(a[3])
    assert e.value.code == st.CMD_INVALID_ENABLED
    a[3].enable()
    with pytest.raises(SyncError) as e:  # a gantry axis cannot be geared
        k.gears.enable_gear(a[3], a[1])
    assert (e.value.code, e.value.axis_id) == (gear.CMD_INVALID_GANTRY_MODE, 3)


def test_a_partner_in_error_stop_keeps_the_pair_off():
    k = kernel(2)
    r, l = k.axes
    l.enable()
    run_until(k, lambda: l.enabled)
    l.drive.inject_fault(0x7500)
    run_until(k, lambda: l.error_stop)
    k.gantries.enable_pair(r, l)
    r.enable()
    run_until(k, lambda: r.enabled)
    cycle(k)
    cycle(k)
    assert not r.enabled and k.gantries.pair_of(0).state == OFF


def test_two_runs_give_identical_traces():
    def trace():
        k = kernel(2)
        g = paired(k)
        g.rhs.move_abs(30.0)
        g.lhs.move_abs(-0.2)
        rows = []
        for _ in range(300):
            cycle(k)
            rows.append((g.rhs.ref_pos, g.lhs.ref_pos, g.linear_fb, g.yaw_fb))
        return rows

    assert trace() == trace()


PROFILE = settings(
    max_examples=400 if os.environ.get("HYPOTHESIS_PROFILE") == "thorough" else 30,
    derandomize=True,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)
positions = hs.floats(-100.0, 100.0)


@PROFILE
@given(positions, positions, positions, hs.floats(-5.0, 5.0))
def test_property_motors_end_at_the_transform_of_the_linear_and_yaw_targets(
    rhs_0, lhs_0, linear, yaw
):
    k = MotionKernel([create({"start_position": rhs_0}), create({"start_position": lhs_0})], DT)
    g = paired(k)
    r, l = g.axes
    assert (r.ref_pos, l.ref_pos) == pytest.approx((rhs_0, lhs_0), abs=1e-4)
    r.move_abs(linear)
    l.move_abs(yaw)
    for _ in range(5000):
        cycle(k)
        want = to_axes(g.linear_ref[0], g.yaw_ref[0])
        assert (r.ref_pos, l.ref_pos) == pytest.approx(want, abs=P_TOL)
        if not g.moving(r):
            break
    assert (r.ref_pos, l.ref_pos) == pytest.approx(to_axes(linear, yaw), abs=P_TOL)


def test_a_limit_stop_of_one_axis_brakes_the_other_at_its_kill_deceleration():
    k = kernel(2)
    g = paired(k)
    r, l = g.axes
    l.move_abs(-1.0)  # yaw -1: the RHS motor is 2 mm behind the LHS motor
    run_until(k, lambda: not g.moving(l) and l.ref_pos == pytest.approx(1.0))
    r.move_vel(500.0)
    run_until(k, lambda: r.error_stop or l.error_stop)
    hit = l if l.error_stop else r
    assert hit is l and l.fault_status & st.FS_SW_RIGHT  # the LHS motor leads
    v_0 = r.ref_vel
    cycle(k)
    assert g.state == STOPPING
    run_until(k, lambda: g.engaged)
    assert r.ref_vel == 0.0 and l.ref_vel == 0.0 and r.enabled and l.enabled
    assert r.ref_pos - l.ref_pos == pytest.approx(-2.0, abs=v_0 * DT)  # one cycle apart at most
    assert g.yaw_ref[0] == pytest.approx(-1.0, abs=1e-3)
