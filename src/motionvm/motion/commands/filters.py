"""Chapter 15, filters: VSF and InShape of an axis, InShape of an axis group.

The axis functions act on the axis's `AxisFilters` (motion/axis_filters.py: the filter
math, where a filter sits in the command path, the manual's refusals). A refused call
returns the axis error (0x83XXCCCC as a C int) and stores it as the axis's last error:
eERR_AXIS_CMD_INVALID_MOVING while the axis moves (Set*, Enable* and, as the reference
would jump, Disable*), eERR_AXIS_FREQUENCY_LIMIT / eERR_AXIS_DAMPINGRATIO_LIMIT for a
parameter out of the manual's range (or a frequency too high for the controller cycle),
eERR_AXIS_CMD_INVALID_PARAMETER for a shaper type other than 0 or 1, and
eERR_AXIS_CMD_INVALID_INPUTSHAPING_ENABLED for VSF and InShape together (15.1).

The group functions keep each group's InShape settings (`MotionKernel.group_inshape`,
one `InShapeSettings` per group id) with the manual's checks: a bad group id is
eERR_HMPL_ARG_OUT_OF_RANGE (system); a frequency outside 3..300 Hz (or too high for the
cycle) eERR_CRD_CMD_INVALID_FREQUENCY, a damping ratio outside 0..0.3
eERR_CRD_CMD_INVALID_DAMPINGRATIO, a shaper type other than 0 or 1
eERR_CRD_CMD_INVALID_INPUTSHAPING_PARAMETER_INCOMPLETE, each stored as the group's last
error. While the group moves, each of the three is refused with
eERR_CRD_CMD_INVALID_MOVING (15.8, 15.10: not while the motors move; Disable too, as
the reference would jump). Enabled, the group's planner shapes its commanded pose with
a `GroupShaper` (motion/group_inshape.py) made from them, one `ShaperState` per
coordinate; the settings, and the switch, hold across DisableGroup and EnableGroup.
"""

from __future__ import annotations

import math

from motionvm.motion import axis_status as st
from motionvm.motion import group as grp
from motionvm.motion import group_inshape, inshape
from motionvm.motion.commands.base import CommandBase
from motionvm.motion.group_checks import GRP_INSHAPE_DAMPING, GRP_INSHAPE_FREQUENCY


class FilterCommands(CommandBase):
    """Chapter 15: EnableAxisVsf ... SetGrpInShape."""

    def _filter_command(self, axis_id: int, method: str, *args) -> int:
        a = self._axis(axis_id)
        if a is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        if a.controlled_by is not None:  # a PDL program or a GDL motor owns the axis
            return self._fail(a, st.CMD_INVALID_CONTROL_MODE)
        return self._run(a, getattr(a.filters, method), *args)

    # ------------------------------------------------------------ axis VSF (15.2-15.4)

    def EnableAxisVsf(self, axis_id: int) -> int:
        return self._filter_command(axis_id, "enable_vsf")

    def DisableAxisVsf(self, axis_id: int) -> int:
        return self._filter_command(axis_id, "disable_vsf")

    def SetAxisVsf(self, axis_id: int, frequency: float, damping_ratio: float) -> int:
        return self._filter_command(axis_id, "set_vsf", frequency, damping_ratio)

    # ------------------------------------------------------------ axis InShape (15.5-15.7)

    def EnableAxisInShape(self, axis_id: int) -> int:
        return self._filter_command(axis_id, "enable_inshape")

    def DisableAxisInShape(self, axis_id: int) -> int:
        return self._filter_command(axis_id, "disable_inshape")

    def SetAxisInShape(
        self, axis_id: int, frequency: float, damping_ratio: float, shaper_type: int
    ) -> int:
        return self._filter_command(axis_id, "set_inshape", frequency, damping_ratio, shaper_type)

    # ------------------------------------------------------------ group InShape (15.8-15.10)

    def _group_inshape(self, group_id: int) -> inshape.InShapeSettings | None:
        shapers = self.motion.group_inshape
        if not 0 <= group_id < len(shapers):
            self._bad_id()
            return None
        return shapers[group_id]

    def _group_fail(self, group_id: int, code: int) -> int:
        self.motion.group_last_error[group_id] = err = st.group_error(code, group_id)
        return err

    def _grp_moving(self, group_id: int) -> bool:
        g = self.motion.groups.get(group_id)
        return g is not None and g.moving

    def _apply_group_inshape(self, group_id: int) -> None:
        group_inshape.install(self.motion, group_id)

    def _set_group_inshape(self, group_id: int, enabled: bool) -> int:
        s = self._group_inshape(group_id)
        if s is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        if self._grp_moving(group_id):  # the reference would jump or vibrate
            return self._group_fail(group_id, grp.CRD_INVALID_MOVING)
        s.enabled = enabled
        self._apply_group_inshape(group_id)
        return 0

    def EnableGrpInShape(self, group_id: int) -> int:
        return self._set_group_inshape(group_id, True)

    def DisableGrpInShape(self, group_id: int) -> int:
        return self._set_group_inshape(group_id, False)

    def SetGrpInShape(
        self, group_id: int, frequency: float, damping_ratio: float, shaper_type: int
    ) -> int:
        s = self._group_inshape(group_id)
        if s is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        if self._grp_moving(group_id):
            return self._group_fail(group_id, grp.CRD_INVALID_MOVING)
        lo, hi = GRP_INSHAPE_FREQUENCY
        if not (math.isfinite(frequency) and lo <= frequency <= hi):
            return self._group_fail(group_id, st.CRD_INVALID_FREQUENCY)
        lo, hi = GRP_INSHAPE_DAMPING
        if not (math.isfinite(damping_ratio) and lo <= damping_ratio <= hi):
            return self._group_fail(group_id, st.CRD_INVALID_DAMPINGRATIO)
        if shaper_type not in inshape.SHAPER_TYPES:
            return self._group_fail(group_id, st.CRD_INVALID_INPUTSHAPING_PARAMETER_INCOMPLETE)
        try:
            inshape.design(frequency, damping_ratio, shaper_type, self.motion.dt)
        except inshape.ShaperDesignError:
            return self._group_fail(group_id, st.CRD_INVALID_FREQUENCY)
        s.frequency, s.damping, s.shaper_type = frequency, damping_ratio, shaper_type
        self._apply_group_inshape(group_id)
        return 0
