"""An axis following an external reference provider (gear slave, gantry, homing sequence).

A provider is any object with `reference(axis) -> (ref_pos [mm], ref_vel [mm/s],
ref_acc [mm/s²])`, called once per cycle in the axis's reference phase instead of the
profile generator. `release()` hands the axis back to its profile generator at the
provider's last reference position; a provider brings the axis to rest before it lets go.
"""

from __future__ import annotations

from typing import Protocol

from motionvm.motion.axis_cycle import EXT, PG


class ReferenceProvider(Protocol):
    def reference(self, axis) -> tuple[float, float, float]: ...


class AxisFollow:
    """Mixin of `Axis` (attributes set up by `Axis.__init__`)."""

    def follow(self, provider: ReferenceProvider) -> None:
        """From the next cycle on, take the reference from `provider`."""
        self._ext = provider
        self._source = EXT
        self._rest = False
        self._fast_ok = None  # the fast path serves the profile generator only

    @property
    def following(self):
        """The provider the axis follows, or None."""
        return self._ext if self._source == EXT else None

    def release(self) -> None:
        """Return to the profile generator, starting from the current reference."""
        if self._source == EXT:
            self._ext = None
            self._source = PG
            self._fast_ok = None
            self.pg.reset(self.ref_pos)
