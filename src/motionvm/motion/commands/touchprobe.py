"""Chapter 13, touch probes: EnableTouchProbe ... SetTouchProbeFunc.

Each axis has one `motionvm.motion.touchprobe.TouchProbe` (the probe's function, the
drive's objects 0x60B8-0x60BD, the latched count in axis units). Enabling arms the
probe; its status follows in the drive's next cycle, hence the manual's
`Till(IsTouchProbeEnabled(axis))`. GetTouchProbePos returns `(status, position [mm or
deg])`. Errors: a bad axis id returns eERR_HMPL_ARG_OUT_OF_RANGE (Is* functions: 0); a
bad parameter eERR_AXIS_CMD_INVALID_PARAMETER; SetTouchProbeFunc on an enabled probe
eERR_AXIS_CMD_INVALID_TP_ENABLED (0x83XX010E).
"""

from __future__ import annotations

from motionvm.motion import axis_status as st
from motionvm.motion.commands.base import CommandBase

NO_SPECIFIC_PDO = 0x0258
"""eERR_AXIS_CMD_INVALID_NO_SPECIFIC_PDO, low half: the PDO lacks an object the command needs."""


class TouchProbeCommands(CommandBase):
    """Chapter 13: EnableTouchProbe ... SetTouchProbeFunc."""

    def EnableTouchProbe(self, axis_id: int) -> int:
        """Needs 0x60B8 in the drive's RxPDO (13.2), else
        eERR_AXIS_CMD_INVALID_NO_SPECIFIC_PDO (0x83XX0258)."""
        a = self._axis(axis_id)
        if a is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        if (0x60B8, 0) not in a.drive.objects.rx:
            return self._fail(a, NO_SPECIFIC_PDO)
        self.motion.probes[axis_id].enable()
        return 0

    def DisableTouchProbe(self, axis_id: int) -> int:
        if self._axis(axis_id) is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        self.motion.probes[axis_id].disable()
        return 0

    def IsTouchProbeEnabled(self, axis_id: int) -> int:
        if self._axis(axis_id) is None:
            return 0
        return 1 if self.motion.probes[axis_id].enabled else 0

    def IsTouchProbeTriggered(self, axis_id: int) -> int:
        if self._axis(axis_id) is None:
            return 0
        return 1 if self.motion.probes[axis_id].triggered else 0

    def GetTouchProbePos(self, axis_id: int) -> tuple[int, float]:
        """(0, the latched position [mm or deg]), or (the error code, 0.0)."""
        if self._axis(axis_id) is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE, 0.0
        return 0, self.motion.probes[axis_id].position

    def SetTouchProbeFunc(
        self, axis_id: int, tp_source: int, cont_trigger: int, detect_edge: int
    ) -> int:
        """tp_source 0: the encoder index, 1: the probe input; cont_trigger 0 single,
        1 continuous; detect_edge 0 positive, 1 negative (probe input only)."""
        a = self._axis(axis_id)
        if a is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        probe = self.motion.probes[axis_id]
        return self._run(a, probe.set_function, tp_source, cont_trigger, detect_edge)
