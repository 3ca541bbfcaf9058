"""The motion commands called directly, without a language: a few functions per chapter,
their results in manual units and their error codes."""

from __future__ import annotations

import pytest
from axis_util import cycle, enabled, machine, until

from motionvm.motion import axis_status as st
from motionvm.motion import gear
from motionvm.motion.commands import MotionCommands
from motionvm.motion.homing import DRIVE_HOME_FAILED
from motionvm.motion.kernel import ECAT_OP
from motionvm.motion.touchprobe import CMD_INVALID_TP_ENABLED

BAD_ID = st.SYS_HMPL_ARG_OUT_OF_RANGE


def bad_id_stored(c: MotionCommands) -> bool:
    return c.GetSystemLastErr() == BAD_ID


# ---------------------------------------------------------------- chapter 2: bus, system


def test_scan_network_takes_the_bus_down_and_up_and_refuses_while_enabled():
    c = enabled(2, 1)
    assert c.GetECATSt() == ECAT_OP and c.IsSystemOper() == 1 and c.GetSlaveNum() == 2
    assert c.ScanNetwork() == st.axis_error(st.CMD_INVALID_ENABLED, 1)
    assert c.Disable(1) == 0
    cycle(c, 5)
    assert c.ScanNetwork() == 0 and c.IsSystemInit() == 1
    assert c.Enable(0) == st.SYS_HMPL_NOT_IN_OP_MODE
    cycle(c)
    assert c.IsSystemPreOp() == 1
    cycle(c, 2)
    assert c.GetECATSt() == ECAT_OP and c.GetSlvECATSt(1) == ECAT_OP
    assert c.GetSlvECATSt(2) == 0 and bad_id_stored(c)


def test_estop_disables_every_axis_and_reports_a_system_error():
    c = enabled(3)
    assert c.MoveVel(0, 50.0) == 0 and c.StopAll() == 0
    c.EStop()
    assert c.IsSystemError() == 1 and c.IsSystemOper() == 0
    assert c.GetSystemLastErr() == st.SYS_EMERGENCY_STOP
    assert not any(c.IsEnabled(i) for i in range(3))


# ---------------------------------------------------------------- chapter 5: axis


def test_move_abs_in_mm_and_its_status():
    c = enabled(2, 0)
    assert c.MoveAbs(0, 12.5) == 0
    assert (c.IsMoving(0), c.IsInPos(0)) == (1, 0)  # at once, in the calling cycle
    until(c, lambda: c.IsInPos(0))
    assert c.GetPosFb(0) == pytest.approx(12.5, abs=1e-6)
    assert c.GetRefPos(0) == 12.5 and c.GetRefVel(0) == 0.0
    assert c.GetAxisNum() == 2


def test_axis_errors_are_the_manuals_codes_and_become_last_errors():
    c = enabled(2, 0)
    code = c.MoveAbs(1, 5.0)  # axis 1 is disabled
    assert code == st.axis_error(st.CMD_INVALID_DISABLED, 1) and code < 0  # a C int
    assert c.GetAxisLastErr(1) == code
    assert c.ClearAxisLastErr(1) == 0 and c.GetAxisLastErr(1) == 0
    assert c.MoveAbs(0, float("nan")) == st.axis_error(st.CMD_INVALID_POS, 0)
    assert c.SetVel(0, -1.0) == st.axis_error(st.CMD_INVALID_VEL, 0)


def test_a_bad_axis_id_is_a_system_error_and_getters_answer_zero():
    c = enabled(2, 0)
    assert c.MoveAbs(7, 1.0) == BAD_ID and bad_id_stored(c)
    c.motion.system_last_error = 0
    assert c.GetPosFb(-1) == 0.0 and bad_id_stored(c)
    c.motion.system_last_error = 0
    assert c.IsInPos(2) == 0 and c.IsEnabled(99) == 0 and bad_id_stored(c)
    assert c.GetAxisLastErr(2) == BAD_ID


def test_move_pvt_takes_sequences_of_one_length():
    c = enabled(1, 0)
    bad = st.axis_error(st.CMD_INVALID_PARAMETER, 0)
    assert c.MovePVT(0, [], [], []) == bad
    assert c.MovePVT(0, [100.0, 200.0], [1.0], [0.0, 0.0]) == bad
    assert c.MovePVT(0, [100.0, 200.0], [1.0, 2.0], [10.0, 0.0]) == 0
    until(c, lambda: c.IsInPos(0))
    assert c.GetPosFb(0) == pytest.approx(2.0, abs=1e-6)


