"""A progress bar on stderr for runs that take a while: simulated time against the end.

The run loop calls a `RunProgress` between cycles (`Session.run(progress=...)`) with the
simulated time; it alone reads the wall clock, to decide when to draw (nothing before
`DELAY`: a short run never shows a bar; then at most once per `INTERVAL`) and to show
the real-time factor (simulated seconds per wall second) and the ETA to the end time. The bar is
transient: it is erased when the run ends, before the summary line. It observes the run
and never changes it. Colour follows `NO_COLOR` (any non-empty value: none).
"""

from __future__ import annotations

import os
import sys
import time

DELAY = 0.5
"""Wall time [s] a run must have taken before the bar appears."""
INTERVAL = 0.1
"""Least wall time [s] between two redraws (at most ~10 per second)."""


def wanted(no_progress: bool) -> bool:
    """A bar is drawn only for a person: stderr is a terminal and --no-progress is absent."""
    if no_progress:
        return False
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):  # a replaced or closed stderr
        return False


def no_color() -> bool:
    """True when the environment asks for no colour (NO_COLOR set and not empty)."""
    return os.environ.get("NO_COLOR", "") != ""


class RunProgress:
    """The progress callback of one run: a bar towards `end` [s] of simulated time, or a
    spinner with the simulated time when the run has no end time."""

    def __init__(self, end: float | None) -> None:
        self.end = end if end is not None and end > 0 else None
        self._bar = None
        self._task = None
        self._wall_0 = time.monotonic()
        self._sim_0: float | None = None
        """Simulated time [s] at the first call (the run may start later than t=0)."""
        self._next_draw = self._wall_0 + DELAY
        """Wall time [s] before which nothing is drawn."""

    def __call__(self, sim_time: float) -> None:
        wall_time = time.monotonic()
        if self._sim_0 is None:
            self._sim_0 = sim_time
        if wall_time < self._next_draw:
            return
        self._next_draw = wall_time + INTERVAL
        if self._bar is None and not self._start():
            self._next_draw = float("inf")  # no terminal toolkit: no bar, no further tries
            return
        done = sim_time if self.end is None else min(sim_time, self.end)
        speed, eta = rate_and_eta(sim_time - self._sim_0, wall_time - self._wall_0, self.end, done)
        self._bar.update(self._task, completed=done, speed=speed, eta=eta)
        if not self._bar.live.is_started:
            self._bar.start()  # draws the first frame
        else:
            self._bar.refresh()

    def _start(self) -> bool:
        try:
            from rich.console import Console
            from rich.progress import (
                BarColumn,
                Progress,
                SpinnerColumn,
                TaskProgressColumn,
                TextColumn,
                TimeElapsedColumn,
            )
        except ImportError:
            return False
        console = Console(stderr=True, no_color=no_color(), highlight=False)
        if self.end is None:
            columns = [
                SpinnerColumn(),
                TextColumn("simulated t={task.completed:.3f} s"),
                TextColumn("{task.fields[speed]}"),
                TextColumn("wall"),
                TimeElapsedColumn(),
            ]
        else:
            columns = [
                BarColumn(),
                TaskProgressColumn(),
                TextColumn("t={task.completed:.3f} / {task.total:g} s"),
                TextColumn("{task.fields[speed]}"),
                TextColumn("wall"),
                TimeElapsedColumn(),
                TextColumn("{task.fields[eta]}"),
            ]
        self._bar = Progress(
            *columns,
            console=console,
            transient=True,
            auto_refresh=False,  # drawn from the run loop only, at most every INTERVAL
            redirect_stdout=_stdout_is_terminal(),
            redirect_stderr=True,
        )
        self._task = self._bar.add_task("run", total=self.end, speed="", eta="")
        return True

    def close(self) -> None:
        """Erase the bar (if one was drawn)."""
        if self._bar is not None:
            self._bar.stop()
            self._bar = None

    def __enter__(self) -> RunProgress:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def rate_and_eta(
    sim_span: float, wall_span: float, end: float | None, done: float
) -> tuple[str, str]:
    """The bar's real-time factor (`12.3x real time`: simulated seconds per wall second
    so far) and ETA (`ETA 0:00:04`: the wall time left at that rate to `end` [s];
    "" without an end or a rate yet)."""
    if wall_span <= 0 or sim_span <= 0:
        return "", ""
    factor = sim_span / wall_span
    speed = f"{factor:.1f}x real time" if factor < 100 else f"{factor:.0f}x real time"
    if end is None:
        return speed, ""
    left = max(0.0, end - done) / factor
    whole = int(left + 0.5)
    return speed, f"ETA {whole // 3600}:{whole // 60 % 60:02d}:{whole % 60:02d}"


def _stdout_is_terminal() -> bool:
    """Program messages on a terminal are printed above the bar; a piped stdout is left
    alone (its bytes never pass through the terminal toolkit)."""
    try:
        return sys.stdout.isatty()
    except (AttributeError, ValueError):
        return False
