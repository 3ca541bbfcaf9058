"""Axis VSF and InShape (manual 15.2-15.7) through the motion commands: the filtered
reference is the axis's, moves end exactly on target one shaper later, the status bits,
the manual's exclusions and refusals, and no effect on a followed reference."""

from __future__ import annotations

import pytest
from axis_util import DT, cycle, enabled, err, machine, until

from motionvm.motion import axis_status as st
from motionvm.motion import inshape
from motionvm.motion.axis_config import create
from motionvm.motion.commands import MotionCommands
from motionvm.motion.kernel import MotionKernel

NORMAL, ROBUST = inshape.SHAPER_NORMAL, inshape.SHAPER_ROBUST


def test_manual_example_1_sets_and_enables_inshape_on_a_disabled_axis():
    c = machine(2)
    assert c.SetAxisInShape(0, 5.5, 0.03, NORMAL) == 0
    assert c.EnableAxisInShape(0) == 0
    a = c.motion.axes[0]
    assert a.motion_status & st.MS_INPUT_SHAPE and not a.motion_status & st.MS_VSF
    assert c.DisableAxisInShape(0) == 0
    assert not a.motion_status & st.MS_INPUT_SHAPE


@pytest.mark.parametrize("shaper_type", [NORMAL, ROBUST])
def test_an_inshape_move_ends_exactly_on_target_one_shaper_later(shaper_type):
    c = enabled(2)
    assert c.SetAxisInShape(0, 5.5, 0.03, shaper_type) == 0
    assert c.EnableAxisInShape(0) == 0
    length = inshape.design(5.5, 0.03, shaper_type, DT).length
    assert c.MoveAbs(0, 100.0) == 0 and c.MoveAbs(1, 100.0) == 0
    until(c, lambda: not c.IsMoving(1))
    assert c.IsMoving(0) and c.GetRefPos(0) < 100.0  # the shaper's tail still runs
    until(c, lambda: not c.IsMoving(0))
    assert c.GetRefPos(0) == 100.0 and c.GetRefVel(0) == 0.0
    assert c.GetMoveTime(0) == pytest.approx(c.GetMoveTime(1) + length, abs=1e-9)
    until(c, lambda: c.IsInPos(0))
    assert c.GetPosOut(0) == 100.0
    cycle(c, 20)
    assert c.motion.axes[0].resting  # nothing pending: the axis rests again


def test_the_drive_gets_the_shaped_position():
    c = enabled(1)
    c.SetAxisInShape(0, 10.0, 0.0, NORMAL)  # two impulses 50 ms apart, gains 1/2
    c.EnableAxisInShape(0)
    a = c.motion.axes[0]
    c.MoveAbs(0, 10.0)
    planned, shaped = [0.0] * 50, [0.0] * 50
    while c.IsMoving(0):
        cycle(c)
        planned.append(a.pg.output[0])
        shaped.append(a.ref_pos)
        assert a.drive.target_position == round(a.ref_pos * a.cpu)
    for n in range(50, len(shaped)):
        assert shaped[n] == pytest.approx(0.5 * (planned[n] + planned[n - 50]), abs=1e-12)
    assert shaped[-1] == 10.0


def test_vsf_moves_end_exactly_on_target_and_show_in_the_status():
    c = enabled(2)
    assert c.SetAxisVsf(0, 20.0, 1.0) == 0 and c.EnableAxisVsf(0) == 0
    assert c.motion.axes[0].motion_status & st.MS_VSF
    c.MoveAbs(0, -40.0)
    c.MoveAbs(1, -40.0)
    until(c, lambda: not c.IsMoving(0))
    assert c.GetRefPos(0) == -40.0
    assert c.GetMoveTime(0) > c.GetMoveTime(1)


