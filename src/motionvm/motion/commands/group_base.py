"""What the group commands share (chapter 8): a group found by id, a refused command
turned into the group's error code, the coordinate frame of a system word, and the
checks of profiles, buffer and transition modes and transition parameters (those of
motion/group_checks.py, which the configuration variables share)."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

from motionvm.motion import axis_status as st
from motionvm.motion import group as grp
from motionvm.motion import group_checks
from motionvm.motion.commands.base import CommandBase
from motionvm.motion.group import AxisGroup, GroupError
from motionvm.motion.group_coords import CS_ACS, CS_MCS, CoordSystems, Frame
from motionvm.motion.group_path import PathError


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

    def _group_flag(self, group_id: int, flag: str) -> int:
        """1 if status flag `flag` of the group is set, else 0; while a task runs with a
        recorder (`MotionKernel.reads`), the answer is recorded as (group, flag, value)
        as the axes' flags are (motion/commands/status_flags.py); a bad id records None."""
        g = self._group(group_id)
        reads = self.motion.reads
        if g is None:
            if reads is not None:
                reads.append(None)
            return 0
        value = getattr(g, flag)
        if reads is not None:
            reads.append((g, flag, value))
        return 1 if value else 0

    def _query(self, group_id: int, fn: Callable[[AxisGroup], float], default=0):
        g = self._group(group_id)
        return default if g is None else fn(g)

    # ------------------------------------------------------------ coordinates

    @staticmethod
    def _frame(g: AxisGroup, cs: int) -> Frame:
        if not CoordSystems.valid(cs) or cs == CS_ACS:
            raise GroupError(grp.CRD_COORD_SYS_UNKNOWN, f"unknown coordinate system {cs:#x}")
        return g.coords.to_mcs(cs)

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

    # ------------------------------------------------------------ checks (group_checks.py)

    _check_profile = staticmethod(group_checks.check_profile)
    _check_bm = staticmethod(group_checks.check_bm)
    _check_tm = staticmethod(group_checks.check_tm)
    _check_prm = staticmethod(group_checks.check_prm)
