"""Machine files (TOML): what the simulated machine is: the controller and its axes.

```toml
axes = 4                # number of axes (default: as many as [[axis]] tables, else 8)

[controller]
cycle_time_ms = 1.0     # controller cycle [ms], 0.125 .. 100
task_slice = 2000       # loop back-edges a task may run per cycle before it yields
data_dir = "data"       # folder for persistent data (user table), relative to this file

[comm]                  # TCP servers and clients (comm/config.py lists the keys)
modbus_port = 1502

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
declaration order. A bad file is reported as one `FILE:LINE:COL: error: MESSAGE` line per
problem, pointing at the key (or section) and naming it; every problem of the file is
reported at once, in file order (exit code 3).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

from motionvm.comm.config import COMM_KEYS, CommConfig, load_comm
from motionvm.io.config import DEFAULT_IO, IOConfig, create_io
from motionvm.motion.axis_config import AxisConfig, AxisConfigError, build_drive
from motionvm.motion.axis_config import create as create_axis
from motionvm.source.toml_places import TomlProblems, parse_toml


class MachineFileError(Exception):
    """A machine file that cannot be used.

    `messages`: one complete line per problem, in file order; `located`: they read
    `FILE:LINE:COL: error: MESSAGE` (False: the file could not be read at all, an error
    of the command line that named it).
    """

    def __init__(self, *messages: str, located: bool = True) -> None:
        super().__init__("\n".join(messages))
        self.messages = list(messages)
        self.located = located


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
    comm: CommConfig = field(default_factory=CommConfig)
    """`[comm]`: the TCP servers' address and ports, the clients' timeout (comm/config.py)."""
    io: IOConfig = DEFAULT_IO
    """Controller GPIO, I/O slaves, wires and sensors (`[io]`, `[[slave]]`, `[[wire]]`,
    `[[sensor]]`: io/config.py)."""


@dataclass(frozen=True)
class PdlDriveSpec:
    """An `[[axis]]` table's `pdl = "..."`: the program its drive runs."""

    axis: int
    path: Path
    """The .pdl file (resolved against the machine file's folder)."""
    starts: tuple[str, ...] = ()
    """Labels the host starts after the drive's reset, in order."""
    where: str = ""
    """`FILE:LINE:COL` of the `pdl_start` key, for errors found after compiling."""


@dataclass(frozen=True)
class GdlMotorSpec:
    """An `[[axis]]` table's `gdl = "NAME"`: the GDL motor object the axis is."""

    axis: int
    name: str
    """The motor object's name, as written (GDL names ignore case)."""
    where: str = ""
    """`FILE:LINE:COL` of the key, for errors found once the application is compiled."""


MAX_AXES = 64
DEFAULT_N_AXES = 8


def default_axes(n: int) -> tuple[AxisConfig, ...]:
    """`n` axes of the built-in machine."""
    return tuple(AxisConfig() for _ in range(n))


DEFAULT_MACHINE = MachineConfig()

_KNOWN = {"controller": {"cycle_time_ms", "task_slice", "data_dir"}, "axis": set(), "axes": set()}
_KNOWN["comm"] = COMM_KEYS
_IO_SECTIONS = ("io", "slave", "wire", "sensor")
"""Sections io/config.py reads and checks."""


class _Problems(TomlProblems):
    """The problems of one machine file."""

    def at_axis(self, index: int, key: str, message: str) -> None:
        """A problem of `key` in the `index`-th [[axis]] table, prefixed `[[axis]] N: `."""
        self.in_array("axis", index, key, f"[[axis]] {index}: {message}")

    def where_in_axis(self, index: int, key: str) -> str:
        return self.where(self.array_place("axis", index, key))

    def io_problem(self, array: str, index: int, key: str | None, message: str) -> None:
        """A problem io/config.py found: in the `index`-th [[array]] table, or in [io]."""
        if index < 0:
            self.at(array or "io", key, message)
        else:
            self.in_array(array, index, key, message)

    def raise_any(self) -> None:
        if self.items:
            raise MachineFileError(*self.headlines())


