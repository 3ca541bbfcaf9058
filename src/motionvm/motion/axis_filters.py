"""An axis's command path after its profile: VSF or InShape (manual 15), error compensation (14).

    profile / PVT / stop ramp --> [VSF | InShape] --> ref_pos --(+ compensation)--> pos_out

Each axis owns one `AxisFilters` (`Axis.filters`): the filters' and the compensation's
settings, and while any of them is on, the streaming state that the axis's cycle calls
once per cycle (`Axis._cmd_path` is then this object; None otherwise, so an axis with
nothing on pays one attribute test per cycle).

Filters. The filtered reference *is* the axis's reference (`ref_pos`, `ref_vel`,
`ref_acc`): like the smooth time, a filter is part of the trajectory the controller
plans (15.1: "filters add path planning time and shorten the settling time"), so the axis
is `moving` until the filter's output has caught up (`pending`), GetMoveTime includes
the shaper's length, and in-position and the position error compare the feedback with
the filtered reference. A filter acts on the axis's own motion (profile moves, PVT, the
stop ramps) and not on a reference an axis follows (group, gear, gantry, homing: 15.1,
"axis InShape has no effect on coordinated motion"); while the axis follows one, the
filter rests at the followed reference. Whenever something else re-seeds the reference
(enable, SetPos, the end of a follow), the filter starts over from there, at rest.

Compensation. While compensation is active and the axis is enabled, the value of the
error map at the reference axes' reference positions is added to the position sent to
the drive (14.1: reference position + position compensation = position output), as a
time-varying part of the position offset: the drive's position is
`ref_pos + comp + pos_offset`, and the feedback in axis coordinates (`pos_fb`,
GetPosFb) is the drive's position minus both, so it compares with `ref_pos` as without
compensation; GetPosFbComp adds the compensation back (the drive's own position). A
reference axis other than the compensated one is read as it stands when the compensated
axis steps (axes step by id: a higher id gives the previous cycle's value). While the
axis is disabled no compensation is sent (GetCompPos 0): enabling it moves the motor by
the compensation at its position (14.1: "enable the axis to start compensating").
A value beyond the limit (1 mm by default) at run time (a spline overshooting its
points) stops the axis at its kill deceleration in error stop with eERR_AXIS_COMP_LIMIT,
the compensation held at the limit.
"""

from __future__ import annotations

import math

from motionvm.motion import axis_status as st
from motionvm.motion import inshape, vsf
from motionvm.motion.axis_cycle import EXT, TORQUE, AxisCycle
from motionvm.motion.axis_status import AxisCommandError
from motionvm.motion.compensation import ALG_LINEAR, ALG_SPLINE, COMP_LIMIT, ErrorMap

INSHAPE_FREQUENCY = (1.5, 300.0)
"""[Hz] SetAxisInShape's frequency range (15.7)."""
INSHAPE_DAMPING = (0.0, 0.3)
VSF_FREQUENCY = (0.1, 200.0)
"""[Hz] SetAxisVsf's frequency range (15.4)."""
VSF_DAMPING = (0.7, 1.5)


def _in(value: float, bounds: tuple[float, float]) -> bool:
    return math.isfinite(value) and bounds[0] <= value <= bounds[1]


