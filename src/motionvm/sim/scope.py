"""Scope recording: a registry of named channels and a recorder that samples them each cycle.

A *channel* is one number observed over time: `axis0.ref_pos`, `system_dtest0`, `gpo3`,
a program's global `count` or `table[4]`. Layers that own values offer them through a
`ChannelSource` (`resolve(name)` gives a getter and a unit, or None if the name is not
theirs); a `ChannelRegistry` asks each source in turn and turns failures into one clear
error with close matches. The `ScopeRecorder` is a `Controller` client: its
`end_cycle()` runs after tasks and motion, so a sample shows the state a cycle left
behind, stamped with that cycle's time (`system_timeInMs` reads the same cycle).
Writers for .csv, .png/.svg and .vcd live in `scope_writers.py`; the sources for HMPL
variables, GPIO and axes in `scope_sources.py`.
"""

from __future__ import annotations

import difflib
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

from motionvm.runtime.scope import BIT_UNIT, RAW_UNIT, ChannelSource, ScopeError

__all__ = [  # the units and the error are the scope protocol's (runtime/scope.py)
    "BIT_UNIT",
    "RAW_UNIT",
    "Channel",
    "ChannelRegistry",
    "ChannelSource",
    "ScopeError",
    "ScopeRecorder",
    "ScopeRequest",
]

OUTPUT_SUFFIXES = (".csv", ".png", ".svg", ".vcd")
PLOT_SUFFIXES = (".png", ".svg")
PLOT_INSTALL_HINT = "pip install 'motionvm[plot]'"


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
            names = getattr(s, "channel_names", None)
            if names is not None:
                out.extend(names())
        return out

    def resolve(self, name: str) -> Channel:
        """The channel called `name`, or ScopeError naming the closest known channels."""
        for s in self.sources:
            found = s.resolve(name)
            if found is not None:
                getter, unit = found
                return Channel(name, unit, getter)
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
class ScopeRequest:
    """What `--scope/--scope-out/--scope-every` asked for, checked before anything runs."""

    channels: tuple[str, ...]
    outputs: tuple[Path, ...]
    every: int = 1

    @classmethod
    def from_options(
        cls, scope: Sequence[str], outputs: Sequence[str], every: int | None
    ) -> ScopeRequest | None:
        """None when no scope was asked for; ScopeError for an incomplete or bad request."""
        every = 1 if every is None else every
        names = parse_channel_list(scope)
        if not names and not outputs:
            if every != 1:
                raise ScopeError("--scope-every needs --scope and --scope-out")
            return None
        if not names:
            raise ScopeError(
                "--scope-out needs --scope CHANNEL,... (e.g. --scope axis0.ref_pos,system_dtest0)"
            )
        if not outputs:
            raise ScopeError("--scope needs --scope-out FILE (.csv, .png, .svg or .vcd)")
        if every < 1:
            raise ScopeError(f"--scope-every must be a whole number of cycles >= 1, got {every}")
        paths = tuple(Path(o) for o in outputs)
        for p in paths:
            check_output_path(p)
        return cls(tuple(names), paths, every)


def check_output_path(path: Path) -> None:
    """ScopeError unless `path` has a known suffix, its folder exists, and plotting is possible."""
    suffix = path.suffix.lower()
    if suffix not in OUTPUT_SUFFIXES:
        raise ScopeError(
            f"--scope-out {path}: unknown file type '{suffix or '(none)'}' "
            f"(expected {', '.join(OUTPUT_SUFFIXES)})"
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


class ScopeRecorder:
    """Samples channels at the end of every `every`-th controller cycle.

    Attach it after every other client, so it sees the cycle's final state. Its
    `next_event` is always the current cycle: while it is attached the controller steps
    every cycle (no jump-ahead), so no sample is skipped.
    A loop without a controller (a standalone PDL drive) calls `sample(cycle)` itself.

    SetHMIScope (manual 2.16): each sample notes the controller's `hmi_scope`. If the
    program called SetHMIScope at all (`controller.hmi_scope_used`), only the samples
    taken while it was on are kept (`save` drops the others), as the vendor's HMI scope
    records only between SetHMIScope(1) and SetHMIScope(0); else every sample is kept.
    """

    def __init__(self, channels: Sequence[Channel], cycle_time: float, every: int = 1) -> None:
        if every < 1:
            raise ValueError(f"every must be >= 1, got {every}")
        self.channels = list(channels)
        self.cycle_time = cycle_time
        """Controller cycle time [s]."""
        self.every = every
        self.cycles: list[int] = []
        """Controller cycle of each sample."""
        self.columns: list[list[float]] = [[] for _ in self.channels]
        """One list of values per channel, parallel to `cycles`."""
        self.hmi_on: list[bool] = []
        """The controller's `hmi_scope` at each sample (True without a controller)."""
        self._controller = None
        self._first_cycle = 0
        self._pairs = list(zip(self.columns, [c.getter for c in self.channels]))

    def attach(self, controller) -> None:
        """Become a client of `controller`, sampling from its current cycle on."""
        self._controller = controller
        self._first_cycle = controller.cycle
        controller.add_client(self)

    def begin_cycle(self) -> None:
        """Nothing: a sample shows the state a cycle left behind."""

    def end_cycle(self) -> None:
        self.sample(self._controller.cycle)

    def busy(self) -> bool:
        """Never: recording does not keep a run going."""
        return False

    def next_event(self) -> int | None:
        """Every cycle is sampled: the clock may not jump."""
        return self._controller.cycle

    def still_running(self) -> list:
        """Nothing: recording never keeps a run going."""
        return []

    def sample(self, cycle: int) -> None:
        """Record every channel as cycle `cycle` (if it is an `every`-th cycle)."""
        if (cycle - self._first_cycle) % self.every:
            return
        self.cycles.append(cycle)
        self.hmi_on.append(bool(getattr(self._controller, "hmi_scope", True)))
        for column, get in self._pairs:
            column.append(get())

    @property
    def hmi_gated(self) -> bool:
        """True if the program called SetHMIScope, so only its on-periods are kept."""
        return bool(getattr(self._controller, "hmi_scope_used", False))

    def apply_hmi_gate(self) -> None:
        """Drop the samples taken while SetHMIScope was off, if the program ever called it."""
        if not self.hmi_gated or all(self.hmi_on):
            return
        keep = [i for i, on in enumerate(self.hmi_on) if on]
        self.cycles[:] = [self.cycles[i] for i in keep]
        for column in self.columns:
            column[:] = [column[i] for i in keep]
        self.hmi_on[:] = [True] * len(keep)

    @property
    def times(self) -> list[float]:
        """Simulated time of each sample [s], rounded to 1 ns so 3 * 0.001 prints as 0.003."""
        dt = self.cycle_time
        return [round(c * dt, 9) for c in self.cycles]

    def save(self, path: str | Path, title: str = "") -> None:
        """Write the recording; the format follows the suffix (.csv, .png, .svg, .vcd)."""
        from motionvm.sim import scope_writers

        self.apply_hmi_gate()
        scope_writers.write(Path(path), self, title=title)
