"""What the studio's panels show of a run, as JSON: the machine's layout, the axes table,
the I/O points, the group path, and the columns of the recording that feed them.

Every panel reads scope channels (sim/scope.py), so that a live view and a recorded row
(history.py) give the same numbers: the axes table shows `axisN.<column>` for
`AXIS_COLUMNS` and a state word `axisN.state` (bits of `STATE_FLAGS`), the I/O panel the
digital channels (`gpiN`, `gpoN`, `slvS.diK`, `slvS.doK`), the path view the first two
(or three) axes' feedback positions and, once the program enables an axis group of two
axes or more, that group's Cartesian feedback pose `groupN.carte_pose_fb[0..2]` (X, Y and,
for a group of three axes or more, Z): each group's path in its own coordinates. The
groups are found through the controller's motion kernel (`controller.motion.groups`);
`Layout.watch_groups` is asked every cycle (one identity test while the enabled groups
stay the same) and adds a group's columns from the cycle it is enabled.
"""

from __future__ import annotations

import re
from collections.abc import Callable

from motionvm.runtime.scope import BIT_UNIT
from motionvm.sim.variables import AXIS_FLAGS

AXIS_COLUMNS = ("ref_pos", "pos_fb", "vel_fb", "pos_err", "fault_status")
"""Axis variables in the axes table: command and feedback position [mm], feedback
velocity [mm/s], following error [mm], fault bits."""

STATE_FLAGS = ("enabled", "moving", "in_pos", "error_stop", "homing", "homed", "drive_fault")
"""The axis flags packed into the recorded state word, bit 0 first."""

DEFAULT_SCOPE = 8
"""Scope channels shown from the start: axes' feedback positions, then velocities."""

_INPUT = re.compile(r"gpi\d+|slv\d+\.(?:s\d+\.)?di\d+")
_OUTPUT = re.compile(r"gpo\d+|slv\d+\.(?:s\d+\.)?do\d+")


def state_getter(axis) -> Callable[[], int]:
    tests = [AXIS_FLAGS[name] for name in STATE_FLAGS]

    def state() -> int:
        word = 0
        for bit, test in enumerate(tests):
            if test(axis):
                word |= 1 << bit
        return word

    return state


def state_text(word: float | None) -> str:
    """The axes table's state of a state word."""
    if word is None:
        return "?"
    w = int(word)
    flags = {name for bit, name in enumerate(STATE_FLAGS) if w >> bit & 1}
    if "error_stop" in flags or "drive_fault" in flags:
        return "error"
    if "homing" in flags:
        return "homing"
    if not flags & {"enabled"}:
        return "disabled"
    if "moving" in flags:
        return "moving"
    return "standstill"


def default_scope(axes: int, names: list[str]) -> list[str]:
    """Up to `DEFAULT_SCOPE` channels: the axes' feedback positions, their feedback and
    command velocities; the outputs on a machine without axes (or else the clock)."""
    out = [f"axis{i}.pos_fb" for i in range(min(4, axes))]
    out += [f"axis{i}.vel_fb" for i in range(min(4, axes))]
    out += [f"axis{i}.ref_vel" for i in range(axes)]
    if not out:
        out = [n for n in names if _OUTPUT.fullmatch(n)]
    return out[:DEFAULT_SCOPE] or [n for n in names if n == "system_timeInMs"][:1]


class Layout:
    """The panels' channels for one machine (the same for every session of a run)."""

    def __init__(
        self,
        controller,
        registry,
        scope: list[str] | None = None,
        groups: dict[int, int] | None = None,
    ) -> None:
        axes = controller.axes
        self.axes = len(axes)
        self.units: dict[str, str] = {}
        self.getters: dict[str, Callable[[], object]] = {}
        names = registry.names()
        self.inputs = [n for n in names if _INPUT.fullmatch(n)]
        self.outputs = [n for n in names if _OUTPUT.fullmatch(n)]
        for i, axis in enumerate(axes):
            for col in AXIS_COLUMNS:
                self._add(registry, f"axis{i}.{col}")
            self.getters[f"axis{i}.state"] = state_getter(axis)
            self.units[f"axis{i}.state"] = ""
        for name in self.inputs + self.outputs:
            self._add(registry, name)
        self.path = [f"axis{i}.pos_fb" for i in range(min(3, self.axes))]
        self.scope = list(scope) if scope is not None else default_scope(self.axes, names)
        for name in self.scope:
            self._add(registry, name)
        self._registry = registry
        self._groups = controller.motion.groups
        self._enabled_seen: object = None
        self.groups: dict[int, int] = {}
        """Group id -> the dimensions of its path (2: XY, 3: XYZ), of every group seen
        enabled with two axes or more (kept over the sessions of a run: `groups`)."""
        for gid, dims in sorted((groups or {}).items()):
            self._add_group(gid, dims)

    def _add_group(self, gid: int, dims: int) -> None:
        self.groups[gid] = dims
        for i in range(dims):
            name = f"group{gid}.carte_pose_fb[{i}]"
            self._add(self._registry, name)
            if name not in self.path:
                self.path.append(name)

    def watch_groups(self) -> dict[str, Callable[[], object]] | None:
        """The getters, if an axis group was enabled with more dimensions than seen so
        far (None: nothing new; cheap while the enabled groups stay the same)."""
        enabled = self._groups.enabled
        if enabled is self._enabled_seen:
            return None
        self._enabled_seen = enabled
        grown = False
        for g in enabled:
            dims = min(3, len(g.axes))
            if dims >= 2 and dims > self.groups.get(g.group_id, 0):
                self._add_group(g.group_id, dims)
                grown = True
        return self.getters if grown else None

    def path_groups(self) -> list[dict]:
        """The groups of the path view: name, dimensions, their columns (X, Y[, Z])."""
        return [{"name": f"group{gid}", "dims": dims,
                 "channels": [f"group{gid}.carte_pose_fb[{i}]" for i in range(dims)]}
                for gid, dims in sorted(self.groups.items())]  # fmt: skip

    def _add(self, registry, name: str) -> None:
        channel = registry.find(name)
        if channel is not None:
            self.getters[name] = channel.getter
            self.units[name] = channel.unit

    def bits(self) -> set[str]:
        return {n for n, u in self.units.items() if u == BIT_UNIT}

    def describe(self) -> dict:
        return {
            "axes": [
                {"name": f"axis{i}", "unit": self.units.get(f"axis{i}.pos_fb", "mm")}
                for i in range(self.axes)
            ],  # fmt: skip
            "inputs": self.inputs,
            "outputs": self.outputs,
            "path": [n for n in self.path if n.startswith("axis")],
            "groups": self.path_groups(),
        }

    def axes_rows(self, row: dict[str, float | None]) -> list[dict]:
        out = []
        for i in range(self.axes):
            out.append({
                "name": f"axis{i}",
                "state": state_text(row.get(f"axis{i}.state")),
                **{col: row.get(f"axis{i}.{col}") for col in AXIS_COLUMNS},
            })  # fmt: skip
        return out

    def io_values(self, row: dict[str, float | None]) -> dict[str, dict[str, int | None]]:
        def bit(v):
            return None if v is None else int(bool(v))

        return {
            "inputs": {n: bit(row.get(n)) for n in self.inputs},
            "outputs": {n: bit(row.get(n)) for n in self.outputs},
        }

    def live_row(self) -> dict[str, float | None]:
        """Every panel column, read now."""
        out: dict[str, float | None] = {}
        for name, get in self.getters.items():
            try:
                out[name] = float(get())  # type: ignore[arg-type]
            except (TypeError, ValueError):
                out[name] = None
        return out
