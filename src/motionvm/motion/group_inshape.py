"""The input shaper of an axis group (HIMC manual 15.8-15.10): the group planner's
`command_filter` built from the group's InShape settings.

`GroupShaper` shapes every coordinate of the commanded pose (after the moving-average
smoothing, `PathPlanner.command_filter`) with its own `inshape.ShaperState`, all with
the same discrete shaper (`inshape.design`). The planner calls it once per cycle while
the group moves; `busy` is True while a coordinate's output still lags a resting input
(the shaper's tail), which keeps the group moving (IsGrpMoving) until the pose has
reached the end of the path exactly. The velocity each `ShaperState` sees is the
difference of successive poses over the cycle (the planner derives the commanded
velocity from the shaped poses in the same way).

`reset(pose)` puts every coordinate at rest at `pose`: when the group is (re-)enabled
(its planner is made anew at the axes' positions), and when the filter is made.
"""

from __future__ import annotations

from motionvm.motion.inshape import Shaper, ShaperState, design


class GroupShaper:
    """`command_filter` of a group planner: one ShaperState per coordinate."""

    __slots__ = ("_inv_dt", "_last", "_states", "shaper")

    def __init__(self, shaper: Shaper, dt: float, pose) -> None:
        self.shaper = shaper
        self._inv_dt = 1.0 / dt
        self.reset(pose)

    def reset(self, pose) -> None:
        """Rest at `pose`: nothing pending, the output is the input."""
        self._states = [ShaperState(self.shaper, p) for p in pose]
        self._last = list(pose)

    @property
    def busy(self) -> bool:
        """True while the shaped pose still changes with a resting input."""
        return any(s.pending for s in self._states)

    def __call__(self, pose: list[float]) -> list[float]:
        if len(pose) != len(self._states):  # the group's axes changed: start at rest
            self.reset(pose)
            return list(pose)
        inv = self._inv_dt
        out = [s.step(p, (p - q) * inv, 0.0)[0] for s, p, q in zip(self._states, pose, self._last)]
        self._last = list(pose)
        return out


def install(kernel, group_id: int) -> None:
    """Put group `group_id`'s shaper on its planner from `kernel.group_inshape` (or
    remove it when disabled); it starts at rest at the present commanded pose."""
    g = kernel.groups.get(group_id)
    if g is None:
        return
    s = kernel.group_inshape[group_id]
    if not s.enabled:
        g.planner.command_filter = None
        return
    shaper = design(s.frequency, s.damping, s.shaper_type, kernel.dt)
    g.planner.command_filter = GroupShaper(shaper, kernel.dt, g.planner.out)
