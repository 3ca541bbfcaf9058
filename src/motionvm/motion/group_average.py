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

    def advance(self, k: int, raw_at, idle: bool, back: int) -> list[list[float]]:
        """Advance k cycles (k >= 1) as k `step`s with `raw_at(c)` (the raw pose of cycle
        c = 1 .. k, a new list each call) and `idle` would, their flush count staying
        below N (idle: `flush + k < N`); returns the outputs of cycles k - back .. k
        (those of cycles before 1 are not asked for: back < k).

        The running sums are replayed from the last cycle at or before k - back where
        the ring index came round to 0 (an exact `fsum`), or from now."""
        n = self.n_avg
        j_0 = self.j
        window = self.window
        lo = k - back
        start = lo - (j_0 + lo) % n  # the last exact sum at or before cycle lo
        raws: dict[int, list[float]] = {}

        def raw(c: int) -> list[float]:
            if c <= 0:  # still in the window: cycle 0 is the newest
                return window[(j_0 + c - 1) % n]
            r = raws.get(c)
            if r is None:
                raws[c] = r = raw_at(c)
            return r

        if start >= 1:
            sums = [_fsum(col) for col in zip(*[raw(c) for c in range(start - n + 1, start + 1)])]
        else:
            start, sums = 0, list(self.sums)
        outs = []
        if start == lo:
            outs.append([s / n for s in sums])
        for c in range(start + 1, k + 1):
            new, old = raw(c), raw(c - n)
            for i, x in enumerate(new):
                sums[i] += x - old[i]
            if (j_0 + c) % n == 0:
                sums = [_fsum(col) for col in zip(*[raw(b) for b in range(c - n + 1, c + 1)])]
            if c >= lo:
                outs.append([s / n for s in sums])
        # the ring after cycle k: slot (j_0 + c - 1) % n holds cycle c
        new_window = list(window)
        for c in range(max(1, k - n + 1), k + 1):
            new_window[(j_0 + c - 1) % n] = raw(c)
        self.window = new_window
        self.j = (j_0 + k) % n
        self.sums = sums
        self.flush = self.flush + k if idle else 0
        return outs