def test_vsf_and_inshape_exclude_each_other():
    c = machine(2)
    assert c.EnableAxisVsf(0) == 0
    assert c.EnableAxisInShape(0) == err(st.CMD_INVALID_INPUTSHAPING_ENABLED)
    assert c.GetAxisLastErr(0) == err(st.CMD_INVALID_INPUTSHAPING_ENABLED)
    assert c.DisableAxisVsf(0) == 0 and c.EnableAxisInShape(0) == 0
    assert c.EnableAxisVsf(0) == err(st.CMD_INVALID_INPUTSHAPING_ENABLED)


def test_filters_cannot_change_while_the_motor_moves():
    c = enabled(2)
    c.EnableAxisInShape(0)
    c.MoveAbs(0, 50.0)
    moving = err(st.CMD_INVALID_MOVING)
    assert c.SetAxisInShape(0, 8.0, 0.1, NORMAL) == moving
    assert c.DisableAxisInShape(0) == moving
    assert c.SetAxisVsf(0, 8.0, 1.0) == moving
    c.MoveAbs(1, 50.0)
    assert c.EnableAxisVsf(1) == err(st.CMD_INVALID_MOVING, 1)


@pytest.mark.parametrize(
    ("call", "code"),
    [
        (lambda c: c.SetAxisInShape(0, 1.4, 0.03, NORMAL), st.FREQUENCY_LIMIT),
        (lambda c: c.SetAxisInShape(0, 300.1, 0.03, NORMAL), st.FREQUENCY_LIMIT),
        (lambda c: c.SetAxisInShape(0, float("nan"), 0.03, NORMAL), st.FREQUENCY_LIMIT),
        (lambda c: c.SetAxisInShape(0, 5.5, 0.31, NORMAL), st.DAMPINGRATIO_LIMIT),
        (lambda c: c.SetAxisInShape(0, 5.5, -0.01, NORMAL), st.DAMPINGRATIO_LIMIT),
        (lambda c: c.SetAxisInShape(0, 5.5, 0.03, 2), st.CMD_INVALID_PARAMETER),
        (lambda c: c.SetAxisVsf(0, 0.09, 1.0), st.FREQUENCY_LIMIT),
        (lambda c: c.SetAxisVsf(0, 200.5, 1.0), st.FREQUENCY_LIMIT),
        (lambda c: c.SetAxisVsf(0, 10.0, 0.69), st.DAMPINGRATIO_LIMIT),
        (lambda c: c.SetAxisVsf(0, 10.0, 1.51), st.DAMPINGRATIO_LIMIT),
    ],
)
def test_parameters_outside_the_manuals_ranges_are_refused(call, code):
    c = machine(2)
    assert call(c) == err(code)
    assert c.GetAxisLastErr(0) == err(code)


def test_the_range_limits_themselves_are_accepted():
    c = machine(2)
    assert c.SetAxisInShape(0, 1.5, 0.0, ROBUST) == 0
    assert c.SetAxisInShape(0, 300.0, 0.3, NORMAL) == 0
    assert c.SetAxisVsf(0, 0.1, 0.7) == 0 and c.SetAxisVsf(0, 200.0, 1.5) == 0


def test_a_frequency_too_high_for_a_slow_cycle_is_refused():
    c = MotionCommands(MotionKernel([create({})], 0.004))
    assert c.SetAxisInShape(0, 300.0, 0.0, NORMAL) == err(st.FREQUENCY_LIMIT)
    assert c.SetAxisVsf(0, 150.0, 1.0) == err(st.FREQUENCY_LIMIT)


def test_bad_ids_are_the_systems_error():
    c = machine(2)
    bad = st.SYS_HMPL_ARG_OUT_OF_RANGE
    assert c.EnableAxisInShape(9) == bad and c.SetAxisVsf(-1, 5.0, 1.0) == bad
    assert c.GetSystemLastErr() == bad


def test_axis_inshape_has_no_effect_on_a_followed_reference():
    # a gear slave follows its master's (synchronous) reference: not shaped (15.1)
    c = enabled(2)
    assert c.EnableAxisInShape(1) == 0
    assert c.EnableGear(0, 1) == 0 and c.GearIn(0, 1, 1.0) == 0
    until(c, lambda: c.IsInGear(1))
    c.MoveAbs(0, 30.0)
    for _ in range(50):
        cycle(c)
        assert c.GetRefPos(1) == pytest.approx(c.GetRefPos(0), abs=1e-12)
    until(c, lambda: not c.IsMoving(0))
    cycle(c, 3)
    assert c.GetRefPos(1) == pytest.approx(30.0, abs=1e-12)


