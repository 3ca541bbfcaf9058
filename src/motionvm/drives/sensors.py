"""Limit, home and index signals of one axis, and the drive's two touch probes.

Switches sit at fixed motor positions [counts] (not wrapped): the negative limit is
active at or below `negative_limit`, the positive limit at or above `positive_limit`,
the home switch on [home_low, home_high]. Index pulses come every `index_spacing`
counts at `index_offset` (+ n * spacing). Each cycle the drive passes the motor
position before and after the cycle; edges are located exactly on the switch or index
position, as a hardware latch would. Between switch edges only the index pulse can
change; the sensors keep the band of positions without a switch edge and the interval
without an index pulse around the last position, and publish both together as the quiet
interval, inside which a cycle changes nothing (the drive then skips `update`). The
switch map (the sorted edges, the inputs between and on them) is built when a switch is
configured, so that finding a new band is a bisection; setting a switch or the index
rebuilds it and drops the bands found with the old configuration.

Touch probes (CiA 402 0x60B8/0x60B9, 0x60BA..0x60BD): probe 1 samples the home switch
or the index pulse, probe 2 an external input (digital input bit 17) or the index.
0x60B8 bits (probe 1; probe 2 the same shifted by 8): 0 enable, 1 continuous (else
first event only), 2 source index pulse (else the probe input), 4 sample the positive
edge, 5 sample the negative edge. Status 0x60B9: bit 0 enabled, 1 positive edge stored,
2 negative edge stored (probe 2: bits 8-10). Clearing an edge-sample bit for a cycle, or
re-enabling the probe, clears the stored flag and re-arms a first-event probe.
"""

from __future__ import annotations

import math
from bisect import bisect_left
from math import floor

from motionvm.drives.mechanics import Config
from motionvm.drives.objects import (
    DI_HOME_SWITCH,
    DI_INDEX_PULSE,
    DI_NEGATIVE_LIMIT,
    DI_POSITIVE_LIMIT,
    DI_PROBE_INPUT,
    wrap_i32,
)

MAX_COUNTS = 1e18
"""Largest switch or index position [counts] (1e9 mm at 1e9 counts/mm)."""


def _switch_property(name: str, doc: str) -> property:
    """The property of switch or index setting `name` of `Sensors`: its slot, and a
    write that rebuilds the switch map and tells the drive's owner."""
    slot = "_" + name

    def set_switch(self, value: float | None) -> None:
        setattr(self, slot, value)
        self._configure()
        if self.on_change is not None:
            self.on_change()

    return property(lambda self: getattr(self, slot), set_switch, doc=doc)


