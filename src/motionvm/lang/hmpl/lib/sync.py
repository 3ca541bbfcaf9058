"""HMPL synchronous motion functions of manual chapter 6: the electronic gear.

Each is the motion command of its name (`motionvm.motion.commands.sync`: errors and
their codes); the behaviour (ramps, order of master and slave, decisions where the
manual is silent) is in `motionvm.motion.gear`. The variables of table 6.1.1.1 and the
gantry's linear/yaw values are scope channels (`SyncScopeSource`, sim/scope_sources.py).
"""

from __future__ import annotations

from motionvm.lang.hmpl.lib.base import Library, command
from motionvm.sim.scope_sources import SyncScopeSource

__all__ = ["SyncLib", "SyncScopeSource"]


class SyncLib(Library):
    """Chapter 6: EnableGear ... IsGearSlave."""

    EnableGear = command()
    DisableGear = command()
    GearIn = command()
    GearOut = command()
    GetGearRatio = command()
    IsInGear = command()
    IsGearMaster = command()
    IsGearSlave = command()
