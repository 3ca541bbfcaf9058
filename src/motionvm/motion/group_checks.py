"""The checks of an axis group's settings (manual chapter 8): profile, buffer mode,
transition mode and parameters, and the input shaper's ranges (15.10); each raises
`GroupError` with the manual's code. The group commands and the group configuration
variables (config_group.py) share them."""

from __future__ import annotations

import math

from motionvm.motion import group as grp
from motionvm.motion import group_motion as gm
from motionvm.motion.group import GroupError
from motionvm.motion.group_plan import BM_LOOKAHEAD
from motionvm.motion.tolerances import MIN_SPEED

GRP_INSHAPE_FREQUENCY = (3.0, 300.0)
"""[Hz] SetGrpInShape's frequency range (15.10)."""
GRP_INSHAPE_DAMPING = (0.0, 0.3)
"""SetGrpInShape's damping ratio range (15.10)."""


def _finite(*values: float) -> bool:
    return all(math.isfinite(v) for v in values)


def check_profile(vel, acc, dec, sm, *, linear: bool) -> None:
    v_top, a_top = (5000.0, 50000.0) if linear else (7200.0, 72000.0)
    codes = ((grp.CRD_INVALID_LIN_VEL, grp.CRD_INVALID_LIN_ACC, grp.CRD_INVALID_LIN_DEC,
              grp.CRD_INVALID_LIN_SM_TIME) if linear else
             (grp.CRD_INVALID_ANG_VEL, grp.CRD_INVALID_ANG_ACC, grp.CRD_INVALID_ANG_DEC,
              grp.CRD_INVALID_ANG_SM_TIME))  # fmt: skip
    if not (_finite(vel) and (vel == 0.0 or MIN_SPEED <= vel <= v_top)):
        raise GroupError(codes[0], f"velocity {vel!r} is outside 0 .. {v_top:g}")
    if not (_finite(acc) and 0.0 < acc <= a_top):
        raise GroupError(codes[1], f"acceleration {acc!r} is outside >0 .. {a_top:g}")
    if not (_finite(dec) and 0.0 < dec <= a_top):
        raise GroupError(codes[2], f"deceleration {dec!r} is outside >0 .. {a_top:g}")
    if not (_finite(sm) and 0.0 <= sm <= 500.0):
        raise GroupError(codes[3], f"smooth time {sm!r} ms is outside 0 .. 500")


def check_bm(bm: int) -> None:
    if not 0 <= bm <= BM_LOOKAHEAD:
        raise GroupError(grp.CRD_BLEND_MODE_UNKNOWN, f"unknown buffer mode {bm}")


def check_tm(tm: int) -> None:
    if not 0 <= tm <= gm.TM_MAX_CORNER_CURV or tm == gm.TM_START_VEL:
        raise GroupError(grp.CRD_TRANS_MODE_UNKNOWN, f"unknown or unsupported transition mode {tm}")


def check_prm(trans_vel, trans_dis, trans_dev, trans_curv) -> None:
    # 0: the lower feed of the two segments; else MIN_SPEED .. < 5000 (8.3.26: > 0)
    if not (_finite(trans_vel) and (trans_vel == 0.0 or MIN_SPEED <= trans_vel < 5000.0)):
        raise GroupError(grp.CRD_INVALID_TRANS_VEL, f"transition velocity {trans_vel!r}")
    if not (_finite(trans_dis) and trans_dis >= 0.0):
        raise GroupError(grp.CRD_INVALID_TRANS_DIS, f"transition distance {trans_dis!r}")
    if not (_finite(trans_dev) and trans_dev >= 0.0):
        raise GroupError(grp.CRD_INVALID_TRANS_DEV, f"transition deviation {trans_dev!r}")
    if not (_finite(trans_curv) and 0.0 <= trans_curv < 1e7):
        raise GroupError(grp.CRD_INVALID_TRANS_CURVE, f"transition curvature {trans_curv!r}")
