"""Homing (manual chapter 20, CiA 402 methods): final position of every method, directions,
offset, timeout, failures, status bits."""

from __future__ import annotations

from functools import cache

import pytest

from motionvm.motion import axis_status as st
from motionvm.motion.axis import Axis
from motionvm.motion.axis_config import create
from motionvm.motion.axis_status import AxisCommandError
from motionvm.motion.homing import DRIVE_HOME_FAILED, DRIVE_HOME_TOUT, AxisHoming
from motionvm.motion.homing_run import METHODS

DT = 0.001


@cache
def homing_of(a: Axis) -> AxisHoming:
    """The homing state of a test axis (a motion kernel keeps one per axis; these have none)."""
    return AxisHoming(a)


DEFAULT = {}
"""The default machine's axis: home switch on [0, 5] mm, index every 10 mm from 0,
limit switches at -1050 / +1050 mm, start at 0 (on the switch and on an index pulse)."""
SHIFTED = {"start_position": 3.7, "home_pos": 20.3, "home_width": 4.0, "index_offset": 2.5}
"""Start left of the switch [20.3, 24.3], index pulses at 2.5 + 10 n."""

# the home position [mm, motor coordinates] of each method on each layout
EXPECTED = {
    #   default   shifted
    1: (-1040.0, -1047.5),  # first index right of the negative limit
    2: (1040.0, 1042.5),  # first index left of the positive limit
    7: (-10.0, 12.5),  # index left of the switch's low edge
    8: (10.0, 22.5),  # index right of the low edge (an index on the edge is not beyond it)
    9: (0.0, 22.5),  # index left of the high edge
    10: (10.0, 32.5),  # index right of the high edge
    11: (10.0, 32.5),
    12: (0.0, 22.5),
    13: (10.0, 22.5),
    14: (-10.0, 12.5),
    17: (-1050.0, -1050.0),  # the negative limit's edge
    18: (1050.0, 1050.0),
    23: (0.0, 20.3),  # the switch's low edge
    24: (0.0, 20.3),
    25: (5.0, 24.3),  # the high edge
    26: (5.0, 24.3),
    27: (5.0, 24.3),
    28: (5.0, 24.3),
    29: (0.0, 20.3),
    30: (0.0, 20.3),
    33: (0.0, 2.5),  # first index moving negative (a pulse under the start counts)
    34: (10.0, 12.5),
    37: (0.0, 3.7),  # the current position
}
FAST = {"switch_vel": 200.0, "zero_vel": 5.0, "acc": 20000.0}
"""Quick settings for the parametrized runs (the limit switches are 1 m away)."""


def enabled(**config) -> Axis:
    a = Axis(0, create(config), DT)
    a.enable()
    for _ in range(100):
        a.step()
    assert a.enabled
    return a


def configure(a: Axis, method: int, *, offset=0.0, timeout_ms=120_000.0, **speeds):
    h = homing_of(a)
    h.set_method(method)
    h.set_offset(offset)
    h.set_timeout(timeout_ms)
    h.set_switch_vel(speeds.get("switch_vel", 20.0))
    h.set_zero_vel(speeds.get("zero_vel", 5.0))
    h.set_acc(speeds.get("acc", 2000.0))
    return h


def home(a: Axis, method: int, **kw):
    """Run one homing to its end; the velocities of the reference on the way."""
    h = configure(a, method, **kw)
    h.start()
    vels = []
    while h.running:
        a.step()
        vels.append(a.ref_vel)
        assert len(vels) < 300_000
    for _ in range(5):
        a.step()
    return h, vels


@pytest.mark.parametrize("layout", [0, 1], ids=["default", "shifted"])
@pytest.mark.parametrize("method", sorted(METHODS))
def test_every_method_ends_on_its_home_position(method, layout):
    a = enabled(**(DEFAULT, SHIFTED)[layout])
    h, _ = home(a, method, **FAST)
    want = EXPECTED[method][layout]
    assert h.error == 0 and h.homed and not h.homing
    assert a.pos_fb_raw == pytest.approx(want, abs=1e-4)  # one count
    assert a.ref_pos == 0.0 and a.pos_fb == pytest.approx(0.0, abs=1e-4)
    assert not a.moving and a.in_pos and not a.error_stop
    assert a.following is None
    assert a.motion_status & st.MS_HOMED and not a.motion_status & st.MS_HOMING


