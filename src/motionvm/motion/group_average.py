"""The moving average of an axis group's raw pose (the smoothing of 5.1 on a path), with
its closed-form advance beside its step.

The raw pose (the geometry at the path position) is averaged over the last N cycles,
N = round(Ts / dt), in every coordinate. The window is a ring of N poses; the running
sum of each coordinate takes one addition per cycle (the new pose minus the one it
replaces) and is recomputed exactly (`math.fsum` of the ring) each time the ring index
comes round to 0: so the sum after any cycle is a function of the last N poses and of
the cycles since the last exact sum, never of the whole history, and `advance` can
replay it from the last exact sum at or before the cycles it needs (as the axis's
profile generator does, motion/profile.py).

While the path rests (`idle`), the flush count grows; once it reaches N the output is
the raw pose itself and the sums restart from it.
"""

from __future__ import annotations

import math

_fsum = math.fsum


class PoseAverage:
    """The averaging window of one group's planner (see the module docstring)."""

    __slots__ = ("flush", "j", "n_avg", "sums", "window")

    def __init__(self, n_avg: int, pose) -> None:
        self.n_avg = n_avg
        self.reset(pose)

    def reset(self, pose) -> None:
        """Rest at `pose`: the window full of it, flushed."""
        n = self.n_avg
        pose = list(pose)
        self.window: list = [pose] * n
        """Ring of the last N raw poses; slot `j` holds the oldest (replaced next)."""
        self.j = 0
        self.sums: list[float] = [x * n for x in pose]
        self.flush = n
        """Cycles the path has rested in (counted up to N; 0 while it moves)."""

    def step(self, raw: list[float], idle: bool) -> list[float]:
        """One cycle: `raw` (never changed in place afterwards) enters the window;
        returns the averaged pose (a new list)."""
        n_avg = self.n_avg
        window = self.window
        if n_avg == 1:  # no smoothing: the output is the raw pose
            window[0] = raw
            self.sums = list(raw)
            self.flush = self.flush + 1 if idle else 0
            return list(raw)
        j = self.j
        old = window[j]
        window[j] = raw
        sums = self.sums
        for k, x in enumerate(raw):
            sums[k] += x - old[k]
        j += 1
        if j == n_avg:
            j = 0
            self.sums = sums = [_fsum(c) for c in zip(*window)]  # bounds the drift
        self.j = j
        if idle:
            self.flush += 1
        else:
            self.flush = 0
        if self.flush >= n_avg:
            self.sums = [x * n_avg for x in raw]
            return list(raw)
        return [s / n_avg for s in sums]

    # ---- closed-form advance (time skipping) ----------------------------------------

    def first_read(self, k: int, back: int) -> int:
        """The first cycle whose raw pose `advance(k, ..., back)` reads (may be <= 0: in
        the ring now)."""
        n = self.n_avg
        lo = k - back
        if n == 1:
            return lo
        start = lo - (self.j + lo) % n
        return (start if start >= 1 else 0) - n + 1

    def advance(self, k: int, raws, idle: bool, back: int) -> list:
        """Advance k cycles (k >= 1) as k `step`s with the raw poses `raws(c_0, c_1)`
        gives (one list per coordinate of the poses of cycles c_0 .. c_1, 1 <= c_0 <= c_1
        <= k) and `idle` would, their flush count staying below N (idle: `flush + k <
        N`); returns the outputs of cycles k - back .. k (those of cycles before 1 are
        not asked for: back < k).

        The running sums are replayed from the last cycle at or before k - back where
        the ring index came round to 0 (an exact `fsum`), or from now: a coordinate at
        a time, with the same additions as stepping, in the same order."""
        n = self.n_avg
        j_0 = self.j
        window = self.window
        lo = k - back
        if n == 1:  # no smoothing: the outputs are the raw poses
            cols = raws(lo, k)
            outs = [list(r) for r in zip(*cols)]
            self.window = [outs[-1]]
            self.sums = list(outs[-1])
            self.flush = self.flush + k if idle else 0
            return outs
        start = lo - (j_0 + lo) % n  # the last exact sum at or before cycle lo
        if start < 1:
            start = 0
        first = start - n + 1  # the first cycle whose raw pose is read
        # every coordinate's raw poses of cycles first .. k: the ring's, then the new
        if first <= 0:
            old = [window[(j_0 + c - 1) % n] for c in range(first, 1)]
            cols = [list(c) for c in zip(*old)]
            for col, new in zip(cols, raws(1, k)):
                col += new
        else:
            cols = raws(first, k)
        a, b = start + 1 - first, lo + 1 - first  # cycles start + 1 .. lo: no exact sum
        outs_cols = []
        sums = []
        for i, col in enumerate(cols):
            s = _fsum(col[:n]) if start else self.sums[i]
            for x, y in zip(col[a:b], col[a - n : b - n]):
                s += x - y
            out = [s / n]
            for c in range(lo + 1, k + 1):
                m = c - first
                s += col[m] - col[m - n]
                if (j_0 + c) % n == 0:
                    s = _fsum(col[m - n + 1 : m + 1])
                out.append(s / n)
            outs_cols.append(out)
            sums.append(s)
        # the ring after cycle k: slot (j_0 + c - 1) % n holds cycle c
        j = (j_0 + k) % n
        rows = list(zip(*[col[k - n + 1 - first :] for col in cols]))
        self.window = rows[n - j :] + rows[: n - j]
        self.j = j
        self.sums = sums
        self.flush = self.flush + k if idle else 0
        return [list(r) for r in zip(*outs_cols)]
