"""HMPL controller variable functions of manual 17.3: GetConfigVar, SetConfigVar.

The table of HCV ids and its axis variables are the motion layer's
(`motionvm.motion.config_vars`, `motionvm.motion.commands.config`). The system
variables of table 17.1.1.1 live in the program's memory (manual 22.2: system_fclk,
system_timeInMs, system_user_table, system_ltest0..9, system_dtest0..9, system_mtest),
so this library registers them when the program is loaded: HCV_ID_fclk and
HCV_ID_timelnMs are read-only; an int variable takes a written value truncated toward
zero (out of the int range: eERR_HCV_VALUE_OUT_OF_RANGE); the arrays' ids
(HCV_ID_user_table, HCV_ID_mtest) address their first element. GetConfigVar writes 0 or
-1 to its `int *result` (a null pointer is not written) and returns the value.
"""

from __future__ import annotations

from motionvm.lang.hmpl.lib.base import Library, builtin, command
from motionvm.motion.config_vars import SYSTEM, manual_ids

_SYSVARS = {
    "HCV_ID_fclk": ("system_fclk", "i32", False),
    "HCV_ID_timelnMs": ("system_timeInMs", "i32", False),
    "HCV_ID_user_table": ("system_user_table", "f64", True),
    "HCV_ID_mtest": ("system_mtest", "f64", True),
}
_SYSVARS.update({f"HCV_ID_ltest{i}": (f"system_ltest{i}", "i32", True) for i in range(10)})
_SYSVARS.update({f"HCV_ID_dtest{i}": (f"system_dtest{i}", "f64", True) for i in range(10)})


class ConfigLib(Library):
    """Chapter 17.3: GetConfigVar, SetConfigVar."""

    def __init__(self, rt) -> None:
        super().__init__(rt)
        table = rt.commands.motion.config_vars
        for var, name in manual_ids()[SYSTEM]:
            sysname, kind, writable = _SYSVARS[name]
            addr = rt.program.sysvars[sysname].addr
            table.add(SYSTEM, var, name, self._getter(addr, kind),
                      self._setter(addr, kind) if writable else None)  # fmt: skip

    def _getter(self, addr: int, kind: str):
        mem = self.mem
        return lambda _obj: float(mem.load(addr, kind))

    def _setter(self, addr: int, kind: str):
        mem = self.mem

        def set_(_obj: int, value: float) -> None:
            if kind == "i32":
                if not -(2**31) <= int(value) < 2**31:
                    raise ValueError(f"{value!r} is outside the int range")
                value = int(value)
            mem.store(addr, kind, value)

        return set_

    @builtin()
    def GetConfigVar(self, hcv_id: int, result: int) -> float:
        status, value = self.rt.commands.GetConfigVar(hcv_id)
        if result:
            self.mem.store(result, "i32", status)
        return value

    SetConfigVar = command()
