"""What the group commands share (chapter 8): a group found by id, a refused command
turned into the group's error code, the coordinate frame of a system word, and the
checks of profiles, buffer and transition modes and transition parameters."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

from motionvm.motion import axis_status as st
from motionvm.motion import group as grp
from motionvm.motion import group_motion as gm
from motionvm.motion.commands.base import CommandBase
from motionvm.motion.group import AxisGroup, GroupError
from motionvm.motion.group_coords import CS_ACS, CS_MCS, CoordSystems, Frame
from motionvm.motion.group_path import PathError
from motionvm.motion.group_plan import BM_LOOKAHEAD
from motionvm.motion.tolerances import MIN_SPEED


def _finite(*values: float) -> bool:
    return all(math.isfinite(v) for v in values)


class GroupCommandBase(CommandBase):
    """Plumbing of the chapter 8 commands (see motion/commands/group.py)."""

    """Chapter 8: EnableGroup ... CircleRel."""

    # ------------------------------------------------------------ plumbing

    def _group(self, group_id: int) -> AxisGroup | None:
        g = self.motion.groups.get(group_id)
        if g is None:
            self.motion.system_last_error = st.SYS_HMPL_ARG_OUT_OF_RANGE
        return g

    def _do(self, group_id: int, fn: Callable[[AxisGroup], object]) -> int:
        """`fn(group)`: 0, or the group error it raised (stored as the last error)."""
        g = self._group(group_id)
        if g is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        try:
            fn(g)
        except (GroupError, PathError) as exc:
            g.last_error = err = st.group_error(exc.code, group_id)
            return err
        return 0

    @staticmethod
    def _check(ok: bool, code: int, message: str) -> None:
        if not ok:
            raise GroupError(code, message)

    def _query(self, group_id: int, fn: Callable[[AxisGroup], float], default=0):
        g = self._group(group_id)
        return default if g is None else fn(g)

    # ------------------------------------------------------------ coordinates

    @staticmethod
    def _frame(g: AxisGroup, cs: int) -> Frame:
        if not CoordSystems.valid(cs) or cs == CS_ACS:
            raise GroupError(grp.CRD_COORD_SYS_UNKNOWN, f"unknown coordinate system {cs:#x}")
        return g.coords.to_mcs(cs)

    @staticmethod
    def _pose(values: Sequence[float], n: int) -> list[float]:
        v = [float(x) for x in list(values)[:n]]
        if len(v) < n or not _finite(*v):
            raise GroupError(grp.CRD_INVALID_POS, f"target {list(values)!r} is not {n} numbers")
        return v

    def _target(self, g: AxisGroup, cs: int, fn: Callable[[list[float]], list[float]]):
        """fn(the present end pose in `cs`) -> the target in `cs`; returns it in MCS."""
        if cs == CS_MCS:  # the common case: no transform
            target = fn(g.end_pose())
            if not _finite(*target):
                raise GroupError(grp.CRD_INVALID_POS, "the target is not a number")
            return target
        f = self._frame(g, cs)
        start = g.end_pose()
        local = f.inverse().apply_pose(start) if not f.is_identity else list(start)
        target = fn(local)
        if not _finite(*target):
            raise GroupError(grp.CRD_INVALID_POS, "the target is not a number")
        return f.apply_pose(target) if not f.is_identity else target

    def _profile(self, g: AxisGroup, profile: Sequence[float] | None):
        if profile is None:
            return g.lin.values()
        vel, acc, dec, sm = (float(x) for x in list(profile)[:4])
        self._check_profile(vel, acc, dec, sm, linear=True)
        if vel <= 0.0:
            raise GroupError(grp.CRD_INVALID_LIN_VEL, "the velocity of a move must be above 0")
        return vel, acc, dec, sm

    def _modes(self, g: AxisGroup, bm: int | None, tm: int | None, prm):
        bm = g.buffer_mode if bm is None else bm
        tm = g.trans_mode if tm is None else tm
        self._check_bm(bm)
        self._check_tm(tm)
        if prm is None:
            return bm, tm, g.trans_prm  # checked by SetGrpTransPrm
        prm = [float(x) for x in list(prm)[:4]]
        prm += [0.0] * (4 - len(prm))
        self._check_prm(*prm)
        return bm, tm, prm

    # ------------------------------------------------------------ checks

    @staticmethod
    def _check_profile(vel, acc, dec, sm, *, linear: bool) -> None:
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

    @staticmethod
    def _check_bm(bm: int) -> None:
        if not 0 <= bm <= BM_LOOKAHEAD:
            raise GroupError(grp.CRD_BLEND_MODE_UNKNOWN, f"unknown buffer mode {bm}")

    @staticmethod
    def _check_tm(tm: int) -> None:
        if not 0 <= tm <= gm.TM_MAX_CORNER_CURV or tm == gm.TM_START_VEL:
            raise GroupError(
                grp.CRD_TRANS_MODE_UNKNOWN, f"unknown or unsupported transition mode {tm}"
            )

    @staticmethod
    def _check_prm(trans_vel, trans_dis, trans_dev, trans_curv) -> None:
        # 0: the lower feed of the two segments; else MIN_SPEED .. < 5000 (8.3.26: > 0)
        if not (_finite(trans_vel) and (trans_vel == 0.0 or MIN_SPEED <= trans_vel < 5000.0)):
            raise GroupError(grp.CRD_INVALID_TRANS_VEL, f"transition velocity {trans_vel!r}")
        if not (_finite(trans_dis) and trans_dis >= 0.0):
            raise GroupError(grp.CRD_INVALID_TRANS_DIS, f"transition distance {trans_dis!r}")
        if not (_finite(trans_dev) and trans_dev >= 0.0):
            raise GroupError(grp.CRD_INVALID_TRANS_DEV, f"transition deviation {trans_dev!r}")
        if not (_finite(trans_curv) and 0.0 <= trans_curv < 1e7):
            raise GroupError(grp.CRD_INVALID_TRANS_CURVE, f"transition curvature {trans_curv!r}")
