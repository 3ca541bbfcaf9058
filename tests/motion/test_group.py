"""Axis groups (manual chapter 8) through the motion commands: membership, states,
settings, errors, stop/halt/resume, the queue and the scope channels."""

from __future__ import annotations

import math

import pytest
from group_util import DT, Recorder, cycle, grouped, grp_err, machine, until

from motionvm.motion import axis_status as st
from motionvm.motion import group as grp
from motionvm.motion.group_coords import CS_ACS, CS_MCS, CS_OFFSET, CS_PCS

BAD_ID = st.SYS_HMPL_ARG_OUT_OF_RANGE


# ---- membership (8.3.1-8.3.5) ---------------------------------------------------------


def test_add_remove_and_ids():
    c = machine()
    assert c.GetGroupID(0) == -1 and c.IsGrouped(0) == 0
    assert c.AddAxisToGrp(3, 0) == 0 and c.AddAxisToGrp(3, 2) == 0
    assert c.GetGroupID(0) == 3 and c.GetGroupID(2) == 3 and c.IsGrouped(2) == 1
    assert c.AddAxisToGrp(3, 0) == grp_err(grp.CRD_AXIS_DUPLICATED, 3)
    assert c.AddAxisToGrp(4, 0) == grp_err(grp.CRD_AXIS_DUPLICATED, 4)
    assert c.GetGrpLastErr(4) == grp_err(grp.CRD_AXIS_DUPLICATED, 4)
    assert c.RemoveAxisFromGrp(3) == 0  # the last one added leaves
    assert c.GetGroupID(2) == -1 and c.GetGroupID(0) == 3
    assert c.UngrpAllAxes(3) == 0 and c.GetGroupID(0) == -1
    assert c.RemoveAxisFromGrp(3) == grp_err(grp.CRD_GRP_SIZE_EMPTY, 3)


def test_bad_ids():
    c = machine()
    assert c.AddAxisToGrp(16, 0) == BAD_ID and c.AddAxisToGrp(0, 9) == BAD_ID
    assert c.GetSystemLastErr() == BAD_ID
    assert c.GetGroupID(99) == -1 and c.IsGrpEnabled(-1) == 0
    assert c.GetGrpMaxVel(16) == 0.0 and c.GetGrpLastErr(16) == BAD_ID


def test_group_is_full_at_nine_axes():
    c = machine(10)
    for i in range(9):
        assert c.AddAxisToGrp(0, i) == 0
    assert c.AddAxisToGrp(0, 9) == grp_err(grp.CRD_GRP_SIZE_FULL)


def test_enable_needs_enabled_axes_and_at_most_six_for_cartesian():
    c = machine(8)
    assert c.EnableGroup(0) == grp_err(grp.CRD_GRP_SIZE_EMPTY)
    c.AddAxisToGrp(0, 0)
    assert c.EnableGroup(0) == grp_err(grp.CRD_GRP_AXIS_INVALID)
    for i in range(7):
        c.Enable(i)
    until(c, lambda: c.IsEnabled(6))
    for i in range(1, 7):
        c.AddAxisToGrp(0, i)
    assert c.EnableGroup(0) == grp_err(grp.CRD_INVALID_KIN_SETTING)
    c.RemoveAxisFromGrp(0)
    assert c.EnableGroup(0) == 0 and c.IsGrpEnabled(0) == 1
    assert c.AddAxisToGrp(0, 7) == grp_err(grp.CRD_INVALID_STATE)


def test_a_cycle_visits_the_enabled_groups_only():
    """The group set keeps the list of enabled groups, by id, as groups are enabled and
    disabled (directly, by UngrpAllAxes): a cycle steps those and no other."""
    c = grouped(2, gid=5)
    groups = c.motion.groups
    assert groups.enabled == [groups[5]]
    assert c.Enable(2) == 0
    until(c, lambda: c.IsEnabled(2))
    assert c.AddAxisToGrp(1, 2) == 0 and c.EnableGroup(1) == 0
    assert groups.enabled == [groups[1], groups[5]]
    assert c.LineAbs2D(5, 3.0, 4.0) == 0
    until(c, lambda: c.IsGrpInPos(5))
    assert [a.ref_pos for a in groups[5].axes] == [3.0, 4.0]
    assert c.DisableGroup(5) == 0 and groups.enabled == [groups[1]]
    assert c.UngrpAllAxes(1) == 0 and groups.enabled == []
    assert not c.motion.groups_moving()


