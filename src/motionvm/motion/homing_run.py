"""One CiA 402 homing sequence (HIMC manual table 20.1.1) as a reference provider of an axis.

The methods, by the switch whose edge they seek (CiA 402 / IEC 61800-7-201 figures):

| method | switch | edge | last pass, index side | initial direction | index |
|---|---|---|---|---|---|
| 1, 17 | negative limit | where it turns inactive | + | - | 1 |
| 2, 18 | positive limit | where it turns inactive | - | + | 2 |
| 7 / 23 | home | low (left) end | - | + | 7 |
| 8 / 24 | home | low end | + | + | 8 |
| 9 / 25 | home | high (right) end | - | + | 9 |
| 10 / 26 | home | high end | + | + | 10 |
| 11 / 27 | home | high end | + | - | 11 |
| 12 / 28 | home | high end | - | - | 12 |
| 13 / 29 | home | low end | + | - | 13 |
| 14 / 30 | home | low end | - | - | 14 |
| 33, 34 | none: the first index pulse moving - (33) or + (34) | | | | all |

The sequence: search the switch at the switch speed in the initial direction (if the
switch is active at the start, towards the edge sought instead; a home method reverses
once on the limit switch in its way); then, at the zero speed, pass the edge in the
"last pass" direction (backing off first if the fast search crossed it that way); the
home position is that edge (17, 18, 23-30), or the first index pulse beyond it in that
direction (1, 2, 7-14). The axis then moves to the home position at the zero speed and
stops on it. All moves use the homing acceleration for speeding up and braking.

Signals are read from the motor position each cycle and located exactly, as a hardware
latch would: switch edges on the switch positions, index pulses on their positions, with
the drive sensors' conventions (a switch is active on its end points; an index pulse at
P is passed moving + when x_0 < P <= x_1 and moving - when x_1 < P <= x_0, which is how
methods 33/34 treat a pulse under the start position). An index pulse exactly on the
edge is not "beyond" it: methods 1-14 take the next one.
Positions here are motor counts unless named `_mm` [mm or deg in axis units].
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from motionvm.motion.profile import ProfileGenerator

NEG, POS, HOME = "negative limit switch", "positive limit switch", "home switch"
LOW, HIGH = "low", "high"
FAST, BACK, APPROACH, INDEX, FINAL, STOPPING = range(6)


@dataclass(frozen=True)
class Method:
    """How one homing method finds its home position."""

    number: int
    switch: str | None
    """NEG, POS, HOME, or None (33, 34: index only; 37: the current position)."""
    edge: str = HIGH
    """Which end of the switch's active region is the edge sought (LOW or HIGH)."""
    final: int = 0
    """Direction [+1/-1] of the last pass over the edge and of the index search."""
    initial: int = 0
    """Direction [+1/-1] of the fast search while the switch is inactive."""
    index: bool = False


def _methods() -> dict[int, Method]:
    out = {
        1: Method(1, NEG, HIGH, +1, -1, True),
        2: Method(2, POS, LOW, -1, +1, True),
        17: Method(17, NEG, HIGH, +1, -1, False),
        18: Method(18, POS, LOW, -1, +1, False),
        33: Method(33, None, final=-1, index=True),
        34: Method(34, None, final=+1, index=True),
        37: Method(37, None),
    }
    home_edges = ((LOW, -1), (LOW, +1), (HIGH, -1), (HIGH, +1))  # 7-10 in figure order
    for i, (edge, final) in enumerate(home_edges):
        out[7 + i] = Method(7 + i, HOME, edge, final, +1, True)
        out[23 + i] = Method(23 + i, HOME, edge, final, +1, False)
    for i, (edge, final) in enumerate(home_edges):  # 11-14 mirror 7-10
        mirrored = HIGH if edge == LOW else LOW
        out[11 + i] = Method(11 + i, HOME, mirrored, -final, -1, True)
        out[27 + i] = Method(27 + i, HOME, mirrored, -final, -1, False)
    return dict(sorted(out.items()))


METHODS: dict[int, Method] = _methods()
"""Every method of table 20.1.1 by number."""


class Switches:
    """The switch regions and index pulses of one drive [counts], read from its sensors."""

    def __init__(self, sensors) -> None:
        s = sensors
        self.regions: dict[str, tuple[float, float] | None] = {
            NEG: None if s.negative_limit is None else (-math.inf, s.negative_limit),
            POS: None if s.positive_limit is None else (s.positive_limit, math.inf),
            HOME: None if s.home_low is None else (s.home_low, s.home_high),
        }
        self.index_spacing = s.index_spacing
        self.index_offset = s.index_offset

    def active(self, switch: str, x: float) -> bool:
        region = self.regions[switch]
        return region is not None and region[0] <= x <= region[1]

    def edge(self, switch: str, which: str) -> float:
        lo, hi = self.regions[switch]
        return lo if which == LOW else hi

    def next_index(self, x: float, direction: int, *, strict: bool) -> float:
        """The first index pulse from x in `direction`; `strict`: never the one at x."""
        sp, off = self.index_spacing, self.index_offset
        n = math.floor((x - off) / sp)
        if direction > 0:
            return off + (n + 1) * sp
        p = off + n * sp
        return p - sp if strict and p == x else p


