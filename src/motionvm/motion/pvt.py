"""PVT motion (manual 5.2.8): cubic Hermite segments through position/velocity/time points.

Between two points (t_0, p_0, v_0) and (t_1, p_1, v_1) the position is the cubic
Hermite polynomial with those end positions and velocities, so the path passes every
point with its velocity and has a continuous velocity. The trajectory starts at
t = 0 [s]; sampled at t = n*dt it ends exactly on the last point's position.
Units: times [s], positions [mm or deg], velocities [mm/s or deg/s].
"""

from __future__ import annotations

import math

MAX_POINTS = 50


class PvtError(ValueError):
    """Bad PVT points; `kind` is "time", "vel" or "acc" (the manual's three PVT errors)."""

    def __init__(self, kind: str, message: str):
        super().__init__(message)
        self.kind = kind


class PvtTrajectory:
    """Cubic Hermite segments; `evaluate(t)` gives (p, v, a)."""

    __slots__ = ("_coef", "_i", "duration", "p_f", "times")

    def __init__(self, times: list[float], pos: list[float], vel: list[float]):
        n = len(times)
        if not 2 <= n <= MAX_POINTS + 1:
            raise PvtError("time", f"{n} PVT points: need 1 to {MAX_POINTS} besides the start")
        for k in range(1, n):
            if not times[k] > times[k - 1]:
                raise PvtError(
                    "time",
                    f"PVT time {times[k] * 1e3:g} ms does not follow {times[k - 1] * 1e3:g} ms",
                )
        for x in pos + vel + times:
            if not math.isfinite(x):
                raise PvtError("time", f"PVT value {x!r} is not finite")
        self.times = times
        self._coef = []
        for k in range(n - 1):
            h = times[k + 1] - times[k]
            p0, p1, v0, v1 = pos[k], pos[k + 1], vel[k] * h, vel[k + 1] * h
            # p(s) = c0 + c1 s + c2 s^2 + c3 s^3, s = (t - t_k)/h in [0, 1]
            c2 = 3.0 * (p1 - p0) - 2.0 * v0 - v1
            c3 = 2.0 * (p0 - p1) + v0 + v1
            self._coef.append((times[k], h, p0, v0, c2, c3))
        self.duration = times[-1]
        self.p_f = pos[-1]
        self._i = 0

    def evaluate(self, t: float) -> tuple[float, float, float]:
        """(position, velocity, acceleration) at time t [s]; the last point from `duration` on."""
        if t >= self.duration:
            return self.p_f, 0.0, 0.0
        coef = self._coef
        i = self._i if coef[self._i][0] <= t else 0
        while i + 1 < len(coef) and coef[i + 1][0] <= t:
            i += 1
        self._i = i
        t_k, h, c0, c1, c2, c3 = coef[i]
        s = (t - t_k) / h
        p = c0 + s * (c1 + s * (c2 + s * c3))
        v = (c1 + s * (2.0 * c2 + 3.0 * s * c3)) / h
        a = (2.0 * c2 + 6.0 * s * c3) / (h * h)
        return p, v, a

    def peaks(self) -> tuple[float, float]:
        """Largest |velocity| and |acceleration| over the whole trajectory (closed form)."""
        v_max = a_max = 0.0
        for _t, h, _c0, c1, c2, c3 in self._coef:
            # v(s) h = c1 + 2 c2 s + 3 c3 s^2 is extreme at the ends or at s = -c2/(3 c3)
            cands = [0.0, 1.0]
            if c3 != 0.0 and 0.0 < -c2 / (3.0 * c3) < 1.0:
                cands.append(-c2 / (3.0 * c3))
            for s in cands:
                v_max = max(v_max, abs(c1 + s * (2.0 * c2 + 3.0 * s * c3)) / h)
            # the acceleration is linear in s: extreme at the ends
            for s in (0.0, 1.0):
                a_max = max(a_max, abs(2.0 * c2 + 6.0 * s * c3) / (h * h))
        return v_max, a_max
