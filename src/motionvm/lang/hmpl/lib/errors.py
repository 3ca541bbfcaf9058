"""HMPL error functions of manual chapter 18: last errors of the system, axes and groups.

Error codes are 32-bit (0x00XXXXXX system, 0x83XXCCCC axis XX, 0x82XXCCCC group XX,
tables 18.1.1-18.1.3) and come back as C ints, so an axis or group code is negative
(print it with "%x"). Every failing axis function stores its code as the axis's last
error; fault reactions (limits, position error, drive fault) store theirs too.
A bad axis or group id stores eERR_HMPL_ARG_OUT_OF_RANGE as the system's last error
and returns it.
"""

from __future__ import annotations

from motionvm.lang.hmpl.lib.base import Library, builtin
from motionvm.motion import axis_status as st
from motionvm.motion.kernel import N_GROUPS


class ErrorLib(Library):
    """Chapter 18: GetSystemLastErr ... GetDriveErr."""

    @property
    def _motion(self):
        return self.rt.controller.motion

    def _bad_id(self) -> int:
        self._motion.system_last_error = st.SYS_HMPL_ARG_OUT_OF_RANGE
        return st.SYS_HMPL_ARG_OUT_OF_RANGE

    @builtin()
    def GetSystemLastErr(self) -> int:
        return st.as_c_int(self._motion.system_last_error)

    @builtin()
    def GetAxisLastErr(self, axis_id: int) -> int:
        a = self._motion.axis(axis_id)
        return self._bad_id() if a is None else a.last_error

    @builtin()
    def ClearAxisLastErr(self, axis_id: int) -> int:
        a = self._motion.axis(axis_id)
        if a is None:
            return self._bad_id()
        a.last_error = 0
        return 0

    @builtin()
    def GetGrpLastErr(self, group_id: int) -> int:
        if not 0 <= group_id < N_GROUPS:
            return self._bad_id()
        return self._motion.group_last_error[group_id]

    @builtin()
    def ClearGrpLastErr(self, group_id: int) -> int:
        if not 0 <= group_id < N_GROUPS:
            return self._bad_id()
        self._motion.group_last_error[group_id] = 0
        return 0

    @builtin()
    def GetDriveErr(self, axis_id: int) -> int:
        """The drive's error code object 0x603F (0 if none)."""
        a = self._motion.axis(axis_id)
        return self._bad_id() if a is None else a.drive.error_code
