"""Dynamic error compensation on axes (manual 14, 5.3.21, 5.4.14) through the motion
commands: what the drive gets, the feedback, the manual's refusals and codes, the
compensation limit, reference axes that are other axes (and wake a resting axis)."""

from __future__ import annotations

import pytest
from axis_util import cycle, enable, err, machine, until

from motionvm.motion import axis_status as st
from motionvm.motion.commands import MotionCommands

EX1 = [-0.2, 0.1, -0.3, 0.4, -0.1]
USER_TABLE = [0.0] * 100


def example_1(c: MotionCommands) -> None:
    """Manual 14.1.1 example 1: axis 0 compensated by the position of axis 1."""
    table = list(USER_TABLE)
    table[1:6] = EX1
    assert c.SetupComp(0, 1, -100.0, 200.0, 5, 1, table) == 0
    assert c.EnableComp(0) == 0


def test_example_1_the_compensation_follows_the_reference_axis():
    c = machine(3)
    example_1(c)
    assert c.IsCompActive(0) == 1 and c.IsCompActive(1) == 0
    assert c.GetCompPos(0) == 0.0  # nothing is sent to a disabled drive
    enable(c, 0, 1)
    cycle(c, 5)
    a = c.motion.axes[0]
    for x, comp in [(-100.0, -0.2), (0.0, -0.05), (100.0, 0.1), (400.0, 0.05), (900.0, -0.1)]:
        c.MoveAbs(1, x)
        until(c, lambda: c.IsInPos(1) and c.IsInPos(0))
        assert c.GetCompPos(0) == pytest.approx(comp, abs=1e-12)
        # reference + compensation = position output; the drive gets it (+ the offset)
        assert c.GetRefPos(0) == 0.0
        assert c.GetPosOut(0) == pytest.approx(comp, abs=1e-12)
        assert a.drive.target_position == round(comp * a.cpu)
        assert a.variable("comp_pos_set") == c.GetCompPos(0)
        # feedback in axis coordinates; GetPosFbComp adds the compensation back
        assert c.GetPosFb(0) == pytest.approx(0.0, abs=1e-4)
        assert c.GetPosFbComp(0) == pytest.approx(comp, abs=1e-4)


def test_a_resting_compensated_axis_wakes_when_its_reference_axis_moves():
    c = machine(3)
    example_1(c)
    enable(c, 0, 1)
    cycle(c, 30)
    assert c.motion.axes[0].resting and c.motion.axes[1].resting
    c.MoveAbs(1, 100.0)
    until(c, lambda: not c.IsMoving(1))
    cycle(c, 30)
    assert c.GetCompPos(0) == pytest.approx(0.1, abs=1e-12)
    assert c.motion.axes[0].resting  # and rests again once axis 1 does


def test_self_referenced_compensation_uses_the_axis_own_reference():
    c = machine(1)
    table = [0.0, 0.5]
    assert c.SetupComp(0, 0, 0.0, 100.0, 2, 0, table) == 0
    assert c.EnableComp(0) == 0
    enable(c, 0)
    c.MoveAbs(0, 50.0)
    until(c, lambda: c.IsInPos(0))
    assert c.GetCompPos(0) == pytest.approx(0.25, abs=1e-12)
    assert c.GetPosOut(0) == pytest.approx(50.25, abs=1e-12)
    assert c.GetPosFb(0) == pytest.approx(50.0, abs=1e-4)


def test_enable_and_disable_comp_only_while_the_axis_is_disabled():
    c = machine(3)
    table = list(USER_TABLE)
    assert c.SetupComp(0, 1, -100.0, 200.0, 5, 1, table) == 0
    enable(c, 0)
    assert c.EnableComp(0) == err(st.CMD_INVALID_ENABLED)
    assert c.GetAxisLastErr(0) == err(st.CMD_INVALID_ENABLED)
    c.Disable(0)
    cycle(c)
    assert c.EnableComp(0) == 0
    enable(c, 0)
    assert c.DisableComp(0) == err(st.CMD_INVALID_ENABLED)
    c.Disable(0)
    cycle(c)
    assert c.DisableComp(0) == 0 and c.IsCompActive(0) == 0
    # DisableComp clears the settings: set up again before enabling
    assert c.EnableComp(0) == err(st.COMP_NOT_CNFG)


def test_disabling_the_axis_stops_sending_the_compensation():
    c = machine(3)
    table = [0.3] * 5
    assert c.SetupComp(0, 0, 0.0, 10.0, 5, 0, table) == 0
    c.EnableComp(0)
    enable(c, 0)
    cycle(c, 10)
    assert c.GetCompPos(0) == pytest.approx(0.3)
    assert c.GetPosFbComp(0) == pytest.approx(0.3, abs=1e-4)
    c.Disable(0)
    cycle(c, 3)
    assert c.GetCompPos(0) == 0.0 and c.IsCompActive(0) == 1
    assert c.GetPosFb(0) == pytest.approx(0.3, abs=1e-4)  # the motor stays where it is


