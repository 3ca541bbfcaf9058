"""A task's wait on an axis's position feedback, for the controller's jumps.

`Till(GetPosFb(a) >= x)` (or >, <=, <) polls once per cycle like any `Till`. While its
condition is false, the task hands the controller a `PositionWatch`: a jump over
cycles nobody computes must end in the cycle the feedback reaches x, so that the task
polls in the next one, as stepping would. The watch answers conservatively (a margin
far above the rounding of x's conversion): it may end a jump a cycle early, where the
task then polls and waits on, never late.

Along a closed-form advance the feedback is monotonic (the advance covers a monotonic
stretch of a T-curve and the settle on its target: motion/axis_coast.py), so a
threshold it passes is found by bisection.
"""

from __future__ import annotations

from motionvm.motion import axis_coast

_REL = 1e-9
"""Relative margin of the position test (plus the same absolute in mm)."""


class PositionWatch:
    """Waiting for axis `axis`'s GetPosFb to reach `threshold` [mm] from below (`rising`:
    >=, >) or from above (<=, <)."""

    __slots__ = ("axis", "rising", "threshold")

    def __init__(self, axis, threshold: float, rising: bool) -> None:
        self.axis = axis
        self.threshold = threshold
        self.rising = rising

    def _reached(self, pos: float) -> bool:
        x = self.threshold
        margin = _REL * (abs(x) + 1.0)
        return pos >= x - margin if self.rising else pos <= x + margin

    def __call__(self) -> bool:
        """True if the wait's condition may hold now (or cannot be told: an axis of an
        engaged gantry reads in pair coordinates, a rollover axis wraps)."""
        a = self.axis
        if a.following is not None or a.rollover:
            return True
        return self._reached(a.pos_fb)

    def cycles(self, k: int) -> int:
        """The first of the next `k` cycles after which the position may be reached, or
        k; 0 if the axis's feedback over them is not known here (smoothing). The axis can
        be advanced k cycles (`coast_cycles`), and the test is false now."""
        a = self.axis
        if a.resting:
            return k
        if a.pg._n_avg != 1:
            return 0
        if not self._reached(axis_coast.feedback_after(a, k)):
            return k  # monotonic: not reached on the way either
        lo, hi = 0, k  # not reached after lo cycles, reached after hi
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if self._reached(axis_coast.feedback_after(a, mid)):
                hi = mid
            else:
                lo = mid
        return hi