def test_the_manuals_defaults_home_a_limit_method():
    a = enabled()
    h = homing_of(a)
    assert (h.settings.method, h.settings.switch_vel, h.settings.zero_vel) == (33, 20.0, 5.0)
    assert (h.settings.acc, h.settings.offset, h.settings.timeout_ms) == (2000.0, 0.0, 120_000.0)
    h, vels = home(a, 1)
    assert a.pos_fb_raw == pytest.approx(-1040.0, abs=1e-4)
    assert min(vels) == pytest.approx(-20.0) and max(vels) <= 5.0 + 1e-9
    assert 1050 / 20 < len(vels) * DT < 60.0


@pytest.mark.parametrize(
    "method, layout, first",
    [
        (7, SHIFTED, +1), (8, SHIFTED, +1), (9, SHIFTED, +1), (10, SHIFTED, +1),
        (11, SHIFTED, -1), (12, SHIFTED, -1), (13, SHIFTED, -1), (14, SHIFTED, -1),
        # on the switch at the start: towards the edge sought
        (7, DEFAULT, -1), (8, DEFAULT, -1), (9, DEFAULT, +1), (10, DEFAULT, +1),
        (11, DEFAULT, +1), (12, DEFAULT, +1), (13, DEFAULT, -1), (14, DEFAULT, -1),
        (1, DEFAULT, -1), (17, DEFAULT, -1), (2, DEFAULT, +1), (18, DEFAULT, +1),
        (33, SHIFTED, -1), (34, SHIFTED, +1),
    ],
)  # fmt: skip
def test_initial_direction(method, layout, first):
    a = enabled(**layout)
    _, vels = home(a, method, **FAST)
    moving = [v for v in vels if v != 0.0]
    assert moving[0] * first > 0


def test_a_home_method_reverses_on_the_limit_switch_in_its_way():
    # method 11 starts negative, away from the switch: it reverses at the negative limit
    a = enabled(**SHIFTED)
    h = configure(a, 11, **FAST)
    h.start()
    x_min = a.pos_fb_raw
    while h.running:
        a.step()
        x_min = min(x_min, a.pos_fb_raw)
    assert -1052.0 < x_min < -1050.0  # into the switch by the braking distance (1 mm)
    assert a.pos_fb_raw == pytest.approx(32.5, abs=1e-4)


def test_a_limit_switch_active_at_the_start():
    a = enabled(start_position=-1052.0)
    h, vels = home(a, 17, **FAST)
    assert h.error == 0 and a.pos_fb_raw == pytest.approx(-1050.0, abs=1e-4)
    assert next(v for v in vels if v) > 0.0  # away from the limit first


def test_zero_speed_is_used_past_the_edge():
    a = enabled(**SHIFTED)
    _, vels = home(a, 34, switch_vel=50.0, zero_vel=2.0, acc=2000.0)
    assert max(abs(v) for v in vels) == pytest.approx(2.0)


@pytest.mark.parametrize("method", [1, 9, 24, 33, 37])
def test_the_home_position_reads_the_offset(method):
    a = enabled(**SHIFTED)
    home(a, method, offset=-7.25, **FAST)
    want = EXPECTED[method][1]
    assert a.pos_fb_raw == pytest.approx(want, abs=1e-4)
    assert a.ref_pos == -7.25 and a.pos_fb == pytest.approx(-7.25, abs=1e-4)
    a.move_abs(0.0)
    for _ in range(3000):
        a.step()
    assert a.pos_fb_raw == pytest.approx(want + 7.25, abs=1e-4)


def test_timeout_fails_with_the_manuals_error_and_stops():
    a = enabled()
    h, vels = home(a, 17, timeout_ms=500.0)
    assert h.error == DRIVE_HOME_TOUT and "timeout 500 ms" in h.message
    assert a.last_error == st.axis_error(DRIVE_HOME_TOUT, 0)
    assert 500 <= len(vels) <= 520  # + braking at the homing acceleration
    assert not h.homed and h.homing  # the procedure did not complete (see homing.py)
    assert not a.moving and a.following is None and a.pos_offset == 0.0
    assert not a.ignore_hwl and not a.ignore_swl  # restored
    h.set_homed(0)
    assert not h.homing


