"""Shared set-up of the axis tests through the motion commands: a motion kernel of plain
axes, controller cycles, waiting for a condition, enabling, axis error codes."""

from __future__ import annotations

from motionvm.motion import axis_status as st
from motionvm.motion.axis_config import create
from motionvm.motion.commands import MotionCommands
from motionvm.motion.kernel import MotionKernel

DT = 0.001


def machine(n: int) -> MotionCommands:
    """`n` axes of the default configuration, all disabled."""
    return MotionCommands(MotionKernel([create({}) for _ in range(n)], DT))


def cycle(c: MotionCommands, n: int = 1) -> None:
    """`n` controller cycles of the motion kernel (no tasks)."""
    for _ in range(n):
        c.motion.begin_cycle()
        c.motion.step()


def until(c: MotionCommands, cond, limit: int = 50_000) -> int:
    """Cycle until `cond()` holds; the number of cycles it took."""
    for n in range(limit):
        if cond():
            return n
        cycle(c)
    raise AssertionError("condition never held")


def enable(c: MotionCommands, *ids: int) -> None:
    """Enable the axes `ids` and cycle until all of them are enabled."""
    for i in ids:
        assert c.Enable(i) == 0
    until(c, lambda: all(c.IsEnabled(i) for i in ids))


def enabled(n: int, *ids: int) -> MotionCommands:
    """A machine of `n` axes, the axes `ids` enabled (none given: all)."""
    c = machine(n)
    enable(c, *(ids or range(n)))
    return c


def err(code: int, axis_id: int = 0) -> int:
    """The error code an axis command returns: `code` of axis `axis_id`."""
    return st.axis_error(code, axis_id)
