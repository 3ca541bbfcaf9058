"""The studio's recording of a run, for the scope, the time slider and scrubbing.

A `History` keeps one value per named column (a scope channel: `axis0.pos_fb`, `gpi3`, a
program variable) at the end of recorded cycles, in compact arrays. Memory is bounded:
when `capacity` rows are held, every other row is dropped and only every `stride`-th
cycle is recorded from then on (stride doubles), so a long run keeps its whole span at a
coarser resolution. A run is deterministic, so a row once recorded stays true while the
inputs before it stay the same: going back and running forward again records nothing
twice (`add` ignores cycles already held), and a new input cuts the rows after it.

A `Recorder` is the cycle client that fills it: a `PassiveClient` sampling its getters
at the end of every cycle the history wants (also those a time jump passes: the jump
advances the axes in closed form from one to the next), like the scope recorder of
`motionvm run --scope`.
"""

from __future__ import annotations

import math
from array import array
from bisect import bisect_left, bisect_right
from collections.abc import Callable, Sequence
from functools import partial

from motionvm.runtime.clients import PassiveClient

CAPACITY = 1 << 15
"""Rows kept before the history halves its resolution."""


class History:
    """Recorded rows: a cycle and one float per column (NaN: not recorded then)."""

    def __init__(self, cycle_time: float, capacity: int = CAPACITY) -> None:
        self.cycle_time = cycle_time
        """Controller cycle time [s]."""
        self.capacity = max(4, capacity)
        self.stride = 1
        """Only cycles that are multiples of this are recorded."""
        self.cycles = array("q")
        self.columns: dict[str, array] = {}

    def __len__(self) -> int:
        return len(self.cycles)

    @property
    def last_cycle(self) -> int:
        """The latest cycle held (-1: none)."""
        return self.cycles[-1] if self.cycles else -1

    def ensure(self, names: Sequence[str]) -> None:
        """Columns for `names` (a new one reads NaN at the rows already held)."""
        for name in names:
            if name not in self.columns:
                self.columns[name] = array("d", [math.nan]) * len(self.cycles)

    def wants(self, cycle: int) -> bool:
        return cycle % self.stride == 0 and cycle > self.last_cycle

    def add(self, cycle: int, values: dict[str, object], always: bool = False) -> None:
        """The row of `cycle` (ignored unless `wants`; `always`: at any later cycle, off
        the stride too: the last row of a run that stops there)."""
        if self.wants(cycle) or (always and cycle > self.last_cycle):
            cells = [(c, partial(values.get, n, math.nan)) for n, c in self.columns.items()]
            self.record(cycle, cells)

    def record(self, cycle: int, cells: Sequence[tuple[array, Callable[[], object]]]) -> None:
        """The row of `cycle`, which `wants`: (column, getter) of every column."""
        self.cycles.append(cycle)
        for column, get in cells:
            value = get()
            try:
                column.append(value)  # type: ignore[arg-type]
            except TypeError:
                column.append(_number(value))
        if len(self.cycles) >= self.capacity:
            self._decimate()

    def coarsen(self, stride: int) -> None:
        """Record only every `stride`-th cycle from now on (a power of two; never finer:
        a run going fast need not be seen at every cycle)."""
        while self.stride < stride:
            self.stride *= 2

    def _decimate(self) -> None:
        stride = self.stride * 2
        keep = [i for i, c in enumerate(self.cycles) if c % stride == 0]
        self.cycles[:] = array("q", (self.cycles[i] for i in keep))
        for column in self.columns.values():  # in place: recorders hold the columns
            column[:] = array("d", (column[i] for i in keep))
        self.stride = stride

    def cut_after(self, cycle: int) -> None:
        """Forget the rows after `cycle` (the run differs from there on)."""
        n = bisect_right(self.cycles, cycle)
        del self.cycles[n:]
        for column in self.columns.values():
            del column[n:]

    def clear(self) -> None:
        self.stride = 1
        del self.cycles[:]
        for column in self.columns.values():
            del column[:]

    def index_at(self, cycle: int) -> int | None:
        """The index of the latest row at or before `cycle` (None: none)."""
        n = bisect_right(self.cycles, cycle)
        return n - 1 if n else None

    def row(self, index: int, names: Sequence[str] | None = None) -> dict[str, float | None]:
        names = self.columns if names is None else names
        return {n: _json(self.columns[n][index]) for n in names if n in self.columns}

    def window(
        self, first: int, last: int, names: Sequence[str], points: int = 2000
    ) -> tuple[list[float], dict[str, list[float | None]]]:
        """The rows with `first` <= cycle <= `last`, thinned to about `points` and
        always ending at the last of them (a path drawn up to a cycle ends where the
        machine was then): (times [s], values by column)."""
        lo, hi = bisect_left(self.cycles, first), bisect_right(self.cycles, last)
        step = max(1, math.ceil((hi - lo) / max(1, points)))
        idx = list(range(lo, hi, step))
        if idx and idx[-1] != hi - 1:
            idx.append(hi - 1)
        dt = self.cycle_time
        times = [round(self.cycles[i] * dt, 9) for i in idx]
        values = {n: [_json(self.columns[n][i]) for i in idx] for n in names if n in self.columns}
        return times, values


def _number(value: object) -> float:
    try:
        return float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return math.nan


def _json(value: float) -> float | None:
    """JSON has no NaN: None."""
    return None if value != value else value


class Recorder(PassiveClient):
    """Samples named getters into a `History` at the end of every cycle."""

    samples_skipped_cycles = True
    observes_motion = False  # a jump advances the axes to each sampled cycle for it

    def __init__(
        self,
        history: History,
        clock,
        getters: dict[str, Callable[[], object]],
        refresh: Callable[[], dict[str, Callable[[], object]] | None] | None = None,
    ):
        self.history = history
        self.clock = clock
        self.refresh = refresh
        """Asked every cycle: new getters (columns added since), or None."""
        self.set_getters(getters)

    def end_cycle(self) -> None:
        if self.refresh is not None:
            getters = self.refresh()
            if getters is not None:
                self.set_getters(getters)
        cycle = self.clock.cycle
        history = self.history
        if cycle % history.stride or cycle <= history.last_cycle:
            return
        history.record(cycle, self._cells)

    def next_sample(self, cycle: int) -> int:
        """The first cycle from `cycle` on that the history wants (a multiple of its
        stride after its last row): a jump advances the axes to it in closed form."""
        history = self.history
        cycle = max(cycle, history.last_cycle + 1)
        return cycle + (-cycle) % history.stride

    def set_getters(self, getters: dict[str, Callable[[], object]]) -> None:
        history = self.history
        history.ensure(list(getters))
        self._cells = [(history.columns[n], getters.get(n, _nan)) for n in history.columns]


def _nan() -> float:
    return math.nan
