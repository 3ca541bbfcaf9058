"""One factory for the device of every GDL object type: motors (motors.py), followers and
plain data objects (devices.py). It stands above both, so that neither imports the other
back."""

from __future__ import annotations

from motionvm.lang.gdl.app import ObjectInfo
from motionvm.lang.gdl.devices import FOLLOWER_CLASSES, MOTOR_TYPES, Device
from motionvm.lang.gdl.motors import MotorDevice


def create_device(obj: ObjectInfo, axis: object = None) -> Device:
    """The device simulating `obj` (a do-nothing `Device` for pure data objects).

    A motor needs its machine axis (`motors.assign_axes`).
    """
    if obj.type.name in MOTOR_TYPES:
        if axis is None:
            raise ValueError(f"motor {obj.name} has no machine axis")
        return MotorDevice(obj, axis)  # type: ignore[arg-type]
    return FOLLOWER_CLASSES.get(obj.type.name, Device)(obj)
