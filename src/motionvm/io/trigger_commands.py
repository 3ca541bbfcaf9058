"""Chapter 12, the position trigger: EnablePT ... SetPT_EndIndex, in manual units and codes.

`TriggerCommands(motion, triggers)` acts on the `PositionTriggers` of a controller
(io/position_trigger.py, where the decisions are documented). Conventions as the motion
commands' (motion/commands/__init__.py): 0 or the manual's error code (a refused
setting or EnablePT stores its axis error as the axis's last error); a bad axis id
returns eERR_HMPL_ARG_OUT_OF_RANGE (IsPTEnabled: 0) and stores it as the system's last
error.
"""

from __future__ import annotations

from motionvm.io.position_trigger import PositionTriggers
from motionvm.motion import axis_status as st
from motionvm.motion.commands.base import CommandBase


class TriggerCommands(CommandBase):
    """Chapter 12: EnablePT ... SetPT_EndIndex."""

    def __init__(self, motion, triggers: PositionTriggers) -> None:
        super().__init__(motion)
        self.triggers = triggers

    def _pt(self, axis_id: int, method: str, *args) -> int:
        a = self._axis(axis_id)
        if a is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        return self._run(a, getattr(self.triggers[axis_id], method), *args)

    def EnablePT(self, axis_id: int) -> int:
        return self._pt(axis_id, "enable", self.triggers.clock.cycle)

    def DisablePT(self, axis_id: int) -> int:
        return self._pt(axis_id, "disable")

    def IsPTEnabled(self, axis_id: int) -> int:
        if self._axis(axis_id) is None:
            return 0
        return 1 if self.triggers[axis_id].enabled else 0

    def SetPT_StartPos(self, axis_id: int, start_pos: float) -> int:
        return self._pt(axis_id, "set_position", "start", start_pos)

    def SetPT_EndPos(self, axis_id: int, end_pos: float) -> int:
        return self._pt(axis_id, "set_position", "end", end_pos)

    def SetPT_Interval(self, axis_id: int, interval: float) -> int:
        return self._pt(axis_id, "set_interval", interval)

    def SetPT_PulseWidth(self, axis_id: int, width_ns: int) -> int:
        return self._pt(axis_id, "set_width", width_ns)

    def SetPT_PosArray(self, axis_id: int, index: int, trigger_pos: float) -> int:
        return self._pt(axis_id, "set_array_position", index, trigger_pos)

    def SetPT_StateArray(self, axis_id: int, index: int, state: int) -> int:
        return self._pt(axis_id, "set_state_word", index, state)

    def SetPT_StartIndex(self, axis_id: int, index: int) -> int:
        return self._pt(axis_id, "set_index", "start", index)

    def SetPT_EndIndex(self, axis_id: int, index: int) -> int:
        return self._pt(axis_id, "set_index", "end", index)
