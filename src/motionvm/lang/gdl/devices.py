"""Behaviour of the GDL hardware objects the RTS simulates: the device base, encoders, home inputs.

A device implements the operators of its type and keeps its state variables up to
date each cycle, writing through `Rts.write` with origin 'update' (so forcing, output
and activators work the same for every change). Motors (`motors.MotorDevice`) command
machine axes; encoders and home inputs follow a motor. Pure data objects (inputs,
outputs, variables, flags, boards) need no device.
"""

from __future__ import annotations

from typing import Protocol

from motionvm.lang.gdl.app import App, ObjectInfo, ProcInfo

V_EPS = 1e-9
"""Velocity below which a motor counts as standing still [units/s]."""


class GdlFault(Exception):
    """A run-time error of a procedure: reported, the procedure aborted, the run goes on."""


class RtsView(Protocol):
    """What devices and the generated code's API use of the run-time support
    (`rts.Rts`, which hands itself to them)."""

    app: App

    def device(self, obj: ObjectInfo) -> Device:
        """The device simulating `obj`."""

    def read(self, obj: ObjectInfo, keyword: str, element: int) -> object:
        """The value a procedure sees (the forced one if forced)."""

    def init_value(self, obj: ObjectInfo, keyword: str, element: int, value: object) -> None:
        """Set a value before the run starts: not an event."""

    def origin(self) -> str:
        """'set' while a procedure runs, else 'update'."""

    def write(
        self, obj: ObjectInfo, keyword: str, element: int, value: object, origin: str
    ) -> bool:
        """Store a value; on a visible change print it, run device hooks, trigger."""

    def before_instruction(self, proc: ProcInfo, line: int) -> None:
        """Called before each instruction of a procedure (the debugger's hook)."""


class Device:
    """Base: no operators, nothing to update."""

    def __init__(self, obj: ObjectInfo) -> None:
        self.obj = obj

    def start(self, rts: RtsView) -> None:
        """Set derived initial state (no events)."""

    def call(self, rts: RtsView, op: str, args: list[int], element: int) -> None:
        raise GdlFault(f"{self.obj.type.name} has no operator {op}")

    def on_write(self, rts: RtsView, keyword: str, element: int, value: object) -> None:
        """React to a change of one of this object's state variables."""

    def update(self, rts: RtsView) -> None:
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

    def start(self, rts: RtsView) -> None:
        key = self.obj.params.get(self.motor_param)
        dev = rts.device(rts.app.objects[key]) if isinstance(key, str) else None
        # a motor object's device is a `motors.MotorDevice` (`device_factory.py`)
        self.motor = dev if dev is not None and dev.obj.type.name in MOTOR_TYPES else None  # type: ignore[assignment]
        self.seen = self.sample()
        self.publish(rts, self.seen, init=True)

    def sample(self) -> object:
        """The state this device shows for the axis as it is now."""
        return None

    def publish(self, rts: RtsView, state: object, init: bool) -> None:
        """Write `state` into the state variables (as initial values when `init`)."""

    def update(self, rts: RtsView) -> None:
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

    def publish(self, rts: RtsView, state: object, init: bool) -> None:
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

    def publish(self, rts: RtsView, state: object, init: bool) -> None:
        if init or self.motor is None:
            return  # starts at POSITION 0, STOPPED, like the axis
        raw, moving = state  # type: ignore[misc]
        rts.write(self.obj, "POSITION", 0, raw + self.preset, "update")
        rts.write(self.obj, "OPERATING$CONDITION", 0, "RUNNING" if moving else "STOPPED", "update")

    def call(self, rts: RtsView, op: str, args: list[int], element: int) -> None:
        if op == "CONFIGURE":
            rts.write(self.obj, "CFG$STATUS", 0, "CONFIGURED", rts.origin())
            rts.write(self.obj, "CFG$UPDATE$REQUEST", 0, False, rts.origin())
        elif op == "PRESET":
            raw = self.sample()[0]  # type: ignore[index]
            self.preset = args[0] - raw
            rts.write(self.obj, "POSITION", 0, args[0], rts.origin())
        else:
            super().call(rts, op, args, element)

    def on_write(self, rts: RtsView, keyword: str, element: int, value: object) -> None:
        if keyword == "CFG$UPDATE$REQUEST" and value is True:
            rts.write(self.obj, "CFG$STATUS", 0, "NOT$CONFIGURED", "update")


FOLLOWER_CLASSES: dict[str, type[Device]] = {
    "STP$MOTOR$AXIS$HOME$INPUT": HomeInputDevice,
    "ABSOLUTE$ENCODER": EncoderDevice,
}

MOTOR_TYPES = ("DC$MOTOR$AXIS", "STEPPER$MOTOR", "STP$MOTOR$AXIS")
"""Object types that are machine axes (`motors.MotorDevice`)."""
