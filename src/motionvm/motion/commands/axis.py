"""Chapter 5, the axis: motion (5.2), settings (5.3), status (5.4).

Units: mm or deg, mm/s, mm/s^2, ms. A command that fails returns the manual's error code
(table 18.1.2.1, 0x83XXCCCC with XX the axis id, as a C int) and stores it as the axis's
last error; a bad axis id returns eERR_HMPL_ARG_OUT_OF_RANGE (0x138F) and stores it as
the system's last error. Getters and Is* functions of a bad axis return 0 and store the
same system error. An axis whose drive runs a PDL program (machine file `pdl = ...`:
the axis has a `controlled_by`) refuses every command of this chapter with
eERR_AXIS_CMD_INVALID_CONTROL_MODE (0x83XX00F0); its getters still answer.
While a gantry pair is engaged, its RHS axis reads as the linear axis and its LHS axis
as the yaw axis (manual 7.1) in GetPosFb, GetVelFb, GetRefPos, GetRefVel, GetRefAcc and
GetPosErr. Decisions where the manual is silent are in `motionvm.motion.axis`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from motionvm.motion import axis_status as st
from motionvm.motion.commands.base import CommandBase
from motionvm.motion.commands.status_flags import StatusFlag
from motionvm.motion.commands.touchprobe import NO_SPECIFIC_PDO
from motionvm.motion.gantry import from_axes
from motionvm.motion.kernel import ECAT_OP
from motionvm.motion.pvt import MAX_POINTS

_INT_MAX = 2**31 - 1
"""The largest count a C int return holds."""

_GANTRY_VIEW = frozenset({"pos_fb", "vel_fb", "ref_pos", "ref_vel", "ref_acc", "pos_err"})
"""Axis variables that a gantry pair's axes report in linear/yaw coordinates (manual 7.1)."""
_MODE_OBJECTS = {9: (0x60FF, 0), 10: (0x6071, 0)}
"""The RxPDO object an op mode needs: target velocity (CSV), target torque (CST)."""


