"""HMPL filter functions of manual chapter 15: VSF and InShape of axes and groups.

Each is the motion command of its name (`motionvm.motion.commands.filters`: checks and
error codes); the filter math is `motionvm.motion.inshape` and `motionvm.motion.vsf`,
their place in the axis's command path `motionvm.motion.axis_filters`.
"""

from __future__ import annotations

from motionvm.lang.hmpl.lib.base import Library, command


class FilterLib(Library):
    """Chapter 15: EnableAxisVsf ... SetGrpInShape."""

    EnableAxisVsf = command()
    DisableAxisVsf = command()
    SetAxisVsf = command()
    EnableAxisInShape = command()
    DisableAxisInShape = command()
    SetAxisInShape = command()
    EnableGrpInShape = command()
    DisableGrpInShape = command()
    SetGrpInShape = command()
