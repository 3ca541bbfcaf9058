"""Machine files (TOML): what the simulated machine is: the controller and its axes.

```toml
axes = 4                # number of axes (default: as many as [[axis]] tables, else 8)

[controller]
cycle_time_ms = 1.0     # controller cycle [ms], 0.125 .. 100
task_slice = 2000       # loop back-edges a task may run per cycle before it yields
data_dir = "data"       # folder for persistent data (user table), relative to this file

[[axis]]                # axis 0; every key is optional (motion/axis_config.py lists them)
type = "linear"         # or "rotary" (units deg instead of mm)
counts_per_unit = 10000 # encoder counts per mm (or deg)
max_vel = 1000.0        # [mm/s]; max_acc, max_dec [mm/s^2], kill_dec [mm/s^2]
sw_left = -1000.0       # software limits [mm]; hw_left/hw_right: limit switches [mm]
drive = { enable_cycles = 4, mechanics = { model = "servo", bandwidth = 50.0 } }
pdl = "x.pdl"           # a PDL program on this axis's drive (relative to this file)
pdl_start = ["_go"]     # host-started labels of it, in order ("top": the first statement)
# gdl = "main_motor"    # or: the GDL motor object this axis is (by name)
```
With `axes = N` and fewer [[axis]] tables, the tables configure axes 0, 1, ... and the
rest are default axes. The built-in machine (no file) has 8 default axes: linear,
10000 counts/mm, 1000 mm/s, 10000 mm/s^2, kill deceleration 100000 mm/s^2, soft limits
+-1000 mm, limit switches at +-1050 mm, home switch on [0, 5] mm, an index pulse every
10 mm, max position error 10 mm, in position within 0.01 mm for 1 ms, and an ideal
drive whose feedback follows the command one cycle late.
The `pdl` and `gdl` keys are read here (the PDL and GDL run sides use them); the other
axis keys go to motion/axis_config.py. An axis has at most one owner: a PDL program on
its drive or a GDL motor object (`gdl`); GDL motors not named here take the free axes in
declaration order. A bad file is reported as `FILE:LINE: error: MESSAGE` naming the key (exit code 3).
"""

from __future__ import annotations

import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from motionvm.motion.axis_config import AxisConfig, AxisConfigError, build_drive
from motionvm.motion.axis_config import create as create_axis


class MachineFileError(Exception):
    """A machine file that cannot be used; the message names file, line and key."""


@dataclass(frozen=True)
class MachineConfig:
    cycle_time: float = 0.001  # [s]
    task_slice: int = 2000
    data_dir: Path | None = None
    path: Path | None = None
    axes: tuple[AxisConfig, ...] = field(default_factory=lambda: default_axes(DEFAULT_N_AXES))
    pdl_drives: tuple[PdlDriveSpec, ...] = ()
    """The drives that run a PDL program, by axis id."""
    gdl_motors: tuple[GdlMotorSpec, ...] = ()
    """The axes that are a GDL motor object named in the machine file, by axis id."""


@dataclass(frozen=True)
class PdlDriveSpec:
    """An `[[axis]]` table's `pdl = "..."`: the program its drive runs."""

    axis: int
    path: Path
    """The .pdl file (resolved against the machine file's folder)."""
    starts: tuple[str, ...] = ()
    """Labels the host starts after the drive's reset, in order."""
    where: str = ""
    """`FILE:LINE` of the `pdl_start` key, for errors found after compiling."""


@dataclass(frozen=True)
class GdlMotorSpec:
    """An `[[axis]]` table's `gdl = "NAME"`: the GDL motor object the axis is."""

    axis: int
    name: str
    """The motor object's name, as written (GDL names ignore case)."""
    where: str = ""
    """`FILE:LINE` of the key, for errors found once the application is compiled."""


MAX_AXES = 64
DEFAULT_N_AXES = 8


def default_axes(n: int) -> tuple[AxisConfig, ...]:
    """`n` axes of the built-in machine."""
    return tuple(AxisConfig() for _ in range(n))


