"""HMPL touch probe functions of manual chapter 13, on the drive's CiA 402 touch probe objects.

The semantics -- the probe's function, its objects 0x60B8-0x60BD, the latched position
in axis units, the error codes -- are the motion commands'
(`motionvm.motion.commands.touchprobe`, `motionvm.motion.touchprobe`); each built-in is
the command of its name, except GetTouchProbePos, which writes the position [mm or deg]
to its `double *output`.
"""

from __future__ import annotations

from motionvm.lang.hmpl.lib.base import Library, builtin, command


class TouchProbeLib(Library):
    """Chapter 13: EnableTouchProbe ... SetTouchProbeFunc."""

    EnableTouchProbe = command()
    DisableTouchProbe = command()
    IsTouchProbeEnabled = command()
    IsTouchProbeTriggered = command()

    @builtin()
    def GetTouchProbePos(self, axis_id: int, output: int) -> int:
        code, pos = self.rt.commands.GetTouchProbePos(axis_id)
        if code:
            return code
        self.mem.check(output, 8, "GetTouchProbePos output")
        self.mem.store(output, "f64", pos)
        return 0

    SetTouchProbeFunc = command()