def load_machine(path: str | Path) -> MachineConfig:
    """Read and validate a machine file; MachineFileError lists every problem of it."""
    p = Path(path)
    try:
        raw = p.read_bytes()
    except OSError as exc:
        raise MachineFileError(
            f"cannot read machine file {p}: {exc.strerror or exc}", located=False
        ) from None
    data, problems = parse_toml(raw, lambda text: _Problems(str(p), text), "invalid TOML")
    if data is None:
        problems.raise_any()
    for sec, val in data.items():
        if sec in ("axis", "axes") or sec in _IO_SECTIONS:
            continue
        if sec not in _KNOWN:
            known = "axis, comm, controller, io, sensor, slave, wire"
            if isinstance(val, dict):
                problems.at(sec, None, f"unknown section [{sec}] (known: {known})")
            else:
                problems.at("", sec, f"unknown key '{sec}' (known: axes, {known})")
            continue
        if not isinstance(val, dict):
            problems.at("", sec, f"'{sec}' must be a table")
            continue
        for key in val:
            if key not in _KNOWN[sec]:
                known = ", ".join(sorted(_KNOWN[sec]))
                problems.at(sec, key, f"unknown key '{key}' in [{sec}] (known: {known})")
    ctl = data.get("controller", {})
    if not isinstance(ctl, dict):
        ctl = {}
    cycle_ms = ctl.get("cycle_time_ms", 1.0)
    if (
        isinstance(cycle_ms, bool)
        or not isinstance(cycle_ms, (int, float))
        or not 0.125 <= cycle_ms <= 100
    ):
        problems.at(
            "controller",
            "cycle_time_ms",
            f"cycle_time_ms = {cycle_ms!r}: must be a number from 0.125 to 100",
        )
        cycle_ms = 1.0
    slice_ = ctl.get("task_slice", 2000)
    if isinstance(slice_, bool) or not isinstance(slice_, int) or not 1 <= slice_ <= 10_000_000:
        problems.at(
            "controller",
            "task_slice",
            f"task_slice = {slice_!r}: must be an integer from 1 to 10000000",
        )
        slice_ = 2000
    data_dir = ctl.get("data_dir")
    if data_dir is not None and not isinstance(data_dir, str):
        problems.at(
            "controller", "data_dir", f"data_dir = {data_dir!r}: must be a string (a folder)"
        )
        data_dir = None
    elif data_dir is not None and "\0" in data_dir:
        problems.at(
            "controller",
            "data_dir",
            "data_dir: a folder name cannot hold a NUL character (\\u0000)",
        )
        data_dir = None
    axes, pdl, gdl = _load_axes(data, problems)
    comm = load_comm(data.get("comm"), problems)
    io = create_io(data, len(axes), problems.io_problem)
    problems.raise_any()
    return MachineConfig(
        cycle_time=cycle_ms / 1000.0,
        task_slice=slice_,
        data_dir=(p.parent / data_dir) if data_dir else None,
        path=p,
        axes=axes,
        pdl_drives=pdl,
        gdl_motors=gdl,
        comm=comm,
        io=io,
    )


def _load_axes(data: dict, problems: _Problems) -> tuple[tuple[AxisConfig, ...], tuple, tuple]:
    tables = data.get("axis", [])
    if not isinstance(tables, list) or not all(isinstance(t, dict) for t in tables):
        problems.at("", "axis", "'axis' must be written as [[axis]] tables")
        tables = []
    n = data.get("axes", len(tables) if tables else DEFAULT_N_AXES)
    if isinstance(n, bool) or not isinstance(n, int) or not 0 <= n <= MAX_AXES:
        problems.at("", "axes", f"axes = {n!r}: must be an integer from 0 to {MAX_AXES}")
        n = max(len(tables), DEFAULT_N_AXES)
    elif len(tables) > n:
        problems.at("", "axes", f"axes = {n} but {len(tables)} [[axis]] tables are given")
        n = len(tables)
    out, pdl, gdl = [], [], []
    for i, table in enumerate(tables):
        table = dict(table)
        spec = _pdl_keys(table, i, problems)
        if spec is not None:
            pdl.append(spec)
        motor = _gdl_key(table, i, problems, "pdl" in tables[i])
        if motor is not None:
            gdl.append(motor)
        out.append(_axis_config(table, i, problems))
    return tuple(out) + default_axes(n - len(tables)), tuple(pdl), tuple(gdl)


