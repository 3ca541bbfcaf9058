"""Scope channel sources of the machine: controller GPIO, axis variables, gears and
gantry pairs; `registry_for` adds them to the sources of a run's language clients.

Channel names (docs/scope.md):
- the controller's I/O: `gpi3`, `gpo5`, `himc_gpi_bits`, slave channels `slv8.di1` ...
  (sim/scope_io.py);
- `axisN.<variable>` — an axis variable of manual 5.1.1 (`axis0.ref_pos`), with the
  manual's unit, read through the axis layer's `variable(name)`;
- `gearN.master_pos_gear`, `gearN.gear_cmd_pos`, `gearN.gear_ratio` — table 6.1.1.1 of
  slave axis N (0 while it is no slave), and `gantryN.linear_ref`, `.yaw_ref`,
  `.linear_fb`, `.yaw_fb` of gantry pair N (0 while there is no such pair):
  `SyncScopeSource`.
- `groupN.<variable>`, `groupN.<array>[i]` — the group variables of manual 8.1.1:
  `GroupScopeSource` (sim/scope_groups.py).
`registry_for()` wires the sources of one run: each language run side's own (its
`scope_sources()`: an HMPL program's variables, the `driveN.<name>` channels of PDL
drives, the `OBJECT.STATE` channels of a GDL application), then these.
"""

from __future__ import annotations

import difflib
import json
import re
from collections.abc import Callable, Iterable
from functools import partial
from importlib import resources

from motionvm.runtime.scope import ScopeAxis
from motionvm.sim.scope import BIT_UNIT, RAW_UNIT, ChannelRegistry, ChannelSource, ScopeError
from motionvm.sim.scope_groups import GroupScopeSource
from motionvm.sim.scope_io import IoSource

_AXIS = re.compile(r"axis(\d+)\.(\w+)")
_SYNC = re.compile(r"(gear|gantry)(\d+)\.(\w+)")
GEAR_VARIABLES: dict[str, Callable] = {
    "master_pos_gear": lambda g: g.master_pos_gear,
    "gear_cmd_pos": lambda g: g.gear_cmd_pos,
    "gear_ratio": lambda g: g.ratio,
}
"""The `gearN.*` channels: what each reads of the gear (motion/gear.py)."""
GANTRY_VARIABLES: dict[str, Callable] = {
    "linear_ref": lambda p: p.linear_ref,
    "yaw_ref": lambda p: p.yaw_ref,
    "linear_fb": lambda p: p.linear_fb,
    "yaw_fb": lambda p: p.yaw_fb,
}
"""The `gantryN.*` channels: what each reads of the pair (motion/gantry.py)."""


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


def axis_unit(axis: ScopeAxis, variable: str, manual: dict[str, str | None]) -> str:
    """The unit of an axis variable: the manual's, in deg if the axis is rotary."""
    if variable.startswith("di_bit_"):
        return BIT_UNIT
    text = manual.get(variable)
    if not text:
        return RAW_UNIT
    linear, _, rotary = text.partition(" or ")
    unit = rotary if (rotary and axis.rotary) else linear
    return unit.replace("^2", "²")


class AxisSource(ChannelSource):
    """Axis variables `axisN.<variable>` of `controller.axes` (None: no axes).

    An axis is a `ScopeAxis`: `variable(name)`, `variable_names()` (default: the
    variables of manual 5.1.1), the manual's units (in deg if `axis.rotary`).
    """

    def __init__(self, controller) -> None:
        self.controller = controller
        self._manual: dict[str, str | None] | None = None

    def _axes(self) -> list[ScopeAxis] | None:
        return self.controller.axes

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

    def _variable_names(self, axis: ScopeAxis) -> list[str]:
        """The axis' own `variable_names()`, else every variable of manual 5.1.1."""
        own = axis.variable_names()
        return list(own if own is not None else self._manual_units())

    def channel_names(self) -> Iterable[str]:
        for n, axis in enumerate(self._axes() or ()):
            yield from (f"axis{n}.{v}" for v in self._variable_names(axis))


class SyncScopeSource(ChannelSource):
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
            return GEAR_VARIABLES[variable](g)
        pair = motion.gantries.pairs.get(n)
        if pair is None:
            return 0.0
        value = GANTRY_VARIABLES[variable](pair)
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


def registry_for(controller, *clients) -> ChannelRegistry:
    """The channels of one run: each client's own (`scope_sources()`: an HMPL program's
    variables, PDL drives, a GDL application's states), in the order given, then the
    machine's: the controller's (sim/controller.py) I/O, position triggers, axes, gears,
    gantry pairs and axis groups."""
    reg = ChannelRegistry()
    for client in clients:
        if client is not None:
            for source in client.scope_sources():
                reg.register(source)
    reg.register(IoSource(controller.io))
    reg.register(
        controller.triggers
    )  # axisN.pt_count, .pt_out, .pt_enabled (io/position_trigger.py)
    reg.register(AxisSource(controller))
    reg.register(SyncScopeSource(controller))
    reg.register(GroupScopeSource(controller))  # groupN.* (sim/scope_groups.py)
    return reg
