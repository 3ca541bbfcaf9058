"""HMPL error functions of manual chapter 18: last errors of the system, axes and groups.

Each is the motion command of its name (`motionvm.motion.commands.system`, which
documents the codes). Codes come back as C ints, so an axis or group code is negative
(print it with "%x").
"""

from __future__ import annotations

from motionvm.lang.hmpl.lib.base import Library, command


class ErrorLib(Library):
    """Chapter 18: GetSystemLastErr ... GetDriveErr."""

    GetSystemLastErr = command()
    GetAxisLastErr = command()
    ClearAxisLastErr = command()
    GetGrpLastErr = command()
    ClearGrpLastErr = command()
    GetDriveErr = command()
