"""The real-time pacer: the one place that reads the wall clock.

With `motionvm run --realtime` the controller never runs ahead of the wall clock: after
each step it sleeps until `wall_time - wall_start >= sim_time - sim_start`. Results are
the same as without pacing; only their timing changes (for HMIs and clients on TCP).
"""

from __future__ import annotations

import time


class RealTimePacer:
    """Keeps simulated time [s] from running ahead of wall time [s]."""

    def __init__(self, sim_time: float) -> None:
        self.sim_start = sim_time
        self.wall_start = time.monotonic()

    def wait(self, sim_time: float) -> None:
        """Sleep until the wall clock reaches `sim_time` (relative to the start)."""
        ahead = (sim_time - self.sim_start) - (time.monotonic() - self.wall_start)
        if ahead > 0.0005:
            time.sleep(ahead)
