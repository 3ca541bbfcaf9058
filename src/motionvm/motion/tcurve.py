"""Closed-form T-curve (trapezoidal velocity) planner: from any state to rest at a target.

A plan is a list of constant-acceleration segments starting at t = 0 [s]. Convention of
the manual's profile generator: the acceleration limit `a_max` applies while |v| grows,
the deceleration limit `d_max` while |v| shrinks. A position plan ends exactly on its
target: after the last segment the plan returns `p_f` itself, not a computed value.

    plan_position(p_0, v_0, p_f, v_max, a_max, d_max)   move to p_f and stop
    plan_velocity(p_0, v_0, v_f, a_max, d_max)          reach v_f and keep it (jog)
    rest_to_rest_time(distance, v_max, a_max, d_max)    closed-form move time [s]

Units: positions [mm], velocities [mm/s], accelerations [mm/s^2], times [s].
"""

from __future__ import annotations

import math

from motionvm.motion.tolerances import OVERSHOOT_REL

INF = math.inf


class TCurve:
    """A piecewise constant-acceleration trajectory, t = 0 at the state it was planned from.

    `segs` holds tuples `(t_0, t_1, p_0, v_0, a)`: on t_0 <= t < t_1 the position is
    p_0 + v_0*(t - t_0) + a*(t - t_0)**2/2. The last segment of a velocity plan is an
    open-ended cruise (t_1 = inf); a finite plan holds `p_f` from `duration` on.
    """

    __slots__ = ("bounds", "duration", "p_f", "segs")

    def __init__(
        self,
        segs: list[tuple[float, float, float, float, float]],
        p_f: float,
        bounds: tuple[float, float, float] | None = None,
    ):
        self.segs = segs
        """Segments `(t_0 [s], t_1 [s], p_0 [mm], v_0 [mm/s], a [mm/s^2])`."""
        self.p_f = p_f
        """Final position [mm] of a finite plan (exactly the target of a position plan)."""
        self.duration = segs[-1][1] if segs else 0.0
        """Time [s] at which the plan comes to rest; inf for a jog."""
        self.bounds = bounds
        """(lowest position [mm], highest position [mm], highest speed [mm/s]) of a plan
        that moves one way only, its positions between its start and its end (up to
        the rounding of its samples); None: not known to be so."""

    def evaluate(self, t: float) -> tuple[float, float, float]:
        """State (position [mm], velocity [mm/s], acceleration [mm/s^2]) at time t [s].

        Uses the same arithmetic as `ProfileGenerator.step`, so a stepped sample and a
        direct evaluation at the same t are bit-identical.
        """
        for t_0, t_1, p_0, v_0, a in self.segs:
            if t < t_1:
                x = t - t_0 if t > t_0 else 0.0
                return segment_position(p_0, v_0, a, x), v_0 + a * x, a
        return self.p_f, 0.0, 0.0


def segment_position(p_0: float, v_0: float, a: float, x: float) -> float:
    """Position [mm] x seconds into a segment that starts at p_0 [mm] with velocity v_0
    [mm/s] and acceleration a [mm/s^2]: the formula of every sample of a T-curve, in the
    arithmetic of `ProfileGenerator.step` (which keeps 0.5 * a: the same float)."""
    return p_0 + (v_0 + 0.5 * a * x) * x


class _Builder:
    """Appends segments, carrying the state (p, v) at the end of the last one."""

    __slots__ = ("p", "segs", "t", "v")

    def __init__(self, p_0: float, v_0: float):
        self.segs: list[tuple[float, float, float, float, float]] = []
        self.t = 0.0
        self.p = p_0
        self.v = v_0

    def add(self, duration: float, a: float) -> None:
        if duration <= 0.0:
            return
        t_1 = self.t + duration
        self.segs.append((self.t, t_1, self.p, self.v, a))
        self.p = self.p + (self.v + 0.5 * a * duration) * duration
        self.v = self.v + a * duration
        self.t = t_1

    def change_velocity(self, v_f: float, a_max: float, d_max: float) -> None:
        """Go from the current velocity to v_f: brake with d_max, speed up with a_max."""
        v = self.v
        if v != 0.0 and (v > 0.0) != (v_f > 0.0) and v_f != 0.0:
            self.add(abs(v) / d_max, -math.copysign(d_max, v))
            self.v = 0.0
            v = 0.0
        if v_f == v:
            return
        rate = a_max if abs(v_f) > abs(v) else d_max
        self.add(abs(v_f - v) / rate, math.copysign(rate, v_f - v))
        self.v = v_f  # exact, so a following cruise starts at exactly v_f


def _peak_sq(dist: float, u: float, a_max: float, d_max: float) -> float:
    """The squared peak velocity of accelerating from `u` with a_max, then braking with
    d_max to rest, over `dist`."""
    v_sq = (2.0 * a_max * d_max * dist + d_max * u * u) / (a_max + d_max)
    if not math.isfinite(v_sq):  # a_max * d_max overflowed: the same over a_max * d_max
        v_sq = (2.0 * dist + u * u / a_max) / (1.0 / a_max + 1.0 / d_max)
    return v_sq


