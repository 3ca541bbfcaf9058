"""Scope channel sources: HMPL system and global variables, controller GPIO, axis
variables, gears and gantry pairs, PDL drives.

Channel names (README "Scope"):
- `system_timeInMs` [ms], `system_fclk`, `system_ltest0..9`, `system_dtest0..9`,
  `system_mtest[i]`, `system_user_table[i]`, and any global variable of the program
  by name (`count`; `table[3]` for an array element) [raw];
- `gpi3`, `gpo5` — one controller general-purpose input/output bit [bool];
  `himc_gpi_bits`, `himc_gpo_bits` — all of them as one integer [raw];
- `axisN.<variable>` — an axis variable of manual 5.1.1 (`axis0.ref_pos`), with the
  manual's unit, read through the axis layer's `variable(name)`;
- `gearN.master_pos_gear`, `gearN.gear_cmd_pos`, `gearN.gear_ratio` — table 6.1.1.1 of
  slave axis N (0 while it is no slave), and `gantryN.linear_ref`, `.yaw_ref`,
  `.linear_fb`, `.yaw_fb` of gantry pair N (0 while there is no such pair):
  `SyncScopeSource`;
- `driveN.<name>` — a system variable or state of the PDL drive of axis N, or a global
  of its program (`drive1.x_ref_pos` [count], `drive1.fclk`, `drive1.x_run` [bool],
  `drive1.ref_pos[0]`, `drive1.p`): `PdlDriveSource`, which `sim/pdl_drives.PdlDrives`
  adds to `controller.scope_sources`.
`registry_for()` wires the sources of one run: the HMPL program's (if any), the
controller's GPIO (`controller.io`), axes, gears and gantry pairs; further layers add
theirs to `controller.scope_sources` (a list) and are asked after these.
"""

from __future__ import annotations

import difflib
import json
import re
from collections.abc import Callable, Iterable
from functools import partial
from importlib import resources

from motionvm.io.gpio import DigitalIO
from motionvm.motion.kernel import MotionKernel
from motionvm.sim.scope import BIT_UNIT, RAW_UNIT, ChannelRegistry, ScopeError

_ELEMENT = re.compile(r"([A-Za-z_]\w*)(?:\[(\d+)\])?")
_GPIO = re.compile(r"(gpi|gpo)(\d+)")
_AXIS = re.compile(r"axis(\d+)\.(\w+)")
_SYNC = re.compile(r"(gear|gantry)(\d+)\.(\w+)")
GEAR_VARIABLES = ("master_pos_gear", "gear_cmd_pos", "gear_ratio")
GANTRY_VARIABLES = ("linear_ref", "yaw_ref", "linear_fb", "yaw_fb")
# Array elements offered as suggestions, per array (system_user_table has 512000).
_SUGGESTED_ELEMENTS = 10


