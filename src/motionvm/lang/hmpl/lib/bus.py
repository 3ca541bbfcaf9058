"""HMPL system functions of manual chapter 2 that concern the bus and every axis.

The bus and axis functions are the motion commands of their names
(`motionvm.motion.commands.system`). EStop also stops every task, the calling one
included. SetHMIScope sets `controller.hmi_scope` (and `hmi_scope_used`); a `--scope`
recording then keeps only the cycles it was on.
"""

from __future__ import annotations

from motionvm.lang.hmpl.lib.base import Library, builtin, command
from motionvm.runtime.errors import TaskExit


class BusLib(Library):
    """Chapter 2.1-2.10, 2.15, 2.16."""

    IsSystemInit = command()
    IsSystemPreOp = command()
    IsSystemOper = command()
    IsSystemError = command()
    GetECATSt = command()
    GetSlvECATSt = command()
    GetSlaveNum = command()
    ScanNetwork = command()
    DisableAll = command()
    StopAll = command()

    @builtin()
    def EStop(self) -> None:
        self.rt.commands.EStop()
        if self.rt.kernel.stop_all():
            raise TaskExit()

    @builtin()
    def SetHMIScope(self, start: int) -> int:
        controller = self.rt.controller
        controller.hmi_scope = bool(start)
        controller.hmi_scope_used = True  # a --scope recording then follows it (sim/scope.py)
        return 0
