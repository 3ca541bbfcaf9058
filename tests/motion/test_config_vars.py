"""Controller variables by HCV id (manual 17.1.1, 17.3): every id of the manual's axis
table is registered and readable, writes take effect, and the group table waits for the
axis groups to register theirs."""

from __future__ import annotations

import math

import pytest

from motionvm.motion import inshape
from motionvm.motion.axis_config import AxisConfig
from motionvm.motion.commands import MotionCommands
from motionvm.motion.config_vars import (
    AXIS,
    GROUP,
    HCV_ID_NOT_FOUND,
    HCV_IS_READ_ONLY,
    HCV_VALUE_OUT_OF_RANGE,
    hcv_id,
    manual_ids,
)
from motionvm.motion.kernel import MotionKernel

DT = 0.001


@pytest.fixture
def cmds() -> MotionCommands:
    return MotionCommands(MotionKernel([AxisConfig() for _ in range(3)], DT))


def test_the_manual_tables_are_package_data():
    ids = manual_ids()
    assert len(ids[0x00]) == 24 and len(ids[AXIS]) == 43 and len(ids[GROUP]) == 30
    assert (0x0033, "HCV_ID_pos_tr") in ids[AXIS]


def test_every_axis_id_of_table_17_1_1_2_reads_for_every_axis(cmds):
    for axis_id in range(3):
        for var, name in manual_ids()[AXIS]:
            result, value = cmds.GetConfigVar(hcv_id(AXIS, axis_id, var))
            assert result == 0, name
            assert math.isfinite(value), name


WRITES = [  # (variable, value written, how the axis shows it)
    (0x0033, 0.25, lambda a, k: a.inpos_radius),
    (0x0034, 5.0, lambda a, k: a.inpos_debounce_ms),
    (0x0065, 500.0, lambda a, k: a.sw_right),
    (0x0066, -500.0, lambda a, k: a.sw_left),
    (0x0067, 300.0, lambda a, k: a.config.vel_limit),
    (0x0068, 3000.0, lambda a, k: a.config.acc_limit),
    (0x0079, 2.0, lambda a, k: a.max_pos_err),
    (0x007A, 0.5, lambda a, k: a.filters.comp_limit),
    (0x00A1, 34.0, lambda a, k: k.homing[a.axis_id].settings.method),
    (0x00A2, 30.0, lambda a, k: k.homing[a.axis_id].settings.switch_vel),
    (0x00A3, 3.0, lambda a, k: k.homing[a.axis_id].settings.zero_vel),
    (0x00A4, 5000.0, lambda a, k: k.homing[a.axis_id].settings.timeout_ms),
    (0x00A5, 500.0, lambda a, k: k.homing[a.axis_id].settings.acc),
    (0x00A6, 1.5, lambda a, k: k.homing[a.axis_id].settings.offset),
    (0x00D3, 123.0, lambda a, k: a.pg.v_max),
    (0x00D4, 4000.0, lambda a, k: a.pg.a_max),
    (0x00D5, 5000.0, lambda a, k: a.pg.d_max),
    (0x00D7, 20.0, lambda a, k: a.smooth_time_ms),
    (0x00DB, 50.0, lambda a, k: a.vel_scale),
    (0x0119, 360.0, lambda a, k: a.rollover),
    (0x01F7, 200.0, lambda a, k: a.enable_timeout_ms),
    (0x0214, 0.8, lambda a, k: a.config.torque_constant),
]


@pytest.mark.parametrize(("var", "value", "shown"), WRITES)
def test_a_write_takes_effect(cmds, var, value, shown):
    axis = cmds.motion.axes[1]
    assert cmds.SetConfigVar(hcv_id(AXIS, 1, var), value) == 0
    assert shown(axis, cmds.motion) == pytest.approx(value)
    assert cmds.GetConfigVar(hcv_id(AXIS, 1, var)) == (0, pytest.approx(value))


def test_home_status_and_last_error(cmds):
    assert cmds.SetConfigVar(hcv_id(AXIS, 0, 0x00A0), 1.0) == 0
    assert cmds.IsHomed(0) == 1
    cmds.SetSWRL(0, -5000.0)  # refused: stored as the last error
    assert cmds.GetConfigVar(hcv_id(AXIS, 0, 0x0263))[1] != 0
    assert cmds.SetConfigVar(hcv_id(AXIS, 0, 0x0263), 0.0) == 0
    assert cmds.GetAxisLastErr(0) == 0


def test_max_comp_lim_is_the_compensation_limit(cmds):
    """1 mm by default (14.1); a lower one refuses a table SetupComp took before."""
    hid = hcv_id(AXIS, 1, 0x007A)
    assert cmds.GetConfigVar(hid) == (0, 1.0)
    table = [0.0, 0.0, 0.8, 0.0]
    assert cmds.SetupComp(1, 1, 0.0, 1.0, 3, 1, table) == 0
    assert cmds.SetConfigVar(hid, 0.5) == 0
    code = cmds.SetupComp(1, 1, 0.0, 1.0, 3, 1, table)
    assert code & 0xFFFFFFFF == 0x83010802  # eERR_AXIS_COMP_LIMIT
    for bad in (0.0, -1.0, math.inf, math.nan):
        assert cmds.SetConfigVar(hid, bad) == HCV_VALUE_OUT_OF_RANGE
    assert cmds.GetConfigVar(hid) == (0, 0.5)


