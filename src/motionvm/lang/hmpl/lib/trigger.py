"""HMPL position trigger functions of manual chapter 12: EnablePT ... SetPT_EndIndex.

Each built-in is the command of its name on the controller's position triggers
(`motionvm.io.trigger_commands`, `motionvm.io.position_trigger`, where the manual's
silences are decided).
"""

from __future__ import annotations

from motionvm.io.trigger_commands import TriggerCommands
from motionvm.lang.hmpl.lib.base import Library, builtin


class TriggerLib(Library):
    """Chapter 12: EnablePT ... SetPT_EndIndex."""

    def __init__(self, rt) -> None:
        super().__init__(rt)
        controller = rt.controller
        self.pt = TriggerCommands(controller.motion, controller.triggers)

    @builtin()
    def EnablePT(self, axis_id: int) -> int:
        return self.pt.EnablePT(axis_id)

    @builtin()
    def DisablePT(self, axis_id: int) -> int:
        return self.pt.DisablePT(axis_id)

    @builtin()
    def IsPTEnabled(self, axis_id: int) -> int:
        return self.pt.IsPTEnabled(axis_id)

    @builtin()
    def SetPT_StartPos(self, axis_id: int, start_pos: float) -> int:
        return self.pt.SetPT_StartPos(axis_id, start_pos)

    @builtin()
    def SetPT_EndPos(self, axis_id: int, end_pos: float) -> int:
        return self.pt.SetPT_EndPos(axis_id, end_pos)

    @builtin()
    def SetPT_Interval(self, axis_id: int, interval: float) -> int:
        return self.pt.SetPT_Interval(axis_id, interval)

    @builtin()
    def SetPT_PulseWidth(self, axis_id: int, width_ns: int) -> int:
        return self.pt.SetPT_PulseWidth(axis_id, width_ns)

    @builtin()
    def SetPT_PosArray(self, axis_id: int, index: int, trigger_pos: float) -> int:
        return self.pt.SetPT_PosArray(axis_id, index, trigger_pos)

    @builtin()
    def SetPT_StateArray(self, axis_id: int, index: int, state: int) -> int:
        return self.pt.SetPT_StateArray(axis_id, index, state)

    @builtin()
    def SetPT_StartIndex(self, axis_id: int, index: int) -> int:
        return self.pt.SetPT_StartIndex(axis_id, index)

    @builtin()
    def SetPT_EndIndex(self, axis_id: int, index: int) -> int:
        return self.pt.SetPT_EndIndex(axis_id, index)
