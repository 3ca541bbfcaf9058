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


class FollowerDevice(Device):
    """A device whose state follows a motor's axis; busy until it has caught up with it.

    Being busy while out of date keeps the clock from jumping over its update, so a
    run gives the same output stepped or jumped.
    """

    motor_param = ""

    def __init__(self, obj: ObjectInfo) -> None:
        super().__init__(obj)
        self.motor: MotorDevice | None = None
        self.seen: object = None

    def start(self, rts: Rts) -> None:
        key = self.obj.params.get(self.motor_param)
        dev = rts.device(rts.app.objects[key]) if isinstance(key, str) else None
        self.motor = dev if isinstance(dev, MotorDevice) else None
        self.seen = self.sample()
        self.publish(rts, self.seen, init=True)

    def sample(self) -> object:
        """The state this device shows for the axis as it is now."""
        return None

    def publish(self, rts: Rts, state: object, init: bool) -> None:
        """Write `state` into the state variables (as initial values when `init`)."""

    def step(self, rts: Rts, dt: float) -> None:
        if self.motor is None:
            return
        state = self.sample()
        self.publish(rts, state, init=False)
        self.seen = state

    @property
    def busy(self) -> bool:
        return self.motor is not None and (self.motor.busy or self.sample() != self.seen)

    @property
    def transient(self) -> bool:
        return self.busy


class HomeInputDevice(FollowerDevice):
    """STP$MOTOR$AXIS$HOME$INPUT: ON while the axis is at or below SWITCH$POSITION."""

    motor_param = "STPMOTOR$NAME"

    def sample(self) -> object:
        assert self.motor is not None
        switch = self.obj.params.get("SWITCH$POSITION", 0)
        return self.motor.axis.position <= switch  # type: ignore[operator]

    def publish(self, rts: Rts, state: object, init: bool) -> None:
        if init:
            rts.init_value(self.obj, "STATUS", 0, state)
        else:
            rts.write(self.obj, "STATUS", 0, state, "update")


class EncoderDevice(FollowerDevice):
    """ABSOLUTE$ENCODER, following the axis named by AXIS$NAME when there is one."""

    motor_param = "AXIS$NAME"

    def __init__(self, obj: ObjectInfo) -> None:
        super().__init__(obj)
        self.preset = 0

    def sample(self) -> object:
        if self.motor is None:
            return (0, False)
        axis = self.motor.axis
        return (round(axis.position), abs(axis.velocity) > V_EPS)

    def publish(self, rts: Rts, state: object, init: bool) -> None:
        if init or self.motor is None:
            return  # starts at POSITION 0, STOPPED, like the axis
        raw, moving = state  # type: ignore[misc]
        rts.write(self.obj, "POSITION", 0, raw + self.preset, "update")
        rts.write(self.obj, "OPERATING$CONDITION", 0, "RUNNING" if moving else "STOPPED", "update")

    def call(self, rts: Rts, op: str, args: list[int], element: int) -> None:
        if op == "CONFIGURE":
            rts.write(self.obj, "CFG$STATUS", 0, "CONFIGURED", rts.origin())
            rts.write(self.obj, "CFG$UPDATE$REQUEST", 0, False, rts.origin())
        elif op == "PRESET":
            raw = self.sample()[0]  # type: ignore[index]
            self.preset = args[0] - raw
            rts.write(self.obj, "POSITION", 0, args[0], rts.origin())
        else:
            super().call(rts, op, args, element)

    def on_write(self, rts: Rts, keyword: str, element: int, value: object) -> None:
        if keyword == "CFG$UPDATE$REQUEST" and value is True:
            rts.write(self.obj, "CFG$STATUS", 0, "NOT$CONFIGURED", "update")


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
