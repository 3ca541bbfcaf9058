"""Input shapers (HIMC manual 15.1, InShape): a ZV or ZVD shaper applied per cycle.

An input shaper convolves the commanded trajectory with a few impulses whose gains sum
to 1, placed so that the vibration they excite in an oscillator of frequency `f` and
damping ratio `zeta` cancels. The manual's two types:

* SHAPER_NORMAL (1): ZV, zero vibration at the mode: two impulses half a damped period
  apart in continuous time;
* SHAPER_ROBUST (0): ZVD, zero vibration and zero derivative with respect to the
  frequency (robust to a frequency that is not quite right): the ZV convolved with
  itself, so its transfer function has a double zero at the mode.

Discrete design, exact on the cycle grid. The controller sends one position per cycle
`dt`, so an impulse must sit on a whole cycle. A ZV impulse at T/2 = (k + r) dt
(0 <= r < 1) is split over the cycles k and k+1, and the three gains (A0, A1, A2) at
delays (0, k, k+1) are the solution of

    A0 + A1 z^-k + A2 z^-(k+1) = 0  at  z = exp((-zeta*w_n + i*w_d) * dt),   sum A = 1,

three real equations. The shaped command then excites no vibration at the mode for any
drive that interpolates the samples in a shift-invariant way (hold, linear): the
residual of each impulse cancels exactly, not only up to the rounding of T/2. The gains
are positive over the manual's ranges; a gain below `TINY_GAIN` (T/2 on the grid) is
dropped. The ZVD is the ZV's taps convolved with themselves (delays up to 2k+2).

Streaming: `ShaperState.step(p, v, a)` takes one cycle's reference (position [mm],
velocity [mm/s], acceleration [mm/s^2]) and returns the shaped one. The position is
computed as `p + sum_i A_i (p[n - k_i] - p)`, so a reference at rest comes out exactly
(bit for bit), whatever rounding the gains carry: a move reaches its target exactly,
`length` cycles (the longest delay) after the unshaped reference does. Velocity and
acceleration are shaped with the same gains (the shaper is linear). `pending` is True
while the output still differs from the input (the last `length` inputs are not all
equal in position and velocity). The module is pure: the axis (motion/axis_filters.py) and an axis group use the
same `ShaperState`, one per coordinate.
"""

from __future__ import annotations

import cmath
import math
from dataclasses import dataclass

SHAPER_ROBUST = 0
SHAPER_NORMAL = 1
SHAPER_TYPES = (SHAPER_ROBUST, SHAPER_NORMAL)

TINY_GAIN = 1e-12
"""A shaper gain below this [-] is rounding of a gain that is exactly 0: it is dropped."""

DEFAULT_FREQUENCY = 5.5
"""[Hz] The manual's default system frequency of InShape (15.7, 15.10)."""
DEFAULT_DAMPING = 0.03
"""[-] The manual's default damping ratio of InShape (15.7, 15.10)."""


class ShaperDesignError(ValueError):
    """The frequency cannot be shaped on this cycle (half a period shorter than a cycle)."""


@dataclass(frozen=True, slots=True)
class Shaper:
    """Impulses of a discrete shaper: `delays` [cycles] ascending, `gains` [-] summing to 1."""

    delays: tuple[int, ...]
    gains: tuple[float, ...]

    @property
    def length(self) -> int:
        """[cycles] The longest delay: how much later a move ends."""
        return self.delays[-1]


@dataclass(slots=True)
class InShapeSettings:
    """The parameters of one InShape filter (an axis's or a group's) and its switch."""

    frequency: float = DEFAULT_FREQUENCY
    """[Hz] the system (vibration) frequency."""
    damping: float = DEFAULT_DAMPING
    """[-] the system's damping ratio."""
    shaper_type: int = SHAPER_NORMAL
    """SHAPER_NORMAL (ZV) or SHAPER_ROBUST (ZVD)."""
    enabled: bool = False


