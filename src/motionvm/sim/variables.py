"""Named variables of a run, read and written by the host: the scope's channel names.

`Variables(registry, controller)` reads any channel of the run's `ChannelRegistry`
(sim/scope.py: HMPL globals and system variables, `gpi3`/`gpo5`, `axisN.<variable>`,
`gearN.*`, `gantryN.*`, `driveN.<name>`, `OBJECT.STATE`) and writes those that can be
written, at once (the next read sees the value):
- `gpiN`, `gpoN`, `slvS.diK` ...: the controller's and the slaves' I/O channels (an
  input at its pin, an output as a program sets it, an analog channel's raw word);
- `axisN.<variable>`: only the variables an HMPL Set* function sets (`WRITABLE_AXIS`),
  through `MotionCommands`, so the manual's checks and error codes apply;
- the sources of the languages that offer `write(name, value)` (True: written, False:
  not theirs; ValueError: refused): HMPL variables as an assignment stores them, PDL
  drive variables as the drive's host (KMI) write, GDL states as a scenario input.
Unknown names are a KeyError with the closest names; refused and read-only writes a
`WriteError`.
"""

from __future__ import annotations

import json
import re
from collections.abc import Callable
from dataclasses import make_dataclass
from importlib import resources

from motionvm.motion import axis_status as st
from motionvm.motion.axis_status import VARIABLES
from motionvm.motion.commands import MotionCommands
from motionvm.runtime.scope import ScopeError
from motionvm.sim.scope import Channel, ChannelRegistry

WRITABLE_AXIS = {
    "max_vel": "SetVel",
    "max_acc": "SetAcc",
    "max_dec": "SetDec",
    "sm_factor": "SetSMTime",
    "pos_fb": "SetPos",
}
"""Axis variable -> the HMPL function that sets it (manual 5.3); the others are read-only."""

_SETTERS: dict[str, Callable[[MotionCommands, int, float], int]] = {
    "SetVel": MotionCommands.SetVel,
    "SetAcc": MotionCommands.SetAcc,
    "SetDec": MotionCommands.SetDec,
    "SetSMTime": MotionCommands.SetSMTime,
    "SetPos": MotionCommands.SetPos,
}
"""The motion command of each function of `WRITABLE_AXIS`."""

_AXIS = re.compile(r"axis(\d+)\.(\w+)")


class WriteError(ValueError):
    """A write that cannot be done: a read-only variable, or a value the controller
    refuses (`code`: the manual's error code, e.g. 0x83000168; None if there is none)."""

    def __init__(self, message: str, code: int | None = None) -> None:
        super().__init__(message)
        self.code = code


def error_name(code: int) -> str:
    """`eERR_AXIS_CMD_INVALID_SM_TIME (0x83000168): the axis smoothing-time ...` for an
    error code of manual chapter 18 (a C int or its 32-bit value)."""
    value = code & 0xFFFFFFFF
    key = f"0x{value:08X}"
    axis_key = f"0x{value >> 24:02X}XX{value & 0xFFFF:04X}"
    for row in _error_table():
        if row["code"].upper() in (key.upper(), axis_key.upper()):
            return f"{row['name']} ({key}): {row['desc']}"
    return key


_ERRORS: list[dict] = []


def _error_table() -> list[dict]:
    if not _ERRORS:
        text = resources.files("motionvm.data").joinpath("hmpl_errors.json").read_text("utf-8")
        _ERRORS.extend(json.loads(text))
    return _ERRORS


