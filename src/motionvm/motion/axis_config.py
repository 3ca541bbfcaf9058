"""The configuration of one axis (a machine file's `[[axis]]` table), validated at load time.

Every key has a default, so `{}` is the default machine's axis: a linear axis of
10000 counts/mm on an ideal drive that follows its command one cycle late.

| key | unit | default | meaning |
|---|---|---|---|
| type | | "linear" | "linear" (mm) or "rotary" (deg) |
| counts_per_unit | counts/mm or counts/deg | 10000 / 1000 | encoder resolution |
| max_vel, max_acc, max_dec | mm/s, mm/s^2 | 1000, 10000, 10000 | profile limits (SetVel ...) |
| kill_dec | mm/s^2 | 100000 | emergency deceleration (SetKillDec) |
| smooth_time_ms | ms | 0 | moving-average time Ts (SetSMTime, 0..500) |
| sw_left, sw_right | mm | -1000, 1000 | software limits (SetSWLL/SetSWRL) |
| max_pos_err | mm | 10 | position error protection range |
| inpos_radius | mm | 0.01 | in-position target radius |
| inpos_debounce_ms | ms | 1 | in-position debounce time |
| hw_left, hw_right | mm or false | -1050, 1050 | limit switch positions (false: none; rotary: none) |
| home_pos, home_width | mm | 0, 5 | home switch active on [home_pos, home_pos + home_width] |
| index_spacing, index_offset | mm | 10, 0 | encoder index pulses at offset + n * spacing |
| vel_limit, acc_limit | mm/s, mm/s^2 | 5000, 1000000 | protection range of PVT motion |
| start_position | mm | 0 | motor position at power-on |
| enable_timeout_ms | ms | 1000 | Enable fails with eERR_AXIS_DRIVE_ENABLE_TOUT after it |
| torque_constant | N*m/A | 0.5 | for GetCurrFb |
| drive | table | {} | `Cia402Drive.create` keys except the sensor positions; its |
|       |       |    | `mechanics` default to ideal with delay_cycles = 1 |

The continuous torque of MoveTrq is the drive's rated_torque [N*m] (default 1).
Each number must lie in its range (`_RANGES`: positions within +-1e9 mm, speeds and
accelerations up to 1e12 and the profile's at least 1e-6 (`tolerances.MIN_SPEED`,
`MIN_ACC`: a move slower would never end), counts_per_unit 0.001 .. 1e9, index pulses at least one count
apart); beyond them the simulation would overflow, so the file is refused at load time.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

from motionvm.motion.tolerances import MIN_ACC, MIN_SPEED


class AxisConfigError(ValueError):
    """A bad axis setting; `key` names it (a dotted path below the axis table).

    `problems` lists every bad setting found in the table, as (key, message), in the
    order checked; the first one is this error's own `key` and message.
    """

    def __init__(self, key: str, message: str, problems: list[tuple[str, str]] | None = None):
        super().__init__(message)
        self.key = key
        self.problems = problems or [(key, message)]


_SENSOR_KEYS = (
    "negative_limit",
    "positive_limit",
    "home_low",
    "home_high",
    "index_spacing",
    "index_offset",
)


@dataclass
class AxisConfig:
    """Validated settings of one axis; units as in the module table."""

    rotary: bool = False
    counts_per_unit: float = 10000.0
    max_vel: float = 1000.0
    max_acc: float = 10000.0
    max_dec: float = 10000.0
    kill_dec: float = 100000.0
    smooth_time_ms: float = 0.0
    sw_left: float = -1000.0
    sw_right: float = 1000.0
    max_pos_err: float = 10.0
    inpos_radius: float = 0.01
    inpos_debounce_ms: float = 1.0
    hw_left: float | None = -1050.0
    hw_right: float | None = 1050.0
    home_pos: float | None = 0.0
    home_width: float = 5.0
    index_spacing: float | None = 10.0
    index_offset: float = 0.0
    vel_limit: float = 5000.0
    acc_limit: float = 1_000_000.0
    start_position: float = 0.0
    enable_timeout_ms: float = 1000.0
    torque_constant: float = 0.5
    drive: dict = field(default_factory=dict)

    def drive_config(self) -> dict:
        """The `Cia402Drive.create` table: the user's drive keys plus sensors in counts."""
        cfg = dict(self.drive)
        cpu = self.counts_per_unit
        mech = dict(cfg.get("mechanics", {"model": "ideal", "delay_cycles": 1}))
        mech.setdefault("counts_per_rev", max(1, round(cpu * (360.0 if self.rotary else 10.0))))
        cfg["mechanics"] = mech
        if self.hw_left is not None:
            cfg["negative_limit"] = self.hw_left * cpu
        if self.hw_right is not None:
            cfg["positive_limit"] = self.hw_right * cpu
        if self.home_pos is not None:
            cfg["home_low"] = self.home_pos * cpu
            cfg["home_high"] = (self.home_pos + self.home_width) * cpu
        if self.index_spacing is not None:
            cfg["index_spacing"] = self.index_spacing * cpu
            cfg["index_offset"] = self.index_offset * cpu
        cfg["position"] = self.start_position * cpu
        return cfg


