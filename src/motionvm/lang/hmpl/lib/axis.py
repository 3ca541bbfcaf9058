"""HMPL axis functions of manual chapter 5: motion (5.2), settings (5.3), status (5.4).

Their semantics -- units, error codes, the refusals of an axis that a PDL program
drives, the linear/yaw view of a gantry pair -- are the motion commands'
(`motionvm.motion.commands.axis`); each built-in here is the command of its name, except
MovePVT, which reads its three arrays of `num_pt` doubles from the program's memory.
"""

from __future__ import annotations

from motionvm.lang.hmpl.lib.base import Library, builtin, command
from motionvm.motion.pvt import MAX_POINTS


class AxisLib(Library):
    """Chapter 5: Enable ... GetCmdNum, IsEnabled ... IsAcc."""

    # ------------------------------------------------------------ 5.2 motion

    Enable = command()
    Disable = command()
    Reset = command()
    MoveAbs = command()
    MoveRel = command()
    MoveVel = command()
    MoveTrq = command()

    @builtin()
    def MovePVT(self, axis_id: int, time: int, pos: int, vel: int, num_pt: int) -> int:
        arrays: list[list[float]] = [[], [], []]
        if 1 <= num_pt <= MAX_POINTS and self.rt.controller.motion.axis(axis_id) is not None:
            for i, (addr, what) in enumerate(((time, "time"), (pos, "pos"), (vel, "vel"))):
                self.mem.check(addr, 8 * num_pt, f"MovePVT {what} array")
                arrays[i] = [self.mem.load(addr + 8 * k, "f64") for k in range(num_pt)]
        return self.rt.commands.MovePVT(axis_id, *arrays)

    Stop = command()
    Halt = command()
    Resume = command()

    # ------------------------------------------------------------ 5.3 settings

    GetMaxVel = command()
    SetVel = command()
    GetMaxAcc = command()
    SetAcc = command()
    SetAccTime = command()
    GetMaxDec = command()
    SetDec = command()
    SetDecTime = command()
    GetKillDec = command()
    SetKillDec = command()
    GetSWRL = command()
    SetSWRL = command()
    GetSWLL = command()
    SetSWLL = command()
    GetSMTime = command()
    SetSMTime = command()
    GetMoveTime = command()
    GetSettlingTime = command()
    SetPos = command()
    GetPosFb = command()
    GetPosFbComp = command()
    GetPosOffset = command()
    GetPosErr = command()
    GetVelFb = command()
    GetVelErr = command()
    GetCurrFb = command()
    GetRefPos = command()
    GetRefVel = command()
    GetRefAcc = command()
    GetPosOut = command()
    GetVelOut = command()
    GetAccOut = command()
    IgnoreHWL = command()
    IgnoreSWL = command()
    IgnorePE = command()
    GetAxisNum = command()
    SetVelScale = command()
    GetVelScale = command()
    SetRollover = command()
    GetRolloverTurns = command()
    SetOpMode = command()
    SetBufferMode = command()
    GetBufferMode = command()
    GetCmdNum = command()

    # ------------------------------------------------------------ 5.4 status

    IsEnabled = command()
    IsMoving = command()
    IsInPos = command()
    IsErrorStop = command()
    IsGantry = command()
    IsGrouped = command()
    IsSync = command()
    IsHWLL = command()
    IsHWRL = command()
    IsSWLL = command()
    IsSWRL = command()
    IsDriveErr = command()
    IsPosErr = command()
    IsCompActive = command()
    IsAcc = command()
