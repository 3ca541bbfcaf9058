"""Scope recording files: .csv table, .png/.svg plot (matplotlib), .vcd value-change dump.

Every file is written atomically: into a temporary file in the target's folder
(`.NAME.PID-XXXXXXXX.tmp`), then moved over the target with `os.replace`, so a reader
never sees half a file and a failed or interrupted write leaves any previous file
untouched and removes its temporary. A process killed while it writes (SIGKILL) cannot
remove its own: the next write of the same target removes the temporaries of processes
that no longer exist. Outputs are deterministic (no dates,
fixed SVG ids), so the same run gives the same bytes.
"""

from __future__ import annotations

import contextlib
import math
import numbers
import os
import re
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path
from typing import IO

from motionvm.runtime.scope import EdgeGetter, ScopeError

PLOT_INSTALL_HINT = "pip install 'motionvm[plot]'"
"""What to install for .png and .svg plots (matplotlib)."""

VCD_FIRST_ID, VCD_LAST_ID = 33, 126  # printable ASCII, as IEEE 1364 allows for identifier codes


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


STALE_AFTER = 3600.0
"""Age [s] after which a temporary without a process id (written by an older motionvm) is stale."""


def remove_stale_temps(path: Path) -> None:
    """Remove the temporaries of `path` that killed writers left behind: those of a process
    that no longer exists, and unstamped ones older than STALE_AFTER."""
    pattern = re.compile(re.escape(f".{path.name}.") + r"(?:(\d+)-)?[a-z0-9_]{8}\.tmp")
    folder = path.parent if str(path.parent) else Path(".")
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return
    for entry in entries:
        m = pattern.fullmatch(entry.name)
        if m is None:
            continue
        with contextlib.suppress(OSError):
            if m.group(1) is not None:
                if _alive(int(m.group(1))):
                    continue
            elif time.time() - entry.stat(follow_symlinks=False).st_mtime < STALE_AFTER:
                continue
            os.unlink(entry.path)


def _alive(pid: int) -> bool:
    """True if a process `pid` exists (this one included: it may write the file now)."""
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OverflowError, ValueError):
        return True  # another user's process (or a number no process can have): keep it
    return True


@contextlib.contextmanager
def atomic_open(path: Path, binary: bool = False) -> Iterator[IO]:
    """A temporary file next to `path` that replaces `path` only if the block succeeds."""
    remove_stale_temps(path)
    fd, tmp = tempfile.mkstemp(
        prefix=f".{path.name}.{os.getpid()}-", suffix=".tmp", dir=path.parent
    )
    text = {} if binary else {"encoding": "utf-8", "newline": "\n"}
    try:
        with os.fdopen(fd, "wb" if binary else "w", **text) as f:
            os.fchmod(f.fileno(), 0o666 & ~_umask())  # mkstemp gives 0600; use open()'s mode
            yield f
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def write(path: Path, recorder, title: str = "") -> None:
    """Write `recorder`'s samples to `path` in the format its suffix names."""
    suffix = path.suffix.lower()
    if suffix == ".csv":
        writer = write_csv
    elif suffix == ".vcd":
        writer = write_vcd
    elif suffix in (".png", ".svg"):
        writer = write_plot
    else:
        raise ScopeError(f"{path}: unknown scope file type '{suffix}'")
    try:
        writer(path, recorder, title)
    except OSError as exc:
        raise ScopeError(f"cannot write {path}: {exc.strerror or exc}") from None


def format_number(v) -> str:
    """Full precision: integers as integers, everything else as Python's shortest float repr."""
    if isinstance(v, numbers.Integral):
        return str(int(v))
    return repr(float(v))


def csv_lines(recorder) -> Iterator[str]:
    """Header `time,<channel>...` (bare names: units are in the plots' legends and the
    VCD's comment), then one row per sample; time [s]; numbers in full precision."""
    yield ",".join(["time"] + [c.name for c in recorder.channels])
    dt = recorder.cycle_time
    for cycle, values in recorder.rows():
        yield ",".join([format_number(round(cycle * dt, 9))] + [format_number(v) for v in values])


def write_csv(path: Path, recorder, title: str = "") -> None:
    """The .csv table of `csv_lines`."""
    with atomic_open(path) as f:
        f.writelines(line + "\n" for line in csv_lines(recorder))


# ---------------------------------------------------------------- VCD


def _vcd_id(i: int) -> str:
    base = VCD_LAST_ID - VCD_FIRST_ID + 1
    code = ""
    while True:
        code += chr(VCD_FIRST_ID + i % base)
        i = i // base - 1
        if i < 0:
            return code


def _vcd_timescale(cycle_time: float) -> tuple[str, float]:
    """1 us when the cycle is a whole number of microseconds, else 1 ns; (text, ticks per s)."""
    us = cycle_time * 1e6
    if abs(us - round(us)) < 1e-6:
        return "1 us", 1e6
    return "1 ns", 1e9


def _vcd_value(v, bit: bool, ident: str) -> str:
    if bit:
        return f"{1 if v else 0}{ident}"
    return f"r{format_number(v)} {ident}"


def _same(a, b) -> bool:
    """Equal, counting NaN as equal to NaN (else a NaN channel would change every sample)."""
    return a == b or (_is_nan(a) and _is_nan(b))


def _is_nan(v) -> bool:
    return isinstance(v, float) and math.isnan(v)