def test_missing_switch_or_index_fails_at_once():
    a = enabled(home_pos=False, index_spacing=False)
    for method in (7, 23, 33):
        with pytest.raises(AxisCommandError) as exc:
            configure(a, method).start()
        assert exc.value.code == DRIVE_HOME_FAILED
    assert "home switch" in homing_of(a).message or "index" in homing_of(a).message
    b = enabled(hw_left=False)
    with pytest.raises(AxisCommandError, match="negative limit switch"):
        configure(b, 17).start()


def test_a_limit_switch_before_the_index_fails():
    a = enabled(hw_right=30.0, index_spacing=100.0, index_offset=50.0)  # 50 > 30
    h, _ = home(a, 34, **FAST)
    assert h.error == DRIVE_HOME_FAILED and "positive limit switch" in h.message
    assert not a.moving and not a.error_stop


def test_stop_interrupts_homing():
    a = enabled()
    h = configure(a, 17)
    h.start()
    for _ in range(100):
        a.step()
    a.stop()
    assert not h.running and h.error == DRIVE_HOME_FAILED and h.homing
    assert not a.ignore_swl


def test_refusals():
    a = Axis(0, create({}), DT)
    h = configure(a, 33)
    with pytest.raises(AxisCommandError) as exc:
        h.start()
    assert exc.value.code == st.CMD_INVALID_DISABLED and not h.homing
    configure(a, 37, offset=2.0).start()  # 37 needs no enabled drive
    assert h.homed and a.pos_fb == 2.0
    b = enabled()
    b.move_abs(50.0)
    with pytest.raises(AxisCommandError) as exc:
        configure(b, 33).start()
    assert exc.value.code == st.CMD_INVALID_MOVING
    for setter, value, code in [
        ("set_method", 3, st.CMD_INVALID_PARAMETER),
        ("set_switch_vel", 0.0, st.CMD_INVALID_VEL),
        ("set_zero_vel", -1.0, st.CMD_INVALID_VEL),
        ("set_acc", float("nan"), st.CMD_INVALID_ACC),
        ("set_offset", float("inf"), st.CMD_INVALID_POS),
        ("set_timeout", 0.0, st.CMD_INVALID_PARAMETER),
        ("set_homed", 2, st.CMD_INVALID_PARAMETER),
    ]:
        with pytest.raises(AxisCommandError) as exc:
            getattr(homing_of(b), setter)(value)
        assert exc.value.code == code


def test_homing_under_a_servo_with_following_error():
    a = enabled(**SHIFTED, drive={"mechanics": {"model": "servo", "bandwidth": 30.0}})
    h, _ = home(a, 8, switch_vel=50.0, zero_vel=2.0, acc=5000.0)
    for _ in range(500):
        a.step()
    assert h.error == 0 and a.pos_fb_raw == pytest.approx(22.5, abs=1e-3)


def test_the_limits_are_restored_and_moves_work_after_homing():
    a = enabled(**SHIFTED)
    a.set_ignore("pe", 1)
    a.ignore_swl = True
    home(a, 2, **FAST)
    assert a.ignore_swl and not a.ignore_hwl
    a.move_rel(-10.0)
    for _ in range(2000):
        a.step()
    assert a.pos_fb == pytest.approx(-10.0, abs=1e-4) and not a.error_stop


def test_homing_again_after_set_pos_and_after_homing():
    a = enabled(**SHIFTED)
    a.set_pos(500.0)
    home(a, 34, **FAST)
    assert a.pos_fb_raw == pytest.approx(12.5, abs=1e-4) and a.ref_pos == 0.0
    a.move_abs(-30.0)
    for _ in range(3000):
        a.step()
    h, _ = home(a, 8, offset=1.0, **FAST)
    assert h.homed and a.pos_fb_raw == pytest.approx(22.5, abs=1e-4) and a.ref_pos == 1.0


def test_a_drive_fault_while_homing_keeps_its_error_code():
    a = enabled()
    h = configure(a, 17)
    h.start()
    for _ in range(50):
        a.step()
    a.drive.inject_fault()
    for _ in range(20):
        a.step()
    assert not h.running and h.error == DRIVE_HOME_FAILED and "interrupted" in h.message
    assert a.error_stop and a.last_error == st.axis_error(st.DRIVE_FAULT, 0)
