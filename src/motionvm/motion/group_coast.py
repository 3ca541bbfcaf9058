"""Closed-form advance of a moving axis group and its axes over cycles nobody observes
(time skipping): how far it can go, and the order in which its parts advance.

A group on its path is a pure function of the cycle number: its planner's path
position is the segment's plan evaluated at a time counted from the plan's first cycle,
the raw pose the segment's geometry there, the commanded pose the moving average of the
raw poses replayed from its last exact sum (`PathPlanner.coast_room`, `advance`,
`coast_bounds`: motion/group_plan.py; `PoseAverage.advance`: motion/group_average.py).
Each of its axes follows the commanded pose through a steady CSP drive and an ideal
motor, so that its cycle is the same function of the poses of its last few cycles as a
profile move's (`axis_coast.following`, `coast_following`).

A group coasts while its planner stays active (so its status, and that of its axes,
which are in region I while it moves, stays the same) and runs on within one segment or
through the ends of segments it passes at speed (the cycle a segment starts in is
computed as a step of the path alone, then its plan in closed form), rests on a corner,
is halted, or flushes its smoothing; a stop at a segment's end, the start of the next
segment after it, a deferred look-ahead pass coming due in a segment's last cycle or
on a corner, a brake and the end of the flush are stepped. A group input shaper is stepped. An axis that is not on the common path (a
filter on its command, a drive other than a steady CSP `Cia402Drive` with an ideal
motor), or whose reference could come near a limit or a position error over the
advance, makes its group step.
"""

from __future__ import annotations

from motionvm.motion import axis_coast
from motionvm.motion.group import MOVING

MIN_BACK = 2
"""Commanded poses an advance returns before its last (the velocity and acceleration)."""


def _back(g) -> int:
    """How many cycles before its last an advance of group `g` must return."""
    most = MIN_BACK
    for a in g.axes:
        b = a.drive.mechanics.delay_cycles + 2
        if b > most:
            most = b
    return most


def coast_cycles(g, wanted: int) -> int:
    """How many cycles (at most `wanted`) moving group `g` and its axes can be advanced
    from now in closed form: 0 if they must be stepped (`coast_room`, then `clear`)."""
    k = coast_room(g, wanted)
    return k if k and clear(g) else 0


def coast_room(g, wanted: int) -> int:
    """The cycles (at most `wanted`) moving group `g` can be advanced by from now as far
    as its path and the drives of its axes go (0: step it), before the limits of its
    axes are looked at (`clear`): the cheap half of `coast_cycles`, asked of every
    moving group first."""
    if g.state != MOVING:
        return 0
    k = g.planner.coast_room(wanted)
    if k <= _back(g):
        return 0
    for a in g.axes:
        if not axis_coast.following(a, g.link):
            return 0
    return k


def clear(g) -> bool:
    """True if over any advance `coast_room(g, ...)` allows, the references of the axes
    of group `g` come near no limit and no position error."""
    bounds = g.planner.coast_bounds()
    if bounds is None:
        return False
    lo, hi, speed = bounds
    for i, a in enumerate(g.axes):
        if not axis_coast.clear_following(a, lo[i], hi[i], speed[i]):
            return False
    return True


def min_cycles(g) -> int:
    """The fewest cycles `coast` computes in closed form (fewer are stepped)."""
    return _back(g) + 1


def coast(g, k: int) -> None:
    """Advance group `g` and its axes by k cycles (`coast_cycles(g, k)` >= k >
    `_back(g)`), exactly as k steps would."""
    back = _back(g)
    planner = g.planner
    outs = planner.advance(k, back)
    g.joint_ref = refs = list(zip(planner.out, planner.out_vel, planner.out_acc))
    if g.last_end is None and planner.mode == "idle":
        g.last_end = list(planner.raw)
    for i, a in enumerate(g.axes):
        delay = a.drive.mechanics.delay_cycles
        ps = [p[i] for p in outs[back - delay - 2 :]]
        axis_coast.coast_following(a, k, ps, refs[i])
