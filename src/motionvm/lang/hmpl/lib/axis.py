"""HMPL axis functions of manual chapter 5: motion (5.2), settings (5.3), status (5.4).

Every function takes the manual's units (mm or deg, mm/s, mm/s^2, ms). A function
that fails returns the manual's error code (table 18.1.2.1, 0x83XXCCCC with XX the
axis id, as a C int) and stores it as the axis's last error (GetAxisLastErr); a bad
axis id returns eERR_HMPL_ARG_OUT_OF_RANGE (0x138F) and stores it as the system's
last error. Getters of a bad axis return 0 and store the same system error.
An axis whose drive runs a PDL program (machine file `pdl = ...`) refuses every command
of this module with eERR_AXIS_CMD_INVALID_CONTROL_MODE (0x83XX00F0).
Decisions where the manual is silent are in `motionvm.motion.axis`.
"""

from __future__ import annotations

from motionvm.lang.hmpl.lib.axis_base import AxisLibrary
from motionvm.lang.hmpl.lib.base import builtin
from motionvm.motion import axis_status as st
from motionvm.motion.gantry import from_axes, gantries_of
from motionvm.motion.kernel import ECAT_OP
from motionvm.motion.pvt import MAX_POINTS

_GANTRY_VIEW = frozenset({"pos_fb", "vel_fb", "ref_pos", "ref_vel", "ref_acc", "pos_err"})
"""Axis variables that a gantry pair's axes report in linear/yaw coordinates (manual 7.1)."""


