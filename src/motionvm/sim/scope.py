"""Scope recording: a registry of named channels and a recorder that samples them each cycle.

A *channel* is one number observed over time: `axis0.ref_pos`, `system_dtest0`, `gpo3`,
a program's global `count` or `table[4]`. Layers that own values offer them through a
`ChannelSource` (`resolve(name)` gives a getter and a unit, or None if the name is not
theirs); a `ChannelRegistry` asks each source in turn and turns failures into one clear
error with close matches. The `ScopeRecorder` is a `Controller` client: its
`end_cycle()` runs after tasks and motion, so a sample shows the state a cycle left
behind, stamped with that cycle's time (`system_timeInMs` reads the same cycle).
`ScopeWindow` picks the part of a recording that is written (`--scope-window`).
Writers for .csv, .png/.svg and .vcd live in `scope_writers.py`, the layout of plots in
`scope_plot.py`; the sources for GPIO, axes, gears and gantries in `scope_sources.py`.
"""

from __future__ import annotations

import difflib
import marshal
import math
import re
import tempfile
from array import array
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

from motionvm.runtime.clients import PassiveClient
from motionvm.runtime.scope import BIT_UNIT, RAW_UNIT, ChannelSource, EdgeGetter, ScopeError
from motionvm.sim import scope_writers
from motionvm.sim.scope_writers import PLOT_INSTALL_HINT

__all__ = [  # the units and the error are the scope protocol's (runtime/scope.py)
    "BIT_UNIT",
    "RAW_UNIT",
    "Channel",
    "ChannelRegistry",
    "ChannelSource",
    "ScopeError",
    "ScopeRecorder",
    "ScopeRequest",
    "ScopeWindow",
]

OUTPUT_SUFFIXES = (".csv", ".png", ".svg", ".vcd")
PLOT_SUFFIXES = (".png", ".svg")
STDOUT = "-"
"""`--scope-out -`: the .csv table on standard output, after the run's messages."""
_TIME = re.compile(r"\s*([-+]?[0-9.]+(?:[eE][-+]?\d+)?)\s*(s|ms|us)?\s*")
_TIME_SCALE = {None: 1.0, "s": 1.0, "ms": 1e-3, "us": 1e-6}


@dataclass(frozen=True, slots=True)
class Channel:
    """One recorded quantity: its name, unit (`mm`, `mm/s`, `ms`, `bool`, `raw`...) and getter."""

    name: str
    unit: str
    getter: Callable[[], float]

    @property
    def is_bit(self) -> bool:
        return self.unit == BIT_UNIT


class ChannelRegistry:
    """Channel sources, asked in the order registered."""

    def __init__(self, sources: Iterable[ChannelSource] = ()) -> None:
        self.sources: list[ChannelSource] = list(sources)

    def register(self, source: ChannelSource) -> None:
        self.sources.append(source)

    def names(self) -> list[str]:
        out: list[str] = []
        for s in self.sources:
            out.extend(s.channel_names())
        return out

    def find(self, name: str) -> Channel | None:
        """The channel called `name`, or None if no source offers it (ScopeError if its
        source finds it wrong). No suggestions: as cheap as asking the sources, for a
        caller that asks about many names (a scenario's events)."""
        for s in self.sources:
            found = s.resolve(name)
            if found is not None:
                getter, unit = found
                return Channel(name, unit, getter)
        return None

    def resolve(self, name: str) -> Channel:
        """The channel called `name`, or ScopeError naming the closest known channels."""
        channel = self.find(name)
        if channel is not None:
            return channel
        close = difflib.get_close_matches(name, self.names(), n=4, cutoff=0.6)
        hint = f"; did you mean {', '.join(close)}?" if close else ""
        if not close and name.startswith("axis"):
            hint = "; axis channels are axisN.<variable>, e.g. axis0.ref_pos, and need the machine's axes"
        elif not close and name.startswith("drive"):
            hint = (
                "; drive channels are driveN.<system variable>, e.g. drive1.x_ref_pos, and "
                'need a PDL program on axis N\'s drive (pdl = "x.pdl" in the machine file)'
            )
        raise ScopeError(f"unknown scope channel '{name}'{hint}")

    def resolve_all(self, names: Sequence[str]) -> list[Channel]:
        """Resolve every name; all unknown names are reported in one error."""
        channels, errors = [], []
        for n in names:
            try:
                channels.append(self.resolve(n))
            except ScopeError as exc:
                errors.append(str(exc))
        if len(errors) == 1:
            raise ScopeError(errors[0])
        if errors:
            raise ScopeError(
                f"{len(errors)} bad scope channels:\n" + "\n".join(f"  {e}" for e in errors)
            )
        return channels


