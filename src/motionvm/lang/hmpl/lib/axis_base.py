"""The plumbing every axis-related built-in library shares: find an axis by id (a bad id
sets the system's last error) and run an axis command, turning `AxisCommandError` into
the manual's error code (stored as that axis's last error)."""

from __future__ import annotations

from motionvm.lang.hmpl.lib.base import Library
from motionvm.motion import axis_status as st
from motionvm.motion.axis_status import AxisCommandError


class AxisLibrary(Library):
    """Base of the axis, homing and touch-probe libraries (not a library itself)."""

    def _axis(self, axis_id: int):
        """Axis `axis_id`, or None (and system last error eERR_HMPL_ARG_OUT_OF_RANGE)."""
        motion = self.rt.controller.motion
        a = motion.axis(axis_id)
        if a is None:
            motion.system_last_error = st.SYS_HMPL_ARG_OUT_OF_RANGE
        return a

    def _target(self, a):
        """The object whose methods `_do` calls for axis `a` (the axis itself by default)."""
        return a

    def _refusal(self, a) -> int:
        """A command-refusal code for axis `a` before any command runs (0: none)."""
        return 0

    def _do(self, axis_id: int, method: str, *args) -> int:
        """Call `method` of the axis's target; 0, or the error code it raised."""
        a = self._axis(axis_id)
        if a is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        refused = self._refusal(a)
        if refused:
            a.last_error = code = st.axis_error(refused, axis_id)
            return code
        try:
            getattr(self._target(a), method)(*args)
        except AxisCommandError as exc:
            a.last_error = code = st.axis_error(exc.code, axis_id)
            return code
        return 0