def test_set_pos_with_a_filter_on_moves_nothing():
    c = enabled(1)
    c.EnableAxisInShape(0)
    c.MoveAbs(0, 10.0)
    until(c, lambda: c.IsInPos(0))
    assert c.SetPos(0, 100.0) == 0
    cycle(c, 200)
    assert c.GetRefPos(0) == 100.0 and not c.IsMoving(0)
    c.MoveRel(0, 5.0)
    until(c, lambda: not c.IsMoving(0))
    assert c.GetRefPos(0) == 105.0


def test_disabling_mid_move_leaves_no_stale_shaper_motion():
    c = enabled(1)
    c.EnableAxisInShape(0)
    c.MoveAbs(0, 80.0)
    cycle(c, 150)
    assert c.Disable(0) == 0
    cycle(c, 5)
    c.Enable(0)
    until(c, lambda: c.IsEnabled(0))
    here = c.GetRefPos(0)
    cycle(c, 300)
    assert c.GetRefPos(0) == here and not c.IsMoving(0)


def test_move_rel_in_the_shapers_tail_counts_from_the_planned_position():
    c = enabled(1)
    c.EnableAxisInShape(0)
    c.MoveRel(0, 10.0)
    a = c.motion.axes[0]
    until(c, lambda: a.pg.is_done)
    assert c.IsMoving(0) and c.GetRefPos(0) < 10.0
    c.MoveRel(0, 10.0)
    until(c, lambda: not c.IsMoving(0))
    assert c.GetRefPos(0) == 20.0


def test_stop_in_the_middle_of_a_shaped_move_comes_to_rest():
    c = enabled(1)
    c.SetAxisInShape(0, 5.5, 0.03, ROBUST)
    c.EnableAxisInShape(0)
    c.MoveAbs(0, 500.0)
    cycle(c, 200)
    assert c.Stop(0) == 0
    until(c, lambda: not c.IsMoving(0))
    p = c.GetRefPos(0)
    cycle(c, 50)
    assert c.GetRefPos(0) == p and 0.0 < p < 500.0


# ---- group InShape: the settings, checked and kept per group id --------------------


def test_group_inshape_settings_are_checked_and_kept():
    c = machine(2)
    g = c.motion.group_inshape[0]
    assert (g.frequency, g.damping, g.shaper_type, g.enabled) == (5.5, 0.03, NORMAL, False)
    assert c.SetGrpInShape(0, 10, 0.15, 1) == 0  # manual example 2
    assert c.EnableGrpInShape(0) == 0
    assert (g.frequency, g.damping, g.shaper_type, g.enabled) == (10.0, 0.15, 1, True)
    assert c.DisableGrpInShape(0) == 0 and not g.enabled


@pytest.mark.parametrize(
    ("args", "code"),
    [
        ((2.9, 0.1, 1), st.CRD_INVALID_FREQUENCY),
        ((300.5, 0.1, 1), st.CRD_INVALID_FREQUENCY),
        ((10.0, 0.31, 1), st.CRD_INVALID_DAMPINGRATIO),
        ((10.0, 0.1, 5), st.CRD_INVALID_INPUTSHAPING_PARAMETER_INCOMPLETE),
    ],
)
def test_group_inshape_refusals_are_group_errors(args, code):
    c = machine(2)
    assert c.SetGrpInShape(3, *args) == st.group_error(code, 3)
    assert c.GetGrpLastErr(3) == st.group_error(code, 3)


def test_group_inshape_bad_group_id():
    c = machine(2)
    bad = st.SYS_HMPL_ARG_OUT_OF_RANGE
    assert c.EnableGrpInShape(16) == bad and c.SetGrpInShape(-1, 5.5, 0.0, 1) == bad
