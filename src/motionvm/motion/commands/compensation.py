"""Chapter 14, dynamic error compensation: error maps of 1 to 3 reference axes.

SetupComp / SetupComp2D / SetupComp3D read the map's values from the User Table
(`user_table`: the front end's view of the controller's 512,000 doubles, any sequence
of floats) when they are called; later writes to the table do not change the map
(call DisableComp and SetupComp again). The map math is `motion.compensation`; where
the compensation enters the axis's command path, and the decisions where the manual
is silent, are `motion.axis_filters`.

Codes: a bad axis id (compensated or reference) is eERR_HMPL_ARG_OUT_OF_RANGE
(system); a bad map (interval <= 0, fewer than 2 points, a range beyond the User
Table, spline in 3-D) eERR_AXIS_CMD_INVALID_PARAMETER; a table value beyond the
compensation limit (1 mm) eERR_AXIS_COMP_LIMIT; SetupComp* or SetCompAlgType while
compensation is active eERR_AXIS_CMD_INVALID_COMP_ENABLED; EnableComp / DisableComp of
an enabled axis eERR_AXIS_CMD_INVALID_ENABLED (14.2, 14.3); EnableComp without a
map eERR_AXIS_COMP_NOT_CNFG; any of them on an axis a PDL program or GDL motor owns
eERR_AXIS_CMD_INVALID_CONTROL_MODE. Each is stored as the axis's last error.
"""

from __future__ import annotations

from collections.abc import Sequence

from motionvm.motion import axis_status as st
from motionvm.motion import compensation
from motionvm.motion.commands.base import CommandBase


def _setup_of_dims(dims: int, name: str):
    """SetupComp2D / SetupComp3D (and SetupComp's work): a map of `dims` reference axes,
    from the first `dims` entries of each array."""

    def setup(
        self,
        axis_id: int,
        start_idx: int,
        base_val: Sequence[float],
        interval: Sequence[float],
        num_pt: Sequence[int],
        ref_axis_id: Sequence[int],
        user_table: Sequence[float] = (),
    ) -> int:
        base_val, interval = base_val[:dims], interval[:dims]
        num_pt, ref_axis_id = num_pt[:dims], ref_axis_id[:dims]
        axes = self._axes(axis_id, *ref_axis_id)
        if axes is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        a = axes[0]
        if a.controlled_by is not None:
            return self._fail(a, st.CMD_INVALID_CONTROL_MODE)
        try:
            emap = compensation.build(
                base_val, interval, num_pt, start_idx, user_table, a.filters.comp_alg
            )
        except compensation.MapError:
            return self._fail(a, st.CMD_INVALID_PARAMETER)
        return self._run(a, a.filters.setup_comp, emap, tuple(ref_axis_id))

    setup.__name__ = name
    setup.__qualname__ = f"CompensationCommands.{name}"
    return setup


class CompensationCommands(CommandBase):
    """Chapter 14: EnableComp ... SetCompAlgType (and GetPosFbComp, IsCompActive of 5)."""

    _setup = _setup_of_dims(1, "_setup")

    def SetupComp(
        self,
        axis_id: int,
        start_idx: int,
        base_val: float,
        interval: float,
        num_pt: int,
        ref_axis_id: int,
        user_table: Sequence[float] = (),
    ) -> int:
        return self._setup(
            axis_id, start_idx, [base_val], [interval], [num_pt], [ref_axis_id], user_table
        )

    SetupComp2D = _setup_of_dims(2, "SetupComp2D")
    SetupComp3D = _setup_of_dims(3, "SetupComp3D")

    def _comp_command(self, axis_id: int, method: str, *args) -> int:
        a = self._axis(axis_id)
        if a is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        if a.controlled_by is not None:  # a PDL program or a GDL motor owns the axis
            return self._fail(a, st.CMD_INVALID_CONTROL_MODE)
        return self._run(a, getattr(a.filters, method), *args)

    def SetCompAlgType(self, axis_id: int, alg_type: int) -> int:
        return self._comp_command(axis_id, "set_comp_alg", alg_type)

    def EnableComp(self, axis_id: int) -> int:
        a = self._axis(axis_id)
        refs = () if a is None else tuple(self.motion.axes[i] for i in a.filters.comp_ref_ids)
        return self._comp_command(axis_id, "enable_comp", refs)

    def DisableComp(self, axis_id: int) -> int:
        return self._comp_command(axis_id, "disable_comp")

    def GetCompPos(self, axis_id: int) -> float:
        a = self._axis(axis_id)
        return 0.0 if a is None else a.comp_pos

    def GetPosFbComp(self, axis_id: int) -> float:
        """The feedback plus the compensation: the drive's own position in axis units."""
        a = self._axis(axis_id)
        return 0.0 if a is None else a._wrapped(a.pos_fb + a.comp_pos)

    def IsCompActive(self, axis_id: int) -> int:
        a = self._axis(axis_id)
        return 1 if a is not None and a.filters.comp_on else 0