def test_grouped_axis_refuses_single_axis_moves():
    c = grouped(2)
    code = st.axis_error(st.CMD_INVALID_GROUPED, 1)
    assert c.MoveAbs(1, 5.0) == code and c.GetAxisLastErr(1) == code
    assert c.MoveVel(1, 5.0) == code
    assert c.DisableGroup(0) == 0
    assert c.MoveAbs(1, 5.0) == 0  # a disabled group lets its axes move on their own


def test_kinematics():
    c = machine()
    assert c.GetGrpKin(0) == 1
    assert c.SetGrpKin(0, 2) == grp_err(grp.CRD_INVALID_KIN_SETTING)
    assert c.SetGrpKin(0, 1) == 0


# ---- settings (8.3.6-8.3.35) ----------------------------------------------------------


def test_profile_defaults_and_ranges():
    c = machine()
    assert (c.GetGrpMaxVel(0), c.GetGrpMaxAcc(0), c.GetGrpMaxDec(0), c.GetGrpSMTime(0)) == (
        100.0, 500.0, 500.0, 50.0)  # fmt: skip
    assert c.SetGrpMotionProfile(0, 200, 2000, 3000, 20) == 0
    assert (c.GetGrpMaxVel(0), c.GetGrpMaxAcc(0), c.GetGrpMaxDec(0), c.GetGrpSMTime(0)) == (
        200.0, 2000.0, 3000.0, 20.0)  # fmt: skip
    assert c.SetGrpVel(0, 5001) == grp_err(grp.CRD_INVALID_LIN_VEL)
    assert c.SetGrpAcc(0, 0) == grp_err(grp.CRD_INVALID_LIN_ACC)
    assert c.SetGrpDec(0, 60000) == grp_err(grp.CRD_INVALID_LIN_DEC)
    assert c.SetGrpSMTime(0, 501) == grp_err(grp.CRD_INVALID_LIN_SM_TIME)
    assert c.SetGrpAccTime(0, 100) == 0 and c.GetGrpMaxAcc(0) == pytest.approx(2000.0)
    assert c.SetGrpDecTime(0, 400) == 0 and c.GetGrpMaxDec(0) == pytest.approx(500.0)
    # a time whose acceleration is no number (5e-324 ms / 1000 is 0) is refused, not divided
    assert c.SetGrpAccTime(0, 5e-324) == grp_err(grp.CRD_INVALID_LIN_ACC)
    assert c.SetGrpDecTime(0, 1e-320) == grp_err(grp.CRD_INVALID_LIN_DEC)
    assert (c.GetGrpMaxAcc(0), c.GetGrpMaxDec(0)) == pytest.approx((2000.0, 500.0))
    assert c.SetGrpAngMotionProfile(0, 7201, 1, 1, 0) == grp_err(grp.CRD_INVALID_ANG_VEL)
    assert c.SetGrpAngMotionProfile(0, 720, 7200, 7200, 0) == 0


def test_modes_scale_queue_lookahead_settings():
    c = machine()
    assert c.GetGrpBufferMode(0) == 0 and c.GetGrpTransMode(0) == 0
    assert c.SetGrpBufferMode(0, 6) == 0 and c.GetGrpBufferMode(0) == 6
    assert c.SetGrpBufferMode(0, 7) == grp_err(grp.CRD_BLEND_MODE_UNKNOWN)
    assert c.SetGrpTransMode(0, 1) == grp_err(grp.CRD_TRANS_MODE_UNKNOWN)  # TM_START_VEL
    assert c.SetGrpTransMode(0, 5) == 0
    assert c.SetGrpTransPrm(0, 50, 20, 0, 0) == 0
    assert c.SetGrpTransPrm(0, 5000, 20, 0, 0) == grp_err(grp.CRD_INVALID_TRANS_VEL)
    assert c.SetGrpTransPrm(0, 50, -1, 0, 0) == grp_err(grp.CRD_INVALID_TRANS_DIS)
    assert c.SetGrpVelScale(0, 50) == 0 and c.GetGrpVelScale(0) == 50.0
    assert c.SetGrpVelScale(0, 101) == grp_err(grp.CRD_INVALID_VEL_SCALE)
    assert c.SetGrpQueueSize(0, 11) == grp_err(grp.CRD_INVALID_QUEUE_SIZE)
    assert c.SetGrpQueueSize(0, 3) == 0 and c.motion.groups[0].queue_size == 8
    assert c.SetGrpLookAheadPrm(0, 0, 0) == grp_err(grp.CRD_LOOKAHEAD_INVALID_PARAM)
    assert c.SetGrpLookAheadPrm(0, 2, 0.01) == 0
    assert c.motion.groups[0].lookahead == [5000.0, 100.0, 0.01]


