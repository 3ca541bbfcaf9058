"""HMPL gantry functions of manual chapter 7: EnableGantryPair ... IsGantryPair.

The pair, its linear/yaw transform and its enable sequence are in
`motionvm.motion.gantry`; IsGantry (5.4.5) is an axis status function (lib/axis.py,
motion_status bit 5). The pairs step once per cycle before the tasks: the first
EnableGantryPair of a program hooks them into the controller's cycle. Errors are
returned and stored as in `motionvm.lang.hmpl.lib.sync`; GetGantryPairID of a bad
axis id returns -1.
"""

from __future__ import annotations

from motionvm.lang.hmpl.lib.base import Library, builtin
from motionvm.lang.hmpl.lib.sync import SyncCalls
from motionvm.motion import axis_status as st
from motionvm.motion.gantry import gantries_of
from motionvm.runtime.clients import PassiveClient


class _GantryCycle(PassiveClient):
    """A controller cycle client: steps the gantry pairs before the tasks run."""

    def __init__(self, controller):
        self.controller = controller

    def begin_cycle(self) -> None:
        gantries_of(self.controller.motion).step()


class GantryLib(SyncCalls, Library):
    """Chapter 7: EnableGantryPair, DisableGantryPair, GetGantryPairID, IsGantryPair."""

    @property
    def _pairs(self):
        return gantries_of(self._motion)

    def _hook(self) -> None:
        clients = self.rt.controller.clients
        if not any(isinstance(c, _GantryCycle) for c in clients):
            clients.append(_GantryCycle(self.rt.controller))

    @builtin()
    def EnableGantryPair(self, rhs_axis_id: int, lhs_axis_id: int) -> int:
        axes = self._axes(rhs_axis_id, lhs_axis_id)
        if axes is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        self._hook()
        return self._call(self._pairs.enable_pair, *axes)

    @builtin()
    def DisableGantryPair(self, axis_id: int) -> int:
        axes = self._axes(axis_id)
        if axes is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        return self._call(self._pairs.disable_pair, *axes)

    @builtin()
    def GetGantryPairID(self, axis_id: int) -> int:
        if self._axes(axis_id) is None:
            return -1
        return self._pairs.pair_id(axis_id)

    @builtin()
    def IsGantryPair(self, axis_id_1: int, axis_id_2: int) -> int:
        if self._axes(axis_id_1, axis_id_2) is None:
            return 0
        return 1 if self._pairs.is_pair(axis_id_1, axis_id_2) else 0
