"""Scope channel sources: HMPL system and global variables, controller GPIO, axis variables.

Channel names (README "Scope"):
- `system_timeInMs` [ms], `system_fclk`, `system_ltest0..9`, `system_dtest0..9`,
  `system_mtest[i]`, `system_user_table[i]`, and any global variable of the program
  by name (`count`; `table[3]` for an array element) [raw];
- `gpi3`, `gpo5` — one controller general-purpose input/output bit [bool];
  `himc_gpi_bits`, `himc_gpo_bits` — all of them as one integer [raw];
- `axisN.<variable>` — an axis variable of manual 5.1.1 (`axis0.ref_pos`), with the
  manual's unit, read through the axis layer's `variable(name)`;
`registry_for()` wires these sources of one run; a language's run side offers further
sources through its own `scope_sources()` (e.g. the `driveN.<name>` channels of PDL
drives), which the assembler of the run registers after these; sources still listed in
`controller.scope_sources` are asked after these too.
"""

from __future__ import annotations

import difflib
import json
import re
from collections.abc import Callable, Iterable
from functools import partial
from importlib import resources

from motionvm.sim.scope import BIT_UNIT, RAW_UNIT, ChannelRegistry, ScopeError

_ELEMENT = re.compile(r"([A-Za-z_]\w*)(?:\[(\d+)\])?")
_GPIO = re.compile(r"(gpi|gpo)(\d+)")
_AXIS = re.compile(r"axis(\d+)\.(\w+)")
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
    """The controller's general-purpose inputs and outputs, as HMPL sees them."""

    def __init__(self, runtime) -> None:
        self.runtime = runtime

    def resolve(self, name: str) -> tuple[Callable[[], float], str] | None:
        if name in ("himc_gpi_bits", "himc_gpo_bits"):
            bits = self.runtime.gpi if name == "himc_gpi_bits" else self.runtime.gpo
            return (lambda: sum((1 << i) for i, b in enumerate(bits) if b)), RAW_UNIT
        m = _GPIO.fullmatch(name)
        if m is None:
            return None
        bits = self.runtime.gpi if m.group(1) == "gpi" else self.runtime.gpo
        i = int(m.group(2))
        if i >= len(bits):
            raise ScopeError(
                f"scope channel '{name}': the controller has {m.group(1)}0..{m.group(1)}{len(bits) - 1}"
            )
        return partial(bits.__getitem__, i), BIT_UNIT

    def channel_names(self) -> Iterable[str]:
        yield "himc_gpi_bits"
        yield "himc_gpo_bits"
        yield from (f"gpi{i}" for i in range(len(self.runtime.gpi)))
        yield from (f"gpo{i}" for i in range(len(self.runtime.gpo)))


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


def registry_for(controller, runtime=None) -> ChannelRegistry:
    """The channels of one run: HMPL variables and GPIO (if `runtime`), axes, then extra sources."""
    reg = ChannelRegistry()
    if runtime is not None:
        reg.register(HmplSource(runtime))
        reg.register(GpioSource(runtime))
    reg.register(AxisSource(controller))
    for source in getattr(controller, "scope_sources", ()):
        reg.register(source)
    return reg
