"""HMPL gantry functions of manual chapter 7: EnableGantryPair ... IsGantryPair.

Each is the motion command of its name (`motionvm.motion.commands.sync`); the pair,
its linear/yaw transform and its enable sequence are in `motionvm.motion.gantry`, and
the motion kernel steps the pairs once per cycle before the tasks. IsGantry (5.4.5) is
an axis status function (lib/axis.py, motion_status bit 5).
"""

from __future__ import annotations

from motionvm.lang.hmpl.lib.base import Library, command


class GantryLib(Library):
    """Chapter 7: EnableGantryPair, DisableGantryPair, GetGantryPairID, IsGantryPair."""

    EnableGantryPair = command()
    DisableGantryPair = command()
    GetGantryPairID = command()
    IsGantryPair = command()