def _axis_config(table: dict, i: int, problems: _Problems) -> AxisConfig:
    """The `i`-th [[axis]] table's configuration; each bad key (of the axis, then the
    first of its drive table) is a problem, and the default axis stands in."""
    try:
        config = create_axis(table)
    except AxisConfigError as exc:
        for key, message in exc.problems:
            problems.at_axis(i, key, message)
        drive = table.get("drive")
        try:  # the drive's own keys are checked with the axis's defaults
            probe = create_axis({"drive": drive} if isinstance(drive, dict) else {})
        except AxisConfigError:  # reported above
            return AxisConfig()
        config = AxisConfig()
    else:
        probe = config
    try:
        build_drive(probe)  # a bad drive or mechanics key fails here, at load time
    except AxisConfigError as exc:
        problems.at_axis(i, exc.key, str(exc))
        return AxisConfig()
    return config


def _gdl_key(table: dict, i: int, problems: _Problems, has_pdl: bool) -> GdlMotorSpec | None:
    """Take `gdl` out of the `i`-th [[axis]] table and check it."""
    name = table.pop("gdl", None)
    if name is None:
        return None
    if not isinstance(name, str) or not re.fullmatch(r"[A-Za-z_][\w$]*", name):
        problems.at_axis(i, "gdl", f"gdl = {name!r}: must be the name of a GDL motor object")
        return None
    if has_pdl:
        problems.at_axis(
            i,
            "gdl",
            f"gdl = {name!r}: the axis's drive already runs a PDL program (an axis has one owner)",
        )
        return None
    return GdlMotorSpec(axis=i, name=name, where=problems.where_in_axis(i, "gdl"))


def _pdl_keys(table: dict, i: int, problems: _Problems) -> PdlDriveSpec | None:
    """Take `pdl` and `pdl_start` out of the `i`-th [[axis]] table and check them."""
    prog = table.pop("pdl", None)
    starts = table.pop("pdl_start", None)
    if prog is None:
        if starts is not None:
            problems.at_axis(i, "pdl_start", 'pdl_start needs a PDL program: add pdl = "FILE.pdl"')
        return None
    ok = True
    path = Path(problems.path).parent / str(prog)
    if not isinstance(prog, str) or not prog.lower().endswith(".pdl"):
        problems.at_axis(i, "pdl", f"pdl = {prog!r}: must be the name of a .pdl file")
        ok = False
    elif not path.is_file():
        problems.at_axis(i, "pdl", f"pdl = {prog!r}: no such file ({path})")
        ok = False
    if starts is None:
        starts = []
    if not isinstance(starts, list) or not all(isinstance(s, str) for s in starts):
        problems.at_axis(
            i, "pdl_start", f'pdl_start = {starts!r}: must be a list of labels, e.g. ["_go"]'
        )
        return None
    for label in starts:
        if label != "top" and not label.startswith("_"):
            problems.at_axis(
                i,
                "pdl_start",
                f"pdl_start: '{label}': the host can only start labels beginning with '_' "
                '(or "top")',
            )
            ok = False
    if not ok:
        return None
    where = problems.where_in_axis(i, "pdl_start" if starts else "pdl")
    return PdlDriveSpec(axis=i, path=path, starts=tuple(starts), where=where)
