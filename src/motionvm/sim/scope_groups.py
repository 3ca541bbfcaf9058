"""Scope channels of the axis groups: the group variables of manual 8.1.1.

`groupN.<variable>` for a scalar (`group0.grp_pg_vel` [mm/s], `group0.grp_motion_status`
[raw]) and `groupN.<variable>[i]` for an element of an array: the Cartesian arrays
(`carte_pose_cmd`, `carte_vel_cmd`, `carte_pose_fb`, `carte_pose_err`) have the six
elements X, Y, Z, A, B, C, the joint arrays (`joint_pos_cmd` ...) one per axis slot of a
group (9); an element the group has no axis for reads 0, as does a group without axes.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable

from motionvm.motion.group import (
    ARRAY_VARIABLES,
    CARTESIAN_ARRAYS,
    MAX_AXES,
    SCALAR_VARIABLES,
    group_variable,
)
from motionvm.sim.scope import RAW_UNIT, ChannelSource, ScopeError

_GROUP = re.compile(r"group(\d+)\.(\w+)(?:\[(\d+)\])?")
_UNITS = {
    "grp_pg_pos": "mm", "grp_pg_vel": "mm/s", "grp_pg_acc": "mm/s²",
    "grp_lin_vel": "mm/s", "grp_lin_acc": "mm/s²", "grp_lin_dec": "mm/s²", "grp_lin_sf": "ms",
    "grp_ang_vel": "deg/s", "grp_ang_acc": "deg/s²", "grp_ang_dec": "deg/s²", "grp_ang_sf": "ms",
    "carte_pose_cmd": "mm", "carte_pose_fb": "mm", "carte_pose_err": "mm", "carte_vel_cmd": "mm/s",
    "joint_pos_cmd": "mm", "joint_pos_fb": "mm", "joint_vel_cmd": "mm/s", "joint_acc_cmd": "mm/s²",
}  # fmt: skip


class GroupScopeSource(ChannelSource):
    """`groupN.*` channels of the groups of a controller's motion kernel (`controller.motion`)."""

    def __init__(self, controller) -> None:
        self.controller = controller

    def _size(self, variable: str) -> int:
        return 6 if variable in CARTESIAN_ARRAYS else MAX_AXES

    def resolve(self, name: str) -> tuple[Callable[[], float], str] | None:
        m = _GROUP.fullmatch(name)
        if m is None:
            return None
        groups = self.controller.motion.groups
        n, variable, index = int(m.group(1)), m.group(2), m.group(3)
        if n >= len(groups):
            raise ScopeError(
                f"scope channel '{name}': no axis group {n} (groups: group0..group{len(groups) - 1})"
            )
        if variable in SCALAR_VARIABLES:
            if index is not None:
                raise ScopeError(f"scope channel '{name}': {variable} is not an array")
            g = groups[n]
            return (lambda: group_variable(g, variable)), _UNITS.get(variable, RAW_UNIT)
        if variable in ARRAY_VARIABLES:
            size = self._size(variable)
            if index is None or int(index) >= size:
                raise ScopeError(f"scope channel '{name}': {variable} is an array; record one element, "
                                 f"group{n}.{variable}[0] .. group{n}.{variable}[{size - 1}]")  # fmt: skip
            g, i = groups[n], int(index)
            unit = _UNITS[variable]
            if variable in CARTESIAN_ARRAYS and i >= 3:
                unit = unit.replace("mm", "deg")
            return (lambda: group_variable(g, variable, i)), unit
        known = ", ".join((*SCALAR_VARIABLES, *ARRAY_VARIABLES))
        raise ScopeError(f"unknown scope channel '{name}'; group variables are: {known}")

    def channel_names(self) -> Iterable[str]:
        for n in range(len(self.controller.motion.groups)):
            yield from (f"group{n}.{v}" for v in SCALAR_VARIABLES)
            for v in ARRAY_VARIABLES:
                yield from (f"group{n}.{v}[{i}]" for i in range(self._size(v)))
