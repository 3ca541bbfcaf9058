"""Behaviour of the GDL hardware objects the RTS simulates: motors, encoders, home inputs.

A device implements the operators of its type and keeps its state variables up to
date each cycle, writing through `Rts.write` with origin 'update' (so forcing, output
and activators work the same for every change). Motors drive an `axis.Axis`.
Pure data objects (inputs, outputs, variables, flags, boards) need no device.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from motionvm.lang.gdl.app import ObjectInfo
from motionvm.lang.gdl.axis import V_EPS, create_axis
from motionvm.lang.gdl.check_proc import dynamic_limit

if TYPE_CHECKING:
    from motionvm.lang.gdl.rts import Rts


class GdlFault(Exception):
    """A run-time error of a procedure: reported, the procedure aborted, the run goes on."""


class Device:
    """Base: no operators, nothing to update."""

    def __init__(self, obj: ObjectInfo) -> None:
        self.obj = obj

    def start(self, rts: Rts) -> None:
        """Set derived initial state (no events)."""

    def call(self, rts: Rts, op: str, args: list[int], element: int) -> None:
        raise GdlFault(f"{self.obj.type.name} has no operator {op}")

    def on_write(self, rts: Rts, keyword: str, element: int, value: object) -> None:
        """React to a change of one of this object's state variables."""

    def step(self, rts: Rts, dt: float) -> None:
        """Advance one cycle of `dt` [s]."""

    @property
    def busy(self) -> bool:
        return False

    @property
    def transient(self) -> bool:
        return False


class MotorDevice(Device):
    """DC$MOTOR$AXIS, STEPPER$MOTOR and STP$MOTOR$AXIS on a trapezoidal axis."""

    def __init__(self, obj: ObjectInfo) -> None:
        super().__init__(obj)
        self.axis = create_axis()
        self.offset = 0.0  # machine position of logical 0, set by homing
        self.homing = False
        self.home: ObjectInfo | None = None

    @property
    def a_max(self) -> float:
        return float(self.obj.params.get("ACCELERATION", 30000))  # type: ignore[arg-type]

    def start(self, rts: Rts) -> None:
        self.home = next(
            (
                o
                for o in rts.app.objects.values()
                if o.type.name == "STP$MOTOR$AXIS$HOME$INPUT"
                and o.params.get("STPMOTOR$NAME") == self.obj.key
            ),
            None,
        )

    def _require_ready(self, rts: Rts, op: str) -> None:
        if rts.read(self.obj, "CONSTANT$STATUS", 0) != "ENABLED":
            raise GdlFault(
                f"{op} OF {self.obj.name}: the motor is DISABLED (assign "
                f"CONSTANT$STATUS OF {self.obj.name} = ENABLED first)"
            )
        if rts.read(self.obj, "DIAGN$STATUS", 0) == "FAULT":
            raise GdlFault(f"{op} OF {self.obj.name}: DIAGN$STATUS is FAULT")

    def _check_limit(self, op: str, name: str, value: int, limit: str) -> None:
        dyn = dynamic_limit(self.obj, limit)
        if dyn is not None and not dyn[0] <= value <= dyn[1]:
            raise GdlFault(
                f"argument {name} of {op} = {value} is outside {dyn[2]} "
                f"{dyn[0]}..{dyn[1]} of {self.obj.name}"
            )

    def call(self, rts: Rts, op: str, args: list[int], element: int) -> None:
        if op == "STOP":
            self.homing = False
            self.axis.stop(self.a_max)
            return
        self._require_ready(rts, op)
        if op == "RUN$AT$SPEED":
            self._check_limit(op, "speed", args[0], "max_speed")
            self.homing = False
            self.axis.run_at(args[0], self.a_max)
        elif op == "MOVE$TO":
            self._check_limit(op, "position", args[0], "travel")
            self.homing = False
            speed = float(self.obj.params.get("MAX$SPEED", 3000))  # type: ignore[arg-type]
            self.axis.move_to(args[0] + self.offset, speed, self.a_max)
        elif op == "HOME$SEARCH":
            if self.home is None:
                raise GdlFault(
                    f"HOME$SEARCH OF {self.obj.name}: no STP$MOTOR$AXIS$HOME$INPUT names this axis"
                )
            self.homing = True
            rts.write(self.obj, "HOMED", 0, False, rts.origin())
            speed = float(self.obj.params.get("HOME$SPEED", 100))  # type: ignore[arg-type]
            self.axis.run_at(-speed, self.a_max)
        else:
            super().call(rts, op, args, element)
        if self.axis.busy:
            rts.write(self.obj, "OPERATING$CONDITION", 0, "RUNNING", rts.origin())

    def on_write(self, rts: Rts, keyword: str, element: int, value: object) -> None:
        if keyword == "CONSTANT$STATUS" and value == "DISABLED":
            self.homing = False
            self.axis.halt()
            rts.write(self.obj, "SPEED", 0, 0, rts.origin())
            rts.write(self.obj, "OPERATING$CONDITION", 0, "STOPPED", rts.origin())

    def step(self, rts: Rts, dt: float) -> None:
        if not self.axis.busy and not self.homing:
            return
        self.axis.step(dt)
        if self.homing and self.home is not None:
            rts.device(self.home).step(rts, dt)
            if rts.read(self.home, "STATUS", 0):
                self.axis.halt()
                self.homing = False
                self.offset = self.axis.position
                rts.write(self.obj, "HOMED", 0, True, "update")
        rts.write(self.obj, "SPEED", 0, round(self.axis.velocity), "update")
        if self.obj.type.state("POSITION") is not None:
            rts.write(self.obj, "POSITION", 0, round(self.axis.position - self.offset), "update")
        if not self.axis.busy and not self.homing:
            rts.write(self.obj, "OPERATING$CONDITION", 0, "STOPPED", "update")

    @property
    def busy(self) -> bool:
        return self.axis.busy or self.homing

    @property
    def transient(self) -> bool:
        return self.axis.transient or self.homing


