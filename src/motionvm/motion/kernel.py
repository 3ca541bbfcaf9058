"""The motion kernel: every axis of the machine, the simulated EtherCAT bus, last errors.

Stepped once per controller cycle after the tasks (`step`). The bus master's state
(GetECATSt: 1 Init, 2 Pre-Operation, 4 Safe-Operation, 8 Operation) is Operation from
power-on; ScanNetwork takes it down to Init and back up one state per cycle, and the
drives cannot be enabled until it is back in Operation. Slave i is axis i's drive.
Group last errors live here for the group functions to come (16 groups).
"""

from __future__ import annotations

from motionvm.motion import axis_status as st
from motionvm.motion.axis import Axis
from motionvm.motion.axis_config import AxisConfig

ECAT_INIT, ECAT_PREOP, ECAT_SAFEOP, ECAT_OP = 1, 2, 4, 8
N_GROUPS = 16


class MotionKernel:
    """All axes of one controller and the bus they sit on."""

    def __init__(self, configs: list[AxisConfig], dt: float):
        self.dt = dt
        self.axes = [Axis(i, c, dt) for i, c in enumerate(configs)]
        self.step_order = list(self.axes)
        """The order the axes step in: by id, gear masters first (motion/gear.py)."""
        self.ecat_state = ECAT_OP
        """Master state of the bus [1, 2, 4, 8]."""
        self.system_last_error = 0
        self.group_last_error = [0] * N_GROUPS
        self.estopped = False
        """True after EStop: IsSystemError answers 1."""
        self._bus_steps: list[int] = []

    @property
    def n_axes(self) -> int:
        return len(self.axes)

    def axis(self, axis_id: int) -> Axis | None:
        """Axis `axis_id`, or None if there is no such axis."""
        if 0 <= axis_id < len(self.axes):
            return self.axes[axis_id]
        return None

    # ---- the cycle ------------------------------------------------------------------

    def step(self) -> None:
        """The motion phase of one cycle: the bus, then every axis in id order."""
        if self._bus_steps:
            self.ecat_state = self._bus_steps.pop(0)
        for a in self.step_order:
            a.step()

    def busy(self) -> bool:
        """True while an axis moves, enables, settles or stops, or the bus starts up."""
        if self._bus_steps:
            return True
        for a in self.axes:
            if a.moving or a._enabling or (a.enabled and not a.in_pos):
                return True
        return False

    def at_rest(self) -> bool:
        """True if no axis needs stepping: the controller may then jump ahead in time."""
        if self._bus_steps:
            return False
        for a in self.axes:
            if not a.resting:
                return False
        return True

    # ---- bus and system (manual 2.5-2.10, 2.15) -------------------------------------

    def slave_state(self, slave_id: int) -> int:
        """State of slave `slave_id` (0 if there is no such slave)."""
        if not 0 <= slave_id < len(self.axes):
            return 0
        return self.ecat_state

    def scan_network(self) -> int:
        """Rescan: the bus goes Init -> Pre-Op -> Safe-Op -> Op, one state per cycle.

        Refused (eERR_AXIS_CMD_INVALID_ENABLED of the first enabled axis) while an axis
        is enabled, as a rescan would cut the drives off.
        """
        for a in self.axes:
            if a.enabled or a._enabling:
                return st.axis_error(st.CMD_INVALID_ENABLED, a.axis_id)
        self.ecat_state = ECAT_INIT
        self._bus_steps = [ECAT_PREOP, ECAT_SAFEOP, ECAT_OP]
        return 0

    def disable_all(self) -> None:
        for a in self.axes:
            a.disable()

    def stop_all(self) -> None:
        """Stop every axis at its kill deceleration; the axes stay enabled."""
        for a in self.axes:
            a.stop(a.kill_dec)

    def estop(self) -> None:
        """Emergency stop: disable every axis; the system reports an error."""
        self.disable_all()
        self.estopped = True
        self.system_last_error = st.SYS_EMERGENCY_STOP