class AxisLib(AxisLibrary):
    """Chapter 5: Enable ... GetCmdNum, IsEnabled ... IsAcc."""

    # ------------------------------------------------------------ plumbing

    def _refusal(self, a) -> int:
        # a PDL program runs the drive (sim/pdl_drives.py): HMPL commands are refused
        return st.CMD_INVALID_CONTROL_MODE if getattr(a, "controlled_by", None) else 0

    def _get(self, axis_id: int, attr: str, default: float = 0.0):
        a = self._axis(axis_id)
        return default if a is None else getattr(a, attr)

    def _var(self, axis_id: int, name: str) -> float:
        a = self._axis(axis_id)
        if a is None:
            return 0.0
        if a.following is not None and name in _GANTRY_VIEW:
            pair = gantries_of(self.rt.controller.motion).pair_of(axis_id)
            if pair is not None and pair.engaged:
                # manual 7.1: a paired RHS axis reads as the linear axis, the LHS as the yaw
                r, lft = float(pair.rhs.variable(name)), float(pair.lhs.variable(name))
                linear, yaw = from_axes(r, lft)
                return linear if a is pair.rhs else yaw
        return float(a.variable(name))

    def _flag(self, axis_id: int, attr: str) -> int:
        a = self._axis(axis_id)
        return 1 if a is not None and getattr(a, attr) else 0

    def _fault(self, axis_id: int, bit: int) -> int:
        a = self._axis(axis_id)
        return 1 if a is not None and a.fault_status & bit else 0

    def _status(self, axis_id: int, bit: int) -> int:
        a = self._axis(axis_id)
        return 1 if a is not None and a.motion_status & bit else 0

    # ------------------------------------------------------------ 5.2 motion

    @builtin()
    def Enable(self, axis_id: int) -> int:
        motion = self.rt.controller.motion
        if motion.axis(axis_id) is not None and motion.ecat_state != ECAT_OP:
            motion.system_last_error = st.SYS_HMPL_NOT_IN_OP_MODE
            return st.SYS_HMPL_NOT_IN_OP_MODE
        return self._do(axis_id, "enable")

    @builtin()
    def Disable(self, axis_id: int) -> int:
        return self._do(axis_id, "disable")

    @builtin()
    def Reset(self, axis_id: int) -> int:
        return self._do(axis_id, "reset")

    @builtin()
    def MoveAbs(self, axis_id: int, pos: float) -> int:
        return self._do(axis_id, "move_abs", pos)

    @builtin()
    def MoveRel(self, axis_id: int, rel_dist: float) -> int:
        return self._do(axis_id, "move_rel", rel_dist)

    @builtin()
    def MoveVel(self, axis_id: int, vel: float) -> int:
        return self._do(axis_id, "move_vel", vel)

    @builtin()
    def MoveTrq(self, axis_id: int, torque_cmd: float) -> int:
        return self._do(axis_id, "move_trq", torque_cmd)

    @builtin()
    def MovePVT(self, axis_id: int, time: int, pos: int, vel: int, num_pt: int) -> int:
        a = self._axis(axis_id)
        if a is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        if not 1 <= num_pt <= MAX_POINTS:
            a.last_error = code = st.axis_error(st.CMD_INVALID_PARAMETER, axis_id)
            return code
        arrays = []
        for addr, what in ((time, "time"), (pos, "pos"), (vel, "vel")):
            self.mem.check(addr, 8 * num_pt, f"MovePVT {what} array")
            arrays.append([self.mem.load(addr + 8 * i, "f64") for i in range(num_pt)])
        return self._do(axis_id, "move_pvt", *arrays)

    @builtin()
    def Stop(self, axis_id: int) -> int:
        return self._do(axis_id, "stop")

    @builtin()
    def Halt(self, axis_id: int) -> int:
        return self._do(axis_id, "halt")

    @builtin()
    def Resume(self, axis_id: int) -> int:
        return self._do(axis_id, "resume")

    # ------------------------------------------------------------ 5.3 settings

    @builtin()
    def GetMaxVel(self, axis_id: int) -> float:
        return self._var(axis_id, "max_vel")

    @builtin()
    def SetVel(self, axis_id: int, vel: float) -> int:
        return self._do(axis_id, "set_vel", vel)

    @builtin()
    def GetMaxAcc(self, axis_id: int) -> float:
        return self._var(axis_id, "max_acc")

    @builtin()
    def SetAcc(self, axis_id: int, acc: float) -> int:
        return self._do(axis_id, "set_acc", acc)

    @builtin()
    def SetAccTime(self, axis_id: int, acc_time: float) -> int:
        return self._do(axis_id, "set_acc_time", acc_time)

    @builtin()
    def GetMaxDec(self, axis_id: int) -> float:
        return self._var(axis_id, "max_dec")

    @builtin()
    def SetDec(self, axis_id: int, dec: float) -> int:
        return self._do(axis_id, "set_dec", dec)

    @builtin()
    def SetDecTime(self, axis_id: int, dec_time: float) -> int:
        return self._do(axis_id, "set_dec_time", dec_time)

    @builtin()
    def GetKillDec(self, axis_id: int) -> float:
        return float(self._get(axis_id, "kill_dec"))

    @builtin()
    def SetKillDec(self, axis_id: int, kill_dec: float) -> int:
        return self._do(axis_id, "set_kill_dec", kill_dec)

    @builtin()
    def GetSWRL(self, axis_id: int) -> float:
        return float(self._get(axis_id, "sw_right"))

    @builtin()
    def SetSWRL(self, axis_id: int, right_limit_pos: float) -> int:
        return self._do(axis_id, "set_sw_right", right_limit_pos)

    @builtin()
    def GetSWLL(self, axis_id: int) -> float:
        return float(self._get(axis_id, "sw_left"))

    @builtin()
    def SetSWLL(self, axis_id: int, left_limit_pos: float) -> int:
        return self._do(axis_id, "set_sw_left", left_limit_pos)

    @builtin()
    def GetSMTime(self, axis_id: int) -> float:
        return self._var(axis_id, "sm_factor")

    @builtin()
    def SetSMTime(self, axis_id: int, smooth_time: float) -> int:
        return self._do(axis_id, "set_smooth_time", smooth_time)

    @builtin()
    def GetMoveTime(self, axis_id: int) -> float:
        return self._var(axis_id, "movetime")

    @builtin()
    def GetSettlingTime(self, axis_id: int) -> float:
        return self._var(axis_id, "settlingtime")

    @builtin()
    def SetPos(self, axis_id: int, pos: float) -> int:
        return self._do(axis_id, "set_pos", pos)

    @builtin()
    def GetPosFb(self, axis_id: int) -> float:
        return self._var(axis_id, "pos_fb")

    @builtin()
    def GetPosFbComp(self, axis_id: int) -> float:
        return self._var(axis_id, "pos_fb")  # no compensation tables yet: the same

    @builtin()
    def GetPosOffset(self, axis_id: int) -> float:
        return self._var(axis_id, "pos_offset")

    @builtin()
    def GetPosErr(self, axis_id: int) -> float:
        return self._var(axis_id, "pos_err")

    @builtin()
    def GetVelFb(self, axis_id: int) -> float:
        return self._var(axis_id, "vel_fb")

    @builtin()
    def GetVelErr(self, axis_id: int) -> float:
        return self._var(axis_id, "vel_err")

    @builtin()
    def GetCurrFb(self, axis_id: int) -> float:
        return float(self._get(axis_id, "current_fb"))

    @builtin()
    def GetRefPos(self, axis_id: int) -> float:
        return self._var(axis_id, "ref_pos")

    @builtin()
    def GetRefVel(self, axis_id: int) -> float:
        return self._var(axis_id, "ref_vel")

    @builtin()
    def GetRefAcc(self, axis_id: int) -> float:
        return self._var(axis_id, "ref_acc")

    @builtin()
    def GetPosOut(self, axis_id: int) -> float:
        return self._var(axis_id, "pos_out")

    @builtin()
    def GetVelOut(self, axis_id: int) -> float:
        return self._var(axis_id, "vel_out")

    @builtin()
    def GetAccOut(self, axis_id: int) -> float:
        return self._var(axis_id, "acc_out")

    @builtin()
    def IgnoreHWL(self, axis_id: int, cmd: int) -> int:
        return self._do(axis_id, "set_ignore", "hwl", cmd)

    @builtin()
    def IgnoreSWL(self, axis_id: int, cmd: int) -> int:
        return self._do(axis_id, "set_ignore", "swl", cmd)

    @builtin()
    def IgnorePE(self, axis_id: int, cmd: int) -> int:
        return self._do(axis_id, "set_ignore", "pe", cmd)

    @builtin()
    def GetAxisNum(self) -> int:
        return self.rt.controller.motion.n_axes

    @builtin()
    def SetVelScale(self, axis_id: int, vel_scale: float) -> int:
        return self._do(axis_id, "set_vel_scale", vel_scale)

    @builtin()
    def GetVelScale(self, axis_id: int) -> float:
        return float(self._get(axis_id, "vel_scale"))

    @builtin()
    def SetRollover(self, axis_id: int, rollover_val: float) -> int:
        return self._do(axis_id, "set_rollover", rollover_val)

    @builtin()
    def GetRolloverTurns(self, axis_id: int) -> int:
        return int(self._get(axis_id, "rollover_turns", 0))

    @builtin()
    def SetOpMode(self, axis_id: int, op_mode: int) -> int:
        return self._do(axis_id, "set_op_mode", op_mode)

    @builtin()
    def SetBufferMode(self, axis_id: int, buf_mode: int) -> int:
        return self._do(axis_id, "set_buffer_mode", buf_mode)

    @builtin()
    def GetBufferMode(self, axis_id: int) -> int:
        return int(self._get(axis_id, "buffer_mode", 0))

    @builtin()
    def GetCmdNum(self, axis_id: int) -> int:
        return int(self._get(axis_id, "cmd_num", 0))

    # ------------------------------------------------------------ 5.4 status

    # the three the manual's idioms poll every cycle (Till(IsInPos(a))) take a short path

    @builtin()
    def IsEnabled(self, axis_id: int) -> int:
        axes = self.rt.controller.motion.axes
        if 0 <= axis_id < len(axes):
            return 1 if axes[axis_id].enabled else 0
        return self._flag(axis_id, "enabled")

    @builtin()
    def IsMoving(self, axis_id: int) -> int:
        axes = self.rt.controller.motion.axes
        if 0 <= axis_id < len(axes):
            return 1 if axes[axis_id].moving else 0
        return self._flag(axis_id, "moving")

    @builtin()
    def IsInPos(self, axis_id: int) -> int:
        if axis_id >= 0:
            try:
                return 1 if self.rt.controller.motion.axes[axis_id].in_pos else 0
            except IndexError:
                pass
        return self._flag(axis_id, "in_pos")

    @builtin()
    def IsErrorStop(self, axis_id: int) -> int:
        return self._flag(axis_id, "error_stop")

    @builtin()
    def IsGantry(self, axis_id: int) -> int:
        return self._status(axis_id, st.MS_GANTRY)

    @builtin()
    def IsGrouped(self, axis_id: int) -> int:
        return self._status(axis_id, st.MS_GROUP)

    @builtin()
    def IsSync(self, axis_id: int) -> int:
        return self._status(axis_id, st.MS_SYNC)

    @builtin()
    def IsHWLL(self, axis_id: int) -> int:
        return self._fault(axis_id, st.FS_HW_LEFT)

    @builtin()
    def IsHWRL(self, axis_id: int) -> int:
        return self._fault(axis_id, st.FS_HW_RIGHT)

    @builtin()
    def IsSWLL(self, axis_id: int) -> int:
        return self._fault(axis_id, st.FS_SW_LEFT)

    @builtin()
    def IsSWRL(self, axis_id: int) -> int:
        return self._fault(axis_id, st.FS_SW_RIGHT)

    @builtin()
    def IsDriveErr(self, axis_id: int) -> int:
        return self._fault(axis_id, st.FS_DRIVE_FAULT)

    @builtin()
    def IsPosErr(self, axis_id: int) -> int:
        return self._fault(axis_id, st.FS_POSITION_ERROR)

    @builtin()
    def IsCompActive(self, axis_id: int) -> int:
        self._axis(axis_id)
        return 0  # no compensation tables are simulated

    @builtin()
    def IsAcc(self, axis_id: int) -> int:
        return self._flag(axis_id, "accelerating")