# The range of each number key: (low, high, low_inclusive). Beyond these the simulation
# overflows (an encoder count beyond float range, an index every 1e-300 counts) or the
# value is meaningless for a machine axis; every range is far wider than any real one.
_POSITION = (-1e9, 1e9, True)  # [mm] or [deg]
_RANGES: dict[str, tuple[float, float, bool]] = {
    "counts_per_unit": (1e-3, 1e9, True),
    "max_vel": (MIN_SPEED, 1e12, True),
    "max_acc": (MIN_ACC, 1e12, True),
    "max_dec": (MIN_ACC, 1e12, True),
    "kill_dec": (MIN_ACC, 1e12, True),
    "vel_limit": (0.0, 1e12, False),
    "acc_limit": (0.0, 1e12, False),
    "max_pos_err": (0.0, 1e9, False),
    "inpos_radius": (0.0, 1e9, False),
    "enable_timeout_ms": (0.0, 1e9, False),
    "torque_constant": (0.0, 1e6, False),
    "inpos_debounce_ms": (0.0, 1e9, True),
    "home_width": (0.0, 1e9, True),
    "smooth_time_ms": (0.0, 500.0, True),
    "index_spacing": (0.0, 1e9, False),
    "sw_left": _POSITION,
    "sw_right": _POSITION,
    "index_offset": _POSITION,
    "start_position": _POSITION,
    "hw_left": _POSITION,
    "hw_right": _POSITION,
    "home_pos": _POSITION,
}


def range_text(key: str) -> str:
    """The range `key` must be in, as `1e-06 <= max_vel <= 1e+12`."""
    low, high, low_inclusive = _RANGES[key]
    return f"{low:g} {'<=' if low_inclusive else '<'} {key} <= {high:g}"


def _number(table: dict, key: str, default: float, *, optional=False):
    if key not in table:
        return default
    value = table[key]
    if optional and value is False:
        return None
    low, high, low_inclusive = _RANGES[key]
    ok = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
    if not ok:
        want = "a finite number" + (" or false" if optional else "")
        raise AxisConfigError(key, f"{key} = {value!r}: must be {want}, {range_text(key)}")
    if not ((low <= value) if low_inclusive else (low < value)) or value > high:
        raise AxisConfigError(key, f"{key} = {value!r}: must be in {range_text(key)}")
    return float(value)


