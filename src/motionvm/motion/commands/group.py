"""Chapter 8, axis groups: motion (8.2, 8.5), membership (8.3.1-8.3.5), status (8.4);
the settings of 8.3.6-8.3.35 are in group_settings.py, the shared plumbing in group_base.py.

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
from motionvm.motion.commands.group_base import GroupCommandBase, _finite
from motionvm.motion.group import AxisGroup, GroupError
from motionvm.motion.group_path import TWO_PI, arc_center_3pt, sweep

_ZEROS6 = (0.0,) * 6


class GroupCommands(GroupCommandBase):
    """Chapter 8: EnableGroup ... Circle2D, AddAxisToGrp ... GetGroupID, IsGrpEnabled ...
    IsGrpErrorStop, LineAbs ... CircleRel (settings: GroupSettingsCommands)."""

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
        """UngrpAllAxes, AddAxisToGrp of each axis in order, EnableGroup. More than 9
        axes (8.3.3) is eERR_CRD_CMD_GRP_SIZE_FULL, the group left as it was."""
        if len(axis_ids) > grp.MAX_AXES:
            n = len(axis_ids)

            def too_many(g: AxisGroup) -> None:
                raise g.fail(grp.CRD_GRP_SIZE_FULL, f"{n} axes, a group takes {grp.MAX_AXES}")

            return self._do(group_id, too_many)
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

    # ------------------------------------------------------------ 8.4 status

    def IsGrpEnabled(self, group_id: int) -> int:
        return self._group_flag(group_id, "enabled")

    def IsGrpMoving(self, group_id: int) -> int:
        return self._group_flag(group_id, "moving")

    def IsGrpInPos(self, group_id: int) -> int:
        return self._group_flag(group_id, "in_pos")  # (in position implies enabled)

    def IsGrpErrorStop(self, group_id: int) -> int:
        return self._group_flag(group_id, "error_stop")
