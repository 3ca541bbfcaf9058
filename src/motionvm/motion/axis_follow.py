"""An axis following an external reference provider (gear slave, gantry, homing sequence).

A provider is any object with `reference(axis) -> (ref_pos [mm], ref_vel [mm/s],
ref_acc [mm/s²])`, called once per cycle in the axis's reference phase instead of the
profile generator. `release()` hands the axis back to its profile generator at the
provider's last reference position; a provider brings the axis to rest before it lets go.
A provider may have `moving(axis)` (region I of the axis, else always) and
`holds_still(axis)` (True: its reference stands still, the axis may rest; it wakes the
axis when the reference moves again; without it the axis never rests).
"""

from __future__ import annotations

from typing import Protocol

from motionvm.motion.axis_cycle import EXT, PG


class ReferenceProvider(Protocol):
    def reference(self, axis) -> tuple[float, float, float]: ...


class AxisFollow:
    """Mixin of `Axis` (attributes set up by `Axis.__init__`)."""

    __slots__ = ()

    def follow(self, provider: ReferenceProvider) -> None:
        """From the next cycle on, take the reference from `provider`."""
        self._provider = provider
        self._reference_source = EXT
        self.resting = False
        if self._comp_dependents:
            self._wake_dependents()

    @property
    def following(self):
        """The provider the axis follows, or None."""
        return self._provider if self._reference_source == EXT else None

    def release(self) -> None:
        """Return to the profile generator, starting from the current reference."""
        if self._reference_source == EXT:
            self._provider = None
            self._reference_source = PG
            self.pg.reset(self.ref_pos)