def _zv(frequency: float, damping: float, dt: float) -> dict[int, float]:
    w_n = 2.0 * math.pi * frequency
    w_d = w_n * math.sqrt(1.0 - damping * damping)
    half = math.pi / w_d  # [s] half the damped period: the continuous ZV's second impulse
    k = math.floor(half / dt + 1e-9)
    if k < 1:
        raise ShaperDesignError(
            f"{frequency:g} Hz: half its period ({half * 1000.0:g} ms) is shorter "
            f"than the cycle ({dt * 1000.0:g} ms)"
        )
    z_inv = cmath.exp(-complex(-damping * w_n, w_d) * dt)
    c1, c2 = z_inv**k, z_inv ** (k + 1)
    # A0 = 1 - A1 - A2;  A1 (c1 - 1) + A2 (c2 - 1) = -1  (real and imaginary parts)
    a11, a12, a21, a22 = c1.real - 1.0, c2.real - 1.0, c1.imag, c2.imag
    det = a11 * a22 - a12 * a21
    g1 = -a22 / det
    g2 = a21 / det
    if abs(g2) < TINY_GAIN:  # the half period is on the grid: two impulses
        g1, g2 = -1.0 / a11, 0.0
    taps = {0: 1.0 - g1 - g2, k: g1}
    if g2:
        taps[k + 1] = g2
    return taps


def design(frequency: float, damping: float, shaper_type: int, dt: float) -> Shaper:
    """The discrete shaper of `shaper_type` for a mode at `frequency` [Hz], `damping` [-]
    on a cycle of `dt` [s]; ShaperDesignError if the frequency is too high for the cycle."""
    if not (frequency > 0.0 and 0.0 <= damping < 1.0):
        raise ValueError(f"no shaper for {frequency!r} Hz, damping {damping!r}")
    taps = _zv(frequency, damping, dt)
    if shaper_type == SHAPER_ROBUST:
        conv: dict[int, float] = {}
        for d1, g1 in taps.items():
            for d2, g2 in taps.items():
                conv[d1 + d2] = conv.get(d1 + d2, 0.0) + g1 * g2
        taps = conv
    elif shaper_type != SHAPER_NORMAL:
        raise ValueError(f"shaper type {shaper_type!r} is not 0 or 1")
    delays = tuple(sorted(taps))
    return Shaper(delays, tuple(taps[d] for d in delays))


class ShaperState:
    """One shaped coordinate: the last `length + 1` references and the shaper's gains."""

    __slots__ = ("_delayed", "_hist", "_i", "_n", "_still", "last_in", "last_out", "shaper")

    def __init__(self, shaper: Shaper, position: float) -> None:
        self.shaper = shaper
        self._n = shaper.length + 1
        self._delayed = tuple((d, g) for d, g in zip(shaper.delays, shaper.gains) if d)
        self.reset(position)

    def reset(self, position: float) -> None:
        """Rest at `position` [mm]: nothing pending, the output is the input."""
        rest = (position, 0.0, 0.0)
        self._hist = [rest] * self._n
        self._i = 0
        self._still = self._n
        self.last_in = rest
        self.last_out = rest

    @property
    def pending(self) -> bool:
        """True while the output has not yet caught up with a resting input."""
        return self._still < self._n - 1

    def step(self, p: float, v: float, a: float) -> tuple[float, float, float]:
        """The shaped reference of this cycle, given the unshaped one."""
        sample = (p, v, a)
        last = self.last_in
        self.last_in = sample
        if p == last[0] and v == last[1]:
            if self._still >= self._n - 1:  # at rest: every stored sample is this one
                return sample
            self._still += 1
        else:
            self._still = 0
        n = self._n
        i = self._i = (self._i + 1) % n
        hist = self._hist
        hist[i] = sample
        g0 = self.shaper.gains[0]
        dp, vs, acc = 0.0, g0 * v, g0 * a
        for d, g in self._delayed:
            q, qv, qa = hist[i - d]  # negative indexes wrap around the ring
            dp += g * (q - p)
            vs += g * qv
            acc += g * qa
        out = (p + dp, vs, acc) if self._still < n - 1 else sample
        self.last_out = out
        return out
