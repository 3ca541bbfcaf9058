"""The vibration suppression filter (HIMC manual 15.1, VSF): a notch on the command.

VSF takes a system frequency f (0.1 to 200 Hz) and a damping ratio zeta (0.7 to 1.5,
1.0 recommended). A damping ratio of 0.7 to 1.5 cannot be a vibrating mechanism's (such
a mechanism does not ring); it is the filter's own. motionvm's VSF is therefore the
command notch

    H(s) = (s^2 + w^2) / (s^2 + 2 zeta w s + w^2),    w = 2 pi f,

whose zeros cancel an undamped mode at f and whose poles, damped by zeta, set how fast
the filtered command follows; its DC gain is 1. Discretised by matching its zeros and
poles to the cycle (z = exp(s dt)) and scaling to a DC gain of exactly 1, so the zeros
lie on the unit circle at f: the filtered command has no component at f, and an
undamped oscillator at f driven by it keeps no residual vibration.

The filter is computed in deviations from the current input (`y - x`), so a reference
at rest produces itself bit for bit once the deviations are 0. Being recursive, the
deviations decay geometrically and never become exactly 0 by themselves: when the
input has rested for two cycles and every deviation is below `FILTER_SETTLE` (position;
/dt and /dt^2 for velocity and acceleration) the filter snaps onto the input and is no
longer `pending`. The snap moves the command by less than FILTER_SETTLE, far below one
encoder count.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from motionvm.motion.tolerances import FILTER_SETTLE

DEFAULT_FREQUENCY = 5.5
"""[Hz] VSF frequency until SetAxisVsf (the manual gives none; InShape's default)."""
DEFAULT_DAMPING = 1.0
"""[-] VSF damping ratio until SetAxisVsf: the manual's recommended value."""


class VsfDesignError(ValueError):
    """The frequency is at or above the Nyquist frequency of the cycle."""


@dataclass(frozen=True, slots=True)
class Notch:
    """y[n] = x[n] + g (d2 - 2c d1) - a1 e1 - a2 e2, in deviations from x[n]."""

    g: float
    c: float
    a1: float
    a2: float


@dataclass(slots=True)
class VsfSettings:
    frequency: float = DEFAULT_FREQUENCY
    damping: float = DEFAULT_DAMPING
    enabled: bool = False


def design(frequency: float, damping: float, dt: float) -> Notch:
    """The discrete notch for `frequency` [Hz] and `damping` [-] on a cycle of `dt` [s]."""
    w = 2.0 * math.pi * frequency
    if not 0.0 < w * dt < math.pi:
        raise VsfDesignError(
            f"{frequency:g} Hz is not below the Nyquist frequency {0.5 / dt:g} Hz of the cycle"
        )
    if damping <= 0.0:
        raise ValueError(f"damping ratio {damping!r} must be positive")
    c = math.cos(w * dt)
    a2 = math.exp(-2.0 * damping * w * dt)  # product of the poles
    if damping < 1.0:
        a1 = -2.0 * math.exp(-damping * w * dt) * math.cos(w * math.sqrt(1.0 - damping**2) * dt)
    else:
        root = w * math.sqrt(damping**2 - 1.0)
        a1 = -(math.exp((-damping * w + root) * dt) + math.exp((-damping * w - root) * dt))
    g = (1.0 + a1 + a2) / (2.0 - 2.0 * c)
    return Notch(g, c, a1, a2)


class VsfState:
    """One filtered coordinate: the deviations of the last two inputs and outputs."""

    __slots__ = ("_dev", "_lim", "_rest", "_same", "last_in", "last_out", "notch")

    def __init__(self, notch: Notch, position: float, dt: float) -> None:
        self.notch = notch
        self._lim = (FILTER_SETTLE, FILTER_SETTLE / dt, FILTER_SETTLE / (dt * dt))
        self.reset(position)

    def reset(self, position: float) -> None:
        """Rest at `position` [mm]: nothing pending, the output is the input."""
        self._rest_at((position, 0.0, 0.0))

    def _rest_at(self, sample: tuple[float, float, float]) -> None:
        # per coordinate (p, v, a): the inputs x[n-1], x[n-2] and outputs y[n-1], y[n-2]
        self._dev = [[x, x, x, x] for x in sample]
        self._rest = True
        self._same = 2
        self.last_in = self.last_out = sample

    @property
    def pending(self) -> bool:
        """True while the output has not yet settled onto a resting input."""
        return not self._rest

    def step(self, p: float, v: float, a: float) -> tuple[float, float, float]:
        """The filtered reference of this cycle, given the unfiltered one."""
        sample = (p, v, a)
        if sample == self.last_in:
            if self._rest:
                return sample
            self._same += 1
        else:
            self.last_in = sample
            self._same = 0
        nt = self.notch
        g, c2, a1, a2 = nt.g, 2.0 * nt.c, nt.a1, nt.a2
        out = []
        settled = self._same >= 2
        for x, s, lim in zip(sample, self._dev, self._lim):
            x1, x2, y1, y2 = s
            y = x + g * ((x2 - x) - c2 * (x1 - x)) - a1 * (y1 - x) - a2 * (y2 - x)
            s[0], s[1], s[2], s[3] = x, x1, y, y1
            if settled and (abs(y - x) >= lim or abs(y1 - x) >= lim):
                settled = False
            out.append(y)
        if settled:  # the input rests and the output is within FILTER_SETTLE of it
            self._rest_at(sample)
            return sample
        self._rest = False
        res = (out[0], out[1], out[2])
        self.last_out = res
        return res
