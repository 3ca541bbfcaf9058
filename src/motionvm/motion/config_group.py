"""The axis group variables of manual table 17.1.1.3 (0x82IIVVVV), bound to the axis
groups of a motion kernel: `register(table, kernel)`.

A write takes effect as the group's own setter would (SetGrpMotionProfile,
SetGrpBufferMode, SetGrpTransPrm, SetGrpVelScale, SetGrpInShape ...) with the same
checks; a value those refuse is eERR_HCV_VALUE_OUT_OF_RANGE. Decisions where the manual
is silent:
- num_axis: the number of axes in the group (read-only; AddAxisToGrp changes it).
- lin_*_lim, ang_*_lim: the largest profile values the group accepts (5000 mm/s,
  50000 mm/s^2; 7200 deg/s, 72000 deg/s^2), read-only.
- *_acc_time, *_dec_time [ms]: velocity / acceleration, as SetGrpAccTime sets them.
- *_sf [ms]: the smoothing time of the profile.
- coord_sys, buffer_mode, trans_mode: the codes of SetGrpCoordSys, SetGrpBufferMode,
  SetGrpTransMode; trans_vel, trans_dis, trans_dev, trans_curvature those of
  SetGrpTransPrm.
- shaper_fr, shaper_xi: the group InShape frequency [Hz] and damping ratio (15.10:
  3..300, 0..0.3; not while the group moves).
- last_err: the group's last error as the C int; writing 0 clears it.
"""

from __future__ import annotations

import math

from motionvm.motion import group as grp
from motionvm.motion import group_inshape, inshape
from motionvm.motion.config_vars import GROUP, ConfigVarTable, manual_ids
from motionvm.motion.group_checks import (
    GRP_INSHAPE_DAMPING,
    GRP_INSHAPE_FREQUENCY,
    check_bm,
    check_prm,
    check_profile,
    check_tm,
)
from motionvm.motion.group_coords import CS_ACS, CoordSystems

LIN_LIMITS = (5000.0, 50000.0, 50000.0)
ANG_LIMITS = (7200.0, 72000.0, 72000.0)


def _checked(fn, *args) -> None:
    """Run a group check; its refusal is a value out of range."""
    try:
        fn(*args)
    except grp.GroupError as exc:
        raise ValueError(str(exc)) from None


def register(table: ConfigVarTable, kernel) -> None:
    """Register every group variable of table 17.1.1.3 for the groups of `kernel`."""
    groups = kernel.groups
    table.add_family(GROUP, lambda i: groups.get(i) is not None)

    def profile(linear: bool, k: int):
        def get(i):
            g = groups[i]
            return float((g.lin if linear else g.ang).values()[k])

        def set_(i, v):
            g = groups[i]
            prof = g.lin if linear else g.ang
            merged = list(prof.values())
            merged[k] = float(v)
            _checked(lambda: check_profile(*merged, linear=linear))
            prof.vel, prof.acc, prof.dec, prof.sm_ms = merged
            if linear:
                g.planner.set_smoothing(prof.sm_ms / 1000.0)

        return get, set_

    def ramp_time(linear: bool, k: int):
        def get(i):
            prof = groups[i].lin if linear else groups[i].ang
            return prof.vel / prof.values()[k] * 1000.0

        def set_(i, ms):
            if not (math.isfinite(ms) and ms > 0.0):
                raise ValueError(f"{ms!r} ms is not a positive time")
            prof = groups[i].lin if linear else groups[i].ang
            profile(linear, k)[1](i, prof.vel / (ms / 1000.0))

        return get, set_

    def trans(k: int):
        def set_(i, v):
            prm = list(groups[i].trans_prm)
            prm[k] = float(v)
            _checked(check_prm, *prm)
            groups[i].trans_prm = prm

        return (lambda i: float(groups[i].trans_prm[k])), set_

    def code_set(attr, ok):
        def set_(i, v):
            if v != int(v) or not ok(int(v)):
                raise ValueError(f"{v!r} is not a valid {attr}")
            setattr(groups[i], attr, int(v))

        return (lambda i: float(getattr(groups[i], attr))), set_

    def _valid(check_fn):
        def ok(v):
            try:
                check_fn(v)
            except grp.GroupError:
                return False
            return True

        return ok

    def vel_scale_set(i, v):
        if not 0.0 <= v <= 100.0:
            raise ValueError(f"velocity scale {v!r} is outside 0 .. 100")
        groups[i].set_vel_scale(float(v))

    def shaper(attr, bounds):
        def set_(i, v):
            lo, hi = bounds
            s = kernel.group_inshape[i]
            if not lo <= v <= hi or groups[i].moving:
                raise ValueError(f"{v!r} is outside {lo:g} .. {hi:g} or the group moves")
            f, z = (v, s.damping) if attr == "frequency" else (s.frequency, v)
            try:
                inshape.design(f, z, s.shaper_type, kernel.dt)
            except inshape.ShaperDesignError as exc:
                raise ValueError(str(exc)) from None
            setattr(s, attr, float(v))
            group_inshape.install(kernel, i)

        return (lambda i: float(getattr(kernel.group_inshape[i], attr))), set_

    def last_err_set(i, v):
        if v != 0:
            raise ValueError("only 0 (clear) can be written")
        kernel.group_last_error[i] = 0

    bindings = {
        "num_axis": (lambda i: float(groups[i].n), None),
        "coord_sys": code_set("coord_sys", lambda v: CoordSystems.valid(v) and v != CS_ACS),
        "buffer_mode": code_set("buffer_mode", _valid(check_bm)),
        "trans_mode": code_set("trans_mode", _valid(check_tm)),
        "trans_vel": trans(0),
        "trans_dis": trans(1),
        "trans_dev": trans(2),
        "trans_curvature": trans(3),
        "vel_scale": (lambda i: float(groups[i].vel_scale), vel_scale_set),
        "shaper_fr": shaper("frequency", GRP_INSHAPE_FREQUENCY),
        "shaper_xi": shaper("damping", GRP_INSHAPE_DAMPING),
        "last_err": (lambda i: float(kernel.group_last_error[i]), last_err_set),
    }
    for kind, linear, limits in (("lin", True, LIN_LIMITS), ("ang", False, ANG_LIMITS)):
        for k, what in enumerate(("vel", "acc", "dec")):
            bindings[f"{kind}_{what}_lim"] = ((lambda lim: lambda i: lim)(limits[k]), None)
            bindings[f"{kind}_{what}"] = profile(linear, k)
        bindings[f"{kind}_sf"] = profile(linear, 3)
        bindings[f"{kind}_acc_time"] = ramp_time(linear, 1)
        bindings[f"{kind}_dec_time"] = ramp_time(linear, 2)
    for var, name in manual_ids()[GROUP]:
        get, set_ = bindings[name.removeprefix("HCV_ID_grp_")]
        table.add(GROUP, var, name, get, set_)
