"""Homing of an axis (HIMC manual chapter 20): settings, MoveHome, homed/homing status.

An `AxisHoming` is the homing state of one axis; the motion kernel keeps one per axis
(`MotionKernel.homing[axis_id]`). `start()` runs one of the CiA 402 methods of table 20.1.1 (sequences in
`homing_run.py`) by making the axis follow a `HomingRun`; the run drives the axis with
its own profile (switch speed [mm/s], zero speed [mm/s], acceleration [mm/s^2]) against
the simulated switches and index pulses of the axis's drive, and releases the axis at
rest on the home position.

The found home position then reads `offset` (CiA 402 object 607Ch, home offset: the
manual's method 37 states 6064h = 607Ch), done like SetPos by changing the axis's
position offset (the simulated drive's counts are not reset). Software and hardware
limits are ignored while homing (the sequence itself reacts to the limit switches) and
restored after it.

Status (motion_status bits 11 homed, 12 homing of table 5.1.1.5): `homing` is set by
`start()` and cleared when the home position is attained. A homing that fails (timeout:
eERR_AXIS_DRIVE_HOME_TOUT; no such switch, a limit switch in the way, the axis stopped,
disabled or faulted meanwhile: eERR_AXIS_DRIVE_HOME_FAILED) brakes the axis to rest and
leaves `homing` set -- the homing procedure did not complete, as the manual's example
20.1.1 reads it (`if (!IsHoming(axis)) success else fail`) -- until the next `start()`
or `set_homed()`. Settings changed while homing apply to the next homing.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from motionvm.drives.objects import MODE_CSP
from motionvm.motion import axis_status as st
from motionvm.motion.axis_status import AxisCommandError
from motionvm.motion.homing_run import METHODS, HomingRun, Switches

DRIVE_HOME_TOUT = 0x0424
"""eERR_AXIS_DRIVE_HOME_TOUT, low half (table 18.1.2.1): homing took too long."""
DRIVE_HOME_FAILED = 0x042E
"""eERR_AXIS_DRIVE_HOME_FAILED, low half (table 18.1.2.1): homing error."""


@dataclass
class HomeSettings:
    """The homing parameters of one axis, defaults as in manual 20.3-20.8."""

    method: int = 33
    switch_vel: float = 20.0
    """Speed while searching the switch [mm/s or deg/s] (SetHomeSwitchVel)."""
    zero_vel: float = 5.0
    """Speed while passing the edge and searching the index [mm/s] (SetHomeZeroVel)."""
    acc: float = 2000.0
    """Acceleration and deceleration [mm/s^2] (SetHomeAcc)."""
    offset: float = 0.0
    """Position the home position reads after homing [mm or deg] (SetHomeOffset)."""
    timeout_ms: float = 120_000.0
    """The homing fails after this time [ms] (SetHomeTimeout)."""


def _positive(value: float, code: int, what: str, axis_id: int) -> float:
    if not (math.isfinite(value) and value > 0.0):
        raise AxisCommandError(code, f"axis {axis_id}: {what} {value!r} must be a positive number")
    return float(value)


class AxisHoming:
    """The homing state of one axis."""

    def __init__(self, axis) -> None:
        self.axis = axis
        self.settings = HomeSettings()
        self.run: HomingRun | None = None
        """The sequence in progress (or the last one)."""
        self.error = 0
        """0, or the low half of the axis error the last homing failed with."""
        self.message = ""
        """Why the last homing failed."""
        self._saved_ignore = (False, False)

    # ---- settings (20.3-20.8) -------------------------------------------------------

    def set_method(self, method: int) -> None:
        if method not in METHODS:
            raise AxisCommandError(
                st.CMD_INVALID_PARAMETER,
                f"axis {self.axis.axis_id}: homing method {method} is not one of "
                f"{', '.join(map(str, METHODS))}",
            )
        self.settings.method = method

    def set_switch_vel(self, vel: float) -> None:
        self.settings.switch_vel = _positive(
            vel, st.CMD_INVALID_VEL, "homing switch speed", self.axis.axis_id
        )

    def set_zero_vel(self, vel: float) -> None:
        self.settings.zero_vel = _positive(
            vel, st.CMD_INVALID_VEL, "homing zero speed", self.axis.axis_id
        )

    def set_acc(self, acc: float) -> None:
        self.settings.acc = _positive(
            acc, st.CMD_INVALID_ACC, "homing acceleration", self.axis.axis_id
        )

    def set_offset(self, offset: float) -> None:
        if not math.isfinite(offset):
            raise AxisCommandError(
                st.CMD_INVALID_POS, f"axis {self.axis.axis_id}: home offset {offset!r}"
            )
        self.settings.offset = float(offset)

    def set_timeout(self, ms: float) -> None:
        self.settings.timeout_ms = _positive(
            ms, st.CMD_INVALID_PARAMETER, "homing timeout [ms]", self.axis.axis_id
        )

    # ---- status (20.9-20.11) --------------------------------------------------------

    def _bits(self, on: int, off: int) -> None:
        self.axis.extra_status = (self.axis.extra_status | on) & ~off

    @property
    def homed(self) -> bool:
        return bool(self.axis.extra_status & st.MS_HOMED)

    @property
    def homing(self) -> bool:
        """True from `start()` until the home position is attained (see the module)."""
        self.poll()
        return bool(self.axis.extra_status & st.MS_HOMING)

    @property
    def running(self) -> bool:
        """True while a homing sequence drives the axis."""
        self.poll()
        return self.run is not None and not self.run.ended

    def set_homed(self, on: int) -> None:
        """SetHomedStatus: 1 homed, 0 not; a failed homing's `homing` flag is cleared."""
        if on not in (0, 1):
            raise AxisCommandError(
                st.CMD_INVALID_PARAMETER, f"axis {self.axis.axis_id}: is_homed {on} must be 0 or 1"
            )
        if self.running:
            raise AxisCommandError(st.CMD_INVALID_MOVING, f"axis {self.axis.axis_id} is homing")
        self._bits(st.MS_HOMED if on else 0, st.MS_HOMING | (0 if on else st.MS_HOMED))

    def poll(self) -> None:
        """Notice a sequence cut off from outside (Stop, Disable, a fault reaction)."""
        run = self.run
        if run is not None and not run.ended and self.axis.following is not run:
            run.error = DRIVE_HOME_FAILED
            run.message = "the homing was interrupted (the axis stopped or was disabled)"
            run.ended = True
            self._finish(run)

    # ---- MoveHome (20.2) ------------------------------------------------------------

    def start(self) -> None:
        """Start homing with the current settings; raises AxisCommandError if refused.

        Method 37 completes at once (even on a disabled axis); the others need the axis
        enabled, at rest, in CSP mode, and the switches and index their method uses.
        """
        a = self.axis
        a.wake()
        if self.running:
            raise AxisCommandError(st.CMD_INVALID_MOVING, f"axis {a.axis_id} is homing")
        if a.error_stop:
            raise AxisCommandError(
                st.CMD_INVALID_ERROR_STATE, f"axis {a.axis_id} is in error stop (call Reset)"
            )
        if a.moving:
            raise AxisCommandError(st.CMD_INVALID_MOVING, f"axis {a.axis_id} is moving")
        if a.filters.locks_origin:  # homing sets the origin, which compensation fixes (14.1)
            raise AxisCommandError(
                st.CMD_INVALID_COMP_ENABLED,
                f"axis {a.axis_id}: dynamic error compensation fixes its origin",
            )
        method = METHODS[self.settings.method]
        if method.number == 37:
            self.error, self.message = 0, ""
            self._rezero(a.pos_fb)
            self._bits(st.MS_HOMED, st.MS_HOMING)
            return
        if not a.enabled:
            raise AxisCommandError(st.CMD_INVALID_DISABLED, f"axis {a.axis_id} is not enabled")
        if a.op_mode != MODE_CSP:
            raise AxisCommandError(
                st.CMD_INVALID_CONTROL_MODE,
                f"axis {a.axis_id}: homing needs op mode 8 (CSP), not {a.op_mode}",
            )
        self.error, self.message = 0, ""
        self._bits(st.MS_HOMING, st.MS_HOMED)
        missing = _missing_signal(Switches(a.drive.sensors), method)
        if missing:
            self.error = DRIVE_HOME_FAILED
            self.message = f"axis {a.axis_id}: homing method {method.number} needs {missing}"
            raise AxisCommandError(DRIVE_HOME_FAILED, self.message)
        self._saved_ignore = (a.ignore_hwl, a.ignore_swl)
        a.set_ignore("hwl", 1)
        a.set_ignore("swl", 1)
        self.run = HomingRun(a, method, self.settings, self._end,
                             (DRIVE_HOME_TOUT, DRIVE_HOME_FAILED))  # fmt: skip
        a.follow(self.run)
        a.moving, a.in_pos = True, False  # as for an accepted move: at once

    def _end(self, run: HomingRun, p: float) -> tuple[float, float, float]:
        """The run has come to rest at p [mm]: re-zero on success, release the axis."""
        a = self.axis
        if not run.error:
            self._rezero(p)
            p = self.settings.offset
        a.release()
        self._finish(run)
        return p, 0.0, 0.0

    def _finish(self, run: HomingRun) -> None:
        a = self.axis
        hwl, swl = self._saved_ignore
        a.set_ignore("hwl", int(hwl))
        a.set_ignore("swl", int(swl))
        if run.error:
            self.error, self.message = run.error, f"axis {a.axis_id}: {run.message}"
            if not a.error_stop:  # a fault reaction's own code says more
                a.last_error = st.axis_error(run.error, a.axis_id)
        else:
            self._bits(st.MS_HOMED, st.MS_HOMING)

    def _rezero(self, home: float) -> None:
        """Make the position `home` [mm] read the home offset (as SetPos does)."""
        self.axis.shift_origin(home, self.settings.offset)


def _missing_signal(switches: Switches, method) -> str:
    """What the machine lacks for `method` ('' if nothing): the manual's "homing fails"."""
    need = []
    if method.switch is not None and switches.regions[method.switch] is None:
        need.append(f"a {method.switch}")
    if method.index and not switches.index_spacing:
        need.append("index pulses")
    return " and ".join(need) + (" (the machine has none)" if need else "")
