"""`plan_position` is planned in one pass over local variables; these tests hold it to
the segment builder it replaced: the same segments, bit for bit, from any state.

The reference below is the recursive `_to_target` that drove that builder (tcurve's
`_Builder`, still used by `plan_velocity`), kept here as the specification of every
float operation and its order.
"""

from __future__ import annotations

import math
import os
import struct

from hypothesis import given, settings
from hypothesis import strategies as st

from motionvm.motion.tcurve import _Builder, _peak_sq, plan_position
from motionvm.motion.tolerances import OVERSHOOT_REL

PROFILE = settings.get_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


def _ref_to_target(b, p_f, v_max, a_max, d_max, reversals):
    dist_signed = p_f - b.p
    u_signed = b.v
    if dist_signed == 0.0 and u_signed == 0.0:
        return
    s = 1.0 if dist_signed > 0.0 or (dist_signed == 0.0 and u_signed < 0.0) else -1.0
    dist = s * dist_signed
    u = s * u_signed
    s_stop = u * u / (2.0 * d_max)
    fits = s_stop <= dist or (dist > 0.0 and s_stop <= dist * (1.0 + OVERSHOOT_REL))
    if u < 0.0 or not fits or reversals == 0:
        b.add(abs(u_signed) / d_max, -math.copysign(d_max, u_signed))
        b.v = 0.0
        if reversals > 0:
            _ref_to_target(b, p_f, v_max, a_max, d_max, reversals - 1)
        return
    if u > v_max:
        b.add((u - v_max) / d_max, -s * d_max)
        v_peak = v_max
        b.v = s * v_peak
    else:
        v_peak = math.sqrt(_peak_sq(dist, u, a_max, d_max))
        v_peak = max(min(v_peak, v_max), u)
        b.add((v_peak - u) / a_max, s * a_max)
        b.v = s * v_peak
    remaining = s * (p_f - b.p)
    cruise = remaining - v_peak * v_peak / (2.0 * d_max)
    if cruise > 0.0 and v_peak > 0.0:
        b.add(cruise / v_peak, 0.0)
        remaining = s * (p_f - b.p)
    if v_peak > 0.0 and remaining > 0.0:
        t_dec = 2.0 * remaining / v_peak
        b.add(t_dec, -s * v_peak / t_dec)


def _reference(p_0, v_0, p_f, v_max, a_max, d_max):
    b = _Builder(p_0, v_0)
    _ref_to_target(b, p_f, v_max, a_max, d_max, 2)
    return b.segs


def _bits(segs) -> list[tuple[bytes, ...]]:
    """Segments as the bytes of their floats: -0.0 != 0.0, nan == nan."""
    return [tuple(struct.pack("<d", x) for x in seg) for seg in segs]


def _check(p_0, v_0, p_f, v_max, a_max, d_max) -> None:
    plan = plan_position(p_0, v_0, p_f, v_max, a_max, d_max)
    assert _bits(plan.segs) == _bits(_reference(p_0, v_0, p_f, v_max, a_max, d_max))
    assert plan.p_f == p_f


CASES = [
    (1.25, 0.0, 101.3, 100.0, 1000.0, 500.0),  # trapezoid
    (0.0, 0.0, 0.05, 100.0, 1000.0, 1000.0),  # triangle
    (0.0, -50.0, 10.0, 100.0, 1000.0, 500.0),  # moving away: brake, then move back
    (0.0, 100.0, 1.0, 100.0, 1000.0, 500.0),  # overshoot: brake, then return
    (0.0, 200.0, 1000.0, 100.0, 1000.0, 500.0),  # above v_max: brake to v_max
    (0.0, -0.0, -33.0, 80.0, 900.0, 700.0),  # negative, from -0.0
    (5.0, 0.0, 5.0, 80.0, 900.0, 700.0),  # no move
    (5.0, 3.0, 5.0, 80.0, 900.0, 700.0),  # on target, moving: brake and return
    (0.0, 0.0, 1e-300, 80.0, 1e-200, 1e-200),  # underflows to a zero peak
    (0.0, 0.0, 100.0, 1e300, 1e300, 1e300),  # a_max * d_max overflows
    (0.0, 0.0, 100.0, 1e-300, 1000.0, 1000.0),  # a cruise of huge duration
    (0.0, 99.0, 4.9005, 100.0, 1000.0, 1000.0),  # exactly on the braking curve
]


def test_plan_position_is_bit_identical_to_the_builder_on_edge_cases():
    for case in CASES:
        _check(*case)


finite = st.floats(-1e4, 1e4)
speeds = st.one_of(st.just(0.0), st.floats(-3000.0, 3000.0))
limits = st.floats(1e-3, 1e6)


@PROFILE
@given(finite, speeds, st.one_of(finite, st.floats(-1e-3, 1e-3)), limits, limits, limits)
def test_plan_position_is_bit_identical_to_the_builder(p_0, v_0, p_f, v_max, a_max, d_max):
    _check(p_0, v_0, p_f, v_max, a_max, d_max)


@PROFILE
@given(finite, st.floats(0.0, 500.0), limits, limits, limits, st.floats(0.0, 1.0))
def test_plan_position_is_bit_identical_on_the_braking_curve(p_0, v, v_max, a_max, d_max, k):
    """Replans mid-deceleration: the stop distance v^2/(2 d) nudged by a few ulps."""
    stop = v * v / (2.0 * d_max)
    p_f = p_0 + stop * (1.0 + (k - 0.5) * 4e-15)
    _check(p_0, v, p_f, v_max, a_max, d_max)