def rest_to_rest_time(distance: float, v_max: float, a_max: float, d_max: float) -> float:
    """Closed-form T-curve time [s] of a move of `distance` [mm] from rest to rest."""
    dist = abs(distance)
    if dist == 0.0:
        return 0.0
    v_peak = math.sqrt(_peak_sq(dist, 0.0, a_max, d_max))
    if v_peak <= v_max:
        return v_peak / a_max + v_peak / d_max
    d_ramps = v_max * v_max / (2.0 * a_max) + v_max * v_max / (2.0 * d_max)
    return v_max / a_max + v_max / d_max + (dist - d_ramps) / v_max


def plan_position(
    p_0: float, v_0: float, p_f: float, v_max: float, a_max: float, d_max: float
) -> TCurve:
    """Time-optimal T-curve from (p_0, v_0) to rest at p_f.

    If the axis cannot stop before p_f (too fast, or moving away) it brakes to rest
    with d_max first and then moves back (at most twice). A start faster than v_max
    (limits lowered on the fly) is braked down to v_max with d_max.

    One pass over local variables: each segment is appended where it is planned, and
    the state at its end is computed only where a later step reads it.
    """
    segs: list[tuple[float, float, float, float, float]] = []
    t = 0.0
    p = p_0
    v = v_0
    reversals = 2
    one_way = True  # no braking to rest before the move to p_f: one direction only
    while True:
        dist_signed = p_f - p
        if dist_signed == 0.0 and v == 0.0:
            return TCurve(segs, p_f)
        s = 1.0 if dist_signed > 0.0 or (dist_signed == 0.0 and v < 0.0) else -1.0
        dist = s * dist_signed
        u = s * v
        s_stop = u * u / (2.0 * d_max)
        # A state that lies on the braking curve (replanned mid-deceleration) may miss it
        # by rounding; accept it instead of planning a micro-reversal.
        if (
            u < 0.0
            or reversals == 0
            or not (s_stop <= dist or (dist > 0.0 and s_stop <= dist * (1.0 + OVERSHOOT_REL)))
        ):
            # brake to rest, then (while reversals remain) plan again from there
            dur = abs(v) / d_max
            if dur > 0.0:
                a = -math.copysign(d_max, v)
                t_1 = t + dur
                segs.append((t, t_1, p, v, a))
                p = p + (v + 0.5 * a * dur) * dur
                t = t_1
            v = 0.0
            one_way = False
            if reversals == 0:
                return TCurve(segs, p_f)
            reversals -= 1
            continue
        break
    if u > v_max:  # brake down to v_max
        dur = (u - v_max) / d_max
        if dur > 0.0:
            a = -s * d_max
            t_1 = t + dur
            segs.append((t, t_1, p, v, a))
            p = p + (v + 0.5 * a * dur) * dur
            t = t_1
        v_peak = v_max
    else:  # speed up to the peak velocity
        v_peak = math.sqrt(_peak_sq(dist, u, a_max, d_max))
        if v_max < v_peak:  # max(min(v_peak, v_max), u)
            v_peak = v_max
        if u > v_peak:
            v_peak = u
        dur = (v_peak - u) / a_max
        if dur > 0.0:
            a = s * a_max
            t_1 = t + dur
            segs.append((t, t_1, p, v, a))
            p = p + (v + 0.5 * a * dur) * dur
            t = t_1
    v = s * v_peak
    remaining = s * (p_f - p)
    cruise = remaining - v_peak * v_peak / (2.0 * d_max)
    if cruise > 0.0 and v_peak > 0.0:
        dur = cruise / v_peak
        if dur > 0.0:
            t_1 = t + dur
            segs.append((t, t_1, p, v, 0.0))
            p = p + (v + 0.5 * 0.0 * dur) * dur
            t = t_1
        remaining = s * (p_f - p)
    if v_peak > 0.0 and remaining > 0.0:
        # Land exactly (in exact arithmetic) on p_f: the deceleration is v_peak^2 /
        # (2*remaining), equal to d_max up to rounding.
        t_dec = 2.0 * remaining / v_peak
        if t_dec > 0.0:
            segs.append((t, t + t_dec, p, v, -s * v_peak / t_dec))
    if not one_way:
        return TCurve(segs, p_f)
    # from p_0 toward p_f (the start's velocity, if any, points there), never faster
    # than the start or the peak
    top = u if u > v_peak else v_peak
    return TCurve(segs, p_f, (p_0, p_f, top) if p_0 <= p_f else (p_f, p_0, top))


def plan_velocity(p_0: float, v_0: float, v_f: float, a_max: float, d_max: float) -> TCurve:
    """T-curve from (p_0, v_0) to the velocity v_f [mm/s], then cruising at v_f forever.

    With v_f == 0 the plan is finite and ends at rest (a stop); `p_f` is where it stops.
    """
    b = _Builder(p_0, v_0)
    b.change_velocity(v_f, a_max, d_max)
    if v_f != 0.0:
        b.segs.append((b.t, INF, b.p, v_f, 0.0))
        return TCurve(b.segs, INF)
    return TCurve(b.segs, b.p)