def test_setup_refusals():
    c = machine(3)
    table = list(USER_TABLE)
    assert c.SetupComp(0, 0, 0.0, 0.0, 5, 1, table) == err(st.CMD_INVALID_PARAMETER)
    assert c.SetupComp(0, 98, 0.0, 1.0, 5, 1, table) == err(st.CMD_INVALID_PARAMETER)
    assert c.SetupComp(0, 0, 0.0, 1.0, 5, 7, table) == st.SYS_HMPL_ARG_OUT_OF_RANGE
    table[3] = -1.2  # beyond the 1 mm limit (14.1)
    assert c.SetupComp(0, 0, 0.0, 1.0, 5, 1, table) == err(st.COMP_LIMIT)
    table[3] = -1.0
    assert c.SetupComp(0, 0, 0.0, 1.0, 5, 1, table) == 0
    assert c.EnableComp(0) == 0
    assert c.SetupComp(0, 0, 0.0, 1.0, 5, 1, table) == err(st.CMD_INVALID_COMP_ENABLED)
    assert c.SetCompAlgType(0, 1) == err(st.CMD_INVALID_COMP_ENABLED)


def test_alg_type_checks():
    c = machine(3)
    assert c.SetCompAlgType(0, 2) == err(st.CMD_INVALID_PARAMETER)
    assert c.SetCompAlgType(0, 1) == 0
    three = [0.0] * 8
    args = ([0.0] * 3, [1.0] * 3, [2] * 3, [0, 1, 2])
    assert c.SetupComp3D(0, 0, *args, three) == err(st.CMD_INVALID_PARAMETER)
    assert c.SetCompAlgType(0, 0) == 0
    assert c.SetupComp3D(0, 0, *args, three) == 0
    assert c.SetCompAlgType(0, 1) == err(st.CMD_INVALID_PARAMETER)


def test_set_pos_and_homing_are_refused_while_compensation_fixes_the_origin():
    c = machine(3)
    example_1(c)
    enable(c, 0, 1, 2)
    assert c.SetPos(0, 5.0) == err(st.CMD_INVALID_COMP_ENABLED)
    assert c.SetPos(1, 5.0) == err(st.CMD_INVALID_COMP_ENABLED, 1)  # a reference axis
    assert c.SetPos(2, 5.0) == 0
    assert c.MoveHome(1) == err(st.CMD_INVALID_COMP_ENABLED, 1)
    c.Disable(0)
    cycle(c)
    assert c.DisableComp(0) == 0
    assert c.SetPos(1, 5.0) == 0


def test_a_spline_beyond_the_limit_stops_the_axis_with_the_limit_error():
    c = machine(2)
    assert c.SetCompAlgType(0, 1) == 0
    table = [0.0, 1.0, 1.0, 0.0]  # the natural spline peaks at 1.15 between the points
    assert c.SetupComp(0, 0, 0.0, 10.0, 4, 1, table) == 0
    c.EnableComp(0)
    enable(c, 0, 1)
    c.MoveAbs(1, 30.0)
    until(c, lambda: c.IsErrorStop(0))
    assert c.GetAxisLastErr(0) == err(st.COMP_LIMIT)
    assert abs(c.GetCompPos(0)) <= 1.0
    until(c, lambda: not c.IsMoving(1))
    assert c.GetCompPos(0) == pytest.approx(0.0, abs=1e-12)


def test_2d_example_axis_2_compensated_by_axes_0_and_1():
    c = machine(3)
    table = [0.0] * 3 + [0.3, 0.1, -0.4, -0.4, 0.0, 0.2, 0.2, -0.1, 0.5]
    args = ([-100.0, -100.0], [200.0, 100.0], [3, 3], [0, 1])
    assert c.SetupComp2D(2, 3, *args, table) == 0 and c.EnableComp(2) == 0
    enable(c, 0, 1, 2)
    c.MoveAbs(0, 0.0)
    c.MoveAbs(1, -50.0)
    until(c, lambda: c.IsInPos(0) and c.IsInPos(1) and c.IsInPos(2))
    assert c.GetCompPos(2) == pytest.approx(0.0, abs=1e-12)
    c.MoveAbs(0, 300.0)
    c.MoveAbs(1, 100.0)
    until(c, lambda: c.IsInPos(0) and c.IsInPos(1) and c.IsInPos(2))
    assert c.GetCompPos(2) == pytest.approx(0.5, abs=1e-12)
