"""Chapter 20, homing: MoveHome, its settings, IsHomed, IsHoming, SetHomedStatus.

MoveHome starts the homing of `motionvm.motion.homing` and returns at once: 0, or the
refusal (not enabled 0x83XX0078, moving 0x83XX0082, error stop, wrong op mode, a
missing switch or index 0x83XX042E; a bad axis id eERR_HMPL_ARG_OUT_OF_RANGE). How the
homing ended is `home_result(axis_id)`: None while it runs, then 0,
eERR_AXIS_DRIVE_HOME_TOUT (0x83XX0424) after the timeout, or eERR_AXIS_DRIVE_HOME_FAILED
(0x83XX042E: a limit switch in the way, the axis stopped or disabled meanwhile). Units:
mm or deg, mm/s, mm/s^2; the timeout in ms.
"""

from __future__ import annotations

from motionvm.motion import axis_status as st
from motionvm.motion.commands.base import CommandBase


class HomingCommands(CommandBase):
    """Chapter 20: MoveHome, SetHomeMethod ... SetHomeTimeout, IsHomed, IsHoming, SetHomedStatus."""

    def _homing_command(self, axis_id: int, method: str, *args) -> int:
        a = self._axis(axis_id)
        if a is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        return self._run(a, getattr(self.motion.homing[axis_id], method), *args)

    def MoveHome(self, axis_id: int) -> int:
        """Start homing; 0 or the refusal (the result: `home_result`)."""
        return self._homing_command(axis_id, "start")

    def home_result(self, axis_id: int) -> int | None:
        """None while axis `axis_id` homes; then 0 or the error its homing ended with."""
        h = self.motion.homing[axis_id]
        if h.running:
            return None
        return st.axis_error(h.error, axis_id) if h.error else 0

    def SetHomeMethod(self, axis_id: int, method: int) -> int:
        return self._homing_command(axis_id, "set_method", method)

    def SetHomeSwitchVel(self, axis_id: int, fast_vel: float) -> int:
        return self._homing_command(axis_id, "set_switch_vel", fast_vel)

    def SetHomeZeroVel(self, axis_id: int, slow_vel: float) -> int:
        return self._homing_command(axis_id, "set_zero_vel", slow_vel)

    def SetHomeAcc(self, axis_id: int, acc: float) -> int:
        return self._homing_command(axis_id, "set_acc", acc)

    def SetHomeOffset(self, axis_id: int, offset: float) -> int:
        return self._homing_command(axis_id, "set_offset", offset)

    def SetHomeTimeout(self, axis_id: int, timeout: int) -> int:
        """`timeout` [ms]."""
        return self._homing_command(axis_id, "set_timeout", float(timeout))

    def IsHomed(self, axis_id: int) -> int:
        return self._homing_flag(axis_id, "homed")

    def IsHoming(self, axis_id: int) -> int:
        return self._homing_flag(axis_id, "homing")

    def _homing_flag(self, axis_id: int, attr: str) -> int:
        """A homing flag; recorded while a task runs, as the axis flags are (axis.py)."""
        reads = self.motion.reads
        if self._axis(axis_id) is None:
            if reads is not None:
                reads.append(None)
            return 0
        h = self.motion.homing[axis_id]
        flag = getattr(h, attr)
        if reads is not None:
            # `homing` notices a cut-off homing when asked: not asked again in a replay
            reads.append((h, attr, flag) if attr == "homed" else None)
        return 1 if flag else 0

    def SetHomedStatus(self, axis_id: int, is_homed: int) -> int:
        return self._homing_command(axis_id, "set_homed", is_homed)
