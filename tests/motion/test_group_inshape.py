"""Group InShape (manual 15.8-15.10) on a moving axis group: the commanded pose is the
unshaped one convolved with the shaper in every coordinate, the path ends exactly on
target one shaper later, the mode's vibration is not excited, the status bit, the
refusals while the group moves, and the filter across DisableGroup / EnableGroup."""

from __future__ import annotations

import math

import pytest
from group_util import DT, Recorder, cycle, grouped, grp_err, until

from motionvm.motion import inshape
from motionvm.motion.group import GMS_INPUT_SHAPE

CRD_INVALID_MOVING = 0x0046


def shaped_run(shaper_type: int | None, f: float = 10.0, zeta: float = 0.15):
    c = grouped(2)
    if shaper_type is not None:
        assert c.SetGrpInShape(0, f, zeta, shaper_type) == 0
        assert c.EnableGrpInShape(0) == 0
    assert c.LineAbs2D(0, 100.0, -40.0) == 0
    rec = Recorder(c)
    rec.run()
    return c, rec


@pytest.mark.parametrize("shaper_type", [inshape.SHAPER_NORMAL, inshape.SHAPER_ROBUST])
def test_the_shaped_path_is_the_unshaped_one_convolved_and_ends_on_target(shaper_type):
    _, plain = shaped_run(None)
    c, rec = shaped_run(shaper_type)
    shaper = inshape.design(10.0, 0.15, shaper_type, DT)
    assert len(rec.poses) == len(plain.poses) + shaper.length
    assert rec.poses[-1] == [100.0, -40.0]  # exactly
    assert [a.ref_pos for a in c.motion.groups[0].axes] == [100.0, -40.0]
    # every coordinate: the discrete convolution of the unshaped poses with the shaper
    padded = plain.poses + [plain.poses[-1]] * shaper.length
    for k in range(2):
        xs = [0.0] * shaper.length + [p[k] for p in padded]
        for n, pose in enumerate(rec.poses):
            want = sum(g * xs[n + shaper.length - d] for d, g in zip(shaper.delays, shaper.gains))
            assert pose[k] == pytest.approx(want, abs=1e-9)


def residual(poses: list[list[float]], f: float, k: int = 0) -> float:
    """Amplitude [mm] of an undamped oscillator at `f` Hz, at rest at 0 (where the path
    starts), driven by coordinate k of the poses (held over each cycle, exact
    discretisation), once they are at rest."""
    w = 2.0 * math.pi * f
    cw, sw = math.cos(w * DT), math.sin(w * DT)
    x, v = 0.0, 0.0
    for p in poses:
        u = p[k]
        e = x - u
        x, v = u + e * cw + v / w * sw, -e * w * sw + v * cw
    return math.hypot(x - poses[-1][k], v / w)


def test_the_shaped_path_leaves_no_vibration_at_the_mode():
    _, plain = shaped_run(None)
    _, rec = shaped_run(inshape.SHAPER_NORMAL, f=7.0, zeta=0.0)
    before = residual(plain.poses, 7.0)
    assert before > 0.5  # [mm] the unshaped line rings at 7 Hz
    assert residual(rec.poses, 7.0) < 1e-9


def test_status_bit_and_the_manual_example():
    c = grouped(2)
    g = c.motion.groups[0]
    assert not g.motion_status & GMS_INPUT_SHAPE
    assert c.SetGrpInShape(0, 10, 0.15, 1) == 0 and c.EnableGrpInShape(0) == 0
    assert g.motion_status & GMS_INPUT_SHAPE
    assert c.DisableGrpInShape(0) == 0
    assert not g.motion_status & GMS_INPUT_SHAPE
    assert g.planner.command_filter is None


def test_refused_while_the_group_moves_even_in_the_shaper_tail():
    c = grouped(2)
    assert c.SetGrpInShape(0, 5.5, 0.03, 1) == 0 and c.EnableGrpInShape(0) == 0
    assert c.LineAbs2D(0, 50.0, 50.0) == 0
    cycle(c, 5)
    moving = grp_err(CRD_INVALID_MOVING)
    assert c.EnableGrpInShape(0) == moving
    assert c.DisableGrpInShape(0) == moving
    assert c.SetGrpInShape(0, 10, 0.1, 0) == moving
    assert c.GetGrpLastErr(0) == moving
    g = c.motion.groups[0]
    until(c, lambda: g.planner.mode == "idle" and g.planner.command_filter.busy)
    assert c.IsGrpMoving(0) and c.DisableGrpInShape(0) == moving  # the tail still moves
    until(c, lambda: not c.IsGrpMoving(0))
    assert g.planner.out == [50.0, 50.0]
    assert c.DisableGrpInShape(0) == 0 and c.EnableGrpInShape(0) == 0


def test_the_filter_holds_across_disable_group_and_starts_where_the_axes_are():
    c = grouped(2)
    assert c.EnableGrpInShape(0) == 0  # the manual's defaults: 5.5 Hz, 0.03
    assert c.DisableGroup(0) == 0
    assert c.MoveAbs(0, 30.0) == 0  # the axis moves alone while the group is disabled
    until(c, lambda: not c.IsMoving(0))
    assert c.EnableGroup(0) == 0
    g = c.motion.groups[0]
    assert g.motion_status & GMS_INPUT_SHAPE and not c.IsGrpMoving(0)
    assert c.LineRel2D(0, 10.0, 0.0) == 0
    rec = Recorder(c)
    rec.run()
    assert min(p[0] for p in rec.poses) >= 30.0 - 1e-9  # no jump back to the old pose
    assert rec.poses[-1] == [40.0, 0.0]


def test_settings_made_while_the_group_rests_take_effect_on_the_next_move():
    c = grouped(2)
    assert c.EnableGrpInShape(0) == 0
    assert c.SetGrpInShape(0, 20.0, 0.1, inshape.SHAPER_ROBUST) == 0
    f = c.motion.groups[0].planner.command_filter
    assert f.shaper == inshape.design(20.0, 0.1, inshape.SHAPER_ROBUST, DT)
