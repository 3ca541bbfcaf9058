"""The touch probe of one axis (HIMC manual chapter 13) on its drive's CiA 402 objects.

The probe writes the touch probe function object 0x60B8 and reads the status 0x60B9
and the latched positions 0x60BA-0x60BD of the axis's drive (`drives/sensors.py` has
the bit layout). Its function (SetTouchProbeFunc) chooses:
- the probe (`source`): 0 = touch probe 1 latching the encoder index pulse (13.1, the
  default), 1 = touch probe 2 latching the drive's touch probe input (digital input
  bit 17, which the plant wiring sets);
- single (0, default) or continuous (1) triggering;
- the edge: 0 positive (default), 1 negative. The simulated index pulse has no width, so
  its falling edge is where its rising edge is: probe 1 always samples the index's
  rising edge (0x60BA), and the edge only matters for probe 2.
Enabling arms the probe (re-enabling after disabling re-arms a single trigger); the
status follows in the drive's next cycle. `position` converts the latched count into
axis units [mm or deg] (feedback coordinates, SetPos offset applied) -- whatever the
latch holds, also before a trigger. The motion kernel keeps one probe per axis
(`MotionKernel.probes[axis_id]`).
"""

from __future__ import annotations

from motionvm.drives.objects import TOUCH_PROBE_1_POS, wrap_i32
from motionvm.motion import axis_status as st
from motionvm.motion.axis_status import AxisCommandError

CMD_INVALID_TP_ENABLED = 0x010E
"""eERR_AXIS_CMD_INVALID_TP_ENABLED, low half (table 18.1.2.1)."""

# bits of one probe's byte in 0x60B8 (function) and 0x60B9 (status)
_ENABLE, _CONTINUOUS, _INDEX, _POSITIVE, _NEGATIVE = 0x01, 0x02, 0x04, 0x10, 0x20
_STORED_POSITIVE, _STORED_NEGATIVE = 0x02, 0x04


class TouchProbe:
    """The touch probe function of one axis and its drive's probe objects."""

    def __init__(self, axis) -> None:
        self.axis = axis
        self.source = 0
        """0: probe 1 on the encoder index; 1: probe 2 on the drive's probe input."""
        self.continuous = 0
        """0: single trigger; 1: continuous."""
        self.edge = 0
        """0: positive edge; 1: negative edge (probe 2 only)."""

    def _latch_edge(self) -> int:
        """0 positive, 1 negative: the edge the probe's latch and status bit are for."""
        return self.edge if self.source == 1 else 0

    def set_function(self, source: int, continuous: int, edge: int) -> None:
        """SetTouchProbeFunc: each argument 0 or 1; refused while a probe is enabled."""
        a = self.axis
        if any(v not in (0, 1) for v in (source, continuous, edge)):
            raise AxisCommandError(
                st.CMD_INVALID_PARAMETER,
                f"axis {a.axis_id}: touch probe function ({source}, {continuous}, {edge}) "
                "takes 0 or 1 each",
            )
        if a.drive.tp_function & (_ENABLE | _ENABLE << 8):
            raise AxisCommandError(
                CMD_INVALID_TP_ENABLED, f"axis {a.axis_id}: the touch probe is enabled"
            )
        self.source, self.continuous, self.edge = source, continuous, edge

    def enable(self) -> None:
        """Arm the probe with its function (EnableTouchProbe)."""
        f = _ENABLE | (_CONTINUOUS if self.continuous else 0)
        if self.source == 0:
            f |= _INDEX | _POSITIVE
        else:
            f |= _NEGATIVE if self._latch_edge() else _POSITIVE
        d = self.axis.drive
        shift = 8 * self.source
        d.tp_function = (d.tp_function & ~(0xFF << shift)) | f << shift
        self.axis.wake()

    def disable(self) -> None:
        """Disarm the probe (DisableTouchProbe)."""
        self.axis.drive.tp_function &= ~(0xFF << 8 * self.source)
        self.axis.wake()

    @property
    def enabled(self) -> bool:
        """The drive reports the probe enabled (IsTouchProbeEnabled)."""
        return bool(self.axis.drive.tp_status >> 8 * self.source & 0x01)

    @property
    def triggered(self) -> bool:
        """The drive has latched a position on the probe's edge (IsTouchProbeTriggered)."""
        bit = _STORED_NEGATIVE if self._latch_edge() else _STORED_POSITIVE
        return bool(self.axis.drive.tp_status >> 8 * self.source & bit)

    @property
    def position(self) -> float:
        """The latched position [mm or deg] (GetTouchProbePos), see the module docstring."""
        a = self.axis
        d = a.drive
        latched = d.read(TOUCH_PROBE_1_POS + 2 * self.source + self._latch_edge())
        # unwrap the int32 latch next to the current feedback count
        counts = round(a.pos_fb_raw * a.cpu) + wrap_i32(latched - d.position_actual)
        return counts / a.cpu - a.slave_offset