def test_an_axis_run_by_a_drive_program_refuses_commands_but_answers_getters():
    c = enabled(2, 0)
    c.motion.axes[0].controlled_by = "PDL drive"  # as a machine file's `pdl = ...` marks it
    assert c.MoveAbs(0, 1.0) == st.axis_error(st.CMD_INVALID_CONTROL_MODE, 0)
    assert c.IsEnabled(0) == 1 and c.GetMaxVel(0) > 0.0


# ---------------------------------------------------------------- chapter 6: gear


def test_gear_commands_and_their_errors():
    c = enabled(3)
    assert c.EnableGear(0, 0) == st.axis_error(gear.CMD_INVALID_MASTER_SLAVE_CONNECTION, 0)
    assert c.GearIn(0, 1, 2.0) == st.axis_error(gear.CMD_GEAR_DISABLED, 1)
    assert c.GetAxisLastErr(1) == st.axis_error(gear.CMD_GEAR_DISABLED, 1)
    assert c.EnableGear(0, 1) == 0
    assert c.GearIn(0, 1, 0.0) == st.axis_error(gear.CMD_INVALID_GEAR_RATIO, 1)
    assert c.GearIn(0, 1, 2.0) == 0
    assert (c.IsInGear(1), c.IsGearMaster(0), c.IsGearSlave(1), c.IsSync(1)) == (1, 1, 1, 1)
    assert c.GetGearRatio(1) == 2.0 and c.GetGearRatio(2) == 0.0
    assert c.MoveAbs(0, 10.0) == 0
    until(c, lambda: c.IsInPos(0) and c.IsInPos(1))
    assert c.GetRefPos(1) == pytest.approx(20.0)
    assert c.DisableGear(1) == st.axis_error(st.CMD_INVALID_IN_SYNC, 1)
    assert c.GearOut(1) == 0 and c.DisableGear(1) == 0 and c.IsGearSlave(1) == 0
    assert c.EnableGear(0, 9) == BAD_ID and c.IsInGear(9) == 0


# ---------------------------------------------------------------- chapter 7: gantry


def test_gantry_pair_enables_together_and_reads_linear_and_yaw():
    c = machine(3)
    assert c.EnableGantryPair(0, 1) == 0
    assert c.GetGantryPairID(1) == 0 and c.GetGantryPairID(2) == -1
    assert c.GetGantryPairID(5) == -1 and bad_id_stored(c)
    assert c.IsGantryPair(0, 1) == 1 and c.IsGantryPair(0, 2) == 0
    assert c.EnableGantryPair(0, 2) == st.axis_error(gear.CMD_INVALID_GANTRY_MODE, 0)
    assert c.Enable(0) == 0
    until(c, lambda: c.IsEnabled(1) and c.motion.gantries.pair_of(0).engaged)
    assert c.IsGantry(0) == c.IsGantry(1) == 1
    assert c.MoveAbs(0, 20.0) == 0 and c.MoveAbs(1, 0.5) == 0  # linear 20, yaw 0.5
    until(c, lambda: c.IsInPos(0) and c.IsInPos(1))
    assert (c.GetPosFb(0), c.GetPosFb(1)) == pytest.approx((20.0, 0.5), abs=1e-6)
    motors = c.motion.axes
    assert (motors[0].pos_fb, motors[1].pos_fb) == pytest.approx((20.5, 19.5), abs=1e-6)
    assert c.DisableGantryPair(1) == st.axis_error(st.CMD_INVALID_ENABLED, 0)
    assert c.Disable(0) == 0
    cycle(c, 2)
    assert c.IsEnabled(1) == 0 and c.DisableGantryPair(1) == 0 and c.IsGantry(0) == 0


def test_the_kernel_steps_the_gantry_pairs_in_begin_cycle():
    c = machine(2)
    c.EnableGantryPair(0, 1)
    c.Enable(0)
    for _ in range(50):
        c.motion.step()  # the motion phase alone does not run the enable sequence
    assert c.IsEnabled(0) == 1 and c.IsEnabled(1) == 0
    c.motion.begin_cycle()
    cycle(c, 50)
    assert c.IsEnabled(1) == 1


