"""Named numerical tolerances of the motion code and its tests, in one place.

The profile generator is exact in its closed form; the only errors are float rounding.
Limits are checked on backward differences of the sampled reference, so rounding of a
position p [mm] shows up as about eps*|p|/dt**k in the k-th difference. A check of a
limit L therefore allows `L * LIMIT_REL + ROUNDOFF_ULPS * eps * max(|p|, 1) / dt**k`
(`limit_slack`).
"""

from __future__ import annotations

import math
import sys

EPS = sys.float_info.epsilon

OVERSHOOT_REL = 1e-9
"""Relative overshoot of the braking distance [-] the planner treats as "stops in time".

A state replanned in the middle of its own deceleration lies on the braking curve up to
rounding; without this slack the planner would add a micro-reversal. The deceleration it
then uses exceeds d_max by at most this fraction."""

LIMIT_REL = 1e-6
"""Relative slack [-] on a velocity, acceleration or jerk limit in checks."""

ROUNDOFF_ULPS = 64.0
"""Units in the last place of a position [-] allowed as rounding noise in a difference."""

P_TOL = 1e-9
"""Absolute position agreement [mm] where a computed (not exact) position is compared."""

MIN_SPEED = 1e-6
"""[mm/s or deg/s] The lowest positive speed a command accepts: below it a 1 ms cycle
advances less than `P_TOL`, and a move (a 4e-117 mm/s transition, a subnormal feed)
would not end in any time a machine runs. A smaller positive value is an invalid
parameter, not a move that never ends."""

MIN_ACC = 1e-6
"""[mm/s^2 or deg/s^2] The lowest acceleration or deceleration a command or the machine
file accepts, for the same reason (a subnormal acceleration never reaches speed)."""


def limit_slack(limit: float, p_scale: float, dt: float, order: int) -> float:
    """Allowed excess [unit of the limit] over `limit` for a difference of order `order`.

    `p_scale` [mm] is the largest |position| involved, `dt` [s] the sampling period.
    """
    return abs(limit) * LIMIT_REL + ROUNDOFF_ULPS * EPS * max(abs(p_scale), 1.0) / dt**order


def limit_violation(
    samples: list[tuple[float, float, float]],
    dt: float,
    v_max: float,
    a_max: float,
    j_max: float | None = None,
) -> str | None:
    """First sample breaking a limit, as a message, or None.

    `samples` are (position [mm], velocity [mm/s], acceleration [mm/s^2]) per cycle, as
    `ProfileGenerator.step` returns them; the jerk [mm/s^3] is the backward difference
    of the acceleration (not checked if `j_max` is None). NaN counts as a violation.
    """
    a_prev = 0.0
    for k, (p, v, a) in enumerate(samples):
        if not (math.isfinite(p) and math.isfinite(v) and math.isfinite(a)):
            return f"cycle {k}: non-finite sample {(p, v, a)}"
        if abs(v) > v_max + limit_slack(v_max, p, dt, 1):
            return f"cycle {k}: velocity {v!r} exceeds the limit {v_max!r}"
        if abs(a) > a_max + limit_slack(a_max, p, dt, 2):
            return f"cycle {k}: acceleration {a!r} exceeds the limit {a_max!r}"
        if j_max is not None:
            jerk = (a - a_prev) / dt
            if abs(jerk) > j_max + limit_slack(j_max, p, dt, 3):
                return f"cycle {k}: jerk {jerk!r} exceeds the limit {j_max!r}"
        a_prev = a
    return None


FILTER_SETTLE = 1e-9
"""[mm] A recursive command filter (VSF) whose output is this close to a resting input
snaps onto it: its output then equals the input exactly and nothing is pending."""
