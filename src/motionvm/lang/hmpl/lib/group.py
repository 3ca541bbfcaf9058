"""HMPL axis group functions of manual chapter 8: motion (8.2, 8.5), settings (8.3),
status (8.4).

Each is the motion command of its name (`motionvm.motion.commands.group`, which documents
units, codes and the decisions taken); the built-ins here only read the C arrays the
commands take (poses of 6 doubles, centres and normals of 3, motion profiles and
transition parameters of 4) and write the out arrays (6 doubles). A null `trans_par`
(the manual's example 4 passes 0) means no transition parameters.
"""

from __future__ import annotations

import math

from motionvm.lang.hmpl.lib.base import Library, builtin, command
from motionvm.runtime.errors import RuntimeFault


def _axis_vararg(value: object) -> int:
    """An axis id after the fixed ones: C passes it untyped, so a double (a finite one is
    truncated as C converts it) or a pointer may arrive; an infinity or NaN is no id."""
    if isinstance(value, float):
        if not math.isfinite(value):
            raise RuntimeFault(f"SetupGroup: axis id {value!r} is not an integer")
        return int(value)
    if not isinstance(value, int):
        raise RuntimeFault(f"SetupGroup: axis id {value!r} is not an integer")
    return value


class GroupLib(Library):
    """Chapter 8: EnableGroup ... CircleRel."""

    def _doubles(self, addr: int, n: int, what: str, *, nullable: bool = False):
        if addr == 0 and nullable:
            return None
        self.mem.check(addr, 8 * n, f"{what} array")
        return [self.mem.load(addr + 8 * k, "f64") for k in range(n)]

    def _out(self, addr: int, values, what: str) -> None:
        self.mem.check(addr, 8 * len(values), f"{what} array")
        for k, v in enumerate(values):
            self.mem.store(addr + 8 * k, "f64", v)

    # ------------------------------------------------------------ 8.2 motion

    EnableGroup = command()
    DisableGroup = command()
    ResetGroup = command()
    StopGroup = command()
    HaltGroup = command()
    ResumeGroup = command()
    JogGroup = command()
    JogGroupAxis = command()
    LineAbs2D = command()
    LineAbs3D = command()
    LineRel2D = command()
    LineRel3D = command()
    Arc2D = command()
    ArcCW2D = command()
    ArcCCW2D = command()
    ArcAngle2D = command()
    Circle2D = command()

    # ------------------------------------------------------------ 8.3 settings

    AddAxisToGrp = command()
    RemoveAxisFromGrp = command()

    @builtin()
    def SetupGroup(self, group_id: int, axis_id: int, *axis_ids) -> int:
        ids = [axis_id, *(_axis_vararg(a) for a in axis_ids)]
        return self.rt.commands.SetupGroup(group_id, *ids)

    UngrpAllAxes = command()
    GetGroupID = command()
    SetGrpMotionProfile = command()
    SetGrpAngMotionProfile = command()
    GetGrpKin = command()
    SetGrpKin = command()
    GetGrpMaxVel = command()
    SetGrpVel = command()
    GetGrpMaxAcc = command()
    SetGrpAcc = command()
    SetGrpAccTime = command()
    GetGrpMaxDec = command()
    SetGrpDec = command()
    SetGrpDecTime = command()
    GetGrpSMTime = command()
    SetGrpSMTime = command()
    GetGrpCoordSys = command()
    SetGrpCoordSys = command()
    GetGrpBufferMode = command()
    SetGrpBufferMode = command()
    GetGrpTransMode = command()
    SetGrpTransMode = command()
    SetGrpTransPrm = command()
    GetGrpCmdNum = command()
    SetGrpVelScale = command()
    GetGrpVelScale = command()

    @builtin()
    def GetGrpCoordTrans(self, group_id: int, coord_sys: int, trans_param: int) -> int:
        status, values = self.rt.commands.GetGrpCoordTrans(group_id, coord_sys)
        if status == 0:
            self._out(trans_param, values, "GetGrpCoordTrans trans_param")
        return status

    @builtin()
    def SetGrpCoordTrans(self, group_id: int, coord_sys: int, trans_param: int) -> int:
        values = self._doubles(trans_param, 6, "SetGrpCoordTrans trans_param")
        return self.rt.commands.SetGrpCoordTrans(group_id, coord_sys, values)

    @builtin()
    def GetGrpPoseCmd(self, group_id: int, coord_sys: int, pose_cmd: int) -> int:
        status, values = self.rt.commands.GetGrpPoseCmd(group_id, coord_sys)
        if status == 0:
            self._out(pose_cmd, values, "GetGrpPoseCmd pose_cmd")
        return status

    @builtin()
    def GetGrpPoseFb(self, group_id: int, coord_sys: int, pose_fb: int) -> int:
        status, values = self.rt.commands.GetGrpPoseFb(group_id, coord_sys)
        if status == 0:
            self._out(pose_fb, values, "GetGrpPoseFb pose_fb")
        return status

    SetGrpLookAheadPrm = command()
    SetGrpQueueSize = command()

    # ------------------------------------------------------------ 8.4 status

    IsGrpEnabled = command()
    IsGrpMoving = command()
    IsGrpInPos = command()
    IsGrpErrorStop = command()

    # ------------------------------------------------------------ 8.5 advanced motion

    def _line(self, name: str, group_id, pos, prof, cs, bm, tm, par) -> int:
        target = self._doubles(pos, 6, f"{name} position")
        profile = self._doubles(prof, 4, f"{name} motion_profile")
        trans = self._doubles(par, 4, f"{name} trans_par", nullable=True)
        return getattr(self.rt.commands, name)(group_id, target, profile, cs, bm, tm, trans)

    @builtin()
    def LineAbs(self, group_id: int, target_pos: int, motion_profile: int, coord_sys: int,
                buff_mode: int, trans_mode: int, trans_par: int) -> int:  # fmt: skip
        return self._line("LineAbs", group_id, target_pos, motion_profile, coord_sys,
                          buff_mode, trans_mode, trans_par)  # fmt: skip

    @builtin()
    def LineRel(self, group_id: int, relative_dist: int, motion_profile: int, coord_sys: int,
                buff_mode: int, trans_mode: int, trans_par: int) -> int:  # fmt: skip
        return self._line("LineRel", group_id, relative_dist, motion_profile, coord_sys,
                          buff_mode, trans_mode, trans_par)  # fmt: skip

    def _circle(self, name: str, group_id, center, normal, turns, pos, prof, cs, bm, tm, par):
        c = self._doubles(center, 3, f"{name} center_pos")
        nv = self._doubles(normal, 3, f"{name} normal_vector")
        target = self._doubles(pos, 6, f"{name} position")
        profile = self._doubles(prof, 4, f"{name} motion_profile")
        trans = self._doubles(par, 4, f"{name} trans_par", nullable=True)
        return getattr(self.rt.commands, name)(group_id, c, nv, turns, target, profile, cs, bm,
                                               tm, trans)  # fmt: skip

    @builtin()
    def CircleAbs(self, group_id: int, center_pos: int, normal_vector: int, turns: int,
                  target_pos: int, motion_profile: int, coord_sys: int, buff_mode: int,
                  trans_mode: int, trans_par: int) -> int:  # fmt: skip
        return self._circle("CircleAbs", group_id, center_pos, normal_vector, turns, target_pos,
                            motion_profile, coord_sys, buff_mode, trans_mode, trans_par)  # fmt: skip

    @builtin()
    def CircleRel(self, group_id: int, center_pos: int, normal_vector: int, turns: int,
                  relative_dist: int, motion_profile: int, coord_sys: int, buff_mode: int,
                  trans_mode: int, trans_par: int) -> int:  # fmt: skip
        return self._circle("CircleRel", group_id, center_pos, normal_vector, turns,
                            relative_dist, motion_profile, coord_sys, buff_mode, trans_mode,
                            trans_par)  # fmt: skip