# ---------------------------------------------------------------- chapter 13: touch probe


def test_touch_probe_on_the_index_latches_in_mm():
    c = enabled(1, 0)
    assert c.SetTouchProbeFunc(0, 2, 0, 0) == st.axis_error(st.CMD_INVALID_PARAMETER, 0)
    assert c.SetTouchProbeFunc(0, 0, 0, 0) == 0
    assert c.EnableTouchProbe(0) == 0
    cycle(c)
    assert c.IsTouchProbeEnabled(0) == 1 and c.IsTouchProbeTriggered(0) == 0
    assert c.SetTouchProbeFunc(0, 1, 0, 0) == st.axis_error(CMD_INVALID_TP_ENABLED, 0)
    assert c.SetPos(0, 100.0) == 0  # the latch reads in the axis's coordinates
    assert c.MoveRel(0, 15.0) == 0
    until(c, lambda: c.IsInPos(0))
    assert c.IsTouchProbeTriggered(0) == 1
    code, pos = c.GetTouchProbePos(0)
    assert code == 0 and pos == pytest.approx(110.0, abs=1e-3)  # the index at 10 mm
    assert c.DisableTouchProbe(0) == 0
    cycle(c)
    assert c.IsTouchProbeEnabled(0) == 0
    assert c.GetTouchProbePos(3) == (BAD_ID, 0.0) and c.IsTouchProbeEnabled(3) == 0


# ---------------------------------------------------------------- chapter 18: errors


def test_group_and_drive_errors():
    c = machine(1)
    assert c.GetGrpLastErr(0) == 0 and c.ClearGrpLastErr(15) == 0
    assert c.GetGrpLastErr(16) == BAD_ID and c.ClearGrpLastErr(-1) == BAD_ID
    assert c.GetDriveErr(0) == 0 and c.GetDriveErr(1) == BAD_ID


# ---------------------------------------------------------------- chapter 20: homing


def test_move_home_starts_and_home_result_tells_how_it_ended():
    c = machine(1)
    assert c.MoveHome(0) == st.axis_error(st.CMD_INVALID_DISABLED, 0)
    assert c.GetAxisLastErr(0) == st.axis_error(st.CMD_INVALID_DISABLED, 0)
    assert c.SetHomeMethod(0, 3) == st.axis_error(st.CMD_INVALID_PARAMETER, 0)
    c.Enable(0)
    until(c, lambda: c.IsEnabled(0))
    assert c.SetHomeMethod(0, 34) == 0 and c.SetHomeOffset(0, 2.0) == 0
    assert c.MoveHome(0) == 0
    assert c.home_result(0) is None and c.IsHoming(0) == 1
    until(c, lambda: c.home_result(0) is not None)
    assert c.home_result(0) == 0 and (c.IsHomed(0), c.IsHoming(0)) == (1, 0)
    assert c.GetPosFb(0) == pytest.approx(2.0, abs=1e-4)
    assert c.SetHomedStatus(0, 0) == 0 and c.IsHomed(0) == 0
    assert c.MoveHome(1) == BAD_ID and c.IsHomed(1) == 0


def test_an_interrupted_homing_ends_with_home_failed():
    c = enabled(1, 0)
    c.SetHomeMethod(0, 17)
    assert c.MoveHome(0) == 0
    cycle(c, 100)
    assert c.Stop(0) == 0
    assert c.home_result(0) == st.axis_error(DRIVE_HOME_FAILED, 0)
    assert c.IsHoming(0) == 1  # the procedure did not complete (motion/homing.py)


# ---------------------------------------------------------------- the state is the kernel's


def test_two_front_ends_on_one_kernel_share_its_state():
    a = enabled(2, 0)
    b = MotionCommands(a.motion)
    assert a.SetTouchProbeFunc(0, 1, 1, 1) == 0 and a.EnableTouchProbe(0) == 0
    assert b.SetTouchProbeFunc(0, 0, 0, 0) == st.axis_error(CMD_INVALID_TP_ENABLED, 0)
    assert a.SetHomeMethod(0, 37) == 0 and b.MoveHome(0) == 0 and a.IsHomed(0) == 1
    assert b.MoveAbs(1, 1.0) == a.GetAxisLastErr(1) != 0