def parse_channel_list(specs: Iterable[str]) -> list[str]:
    """Channel names from one or more comma-separated `--scope` values, duplicates dropped."""
    names: list[str] = []
    for spec in specs:
        for part in spec.split(","):
            name = "".join(part.split())
            if name and name not in names:
                names.append(name)
    return names


def plotting_available() -> bool:
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        return False
    return True


@dataclass(frozen=True, slots=True)
class ScopeWindow:
    """The part of a recording that is written: samples with `start <= sim_time <= end`.

    Either end may be None (open). Text form `START:END` in seconds, `ms` or `us`
    suffixes allowed: `0.1:0.25`, `150ms:`, `:2`.
    """

    start: float | None = None
    """First simulated time kept [s]; None: from the first sample."""
    end: float | None = None
    """Last simulated time kept [s]; None: to the last sample."""

    @classmethod
    def parse(cls, text: str) -> ScopeWindow:
        """The window `START:END`; ScopeError naming what is wrong."""
        left, colon, right = text.partition(":")
        if not colon:
            raise ScopeError(
                f"--scope-window '{text}': expected START:END in seconds "
                "(either may be empty; e.g. 0.1:0.25, 150ms:, :2)"
            )
        start, end = _parse_time(left, text), _parse_time(right, text)
        if start is not None and end is not None and start > end:
            raise ScopeError(f"--scope-window '{text}': start {start:g} s is after end {end:g} s")
        return cls(start, end)

    def __contains__(self, sim_time: float) -> bool:
        return (self.start is None or sim_time >= self.start) and (
            self.end is None or sim_time <= self.end
        )

    def __str__(self) -> str:
        def side(t: float | None) -> str:
            return "" if t is None else f"{t:g}"

        return f"{side(self.start)}:{side(self.end)}"


def _parse_time(side: str, text: str) -> float | None:
    """One side of a window in seconds (None if empty)."""
    if not side.strip():
        return None
    m = _TIME.fullmatch(side)
    try:
        value = float(m.group(1)) * _TIME_SCALE[m.group(2)] if m else math.nan
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise ScopeError(
            f"--scope-window '{text}': '{side.strip()}' is not a time "
            "(seconds, or with a suffix: 150ms, 200us, 1.5s)"
        )
    if value < 0:
        raise ScopeError(f"--scope-window '{text}': time {value:g} s is before the start (0 s)")
    return value


@dataclass(frozen=True, slots=True)
class ScopeRequest:
    """What `--scope/--scope-out/--scope-every/--scope-window` asked for, checked before
    anything runs. An output `-` (`STDOUT`) is the .csv table on standard output."""

    channels: tuple[str, ...]
    outputs: tuple[Path, ...]
    every: int = 1
    window: ScopeWindow | None = None

    @classmethod
    def from_options(
        cls,
        scope: Sequence[str],
        outputs: Sequence[str],
        every: int | None,
        window: str | None = None,
    ) -> ScopeRequest | None:
        """None when no scope was asked for; ScopeError for an incomplete or bad request."""
        every = 1 if every is None else every
        names = parse_channel_list(scope)
        if not names and not outputs:
            if every != 1:
                raise ScopeError("--scope-every needs --scope and --scope-out")
            if window is not None:
                raise ScopeError("--scope-window needs --scope and --scope-out")
            return None
        if not names:
            raise ScopeError(
                "--scope-out needs --scope CHANNEL,... (e.g. --scope axis0.ref_pos,system_dtest0)"
            )
        if not outputs:
            raise ScopeError("--scope needs --scope-out FILE (.csv, .png, .svg or .vcd)")
        if every < 1:
            raise ScopeError(f"--scope-every must be a whole number of cycles >= 1, got {every}")
        if sum(o == STDOUT for o in outputs) > 1:
            raise ScopeError("--scope-out -: standard output can take one table only")
        paths = tuple(Path(o) for o in outputs)
        for o, p in zip(outputs, paths):
            if o != STDOUT:
                check_output_path(p)
        span = None if window is None else ScopeWindow.parse(window)
        return cls(tuple(names), paths, every, span)

    @staticmethod
    def is_stdout(output: Path) -> bool:
        """True for the output `-`: the .csv table on standard output."""
        return str(output) == STDOUT


