"""Chapter 6, the electronic gear, and chapter 7, gantry pairs.

EnableGear couples a slave to a master, GearIn engages it at a ratio, GearOut
disengages it, DisableGear uncouples; the status functions ask about each state
(behaviour: `motionvm.motion.gear`). EnableGantryPair pairs two disabled axes,
DisableGantryPair separates them (behaviour: `motionvm.motion.gantry`; IsGantry, 5.4.5,
is an axis status function). A function that fails returns the manual's axis error
(0x83XXCCCC with XX the axis the error belongs to, as a C int) and stores it as that
axis's last error; a bad axis id returns eERR_HMPL_ARG_OUT_OF_RANGE (0x138F) and stores
it as the system's last error. Queries of a bad axis id return 0 and store the same;
GetGantryPairID of a bad axis id returns -1.
"""

from __future__ import annotations

from motionvm.motion import axis_status as st
from motionvm.motion.commands.base import CommandBase


class GearCommands(CommandBase):
    """Chapter 6: EnableGear ... IsGearSlave."""

    def _gear_command(self, name: str, *ids: int, args: tuple = ()) -> int:
        axes = self._axes(*ids)
        if axes is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        return self._run(axes[-1], getattr(self.motion.gears, name), *axes, *args)

    def _gear_query(self, name: str, axis_id: int):
        if self._axes(axis_id) is None:
            return 0
        return getattr(self.motion.gears, name)(axis_id)

    def EnableGear(self, axis_master_id: int, axis_slave_id: int) -> int:
        return self._gear_command("enable_gear", axis_master_id, axis_slave_id)

    def DisableGear(self, axis_slave_id: int) -> int:
        return self._gear_command("disable_gear", axis_slave_id)

    def GearIn(self, axis_master_id: int, axis_slave_id: int, gear_ratio: float) -> int:
        return self._gear_command("gear_in", axis_master_id, axis_slave_id, args=(gear_ratio,))

    def GearOut(self, axis_slave_id: int) -> int:
        return self._gear_command("gear_out", axis_slave_id)

    def GetGearRatio(self, axis_slave_id: int) -> float:
        return float(self._gear_query("ratio", axis_slave_id))

    def IsInGear(self, axis_id: int) -> int:
        return 1 if self._gear_query("is_in_gear", axis_id) else 0

    def IsGearMaster(self, axis_id: int) -> int:
        return 1 if self._gear_query("is_master", axis_id) else 0

    def IsGearSlave(self, axis_id: int) -> int:
        return 1 if self._gear_query("is_slave", axis_id) else 0


class GantryCommands(CommandBase):
    """Chapter 7: EnableGantryPair, DisableGantryPair, GetGantryPairID, IsGantryPair."""

    def EnableGantryPair(self, rhs_axis_id: int, lhs_axis_id: int) -> int:
        axes = self._axes(rhs_axis_id, lhs_axis_id)
        if axes is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        return self._run(axes[0], self.motion.gantries.enable_pair, *axes)

    def DisableGantryPair(self, axis_id: int) -> int:
        axes = self._axes(axis_id)
        if axes is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        return self._run(axes[0], self.motion.gantries.disable_pair, *axes)

    def GetGantryPairID(self, axis_id: int) -> int:
        if self._axes(axis_id) is None:
            return -1
        return self.motion.gantries.pair_id(axis_id)

    def IsGantryPair(self, axis_id_1: int, axis_id_2: int) -> int:
        if self._axes(axis_id_1, axis_id_2) is None:
            return 0
        return 1 if self.motion.gantries.is_pair(axis_id_1, axis_id_2) else 0
