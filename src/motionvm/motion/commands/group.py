"""Chapter 8, axis groups: motion (8.2, 8.5), settings (8.3), status (8.4).

Units: mm, deg, mm/s, deg/s, mm/s^2, deg/s^2, ms. A function that fails returns the
manual's group error (table 18.1.3.1, 0x82XXCCCC with XX the group id, as a C int) and
stores it as the group's last error (GetGrpLastErr); a bad group or axis id returns
eERR_HMPL_ARG_OUT_OF_RANGE (0x138F) and stores it as the system's last error (getters
and Is* functions then return 0, GetGroupID -1). Functions with C array out-parameters
return `(status, values)`.

Positions of LineAbs2D ... Circle2D are in the group's coordinate system
(SetGrpCoordSys, default CS_MCS); LineAbs ... CircleRel name theirs. A 2-D command
moves X and Y and keeps the other coordinates. A pose array has six values {X, Y, Z,
A, B, C}; a group of n axes uses the first n. Behaviour: `motionvm.motion.group`
(states, membership), `group_motion` (segments, buffer and transition modes),
`group_plan` (look-ahead, profile), `group_coords` (coordinate systems).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

from motionvm.motion import axis_status as st
from motionvm.motion import group as grp
from motionvm.motion import group_motion as gm
from motionvm.motion.commands.base import CommandBase
from motionvm.motion.group import AxisGroup, GroupError
from motionvm.motion.group_coords import CS_ACS, CS_MCS, CoordSystems, Frame
from motionvm.motion.group_path import TWO_PI, PathError, arc_center_3pt, sweep
from motionvm.motion.group_plan import BM_LOOKAHEAD

_ZEROS6 = (0.0,) * 6


def _finite(*values: float) -> bool:
    return all(math.isfinite(v) for v in values)


class GroupCommands(CommandBase):
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
        prm = (
            g.trans_prm
            if prm is None
            else [float(x) for x in list(prm)[:4]] + [0.0] * (4 - len(list(prm)[:4]))
        )
        self._check_prm(*prm)
        return bm, tm, prm

    # ------------------------------------------------------------ 8.2 motion

    def EnableGroup(self, group_id: int) -> int:
        return self._do(group_id, AxisGroup.enable)

    def DisableGroup(self, group_id: int) -> int:
        return self._do(group_id, AxisGroup.disable)

    def ResetGroup(self, group_id: int) -> int:
        return self._do(group_id, AxisGroup.reset)

    def StopGroup(self, group_id: int) -> int:
        return self._do(group_id, AxisGroup.stop)

    def HaltGroup(self, group_id: int) -> int:
        return self._do(group_id, AxisGroup.halt)

    def ResumeGroup(self, group_id: int) -> int:
        return self._do(group_id, AxisGroup.resume)

    def JogGroup(self, group_id: int, carte_dir: int, jog_vel: float) -> int:
        def run(g: AxisGroup) -> None:
            self._check(0 <= carte_dir < min(g.n, 6), grp.CRD_GRP_AXIS_INVALID,
                        f"direction {carte_dir} is not a coordinate of the group")  # fmt: skip
            self._check(_finite(jog_vel), grp.CRD_INVALID_LIN_VEL, "jog velocity")
            gm.jog(g, carte_dir, jog_vel)

        return self._do(group_id, run)

    def JogGroupAxis(self, group_id: int, grp_axis: int, jog_vel: float) -> int:
        """ACS jog; with Cartesian kinematics axis i is coordinate i."""
        return self.JogGroup(group_id, grp_axis, jog_vel)

    def _line(self, group_id, fn, profile=None, cs=None, bm=None, tm=None, prm=None) -> int:
        def run(g: AxisGroup) -> None:
            g.require_motion()
            prof = self._profile(g, profile)
            b, t, p = self._modes(g, bm, tm, prm)
            target = self._target(g, g.coord_sys if cs is None else cs, fn)
            gm.queue_line(g, target, prof, b, t, p)

        return self._do(group_id, run)

    @staticmethod
    def _set(values: dict[int, float]) -> Callable[[list[float]], list[float]]:
        def fn(pose: list[float]) -> list[float]:
            out = list(pose)
            for i, v in values.items():
                if i < len(out):
                    out[i] = float(v)
            return out

        return fn

    @staticmethod
    def _add(values: dict[int, float]) -> Callable[[list[float]], list[float]]:
        def fn(pose: list[float]) -> list[float]:
            out = list(pose)
            for i, v in values.items():
                if i < len(out):
                    out[i] += float(v)
            return out

        return fn

    def LineAbs2D(self, group_id: int, end_x: float, end_y: float) -> int:
        return self._line(group_id, self._set({0: end_x, 1: end_y}))

    def LineAbs3D(self, group_id: int, end_x: float, end_y: float, end_z: float) -> int:
        return self._line(group_id, self._set({0: end_x, 1: end_y, 2: end_z}))

    def LineRel2D(self, group_id: int, distance_x: float, distance_y: float) -> int:
        return self._line(group_id, self._add({0: distance_x, 1: distance_y}))

    def LineRel3D(
        self, group_id: int, distance_x: float, distance_y: float, distance_z: float
    ) -> int:
        return self._line(group_id, self._add({0: distance_x, 1: distance_y, 2: distance_z}))

    def LineAbs(self, group_id: int, target_pos: Sequence[float], motion_profile: Sequence[float],
                coord_sys: int, buff_mode: int, trans_mode: int,
                trans_par: Sequence[float] | None) -> int:  # fmt: skip
        vals = dict(enumerate(list(target_pos)[:6]))
        return self._line(group_id, self._set(vals), motion_profile, coord_sys, buff_mode,
                          trans_mode, trans_par or _ZEROS6[:4])  # fmt: skip

    def LineRel(self, group_id: int, relative_dist: Sequence[float], motion_profile: Sequence[float],
                coord_sys: int, buff_mode: int, trans_mode: int,
                trans_par: Sequence[float] | None) -> int:  # fmt: skip
        vals = dict(enumerate(list(relative_dist)[:6]))
        return self._line(group_id, self._add(vals), motion_profile, coord_sys, buff_mode,
                          trans_mode, trans_par or _ZEROS6[:4])  # fmt: skip

    def _arc(self, group_id: int, plan: Callable, profile=None, cs=None, bm=None, tm=None,
             prm=None) -> int:  # fmt: skip
        """plan(start in cs) -> (centre, normal, end, phi) in cs; queued as an arc."""

        def run(g: AxisGroup) -> None:
            g.require_motion()
            prof = self._profile(g, profile)
            b, t, p = self._modes(g, bm, tm, prm)
            f = self._frame(g, g.coord_sys if cs is None else cs)
            start = g.end_pose()
            local = f.inverse().apply_pose(start) if not f.is_identity else list(start)
            center, normal, end, phi = plan(local)
            if not _finite(*center, *normal, *end, phi):
                raise GroupError(grp.CRD_CIRC_INVALID_PARAM, "the circle is not a number")
            c3 = (list(center) + [0.0] * 3)[:3]
            gm.queue_arc(g, f.apply_point(c3), f.apply_vector((list(normal) + [0.0] * 3)[:3]),
                         phi, f.apply_pose(end) if not f.is_identity else end, prof, b, t, p)  # fmt: skip

        return self._do(group_id, run)

    def Arc2D(
        self, group_id: int, border_x: float, border_y: float, end_x: float, end_y: float
    ) -> int:
        def plan(start):
            c = arc_center_3pt(start, (border_x, border_y), (end_x, end_y))
            if c is None:
                raise GroupError(grp.CRD_CIRC_INVALID_PARAM, "the three points are on a line")
            end = self._set({0: end_x, 1: end_y})(start)
            to_b = sweep(start, (border_x, border_y), c, (0, 0, 1), 0)
            to_e = sweep(start, (end_x, end_y), c, (0, 0, 1), 0)
            phi = to_e if to_b < to_e else to_e - TWO_PI
            return c, (0.0, 0.0, 1.0), end, phi

        return self._arc(group_id, plan)

    def _arc_dir(
        self, group_id: int, cx: float, cy: float, ex: float, ey: float, turns: int
    ) -> int:
        def plan(start):
            end = self._set({0: ex, 1: ey})(start)
            return (cx, cy), (0.0, 0.0, 1.0), end, sweep(start, end, (cx, cy), (0, 0, 1), turns)

        return self._arc(group_id, plan)

    def ArcCW2D(
        self, group_id: int, center_x: float, center_y: float, end_x: float, end_y: float
    ) -> int:
        return self._arc_dir(group_id, center_x, center_y, end_x, end_y, -1)

    def ArcCCW2D(
        self, group_id: int, center_x: float, center_y: float, end_x: float, end_y: float
    ) -> int:
        return self._arc_dir(group_id, center_x, center_y, end_x, end_y, 1)

    def Circle2D(self, group_id: int, center_x: float, center_y: float, end_x: float,
                 end_y: float, turns: int) -> int:  # fmt: skip
        return self._arc_dir(group_id, center_x, center_y, end_x, end_y, turns)

    def ArcAngle2D(self, group_id: int, center_x: float, center_y: float, angle: float) -> int:
        def plan(start):
            if not angle or not _finite(angle):
                raise GroupError(0x0276, f"the arc angle {angle!r} deg is too small")
            phi = math.radians(angle)
            dx, dy = start[0] - center_x, start[1] - center_y
            c, s = math.cos(phi), math.sin(phi)
            end = self._set({0: center_x + c * dx - s * dy, 1: center_y + s * dx + c * dy})(start)
            return (center_x, center_y), (0.0, 0.0, 1.0), end, phi

        return self._arc(group_id, plan)

    def _circle(self, group_id, center_pos, normal_vector, turns, fn, motion_profile,
                coord_sys, buff_mode, trans_mode, trans_par) -> int:  # fmt: skip
        def plan(start):
            end = fn(start)
            c, nv = list(center_pos)[:3], list(normal_vector)[:3]
            return c, nv, end, sweep(start, end, c, nv, turns)

        return self._arc(group_id, plan, motion_profile, coord_sys, buff_mode, trans_mode,
                         trans_par or _ZEROS6[:4])  # fmt: skip

    def CircleAbs(self, group_id: int, center_pos: Sequence[float], normal_vector: Sequence[float],
                  turns: int, target_pos: Sequence[float], motion_profile: Sequence[float],
                  coord_sys: int, buff_mode: int, trans_mode: int,
                  trans_par: Sequence[float] | None) -> int:  # fmt: skip
        fn = self._set(dict(enumerate(list(target_pos)[:6])))
        return self._circle(group_id, center_pos, normal_vector, turns, fn, motion_profile,
                            coord_sys, buff_mode, trans_mode, trans_par)  # fmt: skip

    def CircleRel(self, group_id: int, center_pos: Sequence[float], normal_vector: Sequence[float],
                  turns: int, relative_dist: Sequence[float], motion_profile: Sequence[float],
                  coord_sys: int, buff_mode: int, trans_mode: int,
                  trans_par: Sequence[float] | None) -> int:  # fmt: skip
        fn = self._add(dict(enumerate(list(relative_dist)[:6])))
        return self._circle(group_id, center_pos, normal_vector, turns, fn, motion_profile,
                            coord_sys, buff_mode, trans_mode, trans_par)  # fmt: skip

    # ------------------------------------------------------------ 8.3 membership

    def AddAxisToGrp(self, group_id: int, axis_id: int) -> int:
        a = self._axis(axis_id)
        if a is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        return self._do(group_id, lambda g: g.add_axis(a, self.motion.groups.group_of(axis_id)))

    def RemoveAxisFromGrp(self, group_id: int) -> int:
        return self._do(group_id, AxisGroup.remove_last)

    def SetupGroup(self, group_id: int, *axis_ids: int) -> int:
        """UngrpAllAxes, AddAxisToGrp of each axis in order, EnableGroup."""
        axes = self._axes(*axis_ids)
        if axes is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE

        def run(g: AxisGroup) -> None:
            g.ungroup()
            for a in axes:
                g.add_axis(a, self.motion.groups.group_of(a.axis_id))
            g.enable()

        return self._do(group_id, run)

    def UngrpAllAxes(self, group_id: int) -> int:
        return self._do(group_id, AxisGroup.ungroup)

    def GetGroupID(self, axis_id: int) -> int:
        if self._axis(axis_id) is None:
            return -1
        g = self.motion.groups.group_of(axis_id)
        return -1 if g is None else g.group_id

    # ------------------------------------------------------------ 8.3 profiles

    @staticmethod
    def _check_profile(vel, acc, dec, sm, *, linear: bool) -> None:
        v_top, a_top = (5000.0, 50000.0) if linear else (7200.0, 72000.0)
        codes = ((grp.CRD_INVALID_LIN_VEL, grp.CRD_INVALID_LIN_ACC, grp.CRD_INVALID_LIN_DEC,
                  grp.CRD_INVALID_LIN_SM_TIME) if linear else
                 (grp.CRD_INVALID_ANG_VEL, grp.CRD_INVALID_ANG_ACC, grp.CRD_INVALID_ANG_DEC,
                  grp.CRD_INVALID_ANG_SM_TIME))  # fmt: skip
        if not (_finite(vel) and 0.0 <= vel <= v_top):
            raise GroupError(codes[0], f"velocity {vel!r} is outside 0 .. {v_top:g}")
        if not (_finite(acc) and 0.0 < acc <= a_top):
            raise GroupError(codes[1], f"acceleration {acc!r} is outside >0 .. {a_top:g}")
        if not (_finite(dec) and 0.0 < dec <= a_top):
            raise GroupError(codes[2], f"deceleration {dec!r} is outside >0 .. {a_top:g}")
        if not (_finite(sm) and 0.0 <= sm <= 500.0):
            raise GroupError(codes[3], f"smooth time {sm!r} ms is outside 0 .. 500")

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
        if not (_finite(acc_time) and acc_time > 0.0):
            return self._do(group_id, lambda g: self._check(False, grp.CRD_INVALID_LIN_ACC,
                                                            f"acceleration time {acc_time!r}"))  # fmt: skip
        return self._set_profile(group_id, {1: g.lin.vel / (acc_time / 1000.0)}, linear=True)

    def GetGrpMaxDec(self, group_id: int) -> float:
        return float(self._query(group_id, lambda g: g.lin.dec, 0.0))

    def SetGrpDec(self, group_id: int, dec: float) -> int:
        return self._set_profile(group_id, {2: dec}, linear=True)

    def SetGrpDecTime(self, group_id: int, dec_time: float) -> int:
        g = self._group(group_id)
        if g is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        if not (_finite(dec_time) and dec_time > 0.0):
            return self._do(group_id, lambda g: self._check(False, grp.CRD_INVALID_LIN_DEC,
                                                            f"deceleration time {dec_time!r}"))  # fmt: skip
        return self._set_profile(group_id, {2: g.lin.vel / (dec_time / 1000.0)}, linear=True)

    def GetGrpSMTime(self, group_id: int) -> float:
        return float(self._query(group_id, lambda g: g.lin.sm_ms, 0.0))

    def SetGrpSMTime(self, group_id: int, smooth_time: float) -> int:
        """Takes effect the next time the group starts from rest."""
        return self._set_profile(group_id, {3: smooth_time}, linear=True)

    # ------------------------------------------------------------ 8.3 modes, queue

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
        if not (_finite(trans_vel) and 0.0 <= trans_vel < 5000.0):
            raise GroupError(grp.CRD_INVALID_TRANS_VEL, f"transition velocity {trans_vel!r}")
        if not (_finite(trans_dis) and trans_dis >= 0.0):
            raise GroupError(grp.CRD_INVALID_TRANS_DIS, f"transition distance {trans_dis!r}")
        if not (_finite(trans_dev) and trans_dev >= 0.0):
            raise GroupError(grp.CRD_INVALID_TRANS_DEV, f"transition deviation {trans_dev!r}")
        if not (_finite(trans_curv) and 0.0 <= trans_curv < 1e7):
            raise GroupError(grp.CRD_INVALID_TRANS_CURVE, f"transition curvature {trans_curv!r}")

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

    # ------------------------------------------------------------ 8.4 status

    def IsGrpEnabled(self, group_id: int) -> int:
        return self._query(group_id, lambda g: 1 if g.enabled else 0)

    def IsGrpMoving(self, group_id: int) -> int:
        return self._query(group_id, lambda g: 1 if g.moving else 0)

    def IsGrpInPos(self, group_id: int) -> int:
        return self._query(group_id, lambda g: 1 if g.enabled and g.in_pos else 0)

    def IsGrpErrorStop(self, group_id: int) -> int:
        return self._query(group_id, lambda g: 1 if g.state == grp.ERROR_STOP else 0)