def check_output_path(path: Path) -> None:
    """ScopeError unless `path` has a known suffix, its folder exists, and plotting is possible."""
    suffix = path.suffix.lower()
    if suffix not in OUTPUT_SUFFIXES:
        raise ScopeError(
            f"--scope-out {path}: unknown file type '{suffix or '(none)'}' "
            f"(expected {', '.join(OUTPUT_SUFFIXES)}, or - for a .csv table on standard output)"
        )
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise ScopeError(f"--scope-out {path}: folder '{folder}' does not exist")
    if path.is_dir():
        raise ScopeError(f"--scope-out {path}: is a folder")
    if suffix in PLOT_SUFFIXES and not plotting_available():
        raise ScopeError(
            f"--scope-out {path}: drawing a {suffix} plot needs matplotlib, "
            f"which is not installed; {PLOT_INSTALL_HINT}"
        )


class ScopeRecorder(PassiveClient):
    """Samples channels at the end of every `every`-th controller cycle.

    Attach it after every other client, so it sees the cycle's final state. It has no
    event of its own, does nothing before the tasks and never keeps a run going (a
    `PassiveClient`), and does not keep the clock from jumping: a jump samples each
    `every`-th cycle it passes (`samples_skipped_cycles`, `next_sample`, sim/jumps.py),
    with the state stepping would have left, so no sample is skipped.
    A loop without a controller (a standalone PDL drive) calls `sample(cycle)` itself.

    Memory stays flat however long the run: the samples of the last `CHUNK` cycles are
    kept in memory (the cycles and the SetHMIScope flags in compact arrays), older ones
    are written to an anonymous temporary file in chunks (`marshal`, which keeps every
    value's type, so an integer channel prints as an integer) and read back, one chunk
    at a time, when the recording is written (`rows`).

    SetHMIScope (manual 2.16): each sample notes the controller's `hmi_scope`. If the
    program called SetHMIScope at all (`controller.hmi_scope_used`), only the samples
    taken while it was on are kept (`save` drops the others), as the vendor's HMI scope
    records only between SetHMIScope(1) and SetHMIScope(0); else every sample is kept.
    """

    CHUNK = 16384
    """Samples kept in memory before they go to the temporary file."""
    samples_skipped_cycles = True
    observes_motion = False  # a jump advances the axes to each sampled cycle for it

    def __init__(self, channels: Sequence[Channel], cycle_time: float, every: int = 1) -> None:
        if every < 1:
            raise ValueError(f"every must be >= 1, got {every}")
        self.channels = list(channels)
        self.cycle_time = cycle_time
        """Controller cycle time [s]."""
        self.every = every
        self._cycles = array("q")  # the samples still in memory: cycle, HMI flag, values
        self._hmi = array("b")
        self._columns: list[list[float]] = [[] for _ in self.channels]
        # ((offset, size, samples) of each chunk on file, samples in memory already on file)
        self._committed: tuple[tuple[tuple[int, int, int], ...], int] = ((), 0)
        self._file = None
        self._hmi_only = False  # apply_hmi_gate: keep the samples taken while it was on
        self._window: ScopeWindow | None = None
        self._controller = None
        self._first_cycle = 0
        self._pairs = list(zip(self._columns, [c.getter for c in self.channels]))

    def attach(self, controller) -> None:
        """Become a client of `controller`, sampling from its current cycle on; channels
        with exact edges (an `EdgeGetter`: the position trigger's output) keep them from now."""
        self._controller = controller
        self._first_cycle = controller.cycle
        for channel in self.channels:
            getter = channel.getter
            if isinstance(getter, EdgeGetter):
                getter.record_edges()
        controller.add_client(self)

    def end_cycle(self) -> None:
        """A sample of the state the cycle left behind."""
        self.sample(self._controller.cycle)

    def next_sample(self, cycle: int) -> int:
        """The first `every`-th cycle from `cycle` on (a jump advances the axes to it in
        closed form)."""
        return cycle + (self._first_cycle - cycle) % self.every

    def sample(self, cycle: int) -> None:
        """Record every channel as cycle `cycle` (if it is an `every`-th cycle)."""
        if (cycle - self._first_cycle) % self.every:
            return
        self._cycles.append(cycle)
        controller = self._controller  # (None: sampled by hand, never gated)
        self._hmi.append(1 if controller is None or controller.hmi_scope else 0)
        for column, get in self._pairs:
            column.append(get())
        if len(self._cycles) >= self.CHUNK:
            self._spill()

    def _spill(self) -> None:
        n = self._complete()
        chunk = (
            self._cycles[:n].tobytes(),
            self._hmi[:n].tobytes(),
            [c[:n] for c in self._columns],
        )
        try:
            data = marshal.dumps(chunk)
        except ValueError:  # a value marshal cannot store: keep this chunk in memory
            self.CHUNK *= 2
            return
        if self._file is None:
            self._file = tempfile.TemporaryFile(prefix="motionvm-scope-")
        f = self._file
        f.seek(0, 2)
        offset = f.tell()
        f.write(data)
        # one assignment commits the chunk and skips its samples in memory, so an
        # interrupt (Ctrl-C) at any point never loses a sample nor counts one twice
        spilled, _ = self._committed
        self._committed = ((*spilled, (offset, len(data), n)), n)
        self._cycles = array("q")
        self._hmi = array("b")
        for column in self._columns:
            column.clear()
        self._committed = (self._committed[0], 0)

    def _complete(self) -> int:
        """Samples in memory with every value taken: an interrupt (Ctrl-C) in the middle
        of `sample` may have appended the cycle and some of the channels only."""
        n = min(len(self._cycles), len(self._hmi))
        for column in self._columns:
            n = min(n, len(column))
        return n

    def _chunks(self) -> Iterator[tuple[array, array, list[list[float]]]]:
        """(cycles, HMI flags, columns) of every chunk, the oldest first; complete samples only."""
        f = self._file
        spilled, lo = self._committed
        for offset, size, _ in spilled:
            f.seek(offset)
            cycles, hmi, columns = marshal.loads(f.read(size))
            yield array("q", cycles), array("b", hmi), columns
        n = self._complete()
        if lo or n < len(self._cycles):
            yield self._cycles[lo:n], self._hmi[lo:n], [c[lo:n] for c in self._columns]
        else:
            yield self._cycles, self._hmi, self._columns

    def __len__(self) -> int:
        """Samples recorded (before any gate or window)."""
        spilled, lo = self._committed
        return sum(n for _, _, n in spilled) + max(0, self._complete() - lo)

    def rows(self) -> Iterator[tuple[int, list]]:
        """(cycle, values by channel) of every kept sample, the oldest first: the
        samples the HMI gate (`apply_hmi_gate`) and the window (`keep_window`) keep."""
        hmi_only, window, dt = self._hmi_only, self._window, self.cycle_time
        for cycles, hmi, columns in self._chunks():
            for row, cycle in enumerate(cycles):
                if hmi_only and not hmi[row]:
                    continue
                if window is not None and round(cycle * dt, 9) not in window:
                    continue
                yield cycle, [column[row] for column in columns]

    @property
    def cycles(self) -> list[int]:
        """Controller cycle of each kept sample."""
        return [cycle for cycle, _ in self.rows()]

    @property
    def columns(self) -> list[list[float]]:
        """One list of values per channel, parallel to `cycles`."""
        out: list[list[float]] = [[] for _ in self.channels]
        for _, values in self.rows():
            for column, v in zip(out, values):
                column.append(v)
        return out

    @property
    def hmi_on(self) -> list[bool]:
        """The controller's `hmi_scope` at each kept sample (True without a controller)."""
        out: list[bool] = []
        hmi_only, window, dt = self._hmi_only, self._window, self.cycle_time
        for cycles, hmi, _ in self._chunks():
            for row, cycle in enumerate(cycles):
                if (hmi_only and not hmi[row]) or (
                    window is not None and round(cycle * dt, 9) not in window
                ):
                    continue
                out.append(bool(hmi[row]))
        return out

    @property
    def hmi_gated(self) -> bool:
        """True if the program called SetHMIScope, so only its on-periods are kept."""
        controller = self._controller
        return controller is not None and controller.hmi_scope_used

    def apply_hmi_gate(self) -> None:
        """Drop the samples taken while SetHMIScope was off, if the program ever called it."""
        if self.hmi_gated:
            self._hmi_only = True

    def keep_window(self, window: ScopeWindow | None) -> None:
        """Drop the samples outside `window` (none if it is None); idempotent."""
        if window is not None:
            self._window = window

    @property
    def times(self) -> list[float]:
        """Simulated time of each sample [s], rounded to 1 ns so 3 * 0.001 prints as 0.003."""
        dt = self.cycle_time
        return [round(c * dt, 9) for c in self.cycles]

    def save(self, path: str | Path, title: str = "", window: ScopeWindow | None = None) -> None:
        """Write the recording (only the samples in `window`, if given); the format
        follows the suffix (.csv, .png, .svg, .vcd)."""
        self.apply_hmi_gate()
        self.keep_window(window)
        if window is not None:
            title = ", ".join(filter(None, [title, f"window {window} s"]))
        scope_writers.write(Path(path), self, title=title)

    def csv_lines(self, window: ScopeWindow | None = None) -> Iterator[str]:
        """The lines of the .csv table, without line ends (`--scope-out -`)."""
        self.apply_hmi_gate()
        self.keep_window(window)
        return scope_writers.csv_lines(self)