def write_vcd(path: Path, recorder, title: str = "") -> None:
    """IEEE 1364 value-change dump: `real` channels, `wire 1` bits; `axis0.x` goes in scope axis0.

    A channel whose getter has `edges()` (a list of (sim_time [s], value) since the
    recorder attached, e.g. the position trigger's `axisN.pt_out`, whose pulses are
    shorter than a cycle) is written
    at the exact time of each change between the first and the last sample, in a 1 ns
    timescale, instead of at the samples."""
    chans = recorder.channels
    ids = [_vcd_id(i) for i in range(len(chans))]
    edge_fns = [c.getter.edges if isinstance(c.getter, EdgeGetter) else None for c in chans]
    timescale, ticks_per_s = _vcd_timescale(recorder.cycle_time)
    if any(edge_fns):
        timescale, ticks_per_s = "1 ns", 1e9
    groups: dict[str, list[int]] = {}
    for i, ch in enumerate(chans):
        scope, dot, _ = ch.name.partition(".")
        groups.setdefault(scope if dot else "", []).append(i)

    def var_line(i: int) -> str:
        ch = chans[i]
        ref = ch.name.partition(".")[2] or ch.name
        kind = "wire 1" if ch.is_bit else "real 64"
        return f"$var {kind} {ids[i]} {ref} $end\n"

    with atomic_open(path) as f:
        f.write("$version motionvm scope $end\n")
        if title:
            f.write(f"$comment {title} $end\n")
        f.write(f"$comment channels: {', '.join(f'{c.name} [{c.unit}]' for c in chans)} $end\n")
        f.write(f"$timescale {timescale} $end\n")
        f.write("$scope module motionvm $end\n")
        for i in groups.get("", []):
            f.write(var_line(i))
        for scope, members in groups.items():
            if scope:
                f.write(f"$scope module {scope} $end\n")
                f.writelines(var_line(i) for i in members)
                f.write("$upscope $end\n")
        f.write("$upscope $end\n$enddefinitions $end\n")
        last: list = [None] * len(chans)
        bits = [c.is_bit for c in chans]
        dt = recorder.cycle_time
        sampled = [i for i, fn in enumerate(edge_fns) if fn is None]
        edges = sorted(
            (
                (round(t * ticks_per_s), i, v)
                for i, fn in enumerate(edge_fns)
                if fn is not None
                for t, v in fn()
            ),
            key=lambda e: e[0],
        )  # stable: each channel's edges stay in their order
        k = 0  # the next edge to write
        first_stamp = None
        stamp = None
        for cycle, values in recorder.rows():
            stamp = round(cycle * dt * ticks_per_s)
            if first_stamp is None:
                first_stamp = stamp
                f.write(f"#{stamp}\n$dumpvars\n")
                for i, v in enumerate(values):
                    last[i] = v
                    f.write(_vcd_value(v, bits[i], ids[i]) + "\n")
                f.write("$end\n")
                while k < len(edges) and edges[k][0] <= stamp:  # before the first sample
                    k += 1
                continue
            while k < len(edges) and edges[k][0] < stamp:  # edges between two samples
                k = _write_edges(f, edges, k, last, bits, ids)
            changes: list[str] = []
            for i in sampled:  # inline: once per channel and sample
                v = values[i]
                if not _same(v, last[i]):
                    last[i] = v
                    changes.append(_vcd_value(v, bits[i], ids[i]))
            k = _edge_changes(changes, edges, k, stamp, last, bits, ids)  # at this time
            if changes:
                f.write(f"#{stamp}\n" + "\n".join(changes) + "\n")


def _edge_changes(
    changes: list[str], edges: list, k: int, stamp, last: list, bits: list, ids: list
) -> int:
    """Note the edges at time `stamp` from `edges[k]` on in `changes`; the index of the
    first edge after them."""
    while k < len(edges) and edges[k][0] == stamp:
        _, i, v = edges[k]
        k += 1
        if not _same(v, last[i]):
            last[i] = v
            changes.append(_vcd_value(v, bits[i], ids[i]))
    return k


def _write_edges(f, edges: list, k: int, last: list, bits: list, ids: list) -> int:
    """Write the edges at the time of `edges[k]` (those that change a value); the index
    of the first edge after them."""
    stamp = edges[k][0]
    changes: list[str] = []
    k = _edge_changes(changes, edges, k, stamp, last, bits, ids)
    if changes:
        f.write(f"#{stamp}\n" + "\n".join(changes) + "\n")
    return k


# ---------------------------------------------------------------- plot


def write_plot(path: Path, recorder, title: str = "") -> None:
    """A .png or .svg of `scope_plot.build_figure` (panels by unit and magnitude)."""
    try:
        import matplotlib
    except ImportError:
        raise ScopeError(f"{path}: drawing a plot needs matplotlib; {PLOT_INSTALL_HINT}") from None
    from motionvm.sim.scope_plot import build_figure

    fig = build_figure(recorder, title)
    fmt = path.suffix.lower()[1:]
    metadata = {"Date": None} if fmt == "svg" else {"Software": None}
    rc = {"svg.hashsalt": "motionvm", "svg.fonttype": "path"}  # same run, same bytes
    with matplotlib.rc_context(rc), atomic_open(path, binary=True) as f:
        fig.savefig(f, format=fmt, metadata=metadata)
