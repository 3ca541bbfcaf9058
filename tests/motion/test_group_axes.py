"""What an axis of a group reports and accepts: the synchronous state while its group is
enabled (5.1.1.5 bit 3, IsSync 5.4.7), SetPos refused on a group's axis (5.3.19),
DisableAll and EStop disabling the groups with the axes (2.7, 2.9), and SetupGroup's
limit of 9 axes (8.3.3)."""

from __future__ import annotations

from group_util import cycle, grouped, grp_err, until

from motionvm.motion import axis_status as st
from motionvm.motion import group as grp


def test_an_axis_of_an_enabled_group_is_synchronous():
    c = grouped(2, n=3)
    for i in (0, 1):
        assert c.IsSync(i) == 1
        assert c.motion.axes[i].motion_status & st.MS_SYNC
    assert c.IsSync(2) == 0
    assert c.DisableGroup(0) == 0
    assert c.IsSync(0) == 0 and c.IsGrouped(0) == 1  # a member still, no longer synchronous
    assert not c.motion.axes[0].motion_status & st.MS_SYNC
    assert c.EnableGroup(0) == 0 and c.IsSync(1) == 1
    assert c.UngrpAllAxes(0) == 0 and c.IsSync(1) == 0


def test_an_axis_stays_synchronous_through_its_groups_error_stop():
    c = grouped(2, n=3)
    assert c.Disable(1) == 0
    cycle(c)
    assert c.IsGrpErrorStop(0) == 1
    assert c.IsSync(0) == 1 and c.IsSync(1) == 1  # the group is still enabled


def test_set_pos_refuses_an_axis_of_a_group_enabled_or_not():
    c = grouped(2, n=3)
    a = c.motion.axes[1]
    code = st.axis_error(st.CMD_INVALID_GROUPED, 1)
    assert c.SetPos(1, 50.0) == code and c.GetAxisLastErr(1) == code
    cycle(c, 5)
    assert a.pos_fb == 0.0 and a.pos_offset == 0.0
    assert c.motion.groups[0].pose_fb()[:2] == [0.0, 0.0]
    assert c.DisableGroup(0) == 0
    assert c.SetPos(1, 50.0) == code  # a member of a disabled group still
    assert c.UngrpAllAxes(0) == 0
    assert c.SetPos(1, 50.0) == 0 and a.pos_fb == 50.0


def test_disable_all_disables_the_groups_too():
    """Even a moving group: DisableAll disables at once, the path is dropped."""
    c = grouped(2, n=3)
    g = c.motion.groups[0]
    assert c.LineAbs2D(0, 100.0, 50.0) == 0
    cycle(c, 100)
    assert c.IsGrpMoving(0) == 1
    assert c.DisableAll() == 0
    assert c.IsGrpEnabled(0) == 0 and c.IsGrpMoving(0) == 0 and c.IsGrpErrorStop(0) == 0
    assert c.motion.groups.enabled == []
    assert c.IsEnabled(0) == 0 and c.IsSync(0) == 0 and c.IsGrouped(0) == 1
    cycle(c, 5)
    assert c.IsGrpErrorStop(0) == 0 and c.GetGrpLastErr(0) == 0
    assert not c.motion.busy()
    for i in (0, 1):
        assert c.Enable(i) == 0
    until(c, lambda: c.IsEnabled(0) and c.IsEnabled(1))
    rest = [a.ref_pos for a in g.axes]
    assert c.EnableGroup(0) == 0 and c.LineRel2D(0, 1.0, 1.0) == 0
    until(c, lambda: c.IsGrpInPos(0))
    assert [a.ref_pos for a in g.axes] == [rest[0] + 1.0, rest[1] + 1.0]


def test_estop_disables_the_groups_too():
    c = grouped(2, n=3)
    c.EStop()
    assert c.IsGrpEnabled(0) == 0 and c.IsSync(1) == 0


def test_setup_group_of_more_than_nine_axes_fails_and_changes_nothing():
    c = grouped(2, n=12)
    code = grp_err(grp.CRD_GRP_SIZE_FULL)
    assert c.SetupGroup(0, *range(10)) == code and c.GetGrpLastErr(0) == code
    assert c.IsGrpEnabled(0) == 1 and [a.axis_id for a in c.motion.groups[0].axes] == [0, 1]
    # 9 axes join; Cartesian kinematics then maps 6 of them at most (as EnableGroup)
    assert c.SetupGroup(1, *range(2, 11)) == grp_err(grp.CRD_INVALID_KIN_SETTING, 1)
    assert c.GetGroupID(10) == 1
    assert c.SetupGroup(1, *range(2, 12)) == grp_err(grp.CRD_GRP_SIZE_FULL, 1)
    assert c.SetupGroup(1, *range(2, 20)) == grp_err(grp.CRD_GRP_SIZE_FULL, 1)