def test_failures(cmds):
    assert cmds.GetConfigVar(0x83FF0033) == (-1, 0.0)
    assert cmds.SetConfigVar(0x83000015, 1.0) == HCV_IS_READ_ONLY
    assert cmds.SetConfigVar(0x83000033, -1.0) == HCV_VALUE_OUT_OF_RANGE
    assert cmds.SetConfigVar(0x83000033, math.nan) == HCV_VALUE_OUT_OF_RANGE
    assert cmds.SetConfigVar(0x99000000, 1.0) == HCV_ID_NOT_FOUND
    assert cmds.GetSystemLastErr() == HCV_ID_NOT_FOUND
    code = cmds.SetConfigVar(0x830000D3, 0.0)  # SetVel refuses it: the axis's code
    assert code & 0xFFFFFFFF == 0x83000140
    assert cmds.GetAxisLastErr(0) == code


def test_families_are_extensible(cmds):
    table = cmds.motion.config_vars
    store = {}
    table.add_family(GROUP, lambda g: 0 <= g < 16)
    table.add(GROUP, 0x0104, "HCV_ID_grp_vel_scale", lambda g: store.get(g, 100.0),
              lambda g, v: store.__setitem__(g, v))  # fmt: skip
    assert cmds.SetConfigVar(0x82030104, 40.0) == 0
    assert cmds.GetConfigVar(0x82030104) == (0, 40.0)
    assert cmds.GetConfigVar(0x82100104) == (-1, 0.0)


def test_every_group_id_of_table_17_1_1_3_is_registered(cmds):
    for var, name in manual_ids()[GROUP]:
        assert cmds.GetConfigVar(hcv_id(GROUP, 0, var))[0] == 0, name


GROUP_WRITES = [  # (variable, value written, how the group shows it)
    (0x00DD, 250.0, lambda g, k: g.lin.vel),
    (0x00DE, 2000.0, lambda g, k: g.lin.acc),
    (0x00E0, 20.0, lambda g, k: g.lin.sm_ms),
    (0x00E7, 90.0, lambda g, k: g.ang.vel),
    (0x00F2, 4.0, lambda g, k: g.buffer_mode),
    (0x00F4, 50.0, lambda g, k: g.trans_prm[0]),
    (0x00F5, 2.0, lambda g, k: g.trans_prm[1]),
    (0x0104, 40.0, lambda g, k: g.vel_scale),
    (0x0119, 12.0, lambda g, k: k.group_inshape[g.group_id].frequency),
    (0x011A, 0.2, lambda g, k: k.group_inshape[g.group_id].damping),
]


@pytest.mark.parametrize(("var", "value", "shown"), GROUP_WRITES)
def test_group_variables_write_through_to_the_group(cmds, var, value, shown):
    hid = hcv_id(GROUP, 2, var)
    assert cmds.SetConfigVar(hid, value) == 0
    assert shown(cmds.motion.groups[2], cmds.motion) == value
    assert cmds.GetConfigVar(hid) == (0, value)


def test_group_variables_read_the_group_and_refuse_what_its_setters_refuse(cmds):
    assert cmds.AddAxisToGrp(1, 0) == 0 and cmds.AddAxisToGrp(1, 1) == 0
    assert cmds.GetConfigVar(hcv_id(GROUP, 1, 0x0002)) == (0, 2.0)  # num_axis
    assert cmds.SetConfigVar(hcv_id(GROUP, 1, 0x0002), 3.0) == HCV_IS_READ_ONLY
    assert cmds.GetConfigVar(hcv_id(GROUP, 1, 0x00CA)) == (0, 5000.0)  # lin_vel_lim
    assert cmds.SetConfigVar(hcv_id(GROUP, 1, 0x00E2), 200.0) == 0  # lin_dec_time [ms]
    g = cmds.motion.groups[1]
    assert g.lin.dec == pytest.approx(g.lin.vel / 0.2)
    for var, bad in [(0x00DD, 6000.0), (0x00F2, 9.0), (0x00F4, 4e-117), (0x0104, 101.0),
                     (0x0119, 2.0), (0x011A, 0.5), (0x038F, 5.0)]:  # fmt: skip
        assert cmds.SetConfigVar(hcv_id(GROUP, 1, var), bad) == HCV_VALUE_OUT_OF_RANGE, var
    assert cmds.GetConfigVar(hcv_id(GROUP, 16, 0x0002))[0] != 0  # no group 16
    cmds.SetGrpVelScale(1, 500.0)  # a refusal: the last error
    assert cmds.GetConfigVar(hcv_id(GROUP, 1, 0x038F))[1] != 0
    assert cmds.SetConfigVar(hcv_id(GROUP, 1, 0x038F), 0.0) == 0
    assert cmds.GetGrpLastErr(1) == 0


def test_group_shaper_frequency_variable_reshapes_an_enabled_filter(cmds):
    assert cmds.EnableGrpInShape(0) == 0
    assert cmds.SetConfigVar(hcv_id(GROUP, 0, 0x0119), 20.0) == 0
    f = cmds.motion.groups[0].planner.command_filter
    assert f.shaper == inshape.design(20.0, 0.03, inshape.SHAPER_NORMAL, DT)