class Sensors:
    """Switch and index signals derived from the motor position; touch probe latches."""

    __slots__ = (  # set up in __init__
        "_edge_inputs", "_edges", "_external", "_gap_bands", "_home_high", "_home_low",
        "_home_prev", "_index_high", "_index_low", "_index_n", "_index_offset",
        "_index_spacing", "_negative_limit", "_positive_limit", "_probe_prev",
        "_switch_external", "_switch_high", "_switch_inputs", "_switch_low", "_tp_function",
        "_tp_function_prev", "has_switches", "latched", "on_change", "quiet_high",
        "quiet_inputs", "quiet_low", "tp_status"
    )  # fmt: skip

    def __init__(
        self,
        negative_limit: float | None = None,
        positive_limit: float | None = None,
        home_low: float | None = None,
        home_high: float | None = None,
        index_spacing: float | None = None,
        index_offset: float = 0.0,
    ):
        self._negative_limit = negative_limit
        self._positive_limit = positive_limit
        self._home_low = home_low
        self._home_high = home_high
        self._index_spacing = index_spacing
        self._index_offset = index_offset
        self._external = 0
        self._tp_function = 0
        self.on_change = None
        """Called (no arguments) after each write of `external`, `tp_function` or of a
        switch: the drive's owner learns that its inputs changed (a resting axis wakes)."""
        self.tp_status = 0
        self.latched = [0, 0, 0, 0]
        """Touch probe values [counts]: 1 positive, 1 negative, 2 positive, 2 negative."""
        self._tp_function_prev = 0
        self._home_prev = False
        self._probe_prev = False
        # Bands found by the last evaluation, so that a cycle that crosses no switch
        # edge needs no new one: the switch band (an open interval of positions without
        # a limit or home edge) with its inputs, and the index interval (positions with
        # the same index number, see `_index_number`).
        self._switch_external = 0
        self._switch_inputs = 0
        self.quiet_inputs = 0
        self._configure()

    def _configure(self) -> None:
        """Build the switch map of the configured switches and drop the bands and the
        quiet interval found so far (a switch or the index was set)."""
        self.has_switches = any(
            v is not None
            for v in (self._negative_limit, self._positive_limit, self._home_low,
                      self._index_spacing)
        )  # fmt: skip
        """False if no switch or index is configured (the drive then skips `update`)."""
        edges = sorted(
            {e for e in (self._negative_limit, self._positive_limit, self._home_low,
                         self._home_high) if e is not None}
        )  # fmt: skip
        self._edges = edges
        """The limit and home edges [counts], sorted, each once."""
        self._edge_inputs = [self._switch_bits(e, e) for e in edges]
        """The switch inputs on each edge."""
        bounds = [-math.inf, *edges, math.inf]
        self._gap_bands = [
            (lo, hi, self._switch_bits(lo, hi)) for lo, hi in zip(bounds, bounds[1:])
        ]
        """(low, high, inputs) of the open interval below edge i (the last: above all)."""
        self._switch_low, self._switch_high = math.inf, -math.inf  # none found yet
        self._index_low, self._index_high, self._index_n = math.inf, -math.inf, 0
        self.quiet_low, self.quiet_high = math.inf, -math.inf
        """The quiet interval [counts]: the switch band and the index interval of the
        last `update`'s end position x, both (empty while a probe is on, and after a
        write of `external`, `tp_function` or of a switch). For x_0 = x and any x_1
        inside, `update(x_0, x_1)` would return `quiet_inputs` and change nothing, so the
        caller may skip it."""

    def _switch_bits(self, lo: float, hi: float) -> int:
        """The limit and home inputs of the positions in [lo, hi] (a point, or an open
        interval between two neighbouring edges, where they are all alike)."""
        bits = 0
        if self._negative_limit is not None and hi <= self._negative_limit:
            bits |= DI_NEGATIVE_LIMIT
        if self._positive_limit is not None and lo >= self._positive_limit:
            bits |= DI_POSITIVE_LIMIT
        low, high = self._home_low, self._home_high
        if low is not None and high is not None and low <= lo and hi <= high:
            bits |= DI_HOME_SWITCH
        return bits

    negative_limit = _switch_property(
        "negative_limit", "Negative limit switch [counts]: active at or below (None: none)."
    )
    positive_limit = _switch_property(
        "positive_limit", "Positive limit switch [counts]: active at or above (None: none)."
    )
    home_low = _switch_property("home_low", "Low end of the home switch [counts] (None: none).")
    home_high = _switch_property("home_high", "High end of the home switch [counts].")
    index_spacing = _switch_property(
        "index_spacing", "Counts between index pulses (None: no index pulse)."
    )
    index_offset = _switch_property("index_offset", "Position of an index pulse [counts].")

    @property
    def external(self) -> int:
        """Input bits [0x60FD layout] set by the plant wiring, ORed into the result."""
        return self._external

    @external.setter
    def external(self, value: int) -> None:
        self._external = value
        self.quiet_low, self.quiet_high = math.inf, -math.inf  # the bands are stale
        if self.on_change is not None:
            self.on_change()

    @property
    def tp_function(self) -> int:
        """Touch probe function (0x60B8)."""
        return self._tp_function

    @tp_function.setter
    def tp_function(self, value: int) -> None:
        self._tp_function = value
        self.quiet_low, self.quiet_high = math.inf, -math.inf  # probes are evaluated
        if self.on_change is not None:
            self.on_change()

    @classmethod
    def from_config(cls, cfg: Config) -> Sensors:
        """Read the switch and index keys of a drive's config (absent: no such signal)."""

        def optional(key, low=-MAX_COUNTS, strict=False):
            if key not in cfg.config:
                return None
            return cfg.number(key, 0.0, low=low, strict=strict, high=MAX_COUNTS)

        sensors = cls(
            negative_limit=optional("negative_limit"),
            positive_limit=optional("positive_limit"),
            home_low=optional("home_low"),
            home_high=optional("home_high"),
            index_spacing=optional("index_spacing", low=1.0),
            index_offset=optional("index_offset") or 0.0,
        )
        low, high = sensors.home_low, sensors.home_high
        if (low is None) != (high is None):
            raise ValueError(f"{cfg.where}: home_low and home_high must be given together")
        if low is not None and low > high:
            raise ValueError(f"{cfg.where}: home_low = {low!r} is above home_high = {high!r}")
        return sensors

    def _edge_position(self, x_0: float, x_1: float, rising: bool) -> float:
        """Where the home switch changed between x_0 and x_1: on its low or high end."""
        lo, hi = self._home_low, self._home_high
        entering_from_below = x_0 < lo if rising else x_1 < lo
        return lo if entering_from_below else hi

    def clear_of_limits(self, lo: float, hi: float) -> bool:
        """True if a motor that moves only within [lo, hi] [counts] trips neither limit
        switch (the closed-form advance of time skipping: motion/axis_coast.py)."""
        if self._negative_limit is not None and not self._negative_limit < lo:
            return False
        return self._positive_limit is None or hi < self._positive_limit

    def update(self, x_0: float, x_1: float) -> int:
        """Advance one cycle from motor position x_0 to x_1 [counts]; return 0x60FD.

        Within the switch band of the last evaluation (same external inputs, no probe)
        only the index pulse can change: it is found from the index numbers alone. A
        motor standing on an edge (an empty band at x_0 == x_1) changes nothing either.
        Elsewhere the cycle is evaluated from scratch: switches (from the switch map),
        index pulse, probes; then the new bands: the switch band around x_1 (the widest
        open interval without a limit or home edge; empty if x_1 is on an edge or a probe
        is on), on which the switch inputs stay those of x_1, and the index interval."""
        # the slots behind `external` and `tp_function`: no property call per update
        if x_1 == x_0 == self._switch_low == self._switch_high and not (
            self._external != self._switch_external or self._tp_function or self.tp_status
        ):
            return self._switch_inputs  # what an evaluation would return and leave
        if (self._switch_low < x_1 < self._switch_high
                and self._external == self._switch_external
                and not (self._tp_function or self.tp_status)):  # fmt: skip
            inputs = self._switch_inputs
            low, high = self._switch_low, self._switch_high
            if self._index_spacing:
                # x_0 is mostly in the index interval already (the last update's x_1)
                n_0 = (self._index_n if self._index_low <= x_0 <= self._index_high
                       else self._index_number(x_0))  # fmt: skip
                if n_0 != self._index_number(x_1):
                    inputs |= DI_INDEX_PULSE
            self._quiet(low, high)
            return inputs
        # from scratch
        edges = self._edges
        i = bisect_left(edges, x_1)
        if i < len(edges) and edges[i] == x_1:  # on an edge
            bits = self._edge_inputs[i]
            low = high = x_1
        else:
            low, high, bits = self._gap_bands[i]
        external = self._external
        inputs = external | bits
        index = None  # the position of the first index pulse passed from x_0 to x_1
        spacing = self._index_spacing
        if spacing and x_0 != x_1:
            offset = self._index_offset
            n_0 = floor((x_0 - offset) / spacing)
            n_1 = floor((x_1 - offset) / spacing)
            if n_0 != n_1:
                inputs |= DI_INDEX_PULSE
                index = offset + (n_0 + 1 if x_1 > x_0 else n_0) * spacing
        home = bits & DI_HOME_SWITCH != 0
        probe = inputs & DI_PROBE_INPUT != 0
        if self._tp_function or self.tp_status:
            self._probes(x_0, x_1, home, probe, index)
            if self._tp_function or self.tp_status:  # a probe is on: no band
                low = high = x_1
        self._home_prev = home
        self._probe_prev = probe
        # the new bands
        self._switch_low, self._switch_high = low, high
        self._switch_external = external
        self._switch_inputs = self.quiet_inputs = external | bits
        if self._index_spacing and low < high:
            self._index_number(x_1)
        self._quiet(low, high)
        return inputs

    def _quiet(self, low: float, high: float) -> None:
        """Set the quiet interval: the switch band (low, high) of the last position, inside
        the index interval that `_index_number` found for it (if there is an index and
        the band is not empty)."""
        if self._index_spacing and low < high:
            if self._index_low > low:
                low = self._index_low
            if self._index_high < high:
                high = self._index_high
        self.quiet_low, self.quiet_high = low, high

    def _index_number(self, x: float) -> int:
        """floor((x - index_offset) / index_spacing), as `update` computes it,
        from the index interval when x lies in it. The floor of a rounded quotient grows
        with x, so two ends that give n bound positions that give n; the ends are kept a
        margin far above the rounding inside the exact interval, and checked."""
        if self._index_low <= x <= self._index_high:
            return self._index_n
        offset, spacing = self._index_offset, self._index_spacing
        n = floor((x - offset) / spacing)
        lo, hi = offset + n * spacing, offset + (n + 1) * spacing
        # max(1.0, abs(lo), abs(hi)) and the min/max below, as comparisons (lo <= hi)
        size = hi if hi > -lo else -lo
        margin = 1e-6 * (size if size > 1.0 else 1.0)
        lo += margin
        hi -= margin
        if lo > x:  # x itself gives n
            lo = x
        if hi < x:
            hi = x
        if floor((lo - offset) / spacing) == n == floor((hi - offset) / spacing):
            self._index_low, self._index_high, self._index_n = lo, hi, n
        else:  # a spacing too fine for the margin: no interval
            self._index_low, self._index_high, self._index_n = math.inf, -math.inf, n
        return n

    def _probes(self, x_0, x_1, home, probe, index) -> None:
        fn, prev = self.tp_function, self._tp_function_prev
        self._tp_function_prev = fn
        status = self.tp_status
        for probe_no, shift in ((0, 0), (1, 8)):
            f = (fn >> shift) & 0xFF
            rising_bits = f & ~((prev >> shift) & 0xFF)
            if not f & 1:
                status &= ~(0x07 << shift)
                continue
            status |= 1 << shift
            if rising_bits & 1:
                status &= ~(0x06 << shift)
            if not f & 0x10:
                status &= ~(0x02 << shift)
            if not f & 0x20:
                status &= ~(0x04 << shift)
            continuous = bool(f & 0x02)
            if f & 0x04:  # index pulse: a positive edge where it is crossed
                events = [] if index is None else [(True, index)]
            elif probe_no == 0:
                events = []
                if home != self._home_prev and self._home_low is not None:
                    events.append((home, self._edge_position(x_0, x_1, home)))
            else:
                events = [(probe, x_1)] if probe != self._probe_prev else []
            for rising, position in events:
                bit, enable, slot = (0x02, 0x10, 0) if rising else (0x04, 0x20, 1)
                if f & enable and (continuous or not status & (bit << shift)):
                    status |= bit << shift
                    self.latched[2 * probe_no + slot] = wrap_i32(round(position))
        self.tp_status = status