class HmplSource:
    """System variables and global variables of a loaded HMPL program (an `HmplRuntime`)."""

    def __init__(self, runtime) -> None:
        self.runtime = runtime
        self.program = runtime.program

    def _symbol(self, base: str):
        return self.program.sysvars.get(base) or self.program.globals_.get(base)

    def resolve(self, name: str) -> tuple[Callable[[], float], str] | None:
        m = _ELEMENT.fullmatch(name)
        if m is None:
            return None
        base, index = m.group(1), m.group(2)
        sym = self._symbol(base)
        if sym is None:
            return None
        t = sym.type
        elem_t = getattr(t, "elem", None)
        if index is None:
            if elem_t is not None:
                raise ScopeError(
                    f"scope channel '{name}' is an array of {t.n}; "
                    f"record one element, e.g. '{base}[0]'"
                )
            return self._scalar(name, sym, t, sym.addr), self._unit(base)
        if elem_t is None:
            raise ScopeError(f"scope channel '{name}': '{base}' is not an array")
        i = int(index)
        if t.n is not None and i >= t.n:
            raise ScopeError(
                f"scope channel '{name}': index {i} is out of range for {base}[{t.n}] "
                f"(0..{t.n - 1})"
            )
        if sym.storage == "pylist" and elem_t.is_scalar:  # an array kept as a Python list
            ns, pyname = self.runtime.ns, sym.pyname
            return (lambda: ns[pyname][i]), self._unit(base)
        return self._scalar(name, sym, elem_t, sym.addr + i * elem_t.size), self._unit(base)

    def _scalar(self, name: str, sym, t, addr: int) -> Callable[[], float]:
        if not (t.is_arith or t.is_pointer):
            raise ScopeError(f"scope channel '{name}' is a {t}; the scope records numbers")
        if sym.storage == "const":
            value = sym.const_value
            return lambda: value
        if sym.storage == "pyglobal":
            return partial(self.runtime.ns.get, sym.pyname, 0)
        if sym.storage != "static":
            raise ScopeError(f"scope channel '{name}' is not a global variable")
        kind = "i64" if t.is_pointer else t.code
        size = t.size
        if addr % size == 0:
            return partial(getattr(self.runtime.mem, kind).__getitem__, addr // size)
        return partial(self.runtime.mem.load, addr, kind)

    @staticmethod
    def _unit(base: str) -> str:
        return "ms" if base == "system_timeInMs" else RAW_UNIT

    def channel_names(self) -> Iterable[str]:
        for table in (self.program.sysvars, self.program.globals_):
            for base, sym in table.items():
                n = getattr(sym.type, "n", None)
                if getattr(sym.type, "elem", None) is None:
                    yield base
                else:
                    yield from (f"{base}[{i}]" for i in range(min(n or 1, _SUGGESTED_ELEMENTS)))


class GpioSource:
    """The controller's general-purpose inputs and outputs (a `DigitalIO`)."""

    def __init__(self, io: DigitalIO) -> None:
        self.io = io

    def resolve(self, name: str) -> tuple[Callable[[], float], str] | None:
        io = self.io
        if name == "himc_gpi_bits":
            return (lambda: io.input_bits), RAW_UNIT
        if name == "himc_gpo_bits":
            return (lambda: io.output_bits), RAW_UNIT
        m = _GPIO.fullmatch(name)
        if m is None:
            return None
        bits = io.inputs if m.group(1) == "gpi" else io.outputs
        i = int(m.group(2))
        if i >= len(bits):
            raise ScopeError(
                f"scope channel '{name}': the controller has {m.group(1)}0..{m.group(1)}{len(bits) - 1}"
            )
        return partial(bits.__getitem__, i), BIT_UNIT

    def channel_names(self) -> Iterable[str]:
        yield "himc_gpi_bits"
        yield "himc_gpo_bits"
        yield from (f"gpi{i}" for i in range(self.io.n_inputs))
        yield from (f"gpo{i}" for i in range(self.io.n_outputs))


def _manual_axis_units() -> dict[str, str | None]:
    """variable -> the manual's unit text (table 5.1.1.x), e.g. 'mm/s^2 or deg/s^2'."""
    data = json.loads(
        resources.files("motionvm.data").joinpath("hmpl_variables.json").read_text("utf-8")
    )
    return {
        row["variable"]: row.get("unit")
        for t in data["axis_variables"]["tables"]
        for row in t["rows"]
    }


def axis_unit(axis, variable: str, manual: dict[str, str | None]) -> str:
    """The unit of an axis variable: the axis' own `variable_unit()` if it has one, else the manual's."""
    own = getattr(axis, "variable_unit", None)
    if own is not None:
        return own(variable) or RAW_UNIT
    if variable.startswith("di_bit_"):
        return BIT_UNIT
    text = manual.get(variable)
    if not text:
        return RAW_UNIT
    linear, _, rotary = text.partition(" or ")
    is_rotary = bool(getattr(axis, "rotary", False)) or getattr(axis, "kind", "") == "rotary"
    unit = rotary if (is_rotary and rotary) else linear
    return unit.replace("^2", "²")


class AxisSource:
    """Axis variables `axisN.<variable>` of `controller.axes` or `controller.motion.axes`.

    An axis is any object with `variable(name)`; it may offer `variable_names()` (default: the variables of manual 5.1.1) and
    `variable_unit(name)` (default: the manual's unit, in deg if `axis.rotary`).
    """

    def __init__(self, controller) -> None:
        self.controller = controller
        self._manual: dict[str, str | None] | None = None

    def _axes(self):
        """`controller.axes`, or the axes of the controller's motion kernel."""
        axes = getattr(self.controller, "axes", None)
        if axes is None:
            axes = getattr(getattr(self.controller, "motion", None), "axes", None)
        return axes

    def resolve(self, name: str) -> tuple[Callable[[], float], str] | None:
        m = _AXIS.fullmatch(name)
        if m is None:
            return None
        axes = self._axes()
        if axes is None:
            raise ScopeError(f"scope channel '{name}': this controller has no axes")
        n, variable = int(m.group(1)), m.group(2)
        if n >= len(axes):
            have = f"axis0..axis{len(axes) - 1}" if axes else "none"
            raise ScopeError(f"scope channel '{name}': no axis {n} on this machine (axes: {have})")
        axis = axes[n]
        known = self._variable_names(axis)
        if variable not in known:
            close = difflib.get_close_matches(variable, known, n=5, cutoff=0.5)
            hint = (
                f"did you mean {', '.join(f'axis{n}.{c}' for c in close)}?"
                if close
                else f"axis variables are: {', '.join(known)}"
            )
            raise ScopeError(f"unknown scope channel '{name}'; {hint}")
        return partial(axis.variable, variable), axis_unit(axis, variable, self._manual_units())

    def _manual_units(self) -> dict[str, str | None]:
        if self._manual is None:
            self._manual = _manual_axis_units()
        return self._manual

    def _variable_names(self, axis) -> list[str]:
        """The axis' own `variable_names()`, else every variable of manual 5.1.1."""
        own = getattr(axis, "variable_names", None)
        return list(own() if own is not None else self._manual_units())

    def channel_names(self) -> Iterable[str]:
        for n, axis in enumerate(self._axes() or ()):
            yield from (f"axis{n}.{v}" for v in self._variable_names(axis))


class SyncScopeSource:
    """`gearN.*` and `gantryN.*` channels of the gears and gantry pairs of a controller's
    motion kernel (`controller.motion`)."""

    def __init__(self, controller) -> None:
        self.controller = controller

    def _value(self, kind: str, n: int, variable: str) -> float:
        motion = self.controller.motion
        if kind == "gear":
            g = motion.gears.gear_of(n)
            if g is None:
                return 0.0
            return g.ratio if variable == "gear_ratio" else getattr(g, variable)
        pair = motion.gantries.pairs.get(n)
        if pair is None:
            return 0.0
        value = getattr(pair, variable)
        return value[0] if isinstance(value, tuple) else value

    def resolve(self, name: str) -> tuple[Callable[[], float], str] | None:
        m = _SYNC.fullmatch(name)
        if m is None:
            return None
        kind, n, variable = m.group(1), int(m.group(2)), m.group(3)
        known = GEAR_VARIABLES if kind == "gear" else GANTRY_VARIABLES
        axes = self.controller.motion.axes
        if variable not in known or n >= len(axes):
            raise ScopeError(f"unknown scope channel '{name}'; {kind} channels are "
                             f"{kind}0..{kind}{len(axes) - 1}.{{{', '.join(known)}}}")  # fmt: skip
        unit = RAW_UNIT if variable == "gear_ratio" else "deg" if axes[n].rotary else "mm"
        return (lambda: self._value(kind, n, variable)), unit

    def channel_names(self) -> Iterable[str]:
        n = len(self.controller.motion.axes)
        for i in range(n):
            yield from (f"gear{i}.{v}" for v in GEAR_VARIABLES)
        for i in range(n // 2):
            yield from (f"gantry{i}.{v}" for v in GANTRY_VARIABLES)


_DRIVE = re.compile(r"drive(\d+)\.(.+)")
_UNIT_IN_DOC = re.compile(r"\[([^\]]+)\]\s*$")


class PdlDriveSource:
    """`driveN.<name>` of PDL drives: system variables and states (spec/PDL.md §13, any
    case, as the drive's compiler reads them) and the program's global variables.

    `drives` maps a drive number (the axis id in a machine file) to its `Drive`. With
    `bare` set, that drive's names also resolve without the `driveN.` prefix (a
    standalone `motionvm run prog.pdl` has one drive: `x_ref_pos` is `drive0.x_ref_pos`).
    Units: the catalog's (`count`, `count/s`, `count/s²`, `ms`), `bool` for states,
    `raw` for the rest.
    """

    def __init__(self, drives, bare: int | None = None) -> None:
        self.drives = dict(drives)
        self.bare = bare

    def resolve(self, name: str) -> tuple[Callable[[], float], str] | None:
        m = _DRIVE.fullmatch(name)
        if m is None:
            if self.bare is None or _ELEMENT.fullmatch(name) is None:
                return None
            if not self._known(self.drives[self.bare], name):
                return None
            return self._resolve(name, self.bare, name)
        return self._resolve(name, int(m.group(1)), m.group(2))

    @staticmethod
    def _known(drive, ref: str) -> bool:
        from motionvm.lang.pdl.sysvars import lookup

        base = _ELEMENT.fullmatch(ref)
        if base is None:
            return False
        return base.group(1) in drive.program.globals or lookup(base.group(1)) is not None

    def _resolve(self, name: str, n: int, ref: str) -> tuple[Callable[[], float], str]:
        from motionvm.lang.pdl.sysvars import lookup

        drive = self.drives.get(n)
        if drive is None:
            have = ", ".join(f"drive{k}" for k in sorted(self.drives)) or "none"
            raise ScopeError(
                f"scope channel '{name}': no PDL drive {n} (PDL drives: {have}; "
                f"driveN is the drive of axis N)"
            )
        m = _ELEMENT.fullmatch(ref)
        if m is None or not self._known(drive, ref):
            known = [k.partition(".")[2] for k in self._names(n, drive)]
            close = [
                f"drive{n}.{c}" if name != ref else c
                for c in difflib.get_close_matches(ref, known, n=4, cutoff=0.6)
            ]
            hint = (
                f"did you mean {', '.join(close)}?"
                if close
                else "drive channels are a PDL system variable, state or global, "
                "e.g. drive1.x_ref_pos"
            )
            raise ScopeError(f"unknown scope channel '{name}'; {hint}")
        base, index = m.group(1), m.group(2)
        g = drive.program.globals.get(base)
        if g is not None:
            size, unit = g.size, RAW_UNIT
        else:
            sv = lookup(base)
            size = sv.size
            if sv.kind == "state":
                if index is not None:
                    raise ScopeError(f"scope channel '{name}': state '{sv.name}' is one bit")
                return partial(drive.sysvars.ST.__getitem__, sv.address), BIT_UNIT
            found = _UNIT_IN_DOC.search(sv.doc)
            unit = found.group(1).replace("^2", "²") if found else RAW_UNIT
        if index is None and size > 1:
            raise ScopeError(
                f"scope channel '{name}' is an array of {size}; record one element, "
                f"e.g. '{name}[0]'"
            )
        i = int(index or 0)
        if i >= size:
            raise ScopeError(
                f"scope channel '{name}': index {i} is out of range for {base}[{size}] "
                f"(0..{size - 1})"
            )
        if g is None:
            return partial(drive.sysvars.S.__getitem__, drive.sysvars.slot(base, i)), unit
        return partial(drive.read, base, i), unit

    @staticmethod
    def _names(n: int, drive) -> Iterable[str]:
        from motionvm.lang.pdl.sysvars import SYSVARS

        for sv in SYSVARS.values():
            if sv.size == 1:
                yield f"drive{n}.{sv.name}"
            else:
                yield from (f"drive{n}.{sv.name}[{i}]" for i in range(sv.size))
        for g in drive.program.globals.values():
            if g.size == 1:
                yield f"drive{n}.{g.name}"
            else:
                yield from (
                    f"drive{n}.{g.name}[{i}]" for i in range(min(g.size, _SUGGESTED_ELEMENTS))
                )

    def channel_names(self) -> Iterable[str]:
        for n, drive in sorted(self.drives.items()):
            for name in self._names(n, drive):
                yield name
                if n == self.bare:
                    yield name.partition(".")[2]


def registry_for(controller, runtime=None) -> ChannelRegistry:
    """The channels of one run: HMPL variables (if `runtime`), the controller's GPIO (if
    it has `io`), axes, gears and gantry pairs (if it has a motion kernel), then the
    sources in `controller.scope_sources`."""
    reg = ChannelRegistry()
    if runtime is not None:
        reg.register(HmplSource(runtime))
    io = getattr(controller, "io", None)
    if isinstance(io, DigitalIO):
        reg.register(GpioSource(io))
    reg.register(AxisSource(controller))
    if isinstance(getattr(controller, "motion", None), MotionKernel):
        reg.register(SyncScopeSource(controller))
    for source in getattr(controller, "scope_sources", ()):
        reg.register(source)
    return reg