def create(table: dict) -> AxisConfig:
    """Validate an `[[axis]]` table; unknown keys or bad values raise one AxisConfigError
    listing every one of them (`problems`)."""
    problems: list[tuple[str, str]] = []

    def number(key: str, default, **kind):
        try:
            return _number(table, key, default, **kind)
        except AxisConfigError as exc:
            problems.append((exc.key, str(exc)))
            return default

    known = set(AxisConfig.__dataclass_fields__) - {"rotary"} | {"type"}
    for key in table:
        if key not in known:
            problems.append(
                (key, f"unknown key '{key}' in [[axis]] (known: {', '.join(sorted(known))})")
            )
    kind = table.get("type", "linear")
    if kind not in ("linear", "rotary"):
        problems.append(("type", f'type = {kind!r}: must be "linear" or "rotary"'))
    rotary = kind == "rotary"
    c = AxisConfig(rotary=rotary, counts_per_unit=1000.0 if rotary else 10000.0)
    if rotary:  # a rotary table turns on: no limit switches unless given
        c.hw_left = c.hw_right = None
    c.counts_per_unit = number("counts_per_unit", c.counts_per_unit)
    for key in (
        "max_vel",
        "max_acc",
        "max_dec",
        "kill_dec",
        "max_pos_err",
        "inpos_radius",
        "vel_limit",
        "acc_limit",
        "enable_timeout_ms",
        "torque_constant",
    ):
        setattr(c, key, number(key, getattr(c, key)))
    for key in ("inpos_debounce_ms", "home_width"):
        setattr(c, key, number(key, getattr(c, key)))
    for key in ("sw_left", "sw_right", "index_offset", "start_position"):
        setattr(c, key, number(key, getattr(c, key)))
    for key in ("hw_left", "hw_right", "home_pos"):
        setattr(c, key, number(key, getattr(c, key), optional=True))
    c.index_spacing = number("index_spacing", c.index_spacing, optional=True)
    c.smooth_time_ms = number("smooth_time_ms", 0.0)
    if c.index_spacing is not None and c.index_spacing * c.counts_per_unit < 1:
        given = "index_spacing" in table
        problems.append(
            (
                "index_spacing" if given else "counts_per_unit",
                f"index_spacing = {c.index_spacing:g}{'' if given else ' (the default)'} at "
                f"counts_per_unit = {c.counts_per_unit:g} is "
                f"{c.index_spacing * c.counts_per_unit:g} counts: index pulses must be at "
                "least 1 count apart",
            )
        )
    if c.sw_left >= c.sw_right:
        problems.append(
            ("sw_right", f"sw_right = {c.sw_right:g} must be above sw_left = {c.sw_left:g}")
        )
    if c.hw_left is not None and c.hw_right is not None and c.hw_left >= c.hw_right:
        problems.append(
            ("hw_right", f"hw_right = {c.hw_right:g} must be above hw_left = {c.hw_left:g}")
        )
    if abs(c.start_position) * c.counts_per_unit >= 2**31:
        problems.append(
            (
                "start_position",
                f"start_position = {c.start_position:g} is outside the int32 encoder range",
            )
        )
    drive = table.get("drive", {})
    if not isinstance(drive, dict):
        problems.append(("drive", f"drive = {drive!r}: must be a table"))
        drive = {}
    if "mechanics" in drive and not isinstance(drive["mechanics"], dict):
        problems.append(
            ("drive.mechanics", f"drive.mechanics = {drive['mechanics']!r}: must be a table")
        )
        drive = {}
    for key in _SENSOR_KEYS + ("position",):
        if key in drive:
            problems.append(
                (
                    f"drive.{key}",
                    f"drive.{key}: set the switches and index in the axis table "
                    "(hw_left, hw_right, home_pos, home_width, index_spacing, index_offset, "
                    "start_position)",
                )
            )
    if problems:
        raise AxisConfigError(*problems[0], problems)
    c.drive = drive
    return c


def build_drive(config: AxisConfig):
    """The axis's Cia402Drive; a bad drive key raises AxisConfigError naming it."""
    from motionvm.drives.cia402 import Cia402Drive

    try:
        return Cia402Drive.create(config.drive_config())
    except ValueError as exc:
        msg = str(exc)
        m = re.search(r"unknown key '(\w+)'", msg) or re.search(r"(\w+) = ", msg)
        part = "drive.mechanics" if msg.startswith("mechanics") else "drive"
        raise AxisConfigError(f"{part}.{m.group(1)}" if m else part, msg) from None


def check_range(key: str, value: float) -> bool:
    """True if `value` lies in the machine file's range of `key` (a setter's check)."""
    low, high, low_inclusive = _RANGES[key]
    return (
        math.isfinite(value)
        and ((low <= value) if low_inclusive else (low < value))
        and value <= high
    )
