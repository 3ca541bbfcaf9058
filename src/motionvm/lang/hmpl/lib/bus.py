"""HMPL system functions of manual chapter 2 that concern the bus and every axis.

IsSystemInit/PreOp/Oper follow the simulated EtherCAT master (`MotionKernel.ecat_state`:
Operation from power-on; ScanNetwork takes it through Init, Pre-Op and Safe-Op, one
cycle each). IsSystemError is 1 after EStop. Slaves are the axes' drives, slave i
being axis i's. DisableAll and StopAll clear the axes' path planning (StopAll brakes at
each axis's kill deceleration and keeps it enabled); EStop disables every axis and
stops every task, the calling one included. SetHMIScope sets `controller.hmi_scope`
(and `hmi_scope_used`); a `--scope` recording then keeps only the cycles it was on.
"""

from __future__ import annotations

from motionvm.lang.hmpl.lib.base import Library, builtin
from motionvm.motion import axis_status as st
from motionvm.motion.kernel import ECAT_INIT, ECAT_OP, ECAT_PREOP
from motionvm.runtime.errors import TaskExit


class BusLib(Library):
    """Chapter 2.1-2.10, 2.15, 2.16."""

    @property
    def _motion(self):
        return self.rt.controller.motion

    @builtin()
    def IsSystemInit(self) -> int:
        return 1 if self._motion.ecat_state == ECAT_INIT else 0

    @builtin()
    def IsSystemPreOp(self) -> int:
        return 1 if self._motion.ecat_state == ECAT_PREOP else 0

    @builtin()
    def IsSystemOper(self) -> int:
        return 1 if self._motion.ecat_state == ECAT_OP and not self._motion.estopped else 0

    @builtin()
    def IsSystemError(self) -> int:
        return 1 if self._motion.estopped else 0

    @builtin()
    def GetECATSt(self) -> int:
        return self._motion.ecat_state

    @builtin()
    def GetSlvECATSt(self, slv_id: int) -> int:
        state = self._motion.slave_state(slv_id)
        if state == 0:
            self._motion.system_last_error = st.SYS_HMPL_ARG_OUT_OF_RANGE
        return state

    @builtin()
    def GetSlaveNum(self) -> int:
        return self._motion.n_axes

    @builtin()
    def ScanNetwork(self) -> int:
        return self._motion.scan_network()

    @builtin()
    def DisableAll(self) -> int:
        self._motion.disable_all()
        return 0

    @builtin()
    def StopAll(self) -> int:
        self._motion.stop_all()
        return 0

    @builtin()
    def EStop(self) -> None:
        self._motion.estop()
        if self.rt.kernel.stop_all():
            raise TaskExit()

    @builtin()
    def SetHMIScope(self, start: int) -> int:
        controller = self.rt.controller
        controller.hmi_scope = bool(start)
        controller.hmi_scope_used = True  # a --scope recording then follows it (sim/scope.py)
        return 0