def test_coordinate_transform_settings():
    c = machine()
    assert c.GetGrpCoordSys(0) == CS_MCS
    assert c.SetGrpCoordTrans(0, CS_PCS, [1, 2, 3, 4, 5, 6]) == 0
    assert c.GetGrpCoordTrans(0, CS_PCS) == (0, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
    assert c.GetGrpCoordTrans(0, CS_OFFSET) == (0, [0.0] * 6)
    assert c.SetGrpCoordTrans(0, CS_PCS | CS_OFFSET, [0] * 6) == grp_err(grp.CRD_COORD_SYS_UNKNOWN)
    assert c.SetGrpCoordTrans(0, CS_PCS, [math.nan] * 6) == grp_err(grp.CRD_COORD_INVALID_PARAM)
    assert c.SetGrpCoordSys(0, 0x100) == grp_err(grp.CRD_COORD_SYS_UNKNOWN)
    assert c.SetGrpCoordSys(0, CS_ACS) == grp_err(grp.CRD_COORD_SYS_UNKNOWN)
    assert c.SetGrpCoordSys(0, CS_OFFSET | (3 << 4) | CS_PCS) == 0


# ---- motion and states ----------------------------------------------------------------


def test_line_reaches_its_target_exactly_and_states():
    c = grouped(2)
    g = c.motion.groups[0]
    until(c, lambda: c.IsGrpInPos(0))
    assert g.state == grp.STANDBY
    assert c.LineAbs2D(0, 30.0, -40.0) == 0
    assert c.IsGrpMoving(0) == 1 and c.IsGrpInPos(0) == 0
    cycle(c)
    assert g.state == grp.MOVING
    until(c, lambda: c.IsGrpInPos(0))
    assert g.state == grp.STANDBY
    assert [a.ref_pos for a in g.axes] == [30.0, -40.0]
    assert c.LineRel2D(0, 1.0, 2.0) == 0
    until(c, lambda: c.IsGrpInPos(0))
    assert [a.ref_pos for a in g.axes] == [31.0, -38.0]


def test_line_time_is_the_axis_profile_in_path_length():
    """A line from rest to rest takes the T-curve time of its length plus Ts (5.1)."""
    c = grouped(2)
    c.SetGrpMotionProfile(0, 100, 5000, 5000, 200)
    c.LineAbs2D(0, 100.0, 100.0)
    n = until(c, lambda: not c.IsGrpMoving(0))
    # 141.42 mm at 100 mm/s, 20 ms ramps: 1.4342 s + Ts 0.2 s
    assert n * DT == pytest.approx(100 * math.sqrt(2) / 100 + 0.02 + 0.2, abs=2 * DT)


def test_motion_needs_an_enabled_group():
    c = machine()
    c.AddAxisToGrp(0, 0)
    assert c.LineAbs2D(0, 1, 1) == grp_err(grp.CRD_INVALID_DISABLED)
    assert c.StopGroup(0) == grp_err(grp.CRD_INVALID_DISABLED)


def test_queue_full_and_cmd_num():
    c = grouped(2)
    c.SetGrpQueueSize(0, 2)  # 4 commands
    for i in range(4):
        assert c.LineAbs2D(0, 10.0 * (i + 1), 0.0) == 0
    assert c.GetGrpCmdNum(0) == 3
    assert c.LineAbs2D(0, 99.0, 0.0) == grp_err(grp.CRD_QUEUE_FULL)
    until(c, lambda: c.IsGrpInPos(0))
    assert c.GetGrpCmdNum(0) == 0
    assert c.motion.axes[0].ref_pos == 40.0


def test_stop_brakes_along_the_path_and_clears_the_queue():
    c = grouped(2)
    c.LineAbs2D(0, 100.0, 0.0)
    c.LineAbs2D(0, 100.0, 100.0)
    cycle(c, 300)
    assert c.StopGroup(0) == 0
    g = c.motion.groups[0]
    assert g.state == grp.STOPPING
    assert c.LineAbs2D(0, 0.0, 0.0) == grp_err(grp.CRD_INVALID_STATE)
    until(c, lambda: not c.IsGrpMoving(0))
    assert g.state == grp.STANDBY and c.GetGrpCmdNum(0) == 0
    x, y = (a.ref_pos for a in g.axes)
    assert 0.0 < x < 100.0 and y == 0.0
    assert c.LineRel2D(0, 0.0, 5.0) == 0  # a relative move starts where it stopped
    until(c, lambda: c.IsGrpInPos(0))
    assert [a.ref_pos for a in g.axes] == pytest.approx([x, 5.0])


def test_halt_and_resume():
    c = grouped(2)
    c.LineAbs2D(0, 50.0, 0.0)
    cycle(c, 200)
    assert c.ResumeGroup(0) == grp_err(grp.CRD_INVALID_STATE)
    assert c.HaltGroup(0) == 0
    cycle(c, 500)
    x = c.motion.axes[0].ref_pos
    cycle(c, 10)
    assert c.motion.axes[0].ref_pos == x < 50.0 and c.IsGrpMoving(0) == 1
    assert c.ResumeGroup(0) == 0
    until(c, lambda: c.IsGrpInPos(0))
    assert c.motion.axes[0].ref_pos == 50.0


def test_velocity_scale_scales_the_feed():
    c = grouped(2)
    c.SetGrpVelScale(0, 50)
    rec = Recorder(c)
    c.LineAbs2D(0, 100.0, 0.0)
    rec.run()
    assert max(rec.speeds) == pytest.approx(50.0, rel=1e-6)
    c.SetGrpVelScale(0, 0)
    c.LineAbs2D(0, 0.0, 0.0)
    cycle(c, 100)
    assert c.motion.axes[0].ref_pos == 100.0 and c.IsGrpMoving(0) == 1
    c.SetGrpVelScale(0, 100)
    until(c, lambda: c.IsGrpInPos(0))
    assert c.motion.axes[0].ref_pos == 0.0


def test_axis_fault_puts_the_group_in_error_stop():
    c = grouped(3, n=4)
    c.LineAbs3D(0, 100.0, 100.0, 100.0)
    cycle(c, 100)
    c.Disable(2)
    cycle(c)
    g = c.motion.groups[0]
    assert c.IsGrpErrorStop(0) == 1
    assert c.GetGrpLastErr(0) == grp_err(grp.CRD_AXIS_ABNORMALLY_DISABLED)
    assert g.fault_status & grp.GFS_ERROR_STOP and g.fault_status & grp.GFS_AXIS_FAULT
    assert c.LineAbs3D(0, 0, 0, 0) == grp_err(grp.CRD_INVALID_STATE)
    until(c, lambda: not c.IsGrpMoving(0))
    rest = [a.ref_pos for a in g.axes[:2]]
    cycle(c, 50)
    assert [a.ref_pos for a in g.axes[:2]] == rest  # no motion after the error stop
    assert c.ResetGroup(0) == grp_err(grp.CRD_INVALID_STATE)  # axis 2 is still disabled
    c.Enable(2)
    until(c, lambda: c.IsEnabled(2))
    assert c.ResetGroup(0) == 0 and c.IsGrpErrorStop(0) == 0
    assert c.LineAbs3D(0, 0, 0, 0) == 0
    until(c, lambda: c.IsGrpInPos(0))
    assert [a.ref_pos for a in g.axes] == [0.0, 0.0, 0.0]
    assert c.ClearGrpLastErr(0) == 0 and c.GetGrpLastErr(0) == 0


def test_software_limit_of_an_axis_stops_the_group():
    c = grouped(2)
    c.SetSWRL(0, 20.0)
    c.JogGroup(0, 0, 50.0)
    until(c, lambda: c.IsGrpErrorStop(0), limit=5000)
    assert c.GetGrpLastErr(0) == grp_err(grp.CRD_AXIS_SWL)
    assert c.motion.groups[0].fault_status & grp.GFS_SW_LIMIT


def test_jog_group_and_jog_axis():
    c = grouped(2)
    assert c.JogGroup(0, 1, -40.0) == 0
    cycle(c, 1000)
    assert c.motion.axes[1].ref_vel == pytest.approx(-40.0)
    assert c.LineAbs2D(0, 0, 0) == grp_err(grp.CRD_INVALID_MOVING)
    assert c.JogGroupAxis(0, 0, 10.0) == 0  # switch to axis 0: axis 1 brakes first
    cycle(c, 1500)
    assert c.motion.axes[1].ref_vel == 0.0 and c.motion.axes[0].ref_vel == pytest.approx(10.0)
    assert c.JogGroup(0, 5, 1.0) == grp_err(grp.CRD_GRP_AXIS_INVALID)
    assert c.StopGroup(0) == 0
    until(c, lambda: c.IsGrpInPos(0))


def test_pose_cmd_and_fb_in_systems():
    c = grouped(2)
    c.SetGrpCoordTrans(0, CS_PCS, [100, 50, 0, 0, 0, 90])
    c.LineAbs2D(0, 10.0, 20.0)
    until(c, lambda: c.IsGrpInPos(0))
    assert c.GetGrpPoseCmd(0, CS_MCS) == (0, [10.0, 20.0, 0.0, 0.0, 0.0, 0.0])
    assert c.GetGrpPoseFb(0, CS_ACS)[1][:2] == [10.0, 20.0]
    status, pcs = c.GetGrpPoseCmd(0, CS_PCS)
    # (10, 20) = (100, 50) + Rz(90) (x, y): x = 20 - 50 = -30, y = -(10 - 100) = 90
    assert status == 0 and pcs[:2] == pytest.approx([-30.0, 90.0])


def test_scope_channels_of_a_group():
    from motionvm.sim.scope import ScopeError
    from motionvm.sim.scope_groups import GroupScopeSource

    c = grouped(2)
    until(c, lambda: c.IsGrpInPos(0))

    class Ctl:
        motion = c.motion

    src = GroupScopeSource(Ctl())
    vel, unit = src.resolve("group0.grp_pg_vel")
    assert unit == "mm/s"
    pos_y, _ = src.resolve("group0.carte_pose_cmd[1]")
    status, _ = src.resolve("group0.grp_motion_status")
    assert status() == grp.GMS_ENABLED | grp.GMS_IN_POSITION
    c.LineAbs2D(0, 0.0, 10.0)
    cycle(c, 200)
    assert vel() > 0.0 and 0.0 < pos_y() < 10.0 and int(status()) & grp.GMS_MOVING
    assert src.resolve("axis0.ref_pos") is None
    with pytest.raises(ScopeError):
        src.resolve("group0.carte_pose_cmd")
    with pytest.raises(ScopeError):
        src.resolve("group16.grp_pg_vel")
    assert "group15.joint_pos_fb[8]" in set(src.channel_names())


def test_stop_all_stops_a_group_along_its_path():
    c = grouped(2)
    c.LineAbs2D(0, 100.0, 0.0)
    cycle(c, 300)
    assert c.StopAll() == 0
    until(c, lambda: not c.IsGrpMoving(0))
    assert c.IsGrpErrorStop(0) == 0 and c.IsGrpEnabled(0) == 1
    assert c.motion.axes[1].ref_pos == 0.0 and 0.0 < c.motion.axes[0].ref_pos < 100.0


def test_command_filter_hook_sees_every_commanded_pose():
    """The hook of a group input shaper: a two-impulse filter (half now, half 20 cycles
    later) delays the end of the move; `busy` keeps the group moving through its tail."""

    class TwoImpulses:
        def __init__(self):
            self.history: list[list[float]] = []

        @property
        def busy(self) -> bool:
            return len(self.history) > 20 and self.history[-1] != self.history[-21]

        def __call__(self, pose):
            self.history.append(list(pose))
            old = self.history[-21] if len(self.history) > 20 else self.history[0]
            return [0.5 * (x + y) for x, y in zip(pose, old)]

    plain = grouped(2)
    plain.LineAbs2D(0, 10.0, 0.0)
    n_plain = until(plain, lambda: not plain.IsGrpMoving(0))
    c = grouped(2)
    g = c.motion.groups[0]
    shaper = TwoImpulses()
    g.planner.command_filter = shaper
    assert g.motion_status & grp.GMS_INPUT_SHAPE
    c.LineAbs2D(0, 10.0, 0.0)
    n_shaped = until(c, lambda: not c.IsGrpMoving(0))
    assert c.motion.axes[0].ref_pos == 10.0
    assert n_shaped == n_plain + 20


def test_target_beyond_a_software_limit_is_refused():
    c = grouped(2)
    c.SetSWRL(1, 50.0)
    assert c.LineAbs2D(0, 10.0, 60.0) == grp_err(grp.CRD_INVALID_POS)
    assert c.LineAbs2D(0, 10.0, 40.0) == 0


def test_a_positive_speed_too_small_to_end_a_move_is_refused():
    """A transition velocity or feed above 0 but below MIN_SPEED (a 4e-117 mm/s blend
    would never end) is an invalid parameter; 0 keeps its meaning."""
    from motionvm.motion import group as grp

    c = grouped(2)
    assert c.SetGrpTransPrm(0, 4e-117, 1.0, 0.0, 0.0) == grp_err(grp.CRD_INVALID_TRANS_VEL)
    assert c.SetGrpTransPrm(0, 0.0, 1.0, 0.0, 0.0) == 0
    assert c.SetGrpTransPrm(0, 1e-6, 1.0, 0.0, 0.0) == 0
    assert c.SetGrpMotionProfile(0, 5e-324, 500.0, 500.0, 50.0) == grp_err(grp.CRD_INVALID_LIN_VEL)