class AxisCommands(CommandBase):
    """Chapter 5: Enable ... GetCmdNum, IsEnabled ... IsAcc."""

    # ------------------------------------------------------------ plumbing

    def _command(self, axis_id: int, method: str, *args) -> int:
        """Axis method `method(*args)`: 0, or the error code (see the module docstring)."""
        a = self._axis(axis_id)
        if a is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        if a.controlled_by is not None:  # a PDL program or a GDL motor owns the axis
            return self._fail(a, st.CMD_INVALID_CONTROL_MODE)
        reads = self.motion.reads
        if reads:  # a command acts: what the task read before it is no wait's condition
            reads.clear()
        return self._run(a, getattr(a, method), *args)

    def _get(self, axis_id: int, attr: str, default: float = 0.0):
        a = self._axis(axis_id)
        return default if a is None else getattr(a, attr)

    def _var(self, axis_id: int, name: str) -> float:
        a = self._axis(axis_id)
        if a is None:
            return 0.0
        if a.following is not None and name in _GANTRY_VIEW:
            pair = self.motion.gantries.pair_of(axis_id)
            if pair is not None and pair.engaged:
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

    def Enable(self, axis_id: int) -> int:
        """Refused with eERR_HMPL_NOT_IN_OP_MODE (system) while the bus is not in Operation."""
        motion = self.motion
        if motion.axis(axis_id) is not None and motion.ecat_state != ECAT_OP:
            motion.system_last_error = st.SYS_HMPL_NOT_IN_OP_MODE
            return st.SYS_HMPL_NOT_IN_OP_MODE
        return self._command(axis_id, "enable")

    def Disable(self, axis_id: int) -> int:
        return self._command(axis_id, "disable")

    def Reset(self, axis_id: int) -> int:
        return self._command(axis_id, "reset")

    def MoveAbs(self, axis_id: int, pos: float) -> int:
        return self._command(axis_id, "move_abs", pos)

    def MoveRel(self, axis_id: int, rel_dist: float) -> int:
        return self._command(axis_id, "move_rel", rel_dist)

    def MoveVel(self, axis_id: int, vel: float) -> int:
        return self._command(axis_id, "move_vel", vel)

    def MoveTrq(self, axis_id: int, torque_cmd: float) -> int:
        return self._command(axis_id, "move_trq", torque_cmd)

    def MovePVT(
        self, axis_id: int, time: Sequence[float], pos: Sequence[float], vel: Sequence[float]
    ) -> int:
        """Points at `time` [ms from the call], `pos` [mm], `vel` [mm/s]: 1..MAX_POINTS
        points, the three sequences of one length (else eERR_AXIS_CMD_INVALID_PARAMETER)."""
        a = self._axis(axis_id)
        if a is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        n = len(time)
        if not 1 <= n <= MAX_POINTS or len(pos) != n or len(vel) != n:
            return self._fail(a, st.CMD_INVALID_PARAMETER)
        return self._command(axis_id, "move_pvt", list(time), list(pos), list(vel))

    def Stop(self, axis_id: int) -> int:
        return self._command(axis_id, "stop")

    def Halt(self, axis_id: int) -> int:
        return self._command(axis_id, "halt")

    def Resume(self, axis_id: int) -> int:
        return self._command(axis_id, "resume")

    # ------------------------------------------------------------ 5.3 settings

    def GetMaxVel(self, axis_id: int) -> float:
        return self._var(axis_id, "max_vel")

    def SetVel(self, axis_id: int, vel: float) -> int:
        return self._command(axis_id, "set_vel", vel)

    def GetMaxAcc(self, axis_id: int) -> float:
        return self._var(axis_id, "max_acc")

    def SetAcc(self, axis_id: int, acc: float) -> int:
        return self._command(axis_id, "set_acc", acc)

    def SetAccTime(self, axis_id: int, acc_time: float) -> int:
        return self._command(axis_id, "set_acc_time", acc_time)

    def GetMaxDec(self, axis_id: int) -> float:
        return self._var(axis_id, "max_dec")

    def SetDec(self, axis_id: int, dec: float) -> int:
        return self._command(axis_id, "set_dec", dec)

    def SetDecTime(self, axis_id: int, dec_time: float) -> int:
        return self._command(axis_id, "set_dec_time", dec_time)

    def GetKillDec(self, axis_id: int) -> float:
        return float(self._get(axis_id, "kill_dec"))

    def SetKillDec(self, axis_id: int, kill_dec: float) -> int:
        return self._command(axis_id, "set_kill_dec", kill_dec)

    def GetSWRL(self, axis_id: int) -> float:
        return float(self._get(axis_id, "sw_right"))

    def SetSWRL(self, axis_id: int, right_limit_pos: float) -> int:
        return self._command(axis_id, "set_sw_right", right_limit_pos)

    def GetSWLL(self, axis_id: int) -> float:
        return float(self._get(axis_id, "sw_left"))

    def SetSWLL(self, axis_id: int, left_limit_pos: float) -> int:
        return self._command(axis_id, "set_sw_left", left_limit_pos)

    def GetSMTime(self, axis_id: int) -> float:
        return self._var(axis_id, "sm_factor")

    def SetSMTime(self, axis_id: int, smooth_time: float) -> int:
        return self._command(axis_id, "set_smooth_time", smooth_time)

    def GetMoveTime(self, axis_id: int) -> float:
        return self._var(axis_id, "movetime")

    def GetSettlingTime(self, axis_id: int) -> float:
        return self._var(axis_id, "settlingtime")

    def SetPos(self, axis_id: int, pos: float) -> int:
        a = self._axis(axis_id)
        before = a.ref_pos if a is not None else 0.0
        err = self._command(axis_id, "set_pos", pos)
        if err == 0 and a is not None:  # a gear master's slaves stay where they are
            self.motion.gears.master_shifted(a, a.ref_pos - before)
        return err

    def GetPosFb(self, axis_id: int) -> float:
        return self._var(axis_id, "pos_fb")

    def GetPosOffset(self, axis_id: int) -> float:
        return self._var(axis_id, "pos_offset")

    def GetPosErr(self, axis_id: int) -> float:
        return self._var(axis_id, "pos_err")

    def GetVelFb(self, axis_id: int) -> float:
        return self._var(axis_id, "vel_fb")

    def GetVelErr(self, axis_id: int) -> float:
        return self._var(axis_id, "vel_err")

    def GetCurrFb(self, axis_id: int) -> float:
        return float(self._get(axis_id, "current_fb"))

    def GetRefPos(self, axis_id: int) -> float:
        return self._var(axis_id, "ref_pos")

    def GetRefVel(self, axis_id: int) -> float:
        return self._var(axis_id, "ref_vel")

    def GetRefAcc(self, axis_id: int) -> float:
        return self._var(axis_id, "ref_acc")

    def GetPosOut(self, axis_id: int) -> float:
        return self._var(axis_id, "pos_out")

    def GetVelOut(self, axis_id: int) -> float:
        return self._var(axis_id, "vel_out")

    def GetAccOut(self, axis_id: int) -> float:
        return self._var(axis_id, "acc_out")

    def IgnoreHWL(self, axis_id: int, cmd: int) -> int:
        return self._command(axis_id, "set_ignore", "hwl", cmd)

    def IgnoreSWL(self, axis_id: int, cmd: int) -> int:
        return self._command(axis_id, "set_ignore", "swl", cmd)

    def IgnorePE(self, axis_id: int, cmd: int) -> int:
        return self._command(axis_id, "set_ignore", "pe", cmd)

    def GetAxisNum(self) -> int:
        return self.motion.n_axes

    def SetVelScale(self, axis_id: int, vel_scale: float) -> int:
        return self._command(axis_id, "set_vel_scale", vel_scale)

    def GetVelScale(self, axis_id: int) -> float:
        return float(self._get(axis_id, "vel_scale"))

    def SetRollover(self, axis_id: int, rollover_val: float) -> int:
        return self._command(axis_id, "set_rollover", rollover_val)

    def GetRolloverTurns(self, axis_id: int) -> int:
        """Whole turns of the feedback position; the controller counts them in a C int, so
        a count beyond it (a rollover of one encoder count a metre from the origin)
        saturates at INT_MIN / INT_MAX instead of failing."""
        a = self._axis(axis_id)
        if a is None or not a.rollover:
            return 0
        turns = a.pos_fb / a.rollover
        if not math.isfinite(turns) or abs(turns) >= _INT_MAX:
            return _INT_MAX if turns > 0 else -_INT_MAX - 1
        return int(a.rollover_turns)

    def SetOpMode(self, axis_id: int, op_mode: int) -> int:
        """CSV (9) needs 0x60FF, CST (10) 0x6071 in the drive's RxPDO, else
        eERR_AXIS_CMD_INVALID_NO_SPECIFIC_PDO (0x83XX0258)."""
        a = self._axis(axis_id)
        need = _MODE_OBJECTS.get(op_mode)
        if a is not None and need is not None and need not in a.drive.objects.rx:
            return self._fail(a, NO_SPECIFIC_PDO)
        return self._command(axis_id, "set_op_mode", op_mode)

    def SetBufferMode(self, axis_id: int, buf_mode: int) -> int:
        return self._command(axis_id, "set_buffer_mode", buf_mode)

    def GetBufferMode(self, axis_id: int) -> int:
        return int(self._get(axis_id, "buffer_mode", 0))

    def GetCmdNum(self, axis_id: int) -> int:
        return int(self._get(axis_id, "cmd_num", 0))

    # ------------------------------------------------------------ 5.4 status

    # the four status flags (one owner of their rule: status_flags.py)
    IsEnabled = StatusFlag("enabled")
    IsMoving = StatusFlag("moving")
    IsInPos = StatusFlag("in_pos")
    IsErrorStop = StatusFlag("error_stop")

    def _status_of_bad_id(self, axis_id: int, attr: str) -> int:
        """A status flag's answer for a bad axis id (0, the system's error stored), not
        replayable by a status wait's record."""
        reads = self.motion.reads
        if reads is not None:
            reads.append(None)
        return self._flag(axis_id, attr)

    def IsGantry(self, axis_id: int) -> int:
        return self._status(axis_id, st.MS_GANTRY)

    def IsGrouped(self, axis_id: int) -> int:
        return self._status(axis_id, st.MS_GROUP)

    def IsSync(self, axis_id: int) -> int:
        return self._status(axis_id, st.MS_SYNC)

    def IsHWLL(self, axis_id: int) -> int:
        return self._fault(axis_id, st.FS_HW_LEFT)

    def IsHWRL(self, axis_id: int) -> int:
        return self._fault(axis_id, st.FS_HW_RIGHT)

    def IsSWLL(self, axis_id: int) -> int:
        return self._fault(axis_id, st.FS_SW_LEFT)

    def IsSWRL(self, axis_id: int) -> int:
        return self._fault(axis_id, st.FS_SW_RIGHT)

    def IsDriveErr(self, axis_id: int) -> int:
        return self._fault(axis_id, st.FS_DRIVE_FAULT)

    def IsPosErr(self, axis_id: int) -> int:
        return self._fault(axis_id, st.FS_POSITION_ERROR)

    def IsAcc(self, axis_id: int) -> int:
        return self._flag(axis_id, "accelerating")
