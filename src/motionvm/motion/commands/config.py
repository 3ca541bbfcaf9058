"""Chapter 17.3, controller variables: GetConfigVar, SetConfigVar, by HCV id (17.1.1).

The variables are the motion kernel's `config_vars` registry (motion/config_vars.py):
axis variables are registered by the kernel, system variables by the language run time
that keeps them, group variables by the axis groups. GetConfigVar returns `(result,
value)`: result 0 and the value, or -1 and 0.0 for an id that names nothing (the
system's last error then eERR_HCV_ID_NOT_FOUND). SetConfigVar returns 0, or: an unknown
id eERR_HCV_ID_NOT_FOUND (1), a read-only variable eERR_HCV_IS_READ_ONLY (3), a value
out of range eERR_HCV_VALUE_OUT_OF_RANGE (4) -- stored as the system's last error --, or
the error code of the axis setter that refused it (stored as that axis's last error,
e.g. eERR_AXIS_CMD_INVALID_POS for a software right limit below the left one).
"""

from __future__ import annotations

import math

from motionvm.motion import config_vars as cv
from motionvm.motion.axis_status import AxisCommandError, axis_error
from motionvm.motion.commands.base import CommandBase


class ConfigCommands(CommandBase):
    """Chapter 17.3: GetConfigVar, SetConfigVar."""

    def _system_error(self, code: int) -> int:
        self.motion.system_last_error = code
        return code

    def GetConfigVar(self, hcv_id: int) -> tuple[int, float]:
        """(0, the value) or (-1, 0.0)."""
        found = self.motion.config_vars.lookup(hcv_id)
        if found is None:
            self._system_error(cv.HCV_ID_NOT_FOUND)
            return -1, 0.0
        var, obj = found
        return 0, float(var.get(obj))

    def SetConfigVar(self, hcv_id: int, value: float) -> int:
        found = self.motion.config_vars.lookup(hcv_id)
        if found is None:
            return self._system_error(cv.HCV_ID_NOT_FOUND)
        var, obj = found
        if var.set is None:
            return self._system_error(cv.HCV_IS_READ_ONLY)
        if not math.isfinite(value):
            return self._system_error(cv.HCV_VALUE_OUT_OF_RANGE)
        try:
            var.set(obj, value)
        except AxisCommandError as exc:
            axis_id = getattr(exc, "axis_id", obj) if (hcv_id >> 24) & 0xFF == cv.AXIS else None
            if axis_id is None:
                return self._system_error(cv.HCV_VALUE_OUT_OF_RANGE)
            a = self.motion.axes[axis_id]
            a.last_error = err = axis_error(exc.code, axis_id)
            return err
        except ValueError:
            return self._system_error(cv.HCV_VALUE_OUT_OF_RANGE)
        return 0
