"""The axis behind a GDL motor object: a small interface, a stand-in and an adapter.

The RTS talks to motors only through `Axis`. `create_axis` returns the stand-in
`TrapezoidAxis`; `ProfileAxis` adapts `motionvm.motion.profile.ProfileGenerator` (the
manual's profile generator) to the same interface, ready to be switched on. The stand-in integrates
one cycle at a time (no jerk limit): velocity moves toward its target by at most
`a_max * dt` per cycle; a positioning move brakes when the discrete stopping distance
reaches the remaining distance and snaps onto the target when it would pass it. Units are the GDL object's: position [units], velocity [units/s],
acceleration [units/s^2].
"""

from __future__ import annotations

import math
from typing import Protocol

V_EPS = 1e-9
"""Velocity below which an axis counts as standing still [units/s]."""


class Axis(Protocol):
    """What a GDL motor object needs from an axis model."""

    position: float
    velocity: float

    def move_to(self, p_f: float, v_max: float, a_max: float) -> None: ...
    def run_at(self, v: float, a_max: float) -> None: ...
    def stop(self, a_max: float) -> None: ...
    def halt(self) -> None: ...
    def step(self, dt: float) -> None: ...
    @property
    def busy(self) -> bool: ...
    @property
    def transient(self) -> bool: ...


class TrapezoidAxis:
    """Trapezoidal velocity profile, integrated cycle by cycle (see the module docstring)."""

    def __init__(self) -> None:
        self.position = 0.0
        self.velocity = 0.0
        self.a_max = 1.0
        self.v_target = 0.0
        self.p_target: float | None = None
        self.v_max = 0.0

    def move_to(self, p_f: float, v_max: float, a_max: float) -> None:
        """Start a positioning move to `p_f` [units]."""
        self.p_target, self.v_max, self.a_max = float(p_f), abs(v_max), a_max

    def run_at(self, v: float, a_max: float) -> None:
        """Ramp to the constant velocity `v` [units/s] and keep it."""
        self.p_target, self.v_target, self.a_max = None, float(v), a_max

    def stop(self, a_max: float) -> None:
        """Ramp down to standstill with deceleration `a_max`."""
        self.run_at(0.0, a_max)

    def halt(self) -> None:
        """Stop at once (power cut): no ramp."""
        self.p_target, self.v_target, self.velocity = None, 0.0, 0.0

    @property
    def busy(self) -> bool:
        """Moving, or about to move."""
        if self.p_target is not None:
            return True
        return abs(self.velocity) > V_EPS or abs(self.v_target) > V_EPS

    @property
    def transient(self) -> bool:
        """Changing in a way that will end in an event (arrival, standstill, reaching speed)."""
        if self.p_target is not None:
            return True
        return abs(self.velocity - self.v_target) > V_EPS

    def step(self, dt: float) -> None:
        """Advance by one cycle of `dt` [s]."""
        dv = self.a_max * dt
        if self.p_target is not None:
            remaining = self.p_target - self.position
            direction = 1.0 if remaining > 0 else -1.0
            # Largest speed from which whole cycles of braking by dv stop exactly in
            # `remaining`: d = dt * dv * n (n + 1) / 2 with v = n dv.
            v_brake = dv * (math.sqrt(0.25 + 2.0 * abs(remaining) / (dv * dt)) - 0.5)
            v_want = direction * min(self.v_max, v_brake)
            self.velocity += max(-dv, min(dv, v_want - self.velocity))
            self.position += self.velocity * dt
            left = self.p_target - self.position
            if abs(left) < 1e-6 or (left > 0) != (remaining > 0):
                self.position, self.velocity, self.p_target = self.p_target, 0.0, None
                self.v_target = 0.0
            return
        self.velocity += max(-dv, min(dv, self.v_target - self.velocity))
        if abs(self.velocity - self.v_target) < V_EPS:
            self.velocity = self.v_target
        self.position += self.velocity * dt


class ProfileAxis:
    """Adapter onto `motionvm.motion.profile.ProfileGenerator` (T-curve, no smoothing).

    Ready for the switch in `create_axis`; the goldens are recorded with `TrapezoidAxis`.
    """

    V_REL = 1e-9
    """Relative velocity tolerance for "at the commanded speed" [-]."""

    def __init__(self, dt: float = 0.001) -> None:
        from motionvm.motion.profile import ProfileGenerator

        self.pg = ProfileGenerator(dt=dt, v_max=3000.0, a_max=30000.0, d_max=30000.0)
        self.position = 0.0
        self.velocity = 0.0
        self.v_cmd: float | None = None  # commanded jog velocity, None when positioning

    def move_to(self, p_f: float, v_max: float, a_max: float) -> None:
        self.pg.set_limits(v_max=abs(v_max), a_max=a_max, d_max=a_max)
        self.v_cmd = None
        self.pg.move_to(p_f)

    def run_at(self, v: float, a_max: float) -> None:
        self.pg.set_limits(v_max=max(abs(v), self.pg.v_max), a_max=a_max, d_max=a_max)
        self.v_cmd = float(v)
        self.pg.move_velocity(v)

    def stop(self, a_max: float) -> None:
        self.v_cmd = 0.0
        self.pg.stop(a_max)

    def halt(self) -> None:
        self.v_cmd = None
        self.pg.reset(self.position)
        self.velocity = 0.0

    @property
    def busy(self) -> bool:
        return not self.pg.is_done and self.pg.mode != "idle"

    @property
    def transient(self) -> bool:
        if not self.busy:
            return False
        if self.v_cmd is None or self.v_cmd == 0.0:
            return True
        return abs(self.velocity - self.v_cmd) > self.V_REL * abs(self.v_cmd)

    def step(self, dt: float) -> None:
        self.position, self.velocity, _ = self.pg.step()
        if self.pg.is_done:
            self.velocity = 0.0  # arrived: the generator reports 0 one cycle later


def create_axis() -> Axis:
    """The axis model used for every GDL motor object: the manual's profile generator
    (`motion/profile.py`), the same one HMPL axes use. `TrapezoidAxis` stays as a
    minimal reference model for tests."""
    return ProfileAxis()
