"""Shared set-up of the axis group tests: a motion kernel with commands, cycles, samples."""

from __future__ import annotations

import math

from motionvm.motion import axis_status as st
from motionvm.motion.axis_config import create
from motionvm.motion.commands import MotionCommands
from motionvm.motion.kernel import MotionKernel

DT = 0.001


def grp_err(code: int, gid: int = 0) -> int:
    return st.group_error(code, gid)


def machine(n: int = 4, **config) -> MotionCommands:
    return MotionCommands(MotionKernel([create(dict(config)) for _ in range(n)], DT))


def cycle(c: MotionCommands, n: int = 1) -> None:
    for _ in range(n):
        c.motion.begin_cycle()
        c.motion.step()


def until(c: MotionCommands, cond, limit: int = 200_000) -> int:
    for n in range(limit):
        if cond():
            return n
        cycle(c)
    raise AssertionError("condition never held")


def grouped(n_axes: int = 2, gid: int = 0, n: int = 4, **config) -> MotionCommands:
    """A machine whose axes 0 .. n_axes-1 are enabled and form group `gid` (enabled)."""
    c = machine(n, **config)
    for i in range(n_axes):
        assert c.Enable(i) == 0
    until(c, lambda: all(c.IsEnabled(i) for i in range(n_axes)))
    assert c.SetupGroup(gid, *range(n_axes)) == 0
    return c


class Recorder:
    """Every cycle's commanded pose, path speed and axis references until the group rests."""

    def __init__(self, c: MotionCommands, gid: int = 0):
        self.c = c
        self.g = c.motion.groups[gid]
        self.poses: list[list[float]] = []
        self.speeds: list[float] = []
        self.axis_vel: list[list[float]] = []
        self.axis_acc: list[list[float]] = []
        self.path_speeds: list[float] = []
        """Path speed before smoothing [mm/s] (grp_pg_vel)."""
        self.junctions: list[float] = []
        """Path speed [mm/s] in the cycle each segment after the first began."""
        self._queued = 0

    def step(self) -> None:
        if not self.poses:
            self._queued = len(self.g.planner.queue)
        cycle(self.c)
        g = self.g
        self.poses.append(list(g.planner.out))
        self.speeds.append(math.sqrt(sum(v * v for v in g.planner.out_vel[:3])))
        self.axis_vel.append([a.ref_vel for a in g.axes])
        self.axis_acc.append([a.ref_acc for a in g.axes])
        self.path_speeds.append(g.planner.v)
        n = len(g.planner.queue)
        if 0 < n < self._queued:
            self.junctions.append(g.planner.v)
        self._queued = n

    def run(self, limit: int = 500_000) -> int:
        n = 0
        while self.g.moving or not self.poses:
            self.step()
            n += 1
            assert n < limit, "the group never came to rest"
        return n


def distance_to_segment(p, a, b) -> float:
    """Distance from point p to the segment a-b (any dimension)."""
    ab = [y - x for x, y in zip(a, b)]
    ap = [y - x for x, y in zip(a, p)]
    den = sum(x * x for x in ab)
    t = 0.0 if den == 0.0 else max(0.0, min(1.0, sum(x * y for x, y in zip(ab, ap)) / den))
    q = [x + t * y for x, y in zip(a, ab)]
    return math.sqrt(sum((x - y) ** 2 for x, y in zip(p, q)))