DEFAULT_MACHINE = MachineConfig()

_KNOWN = {"controller": {"cycle_time_ms", "task_slice", "data_dir"}, "axis": set(), "axes": set()}


def _line_of(text: str, section: str, key: str | None) -> int:
    lines = text.splitlines()
    in_sec = section == ""
    for i, line in enumerate(lines, 1):
        s = line.strip()
        if s.startswith("["):
            in_sec = s.strip("[]").strip() == section
            if key is None and in_sec:
                return i
            continue
        if in_sec and key is not None and re.match(rf"{re.escape(key)}\s*=", s):
            return i
    return 1


def _line_of_axis(text: str, index: int, key: str) -> int:
    """Line of `key` (dotted: its last part) in the `index`-th [[axis]] table."""
    last = key.split(".")[-1]
    seen, header = -1, 1
    for i, line in enumerate(text.splitlines(), 1):
        s = line.strip()
        if re.match(r"\[\[\s*axis\s*\]\]", s):
            seen += 1
            if seen == index:
                header = i
            elif seen > index:
                break
            continue
        if seen == index and re.search(rf"(^|[{{,\s]){re.escape(last)}\s*=", s):
            return i
    return header


def load_machine(path: str | Path) -> MachineConfig:
    """Read and validate a machine file."""
    p = Path(path)
    try:
        text = p.read_text("utf-8")
    except OSError as exc:
        raise MachineFileError(f"{p}: error: cannot read machine file: {exc.strerror}") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        m = re.search(r"line (\d+)", str(exc))
        line = m.group(1) if m else "1"
        raise MachineFileError(f"{p}:{line}: error: invalid TOML: {exc}") from None

    def bad(section: str, key: str | None, msg: str) -> MachineFileError:
        return MachineFileError(f"{p}:{_line_of(text, section, key)}: error: {msg}")

    for sec, val in data.items():
        if sec not in _KNOWN:
            raise bad(sec, None, f"unknown section [{sec}] (known: {', '.join(sorted(_KNOWN))})")
        if sec in ("axis", "axes"):
            continue
        if not isinstance(val, dict):
            raise bad("", sec, f"'{sec}' must be a table")
        for key in val:
            if key not in _KNOWN[sec]:
                raise bad(
                    sec,
                    key,
                    f"unknown key '{key}' in [{sec}] (known: {', '.join(sorted(_KNOWN[sec]))})",
                )
    ctl = data.get("controller", {})
    cycle_ms = ctl.get("cycle_time_ms", 1.0)
    if (
        isinstance(cycle_ms, bool)
        or not isinstance(cycle_ms, (int, float))
        or not 0.125 <= cycle_ms <= 100
    ):
        raise bad(
            "controller",
            "cycle_time_ms",
            f"cycle_time_ms = {cycle_ms!r}: must be a number from 0.125 to 100",
        )
    slice_ = ctl.get("task_slice", 2000)
    if isinstance(slice_, bool) or not isinstance(slice_, int) or not 1 <= slice_ <= 10_000_000:
        raise bad(
            "controller",
            "task_slice",
            f"task_slice = {slice_!r}: must be an integer from 1 to 10000000",
        )
    data_dir = ctl.get("data_dir")
    if data_dir is not None and not isinstance(data_dir, str):
        raise bad("controller", "data_dir", f"data_dir = {data_dir!r}: must be a string (a folder)")
    axes, pdl, gdl = _load_axes(data, text, p)
    return MachineConfig(
        cycle_time=cycle_ms / 1000.0,
        task_slice=slice_,
        data_dir=(p.parent / data_dir) if data_dir else None,
        path=p,
        axes=axes,
        pdl_drives=pdl,
        gdl_motors=gdl,
    )


