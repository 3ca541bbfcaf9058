"""Behaviour of the GDL hardware objects the RTS simulates: the device base, encoders, home inputs.

A device implements the operators of its type and keeps its state variables up to
date each cycle, writing through `Rts.write` with origin 'update' (so forcing, output
and activators work the same for every change). Motors (`motors.MotorDevice`) command
machine axes; encoders and home inputs follow a motor. Pure data objects (inputs,
outputs, variables, flags, boards) need no device.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Protocol

from motionvm.lang.gdl.app import ObjectInfo

if TYPE_CHECKING:
    from motionvm.lang.gdl.rts import Rts

V_EPS = 1e-9
"""Velocity below which a motor counts as standing still [units/s]."""


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

    def update(self, rts: Rts) -> None:
        """Bring the state variables up to date after the controller's motion step."""

    @property
    def busy(self) -> bool:
        """Still changing: the clock may not jump over the next cycle."""
        return False

    @property
    def transient(self) -> bool:
        """Will still change on its own (keeps a run without an end time going)."""
        return False


class Motion(Protocol):
    """What followers read of a motor (`motors.MotorDevice`), as of its last update."""

    position: float
    """Axis position [units], without the homing offset."""
    velocity: float
    """Axis velocity [units/s]; 0 from the cycle a move or stop arrives."""

    @property
    def busy(self) -> bool: ...


class FollowerDevice(Device):
    """A device whose state follows a motor's axis; busy until it has caught up with it.

    Being busy while out of date keeps the clock from jumping over its update, so a
    run gives the same output stepped or jumped.
    """

    motor_param = ""

    def __init__(self, obj: ObjectInfo) -> None:
        super().__init__(obj)
        self.motor: Motion | None = None
        self.seen: object = None

    def start(self, rts: Rts) -> None:
        from motionvm.lang.gdl.motors import MotorDevice  # motors builds on this module

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

    def update(self, rts: Rts) -> None:
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
        return self.motor.position <= switch  # type: ignore[operator]

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
        return (round(self.motor.position), abs(self.motor.velocity) > V_EPS)

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


FOLLOWER_CLASSES: dict[str, type[Device]] = {
    "STP$MOTOR$AXIS$HOME$INPUT": HomeInputDevice,
    "ABSOLUTE$ENCODER": EncoderDevice,
}

MOTOR_TYPES = ("DC$MOTOR$AXIS", "STEPPER$MOTOR", "STP$MOTOR$AXIS")
"""Object types that are machine axes (`motors.MotorDevice`)."""


def create_device(obj: ObjectInfo, axis: object = None) -> Device:
    """The device simulating `obj` (a do-nothing `Device` for pure data objects).

    A motor needs its machine axis (`motors.assign_axes`).
    """
    if obj.type.name in MOTOR_TYPES:
        from motionvm.lang.gdl.motors import MotorDevice  # motors builds on this module

        if axis is None:
            raise ValueError(f"motor {obj.name} has no machine axis")
        return MotorDevice(obj, axis)  # type: ignore[arg-type]
    return FOLLOWER_CLASSES.get(obj.type.name, Device)(obj)
