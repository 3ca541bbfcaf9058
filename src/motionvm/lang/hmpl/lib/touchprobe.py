"""HMPL touch probe functions of manual chapter 13, on the drive's CiA 402 touch probe objects.

The functions write the touch probe function object 0x60B8 and read the status 0x60B9
and the latched positions 0x60BA-0x60BD of the axis's drive (`drives/sensors.py` has the
bit layout). SetTouchProbeFunc chooses, per axis:
- the probe (tp_source): 0 = touch probe 1 latching the encoder index pulse (13.1,
  the default), 1 = touch probe 2 latching the drive's touch probe input (digital input
  bit 17, which the plant wiring sets);
- single (0, default) or continuous (1) triggering;
- the edge: 0 positive (default), 1 negative. The simulated index pulse has no width, so
  its falling edge is where its rising edge is: probe 1 always samples the index's
  rising edge (0x60BA), and detect_edge only matters for probe 2.
EnableTouchProbe arms the probe (re-enabling after DisableTouchProbe re-arms a single
trigger); the status follows in the drive's next cycle, hence the manual's
`Till(IsTouchProbeEnabled(axis))`. GetTouchProbePos gives the latched position in axis
units [mm or deg] (feedback coordinates, SetPos offset applied) -- whatever the latch
holds, also before a trigger. Errors: a bad axis id returns eERR_HMPL_ARG_OUT_OF_RANGE;
a bad parameter eERR_AXIS_CMD_INVALID_PARAMETER; SetTouchProbeFunc on an enabled probe
eERR_AXIS_CMD_INVALID_TP_ENABLED (0x83XX010E).
"""

from __future__ import annotations

from motionvm.drives.objects import TOUCH_PROBE_1_POS, wrap_i32
from motionvm.lang.hmpl.lib.axis_base import AxisLibrary
from motionvm.lang.hmpl.lib.base import builtin
from motionvm.motion import axis_status as st

CMD_INVALID_TP_ENABLED = 0x010E
"""eERR_AXIS_CMD_INVALID_TP_ENABLED, low half (table 18.1.2.1)."""

_ENABLE, _CONTINUOUS, _INDEX, _POSITIVE, _NEGATIVE = 0x01, 0x02, 0x04, 0x10, 0x20
_STORED_POSITIVE, _STORED_NEGATIVE = 0x02, 0x04


class TouchProbeLib(AxisLibrary):
    """Chapter 13: EnableTouchProbe ... SetTouchProbeFunc."""

    def __init__(self, rt) -> None:
        super().__init__(rt)
        self._func: dict[int, tuple[int, int, int]] = {}
        """axis id -> (probe 0/1, continuous 0/1, edge 0/1) set by SetTouchProbeFunc."""

    def _setup(self, axis_id: int) -> tuple[int, int, int]:
        return self._func.get(axis_id, (0, 0, 0))

    def _edge_of(self, axis_id: int) -> int:
        """0 positive, 1 negative: the edge the probe's latch and status bit are for."""
        probe, _cont, edge = self._setup(axis_id)
        return edge if probe == 1 else 0

    def _fail(self, a, code: int) -> int:
        a.last_error = err = st.axis_error(code, a.axis_id)
        return err

    @builtin()
    def EnableTouchProbe(self, axis_id: int) -> int:
        a = self._axis(axis_id)
        if a is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        probe, cont, _edge = self._setup(axis_id)
        f = _ENABLE | (_CONTINUOUS if cont else 0)
        if probe == 0:
            f |= _INDEX | _POSITIVE
        else:
            f |= _NEGATIVE if self._edge_of(axis_id) else _POSITIVE
        d = a.drive
        shift = 8 * probe
        d.tp_function = (d.tp_function & ~(0xFF << shift)) | f << shift
        a.wake()
        return 0

    @builtin()
    def DisableTouchProbe(self, axis_id: int) -> int:
        a = self._axis(axis_id)
        if a is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        d = a.drive
        d.tp_function &= ~(0xFF << 8 * self._setup(axis_id)[0])
        a.wake()
        return 0

    @builtin()
    def IsTouchProbeEnabled(self, axis_id: int) -> int:
        a = self._axis(axis_id)
        if a is None:
            return 0
        return 1 if a.drive.tp_status >> 8 * self._setup(axis_id)[0] & 0x01 else 0

    @builtin()
    def IsTouchProbeTriggered(self, axis_id: int) -> int:
        a = self._axis(axis_id)
        if a is None:
            return 0
        bit = _STORED_NEGATIVE if self._edge_of(axis_id) else _STORED_POSITIVE
        return 1 if a.drive.tp_status >> 8 * self._setup(axis_id)[0] & bit else 0

    @builtin()
    def GetTouchProbePos(self, axis_id: int, output: int) -> int:
        a = self._axis(axis_id)
        if a is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        self.mem.check(output, 8, "GetTouchProbePos output")
        d = a.drive
        latched = d.read(TOUCH_PROBE_1_POS + 2 * self._setup(axis_id)[0] + self._edge_of(axis_id))
        # unwrap the int32 latch next to the current feedback count
        counts = round(a.pos_fb_raw * a.cpu) + wrap_i32(latched - d.position_actual)
        self.mem.store(output, "f64", counts / a.cpu - a.pos_offset)
        return 0

    @builtin()
    def SetTouchProbeFunc(
        self, axis_id: int, tp_source: int, cont_trigger: int, detect_edge: int
    ) -> int:
        a = self._axis(axis_id)
        if a is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        if any(v not in (0, 1) for v in (tp_source, cont_trigger, detect_edge)):
            return self._fail(a, st.CMD_INVALID_PARAMETER)
        if a.drive.tp_function & (_ENABLE | _ENABLE << 8):
            return self._fail(a, CMD_INVALID_TP_ENABLED)
        self._func[axis_id] = (tp_source, cont_trigger, detect_edge)
        return 0