def _load_axes(data: dict, text: str, p: Path) -> tuple[tuple[AxisConfig, ...], tuple, tuple]:
    tables = data.get("axis", [])
    if not isinstance(tables, list) or not all(isinstance(t, dict) for t in tables):
        raise MachineFileError(
            f"{p}:{_line_of(text, '', 'axis')}: error: 'axis' must be written as [[axis]] tables"
        )
    n = data.get("axes", len(tables) if tables else DEFAULT_N_AXES)
    if isinstance(n, bool) or not isinstance(n, int) or not 0 <= n <= MAX_AXES:
        raise MachineFileError(
            f"{p}:{_line_of(text, '', 'axes')}: error: axes = {n!r}: must be an integer from 0 to {MAX_AXES}"
        )
    if len(tables) > n:
        raise MachineFileError(
            f"{p}:{_line_of(text, '', 'axes')}: error: axes = {n} but {len(tables)} [[axis]] tables are given"
        )
    out, pdl, gdl = [], [], []
    for i, table in enumerate(tables):
        table = dict(table)
        spec = _pdl_keys(table, i, text, p)
        if spec is not None:
            pdl.append(spec)
        motor = _gdl_key(table, i, text, p, spec is not None)
        if motor is not None:
            gdl.append(motor)
        try:
            config = create_axis(table)
            build_drive(config)  # a bad drive or mechanics key fails here, at load time
        except AxisConfigError as exc:
            line = _line_of_axis(text, i, exc.key)
            raise MachineFileError(f"{p}:{line}: error: [[axis]] {i}: {exc}") from None
        out.append(config)
    return tuple(out) + default_axes(n - len(tables)), tuple(pdl), tuple(gdl)


def _gdl_key(table: dict, i: int, text: str, p: Path, has_pdl: bool) -> GdlMotorSpec | None:
    """Take `gdl` out of the `i`-th [[axis]] table and check it."""
    name = table.pop("gdl", None)
    if name is None:
        return None
    line = _line_of_axis(text, i, "gdl")
    if not isinstance(name, str) or not re.fullmatch(r"[A-Za-z_][\w$]*", name):
        raise MachineFileError(
            f"{p}:{line}: error: [[axis]] {i}: gdl = {name!r}: must be the name of a GDL "
            "motor object"
        )
    if has_pdl:
        raise MachineFileError(
            f"{p}:{line}: error: [[axis]] {i}: gdl = {name!r}: the axis's drive already runs "
            "a PDL program (an axis has one owner)"
        )
    return GdlMotorSpec(axis=i, name=name, where=f"{p}:{line}")


def _pdl_keys(table: dict, i: int, text: str, p: Path) -> PdlDriveSpec | None:
    """Take `pdl` and `pdl_start` out of the `i`-th [[axis]] table and check them."""
    prog = table.pop("pdl", None)
    starts = table.pop("pdl_start", None)

    def bad(key: str, msg: str) -> MachineFileError:
        return MachineFileError(f"{p}:{_line_of_axis(text, i, key)}: error: [[axis]] {i}: {msg}")

    if prog is None:
        if starts is not None:
            raise bad("pdl_start", 'pdl_start needs a PDL program: add pdl = "FILE.pdl"')
        return None
    if not isinstance(prog, str) or not prog.lower().endswith(".pdl"):
        raise bad("pdl", f"pdl = {prog!r}: must be the name of a .pdl file")
    path = p.parent / prog
    if not path.is_file():
        raise bad("pdl", f"pdl = {prog!r}: no such file ({path})")
    if starts is None:
        starts = []
    if not isinstance(starts, list) or not all(isinstance(s, str) for s in starts):
        raise bad("pdl_start", f'pdl_start = {starts!r}: must be a list of labels, e.g. ["_go"]')
    for label in starts:
        if label != "top" and not label.startswith("_"):
            raise bad(
                "pdl_start",
                f"pdl_start: '{label}': the host can only start labels beginning with '_' (or \"top\")",
            )
    line = _line_of_axis(text, i, "pdl_start" if starts else "pdl")
    return PdlDriveSpec(axis=i, path=path, starts=tuple(starts), where=f"{p}:{line}")
