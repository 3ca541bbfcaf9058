"""HMPL homing functions of manual chapter 20: MoveHome, its settings, IsHomed/IsHoming.

MoveHome is blocking: the calling task waits until the homing has ended, and gets 0 or
the error it failed with (eERR_AXIS_DRIVE_HOME_TOUT 0x83XX0424 after the timeout,
eERR_AXIS_DRIVE_HOME_FAILED 0x83XX042E when the machine lacks the switch or index, a
limit switch is in the way, or the axis is stopped or disabled meanwhile); the manual's
example 20.1.1 tests IsHoming right after MoveHome returns. Other tasks see IsHoming 1
meanwhile. Refusals use the codes of the axis functions (not enabled 0x83XX0078, moving
0x83XX0082, bad parameter 0x83XX012C ...), a bad axis id eERR_HMPL_ARG_OUT_OF_RANGE.
Units: mm or deg, mm/s, mm/s^2; the timeout in ms. Semantics: `motionvm.motion.homing`.
"""

from __future__ import annotations

from motionvm.lang.hmpl.lib.axis_base import AxisLibrary
from motionvm.lang.hmpl.lib.base import builtin
from motionvm.motion import axis_status as st
from motionvm.motion.homing import homing_of


class HomingLib(AxisLibrary):
    """Chapter 20: MoveHome, SetHomeMethod ... SetHomeTimeout, IsHomed, IsHoming, SetHomedStatus."""

    def _target(self, a):
        return homing_of(a)

    @builtin(blocking=True)
    def MoveHome(self, axis_id: int):
        code = self._do(axis_id, "start")
        if code:
            return code
        h = homing_of(self.rt.controller.motion.axes[axis_id])
        while h.running:
            yield None
        return st.axis_error(h.error, axis_id) if h.error else 0

    @builtin()
    def SetHomeMethod(self, axis_id: int, method: int) -> int:
        return self._do(axis_id, "set_method", method)

    @builtin()
    def SetHomeSwitchVel(self, axis_id: int, fast_vel: float) -> int:
        return self._do(axis_id, "set_switch_vel", fast_vel)

    @builtin()
    def SetHomeZeroVel(self, axis_id: int, slow_vel: float) -> int:
        return self._do(axis_id, "set_zero_vel", slow_vel)

    @builtin()
    def SetHomeAcc(self, axis_id: int, acc: float) -> int:
        return self._do(axis_id, "set_acc", acc)

    @builtin()
    def SetHomeOffset(self, axis_id: int, offset: float) -> int:
        return self._do(axis_id, "set_offset", offset)

    @builtin()
    def SetHomeTimeout(self, axis_id: int, timeout: int) -> int:
        return self._do(axis_id, "set_timeout", float(timeout))

    @builtin()
    def IsHomed(self, axis_id: int) -> int:
        a = self._axis(axis_id)
        return 1 if a is not None and homing_of(a).homed else 0

    @builtin()
    def IsHoming(self, axis_id: int) -> int:
        a = self._axis(axis_id)
        return 1 if a is not None and homing_of(a).homing else 0

    @builtin()
    def SetHomedStatus(self, axis_id: int, is_homed: int) -> int:
        return self._do(axis_id, "set_homed", is_homed)
