"""A move planned with an acceleration or deceleration near the largest double still
stops at its target: the peak velocity's product a_max * d_max overflowed to infinity,
the plan cruised at v_max and overshot (SetDec(0, 1e308) then MoveRel(0, 1) ended at
49 mm with a following error)."""

from __future__ import annotations

import math
import os

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from motionvm.api import Simulation
from motionvm.motion.tcurve import plan_position

settings.register_profile(
    "tcurve-robust-ci", max_examples=60, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)  # fmt: skip
settings.register_profile(
    "tcurve-robust-thorough", max_examples=1000, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)  # fmt: skip
PROFILE = settings.get_profile(
    "tcurve-robust-thorough"
    if os.environ.get("HYPOTHESIS_PROFILE") == "thorough"
    else "tcurve-robust-ci"
)

limits = st.floats(1.0, 1e308)
"""Accelerations [mm/s^2] up to the largest double's order."""


@PROFILE
@given(
    dist=st.floats(1e-3, 1e3),
    v_max=st.floats(1.0, 1e4),
    a_max=st.one_of(limits, st.sampled_from([1e300, 1e308])),
    d_max=st.one_of(limits, st.sampled_from([1e300, 1e308])),
)
def test_a_rest_to_rest_plan_never_passes_its_target(dist, v_max, a_max, d_max):
    curve = plan_position(0.0, 0.0, dist, v_max, a_max, d_max)
    ends = [
        p_0 + (v_0 + 0.5 * a * (t_1 - t_0)) * (t_1 - t_0) for t_0, t_1, p_0, v_0, a in curve.segs
    ]
    assert all(math.isfinite(p) for p in ends)
    assert max(ends) <= dist * (1 + 1e-9), (max(ends), dist)
    assert curve.evaluate(curve.duration)[0] == dist


def test_setdec_1e308_is_refused_and_the_move_ends_at_its_target():
    """SetDec above the machine file's 1e12 is eERR_AXIS_CMD_INVALID_DEC (0x83000154)."""
    program = """void main() {
    Enable(0); while (!IsEnabled(0)) Sleep(1);
    SetDec(0, 1e308);
    MoveRel(0, 1.0);
    Sleep(300);
    Print("%f %x", GetPosFb(0), GetAxisLastErr(0));
}
"""
    with Simulation.from_source(program) as sim:
        sim.run(until=1.0)
        assert sim.messages == ["1.000000 83000154"]


def test_the_closed_form_move_time_survives_the_same_limits():
    from motionvm.motion.tcurve import rest_to_rest_time

    # the peak is limited by the 1000 mm/s^2 ramp alone: sqrt(2 * 1000 * 1) mm/s
    assert math.isclose(rest_to_rest_time(1.0, 300.0, 1000.0, 1e308), math.sqrt(2000.0) / 1000.0)
