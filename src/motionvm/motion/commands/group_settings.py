"""Chapter 8 settings (8.3.6-8.3.35): motion profiles, kinematics, buffer and transition
modes, queue, velocity scale, look-ahead, coordinate systems and poses.

Conventions and codes as `motionvm.motion.commands.group`; behaviour in
`motionvm.motion.group` and `motionvm.motion.group_coords`.
"""

from __future__ import annotations

from collections.abc import Sequence

from motionvm.motion import axis_status as st
from motionvm.motion import group as grp
from motionvm.motion.commands.group_base import GroupCommandBase, _finite
from motionvm.motion.group import AxisGroup
from motionvm.motion.group_coords import CS_ACS, CS_MCS, CoordSystems


def _rate(vel: float, time_ms: float) -> float | None:
    """The acceleration that reaches `vel` in `time_ms` [ms], or None when there is none: a
    time that is not a positive finite number, or one so short (5e-324 ms) that the
    acceleration is no finite number."""
    if not (_finite(time_ms) and time_ms > 0.0):
        return None
    seconds = time_ms / 1000.0
    rate = vel / seconds if seconds > 0.0 else float("inf")
    return rate if _finite(rate) else None


class GroupSettingsCommands(GroupCommandBase):
    """Chapter 8.3: SetGrpMotionProfile ... SetGrpQueueSize (membership: GroupCommands)."""

    # ------------------------------------------------------------ 8.3 profiles

    def _set_profile(self, group_id, values, *, linear: bool) -> int:
        def run(g: AxisGroup) -> None:
            prof = g.lin if linear else g.ang
            merged = [prof.vel, prof.acc, prof.dec, prof.sm_ms]
            for i, v in values.items():
                merged[i] = float(v)
            self._check_profile(*merged, linear=linear)
            prof.vel, prof.acc, prof.dec, prof.sm_ms = merged
            if linear:
                g.planner.set_smoothing(prof.sm_ms / 1000.0)

        return self._do(group_id, run)

    def SetGrpMotionProfile(self, group_id: int, max_velocity: float, max_acceleration: float,
                            max_deceleration: float, smooth_time: float) -> int:  # fmt: skip
        values = {0: max_velocity, 1: max_acceleration, 2: max_deceleration, 3: smooth_time}
        return self._set_profile(group_id, values, linear=True)

    def SetGrpAngMotionProfile(self, group_id: int, max_velocity: float, max_acceleration: float,
                               max_deceleration: float, smooth_time: float) -> int:  # fmt: skip
        values = {0: max_velocity, 1: max_acceleration, 2: max_deceleration, 3: smooth_time}
        return self._set_profile(group_id, values, linear=False)

    def GetGrpKin(self, group_id: int) -> int:
        return self._query(group_id, lambda g: g.kin)

    def SetGrpKin(self, group_id: int, kin_type: int) -> int:
        def run(g: AxisGroup) -> None:
            self._check(kin_type == grp.CARTESIAN, grp.CRD_INVALID_KIN_SETTING,
                        f"kinematics {kin_type} is not available (1: Cartesian)")  # fmt: skip
            self._check(g.state == grp.DISABLED, grp.CRD_INVALID_STATE, "the group is enabled")
            g.kin = kin_type

        return self._do(group_id, run)

    def GetGrpMaxVel(self, group_id: int) -> float:
        return float(self._query(group_id, lambda g: g.lin.vel, 0.0))

    def SetGrpVel(self, group_id: int, vel: float) -> int:
        return self._set_profile(group_id, {0: vel}, linear=True)

    def GetGrpMaxAcc(self, group_id: int) -> float:
        return float(self._query(group_id, lambda g: g.lin.acc, 0.0))

    def SetGrpAcc(self, group_id: int, acc: float) -> int:
        return self._set_profile(group_id, {1: acc}, linear=True)

    def SetGrpAccTime(self, group_id: int, acc_time: float) -> int:
        """Acceleration = maximum velocity / acc_time."""
        g = self._group(group_id)
        if g is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        rate = _rate(g.lin.vel, acc_time)
        if rate is None:
            return self._do(group_id, lambda g: self._check(False, grp.CRD_INVALID_LIN_ACC,
                                                            f"acceleration time {acc_time!r}"))  # fmt: skip
        return self._set_profile(group_id, {1: rate}, linear=True)

    def GetGrpMaxDec(self, group_id: int) -> float:
        return float(self._query(group_id, lambda g: g.lin.dec, 0.0))

    def SetGrpDec(self, group_id: int, dec: float) -> int:
        return self._set_profile(group_id, {2: dec}, linear=True)

    def SetGrpDecTime(self, group_id: int, dec_time: float) -> int:
        g = self._group(group_id)
        if g is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        rate = _rate(g.lin.vel, dec_time)
        if rate is None:
            return self._do(group_id, lambda g: self._check(False, grp.CRD_INVALID_LIN_DEC,
                                                            f"deceleration time {dec_time!r}"))  # fmt: skip
        return self._set_profile(group_id, {2: rate}, linear=True)

    def GetGrpSMTime(self, group_id: int) -> float:
        return float(self._query(group_id, lambda g: g.lin.sm_ms, 0.0))

    def SetGrpSMTime(self, group_id: int, smooth_time: float) -> int:
        """Takes effect the next time the group starts from rest."""
        return self._set_profile(group_id, {3: smooth_time}, linear=True)

    # ------------------------------------------------------------ 8.3 modes, queue

    def GetGrpBufferMode(self, group_id: int) -> int:
        return self._query(group_id, lambda g: g.buffer_mode)

    def SetGrpBufferMode(self, group_id: int, buffer_mode: int) -> int:
        def run(g: AxisGroup) -> None:
            self._check_bm(buffer_mode)
            g.buffer_mode = buffer_mode

        return self._do(group_id, run)

    def GetGrpTransMode(self, group_id: int) -> int:
        return self._query(group_id, lambda g: g.trans_mode)

    def SetGrpTransMode(self, group_id: int, trans_mode: int) -> int:
        def run(g: AxisGroup) -> None:
            self._check_tm(trans_mode)
            g.trans_mode = trans_mode

        return self._do(group_id, run)

    def SetGrpTransPrm(self, group_id: int, trans_vel: float, trans_dis: float,
                       trans_dev: float, trans_curv: float) -> int:  # fmt: skip
        def run(g: AxisGroup) -> None:
            self._check_prm(trans_vel, trans_dis, trans_dev, trans_curv)
            g.trans_prm = [float(trans_vel), float(trans_dis), float(trans_dev), float(trans_curv)]

        return self._do(group_id, run)

    def GetGrpCmdNum(self, group_id: int) -> int:
        return self._query(group_id, lambda g: g.cmd_num)

    def SetGrpVelScale(self, group_id: int, vel_scale: float) -> int:
        def run(g: AxisGroup) -> None:
            self._check(_finite(vel_scale) and 0.0 <= vel_scale <= 100.0,
                        grp.CRD_INVALID_VEL_SCALE, f"velocity scale {vel_scale!r} is outside 0 .. 100")  # fmt: skip
            g.set_vel_scale(float(vel_scale))

        return self._do(group_id, run)

    def GetGrpVelScale(self, group_id: int) -> float:
        return float(self._query(group_id, lambda g: g.vel_scale, 0.0))

    def SetGrpLookAheadPrm(self, group_id: int, prm_id: int, value: float) -> int:
        """0: corner acceleration [mm/s^2] (> 0), 1: arc acceleration [mm/s^2] (> 0),
        2: chord error [mm] (>= 0, 0: off)."""

        def run(g: AxisGroup) -> None:
            ok = (
                0 <= prm_id <= 2
                and _finite(value)
                and (value > 0.0 or (prm_id == 2 and value == 0.0))
            )
            self._check(ok, grp.CRD_LOOKAHEAD_INVALID_PARAM,
                        f"look-ahead parameter {prm_id} = {value!r}")  # fmt: skip
            g.lookahead[prm_id] = float(value)

        return self._do(group_id, run)

    def SetGrpQueueSize(self, group_id: int, queue_size: int) -> int:
        """The queue holds 2**queue_size commands (0 .. 10); only while it is empty."""

        def run(g: AxisGroup) -> None:
            self._check(0 <= queue_size <= 10, grp.CRD_INVALID_QUEUE_SIZE,
                        f"queue size {queue_size} is outside 0 .. 10")  # fmt: skip
            self._check(not g.planner.queue, 0x008C, "its queue is not empty")
            g.queue_size = 1 << queue_size

        return self._do(group_id, run)

    # ------------------------------------------------------------ 8.3 coordinates

    def GetGrpCoordSys(self, group_id: int) -> int:
        return self._query(group_id, lambda g: g.coord_sys, CS_MCS)

    def SetGrpCoordSys(self, group_id: int, coord_sys: int) -> int:
        def run(g: AxisGroup) -> None:
            self._check(CoordSystems.valid(coord_sys) and coord_sys != CS_ACS,
                        grp.CRD_COORD_SYS_UNKNOWN, f"unknown coordinate system {coord_sys:#x}")  # fmt: skip
            g.coord_sys = coord_sys

        return self._do(group_id, run)

    def GetGrpCoordTrans(self, group_id: int, coord_sys: int) -> tuple[int, list[float]]:
        out: list[list[float]] = [[0.0] * 6]

        def run(g: AxisGroup) -> None:
            self._check(CoordSystems.single(coord_sys), grp.CRD_COORD_SYS_UNKNOWN,
                        f"coordinate system {coord_sys:#x} has no transform")  # fmt: skip
            out[0] = g.coords.get(coord_sys)

        status = self._do(group_id, run)
        return status, out[0] if status == 0 else [0.0] * 6

    def SetGrpCoordTrans(self, group_id: int, coord_sys: int, trans_param: Sequence[float]) -> int:
        def run(g: AxisGroup) -> None:
            self._check(CoordSystems.single(coord_sys), grp.CRD_COORD_SYS_UNKNOWN,
                        f"coordinate system {coord_sys:#x} has no transform")  # fmt: skip
            vals = [float(x) for x in list(trans_param)[:6]]
            self._check(len(vals) == 6 and _finite(*vals), grp.CRD_COORD_INVALID_PARAM,
                        f"transform {vals!r}")  # fmt: skip
            g.coords.set(coord_sys, vals)

        return self._do(group_id, run)

    def _pose_in(self, group_id: int, coord_sys: int, which: str) -> tuple[int, list[float]]:
        out: list[list[float]] = [[0.0] * 6]

        def run(g: AxisGroup) -> None:
            if which == "cmd":
                joints = [a.ref_pos for a in g.axes]
            else:
                joints = [a.pos_fb for a in g.axes]
            if coord_sys == CS_ACS:
                pose = joints
            else:
                pose = self._frame(g, coord_sys).inverse().apply_pose(joints)
            out[0] = (list(pose) + [0.0] * 6)[:6]

        status = self._do(group_id, run)
        return status, out[0] if status == 0 else [0.0] * 6

    def GetGrpPoseCmd(self, group_id: int, coord_sys: int) -> tuple[int, list[float]]:
        return self._pose_in(group_id, coord_sys, "cmd")

    def GetGrpPoseFb(self, group_id: int, coord_sys: int) -> tuple[int, list[float]]:
        return self._pose_in(group_id, coord_sys, "fb")
