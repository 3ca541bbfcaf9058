"""HMPL synchronous motion functions of manual chapter 6: the electronic gear.

EnableGear couples a slave to a master, GearIn engages it at a ratio, GearOut
disengages it, DisableGear uncouples; the status functions ask about each state. The
behaviour (ramps, order of master and slave, decisions where the manual is silent) is
in `motionvm.motion.gear`. A function that fails returns the manual's axis error
(0x83XXCCCC with XX the axis the error belongs to, as a C int) and stores it as that
axis's last error; a bad axis id returns eERR_HMPL_ARG_OUT_OF_RANGE (0x138F) and stores
it as the system's last error. Queries of a bad axis id return 0 and store the same.

The variables of table 6.1.1.1 and the gantry's linear/yaw values are scope channels
(`SyncScopeSource`): `gearN.master_pos_gear`, `gearN.gear_cmd_pos`, `gearN.gear_ratio`
of slave axis N (0 while it is no slave), and `gantryN.linear_ref`, `.yaw_ref`,
`.linear_fb`, `.yaw_fb` of gantry pair N (0 while there is no such pair).
"""

from __future__ import annotations

import re

from motionvm.lang.hmpl.lib.base import Library, builtin
from motionvm.motion import axis_status as st
from motionvm.motion.gantry import gantries_of
from motionvm.motion.gear import SyncError, gearbox_of

GEAR_VARIABLES = ("master_pos_gear", "gear_cmd_pos", "gear_ratio")
GANTRY_VARIABLES = ("linear_ref", "yaw_ref", "linear_fb", "yaw_fb")
_CHANNEL = re.compile(r"(gear|gantry)(\d+)\.(\w+)")


class SyncScopeSource:
    """Scope channels of the gears and gantry pairs of a controller (see the module doc)."""

    def __init__(self, controller):
        self.controller = controller

    def _value(self, kind: str, n: int, variable: str) -> float:
        motion = self.controller.motion
        if kind == "gear":
            g = gearbox_of(motion).gear_of(n)
            if g is None:
                return 0.0
            return g.ratio if variable == "gear_ratio" else getattr(g, variable)
        pair = gantries_of(motion).pairs.get(n)
        if pair is None:
            return 0.0
        value = getattr(pair, variable)
        return value[0] if isinstance(value, tuple) else value

    def resolve(self, name: str):
        m = _CHANNEL.fullmatch(name)
        if m is None:
            return None
        kind, n, variable = m.group(1), int(m.group(2)), m.group(3)
        known = GEAR_VARIABLES if kind == "gear" else GANTRY_VARIABLES
        axes = self.controller.motion.axes
        if variable not in known or n >= len(axes):
            from motionvm.sim.scope import ScopeError

            raise ScopeError(f"unknown scope channel '{name}'; {kind} channels are "
                             f"{kind}0..{kind}{len(axes) - 1}.{{{', '.join(known)}}}")  # fmt: skip
        unit = "raw" if variable == "gear_ratio" else "deg" if axes[n].rotary else "mm"
        return (lambda: self._value(kind, n, variable)), unit

    def channel_names(self):
        n = len(self.controller.motion.axes)
        for i in range(n):
            yield from (f"gear{i}.{v}" for v in GEAR_VARIABLES)
        for i in range(n // 2):
            yield from (f"gantry{i}.{v}" for v in GANTRY_VARIABLES)


class SyncCalls:
    """Plumbing shared by the gear and gantry built-ins (a mixin of their libraries)."""

    @property
    def _motion(self):
        return self.rt.controller.motion

    def _axes(self, *ids: int) -> list | None:
        """The axes of `ids`, or None (and the system's last error set) if one is bad."""
        motion = self._motion
        out = [motion.axis(i) for i in ids]
        if None in out:
            motion.system_last_error = st.SYS_HMPL_ARG_OUT_OF_RANGE
            return None
        return out

    def _call(self, fn, *axes) -> int:
        """`fn(*axes)`: 0, or the error it raised (stored as the last error of its axis)."""
        try:
            fn(*axes)
        except SyncError as exc:
            code = st.axis_error(exc.code, exc.axis_id)
            self._motion.axes[exc.axis_id].last_error = code
            return code
        return 0


class SyncLib(SyncCalls, Library):
    """Chapter 6: EnableGear ... IsGearSlave."""

    def __init__(self, rt) -> None:
        super().__init__(rt)
        controller = getattr(rt, "controller", None)
        if controller is not None:  # offer the channels to a scope (sim/scope_sources.py)
            sources = controller.__dict__.setdefault("scope_sources", [])
            if not any(isinstance(s, SyncScopeSource) for s in sources):
                sources.append(SyncScopeSource(controller))

    @property
    def _gears(self):
        return gearbox_of(self._motion)

    def _command(self, name: str, *ids: int, args: tuple = ()) -> int:
        axes = self._axes(*ids)
        if axes is None:
            return st.SYS_HMPL_ARG_OUT_OF_RANGE
        return self._call(getattr(self._gears, name), *axes, *args)

    def _query(self, name: str, axis_id: int):
        if self._axes(axis_id) is None:
            return 0
        return getattr(self._gears, name)(axis_id)

    @builtin()
    def EnableGear(self, axis_master_id: int, axis_slave_id: int) -> int:
        return self._command("enable_gear", axis_master_id, axis_slave_id)

    @builtin()
    def DisableGear(self, axis_slave_id: int) -> int:
        return self._command("disable_gear", axis_slave_id)

    @builtin()
    def GearIn(self, axis_master_id: int, axis_slave_id: int, gear_ratio: float) -> int:
        return self._command("gear_in", axis_master_id, axis_slave_id, args=(gear_ratio,))

    @builtin()
    def GearOut(self, axis_slave_id: int) -> int:
        return self._command("gear_out", axis_slave_id)

    @builtin()
    def GetGearRatio(self, axis_slave_id: int) -> float:
        return float(self._query("ratio", axis_slave_id))

    @builtin()
    def IsInGear(self, axis_id: int) -> int:
        return 1 if self._query("is_in_gear", axis_id) else 0

    @builtin()
    def IsGearMaster(self, axis_id: int) -> int:
        return 1 if self._query("is_master", axis_id) else 0

    @builtin()
    def IsGearSlave(self, axis_id: int) -> int:
        return 1 if self._query("is_slave", axis_id) else 0