class AxisFilters:
    """Filters and compensation of one axis: settings, and their state while on."""

    __slots__ = (
        "_filter", "_refs", "axis", "comp_alg", "comp_limit", "comp_map", "comp_on", "comp_ref_ids",
        "inshape", "vsf",
    )  # fmt: skip

    def __init__(self, axis: AxisCycle) -> None:
        self.axis = axis
        self.inshape = inshape.InShapeSettings()
        self.vsf = vsf.VsfSettings()
        self._filter: inshape.ShaperState | vsf.VsfState | None = None
        self.comp_map: ErrorMap | None = None
        """The error map of SetupComp*, None before (or after DisableComp)."""
        self.comp_ref_ids: tuple[int, ...] = ()
        """The reference axes of `comp_map`, one per dimension."""
        self.comp_alg = ALG_LINEAR
        self.comp_limit = COMP_LIMIT
        """[mm or deg] The largest compensation the axis accepts (HCV_ID_max_comp_lim)."""
        self.comp_on = False
        self._refs: tuple[AxisCycle, ...] = ()

    # ---- the cycle ------------------------------------------------------------------

    def step(self, axis: AxisCycle, p: float, v: float, a: float) -> tuple[float, float, float]:
        """This cycle's reference through the filter; the compensation set on the axis."""
        f = self._filter
        if f is not None:
            if axis._reference_source in (EXT, TORQUE):  # followed or torque: unfiltered
                if f.last_out[0] != p or f.pending:
                    f.reset(p)
            else:
                if axis.ref_pos != f.last_out[0]:  # re-seeded since the last cycle
                    f.reset(axis.ref_pos)
                p, v, a = f.step(p, v, a)
        if self.comp_on:
            self._compensate(axis, p)
        return p, v, a

    def _compensate(self, axis: AxisCycle, p: float) -> None:
        c = self.comp_map.value([p if r is axis else r.ref_pos for r in self._refs])
        lim = self.comp_limit
        if not -lim <= c <= lim:
            c = math.copysign(lim, c)
            if not axis.error_stop:
                axis._limit_stop(st.COMP_LIMIT, 0)
        axis._set_comp(c)

    @property
    def pending(self) -> bool:
        """True while the filter's output has not caught up with a resting reference."""
        f = self._filter
        return f is not None and f.pending

    @property
    def unfiltered_pos(self) -> float:
        """[mm] The reference before the filter (where the plan is), as of the last cycle."""
        f = self._filter
        return self.axis.ref_pos if f is None else f.last_in[0]

    def may_rest(self) -> bool:
        """False while a reference axis of the compensation is active (it moves the map)."""
        axis = self.axis
        return all(r.resting or r is axis for r in self._refs)

    def dropped(self) -> None:
        """The axis was disabled: no compensation is sent, the filter starts over."""
        axis = self.axis
        if self._filter is not None:
            self._filter.reset(axis.pos_fb_raw - axis.pos_offset)
        axis._set_comp(0.0)

    def _update_path(self) -> None:
        axis = self.axis
        on = self._filter is not None or self.comp_on
        axis._cmd_path = self if on else None
        bits = (st.MS_INPUT_SHAPE if self.inshape.enabled else 0) | (
            st.MS_VSF if self.vsf.enabled else 0
        )
        axis.extra_status = (axis.extra_status & ~(st.MS_INPUT_SHAPE | st.MS_VSF)) | bits

    # ---- filters (15.2-15.7) --------------------------------------------------------

    def _require_still(self) -> None:
        axis = self.axis
        axis.wake()
        if axis.moving:
            raise AxisCommandError(st.CMD_INVALID_MOVING, f"axis {axis.axis_id} is moving")

    def _start_filter(self) -> None:
        """The filter of the settings that are on, at rest at the current reference."""
        axis = self.axis
        if self.inshape.enabled:
            s = self.inshape
            shaper = inshape.design(s.frequency, s.damping, s.shaper_type, axis.dt)
            self._filter = inshape.ShaperState(shaper, axis.ref_pos)
        elif self.vsf.enabled:
            notch = vsf.design(self.vsf.frequency, self.vsf.damping, axis.dt)
            self._filter = vsf.VsfState(notch, axis.ref_pos, axis.dt)
        else:
            self._filter = None
        self._update_path()

    def _check_frequency(self, freq: float, damping: float, shaper_type: int | None) -> None:
        axis = self.axis
        try:
            if shaper_type is None:
                vsf.design(freq, damping, axis.dt)
            else:
                inshape.design(freq, damping, shaper_type, axis.dt)
        except ValueError as exc:
            raise AxisCommandError(st.FREQUENCY_LIMIT, f"axis {axis.axis_id}: {exc}") from None

    def set_inshape(self, frequency: float, damping: float, shaper_type: int) -> None:
        """SetAxisInShape: frequency [Hz] 1.5..300, damping 0..0.3, type 0 or 1."""
        self._require_still()
        aid = self.axis.axis_id
        if not _in(frequency, INSHAPE_FREQUENCY):
            raise AxisCommandError(
                st.FREQUENCY_LIMIT, f"axis {aid}: frequency {frequency!r} Hz is not in 1.5..300"
            )
        if not _in(damping, INSHAPE_DAMPING):
            raise AxisCommandError(
                st.DAMPINGRATIO_LIMIT, f"axis {aid}: damping ratio {damping!r} is not in 0..0.3"
            )
        if shaper_type not in inshape.SHAPER_TYPES:
            raise AxisCommandError(
                st.CMD_INVALID_PARAMETER, f"axis {aid}: shaper type {shaper_type} is not 0 or 1"
            )
        self._check_frequency(frequency, damping, shaper_type)
        s = self.inshape
        s.frequency, s.damping, s.shaper_type = frequency, damping, shaper_type
        if s.enabled:
            self._start_filter()

    def set_vsf(self, frequency: float, damping: float) -> None:
        """SetAxisVsf: frequency [Hz] 0.1..200, damping 0.7..1.5."""
        self._require_still()
        aid = self.axis.axis_id
        if not _in(frequency, VSF_FREQUENCY):
            raise AxisCommandError(
                st.FREQUENCY_LIMIT, f"axis {aid}: frequency {frequency!r} Hz is not in 0.1..200"
            )
        if not _in(damping, VSF_DAMPING):
            raise AxisCommandError(
                st.DAMPINGRATIO_LIMIT, f"axis {aid}: damping ratio {damping!r} is not in 0.7..1.5"
            )
        self._check_frequency(frequency, damping, None)
        self.vsf.frequency, self.vsf.damping = frequency, damping
        if self.vsf.enabled:
            self._start_filter()

    def enable_inshape(self) -> None:
        """EnableAxisInShape; refused while VSF is on (15.1: not both)."""
        self._require_still()
        if self.vsf.enabled:
            raise AxisCommandError(
                st.CMD_INVALID_INPUTSHAPING_ENABLED,
                f"axis {self.axis.axis_id}: VSF is on (VSF and InShape exclude each other)",
            )
        s = self.inshape
        self._check_frequency(s.frequency, s.damping, s.shaper_type)
        s.enabled = True
        self._start_filter()

    def enable_vsf(self) -> None:
        """EnableAxisVsf; refused while InShape is on (15.1: not both)."""
        self._require_still()
        if self.inshape.enabled:
            raise AxisCommandError(
                st.CMD_INVALID_INPUTSHAPING_ENABLED,
                f"axis {self.axis.axis_id}: InShape is on (VSF and InShape exclude each other)",
            )
        self._check_frequency(self.vsf.frequency, self.vsf.damping, None)
        self.vsf.enabled = True
        self._start_filter()

    def disable_inshape(self) -> None:
        """DisableAxisInShape; not while moving (the reference would jump)."""
        self._require_still()
        self.inshape.enabled = False
        self._start_filter()

    def disable_vsf(self) -> None:
        """DisableAxisVsf; not while moving (the reference would jump)."""
        self._require_still()
        self.vsf.enabled = False
        self._start_filter()

    # ---- compensation (14.2-14.8) ---------------------------------------------------

    def _require_disabled(self) -> None:
        axis = self.axis
        axis.wake()
        if axis.enabled or axis._enabling:
            raise AxisCommandError(st.CMD_INVALID_ENABLED, f"axis {axis.axis_id} is enabled")

    def setup_comp(self, error_map: ErrorMap, ref_ids: tuple[int, ...]) -> None:
        """SetupComp*: keep `error_map` of reference axes `ref_ids` for EnableComp;
        refused while compensation is on."""
        axis = self.axis
        axis.wake()
        if self.comp_on:
            raise AxisCommandError(
                st.CMD_INVALID_COMP_ENABLED, f"axis {axis.axis_id}: compensation is active"
            )
        worst = max(abs(x) for x in error_map.values)
        if worst > self.comp_limit:
            raise AxisCommandError(
                st.COMP_LIMIT,
                f"axis {axis.axis_id}: compensation value {worst:g} exceeds "
                f"the limit {self.comp_limit:g}",
            )
        self.comp_map = error_map
        self.comp_ref_ids = ref_ids

    def set_comp_alg(self, alg_type: int) -> None:
        """SetCompAlgType: 0 linear, 1 spline (not for a 3-D map); not while active."""
        axis = self.axis
        axis.wake()
        if alg_type not in (ALG_LINEAR, ALG_SPLINE):
            raise AxisCommandError(
                st.CMD_INVALID_PARAMETER, f"axis {axis.axis_id}: alg_type {alg_type} is not 0 or 1"
            )
        if self.comp_on:
            raise AxisCommandError(
                st.CMD_INVALID_COMP_ENABLED, f"axis {axis.axis_id}: compensation is active"
            )
        m = self.comp_map
        if m is not None and alg_type == ALG_SPLINE and m.dims == 3:
            raise AxisCommandError(
                st.CMD_INVALID_PARAMETER,
                f"axis {axis.axis_id}: 3-D compensation does not support spline interpolation",
            )
        self.comp_alg = alg_type
        if m is not None:
            self.comp_map = ErrorMap(m.base, m.interval, m.num_pt, m.values, alg_type)

    def enable_comp(self, refs: tuple[AxisCycle, ...]) -> None:
        """EnableComp with the reference axes of the map; only while the axis is disabled."""
        self._require_disabled()
        axis = self.axis
        if self.comp_map is None:
            raise AxisCommandError(
                st.COMP_NOT_CNFG, f"axis {axis.axis_id}: no compensation set up (SetupComp)"
            )
        if self.comp_on:
            return
        self._refs = refs
        self.comp_on = True
        for r in refs:
            if r is not axis:
                r._comp_dependents += (axis,)
        self._update_path()

    def disable_comp(self) -> None:
        """DisableComp: off, and the settings cleared; only while the axis is disabled."""
        self._require_disabled()
        axis = self.axis
        for r in self._refs:
            if r is not axis:
                deps = list(r._comp_dependents)
                deps.remove(axis)
                r._comp_dependents = tuple(deps)
        self._refs = ()
        self.comp_on = False
        self.comp_map = None
        self.comp_ref_ids = ()
        axis._set_comp(0.0)
        axis.ref_pos = axis.pos_fb
        self._update_path()

    @property
    def locks_origin(self) -> bool:
        """True while an active compensation fixes this axis's coordinates (14.1): it is
        compensated, or the reference axis of an active compensation."""
        return self.comp_on or bool(self.axis._comp_dependents)