class HomeInputDevice(Device):
    """STP$MOTOR$AXIS$HOME$INPUT: ON while the axis is at or below SWITCH$POSITION."""

    def _motor(self, rts: Rts) -> MotorDevice:
        axis_obj = rts.app.objects[str(self.obj.params["STPMOTOR$NAME"])]
        dev = rts.device(axis_obj)
        assert isinstance(dev, MotorDevice)
        return dev

    def start(self, rts: Rts) -> None:
        self._update(rts, init=True)

    def step(self, rts: Rts, dt: float) -> None:
        self._update(rts, init=False)

    def _update(self, rts: Rts, init: bool) -> None:
        motor = self._motor(rts)
        switch = self.obj.params.get("SWITCH$POSITION", 0)
        on = motor.axis.position <= switch  # type: ignore[operator]
        if init:
            rts.init_value(self.obj, "STATUS", 0, on)
        else:
            rts.write(self.obj, "STATUS", 0, on, "update")


class EncoderDevice(Device):
    """ABSOLUTE$ENCODER, following the axis named by AXIS$NAME when there is one."""

    def __init__(self, obj: ObjectInfo) -> None:
        super().__init__(obj)
        self.preset = 0

    def _motor(self, rts: Rts) -> MotorDevice | None:
        key = self.obj.params.get("AXIS$NAME")
        if not isinstance(key, str):
            return None
        dev = rts.device(rts.app.objects[key])
        return dev if isinstance(dev, MotorDevice) else None

    def _raw(self, rts: Rts) -> int:
        motor = self._motor(rts)
        return round(motor.axis.position) if motor is not None else 0

    def call(self, rts: Rts, op: str, args: list[int], element: int) -> None:
        if op == "CONFIGURE":
            rts.write(self.obj, "CFG$STATUS", 0, "CONFIGURED", rts.origin())
            rts.write(self.obj, "CFG$UPDATE$REQUEST", 0, False, rts.origin())
        elif op == "PRESET":
            self.preset = args[0] - self._raw(rts)
            rts.write(self.obj, "POSITION", 0, args[0], rts.origin())
        else:
            super().call(rts, op, args, element)

    def on_write(self, rts: Rts, keyword: str, element: int, value: object) -> None:
        if keyword == "CFG$UPDATE$REQUEST" and value is True:
            rts.write(self.obj, "CFG$STATUS", 0, "NOT$CONFIGURED", "update")

    def step(self, rts: Rts, dt: float) -> None:
        motor = self._motor(rts)
        if motor is None:
            return
        rts.write(self.obj, "POSITION", 0, self._raw(rts) + self.preset, "update")
        moving = abs(motor.axis.velocity) > V_EPS
        rts.write(self.obj, "OPERATING$CONDITION", 0, "RUNNING" if moving else "STOPPED", "update")


DEVICE_CLASSES: dict[str, type[Device]] = {
    "DC$MOTOR$AXIS": MotorDevice,
    "STEPPER$MOTOR": MotorDevice,
    "STP$MOTOR$AXIS": MotorDevice,
    "STP$MOTOR$AXIS$HOME$INPUT": HomeInputDevice,
    "ABSOLUTE$ENCODER": EncoderDevice,
}


def create_device(obj: ObjectInfo) -> Device:
    """The device simulating `obj` (a do-nothing `Device` for pure data objects)."""
    return DEVICE_CLASSES.get(obj.type.name, Device)(obj)
