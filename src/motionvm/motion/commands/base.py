"""What every motion command shares: an axis found by id (a bad id sets the system's last
error), and a refused command turned into the manual's error code (stored as the last
error of the axis it belongs to)."""

from __future__ import annotations

from collections.abc import Callable

from motionvm.motion import axis_status as st
from motionvm.motion.axis import Axis
from motionvm.motion.axis_status import AxisCommandError
from motionvm.motion.gear import SyncError
from motionvm.motion.kernel import MotionKernel


class CommandBase:
    """The motion kernel the commands act on, and their shared plumbing."""

    def __init__(self, motion: MotionKernel) -> None:
        self.motion = motion

    def _bad_id(self) -> int:
        """Store and return eERR_HMPL_ARG_OUT_OF_RANGE as the system's last error."""
        self.motion.system_last_error = st.SYS_HMPL_ARG_OUT_OF_RANGE
        return st.SYS_HMPL_ARG_OUT_OF_RANGE

    def _axis(self, axis_id: int) -> Axis | None:
        """Axis `axis_id`, or None (and the system's last error set)."""
        a = self.motion.axis(axis_id)
        if a is None:
            self.motion.system_last_error = st.SYS_HMPL_ARG_OUT_OF_RANGE
        return a

    def _axes(self, *ids: int) -> list[Axis] | None:
        """The axes of `ids`, or None (and the system's last error set) if one is bad."""
        motion = self.motion
        out = [motion.axis(i) for i in ids]
        if None in out:
            motion.system_last_error = st.SYS_HMPL_ARG_OUT_OF_RANGE
            return None
        return out  # type: ignore[return-value]

    @staticmethod
    def _fail(a: Axis, code: int) -> int:
        """Store axis error `code` (low half) as `a`'s last error; return it as a C int."""
        a.last_error = err = st.axis_error(code, a.axis_id)
        return err

    def _run(self, a: Axis, fn: Callable, *args) -> int:
        """`fn(*args)`: 0, or the error it raised, stored as the last error of its axis
        (`a`, or the axis a gear or gantry error names)."""
        try:
            fn(*args)
        except SyncError as exc:
            return self._fail(self.motion.axes[exc.axis_id], exc.code)
        except AxisCommandError as exc:
            return self._fail(a, exc.code)
        return 0