def crossed(edge: float, which: str, x_0: float, x_1: float) -> int:
    """Direction [+1/-1] in which the `which` end of a region at `edge` was crossed, or 0."""
    if which == LOW:
        inside_0, inside_1 = x_0 >= edge, x_1 >= edge
    else:
        inside_0, inside_1 = x_0 <= edge, x_1 <= edge
    if inside_0 == inside_1:
        return 0
    return 1 if x_1 > x_0 else -1


class HomingRun:
    """The reference provider of one homing sequence (`Axis.follow(run)`).

    `on_end(run, p)` is called in the cycle the axis comes to rest at the end (success:
    on the home position; failure: wherever it stopped) and returns that cycle's
    reference; it releases the axis. `error` is 0 or the axis error code (low half).
    """

    def __init__(self, axis, method: Method, settings, on_end, fail_codes: tuple[int, int]):
        self.axis = axis
        self.method = method
        self.settings = settings
        self.on_end = on_end
        self.timeout_code, self.failed_code = fail_codes
        self.switches = Switches(axis.drive.sensors)
        self.pg = ProfileGenerator(
            axis.dt, settings.switch_vel, settings.acc, settings.acc, 0.0, axis.ref_pos
        )
        self.max_cycles = math.ceil(settings.timeout_ms / 1000.0 / axis.dt - 1e-9)
        self.cycles = 0
        self.error = 0
        self.message = ""
        self.home_mm: float | None = None
        """The home position found [axis units, before re-zeroing]."""
        self.ended = False
        self._x_prev = x = axis.drive.mechanics.position
        self._edge = 0.0
        self._index = 0.0
        self._reversed = False
        m = method
        if m.switch is None:
            self._search_index(self.switches.next_index(x, m.final, strict=False))
        else:
            self._edge = self.switches.edge(m.switch, m.edge)
            if self.switches.active(m.switch, x):
                self._jog(FAST, 1 if m.edge == HIGH else -1, settings.switch_vel)
            else:
                self._jog(FAST, m.initial, settings.switch_vel)

    # ---- the provider ---------------------------------------------------------------

    def reference(self, axis) -> tuple[float, float, float]:
        x = axis.drive.mechanics.position
        x_0, self._x_prev = self._x_prev, x
        self.cycles += 1
        if self.phase != STOPPING:
            if self.cycles > self.max_cycles:
                self.fail(
                    self.timeout_code,
                    f"homing took longer than the timeout {self.settings.timeout_ms:g} ms",
                )
            else:
                self._advance(x_0, x)
        p, v, a = self.pg.step()
        if self.phase in (FINAL, STOPPING) and v == 0.0 and a == 0.0 and self.pg.is_done:
            self.ended = True
            return self.on_end(self, p)
        return p, v, a

    def fail(self, code: int, message: str) -> None:
        """Give up: brake to rest at the homing acceleration, then end."""
        self.error = code
        self.message = message
        self.phase = STOPPING
        self.pg.stop(self.settings.acc)

    # ---- phases ---------------------------------------------------------------------

    def _jog(self, phase: int, direction: int, vel: float) -> None:
        self.phase = phase
        self.direction = direction
        self.pg.set_limits(v_max=vel)
        self.pg.move_velocity(direction * vel)

    def _search_index(self, pulse: float) -> None:
        self._index = pulse
        self._jog(INDEX, self.method.final, self.settings.zero_vel)

    def _to_home(self, x_home: float) -> None:
        self.home_mm = x_home / self.axis.cpu - self.axis.pos_offset
        self.phase = FINAL
        self.pg.set_limits(v_max=self.settings.zero_vel)
        self.pg.move_to(self.home_mm)

    def _advance(self, x_0: float, x_1: float) -> None:
        phase = self.phase
        if phase == FINAL:
            return
        m = self.method
        sw = self.switches
        for limit, towards in ((NEG, -1), (POS, 1)):
            if limit != m.switch and self.direction == towards and sw.active(limit, x_1):
                if phase == FAST and m.switch == HOME and not self._reversed:
                    self._reversed = True
                    self._jog(FAST, -towards, self.settings.switch_vel)
                    return
                self.fail(self.failed_code, f"the {limit} was reached before the home position")
                return
        if phase == INDEX:
            if (x_1 >= self._index) if m.final > 0 else (x_1 < self._index):
                self._to_home(self._index)
            return
        c = crossed(self._edge, m.edge, x_0, x_1)
        if c == 0:
            return
        zero_vel = self.settings.zero_vel
        if phase == FAST:
            if c == m.final:
                self._jog(BACK, -m.final, zero_vel)
            else:
                self._jog(APPROACH, m.final, zero_vel)
        elif phase == BACK and c == -m.final:
            self._jog(APPROACH, m.final, zero_vel)
        elif phase == APPROACH and c == m.final:
            if m.index:
                self._search_index(sw.next_index(self._edge, m.final, strict=True))
            else:
                self._to_home(self._edge)