class Variables:
    """Read and write the variables of one run by name (see the module docstring)."""

    def __init__(self, registry: ChannelRegistry, controller) -> None:
        self.registry = registry
        self.controller = controller
        self.commands = MotionCommands(controller.motion)
        self._channels: dict[str, Channel] = {}
        self._writers: list[Callable[[str, object], bool]] = [self._write_gpio, self._write_axis]
        self._writers.extend(source.write for source in registry.sources)

    def channel(self, name: str) -> Channel:
        """The channel `name` (KeyError with the closest names if there is none)."""
        ch = self._channels.get(name)
        if ch is None:
            try:
                ch = self.registry.resolve(name)
            except ScopeError as exc:
                raise KeyError(str(exc).replace("scope channel", "variable")) from None
            self._channels[name] = ch
        return ch

    def known(self, name: str) -> bool:
        """True if `name` is a channel of the run (without `channel`'s suggestions for
        an unknown name, which cost a comparison with every channel name)."""
        if name in self._channels:
            return True
        try:
            ch = self.registry.find(name)
        except ScopeError:
            return False
        if ch is not None:
            self._channels[name] = ch
        return ch is not None

    def read(self, name: str) -> float:
        """The value of `name` now, in the unit of its channel."""
        return self.channel(name).getter()

    def write(self, name: str, value: object) -> None:
        """Set `name` to `value` now (see the module docstring for what can be written)."""
        self.channel(name)
        for write in self._writers:
            try:
                if write(name, value):
                    return
            except WriteError:
                raise
            except (ValueError, TypeError, ScopeError) as exc:
                raise WriteError(f"cannot write {name} = {value!r}: {exc}") from None
        raise WriteError(f"'{name}' is read-only")

    def read_only(self, name: str) -> bool:
        """True for a channel known to refuse every write: the controller's bit sums,
        converted analog values and slave states; axis variables no Set* function sets;
        what a source says is read-only (the HMPL system time)."""
        if name in ("himc_gpi_bits", "himc_gpo_bits"):
            return True
        if name.startswith("slv") and name.endswith((".value", ".state")):
            return True
        m = _AXIS.fullmatch(name)
        if m is not None:
            return m.group(2) not in WRITABLE_AXIS
        return any(source.read_only(name) for source in self.registry.sources)

    def _write_gpio(self, name: str, value: object) -> bool:
        """An I/O channel (io/system.py): an input's pin, an output's state, a word."""
        found = self.controller.io.channel(name)
        if found is None:
            return False
        if found[1] is None:
            raise WriteError(f"'{name}' is read-only")
        found[1](value)
        return True

    def _write_axis(self, name: str, value: object) -> bool:
        m = _AXIS.fullmatch(name)
        if m is None:
            return False
        n, variable = int(m.group(1)), m.group(2)
        function = WRITABLE_AXIS.get(variable)
        if function is None:
            settable = ", ".join(f"{v} ({f})" for v, f in WRITABLE_AXIS.items())
            raise WriteError(
                f"axis variable '{name}' is read-only; the writable ones are those an HMPL "
                f"Set* function sets: {settable}"
            )
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise WriteError(f"{name} takes a number, not {value!r}")
        status = _SETTERS[function](self.commands, n, float(value))
        if status:
            raise WriteError(f"{function}({n}, {value!r}) refused: {error_name(status)}", status)
        return True


AXIS_FLAGS: dict[str, Callable[[object], object]] = {
    "enabled": lambda axis: axis.enabled,
    "moving": lambda axis: axis.moving,
    "in_pos": lambda axis: axis.in_pos,
    "error_stop": lambda axis: axis.error_stop,
    "stopping": lambda axis: axis.stopping,
    "halted": lambda axis: axis.halted,
    "accelerating": lambda axis: axis.motion_status & st.MS_ACCELERATING,
    "homing": lambda axis: axis.motion_status & st.MS_HOMING,
    "homed": lambda axis: axis.motion_status & st.MS_HOMED,
    "drive_fault": lambda axis: axis.fault_status & st.FS_DRIVE_FAULT,
    "position_error": lambda axis: axis.fault_status & st.FS_POSITION_ERROR,
    "hw_left": lambda axis: axis.fault_status & st.FS_HW_LEFT,  # at the left hardware limit
    "hw_right": lambda axis: axis.fault_status & st.FS_HW_RIGHT,
    "sw_left": lambda axis: axis.fault_status & st.FS_SW_LEFT,  # beyond the left soft limit
    "sw_right": lambda axis: axis.fault_status & st.FS_SW_RIGHT,
}
"""The status flags of an axis snapshot (manual 5.4: IsEnabled, IsMoving, IsInPos, ...):
flag name -> its test on a `motion.axis.Axis`."""


def _variable_type(unit: str) -> type:
    """An axis variable's Python type: int for words, bit sets and counts (no unit or a
    count unit), float for the rest (mm or deg, their rates, ms)."""
    return int if unit == "" or unit.startswith("count") else float


def _snapshot(cls, axis, sim_time: float):
    """The snapshot of `axis` (a `motion.axis.Axis`) at `sim_time` [s]."""
    flags = {name: bool(test(axis)) for name, test in AXIS_FLAGS.items()}
    values = {name: axis.variable(name) for name in VARIABLES}
    return cls(axis_id=axis.axis_id, sim_time=sim_time, **flags, **values)


AxisState = make_dataclass(
    "AxisState",
    [
        ("axis_id", int),
        ("sim_time", float),  # [s]
        *((name, bool) for name in AXIS_FLAGS),
        *((name, _variable_type(unit)) for name, unit in VARIABLES.items()),
    ],
    namespace={
        "__doc__": """One axis at one instant: the axis id, the time [s], the status flags
    (`AXIS_FLAGS`) and every axis variable of manual 5.1.1 by its manual name, in the
    manual's unit (`motion.axis_status.VARIABLES`: positions in mm or deg, the axis'
    unit). `AxisState.of(axis, sim_time)` takes the snapshot.""",
        "of": classmethod(_snapshot),
    },
    frozen=True,
    slots=True,
)
AxisState.__module__ = __name__
