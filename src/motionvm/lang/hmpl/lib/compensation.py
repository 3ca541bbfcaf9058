"""HMPL dynamic error compensation functions of manual chapter 14.

SetupComp, SetupComp2D and SetupComp3D read the map's values from the User Table
(`system_user_table`, lib/usertable.py) through `UserTableView`, and the 2-D and 3-D
forms their four arrays of two or three elements from the program's memory; the other
functions are the motion commands of their names (`motionvm.motion.commands.compensation`:
checks, codes, decisions).
"""

from __future__ import annotations

from motionvm.lang.hmpl.lib.base import Library, builtin, command
from motionvm.lang.hmpl.lib.usertable import TABLE_LEN


class UserTableView:
    """The User Table as a read-only sequence of floats (for the motion commands)."""

    __slots__ = ("_addr", "_mem")

    def __init__(self, mem, addr: int) -> None:
        self._mem, self._addr = mem, addr

    def __len__(self) -> int:
        return TABLE_LEN

    def __getitem__(self, index: int) -> float:
        if not 0 <= index < TABLE_LEN:
            raise IndexError(index)
        return self._mem.load(self._addr + 8 * index, "f64")


class CompensationLib(Library):
    """Chapter 14: EnableComp ... SetCompAlgType."""

    EnableComp = command()
    DisableComp = command()
    GetCompPos = command()
    SetCompAlgType = command()

    def _table(self) -> UserTableView:
        return UserTableView(self.mem, self.rt.user_table_addr)

    def _arrays(self, func: str, n: int, base: int, interval: int, num_pt: int, ref: int):
        mem = self.mem
        for addr, size, what in ((base, 8, "base_val"), (interval, 8, "interval"),
                                 (num_pt, 4, "num_pt"), (ref, 4, "ref_axis_id")):  # fmt: skip
            mem.check(addr, size * n, f"{func} {what} array")
        return (
            [mem.load(base + 8 * i, "f64") for i in range(n)],
            [mem.load(interval + 8 * i, "f64") for i in range(n)],
            [mem.load(num_pt + 4 * i, "i32") for i in range(n)],
            [mem.load(ref + 4 * i, "i32") for i in range(n)],
        )

    @builtin()
    def SetupComp(
        self, axis_id: int, start_idx: int, base_val: float, interval: float, num_pt: int,
        ref_axis_id: int,
    ) -> int:  # fmt: skip
        return self.rt.commands.SetupComp(
            axis_id, start_idx, base_val, interval, num_pt, ref_axis_id, self._table()
        )

    @builtin()
    def SetupComp2D(
        self, axis_id: int, start_idx: int, base_val: int, interval: int, num_pt: int,
        ref_axis_id: int,
    ) -> int:  # fmt: skip
        arrays = self._arrays("SetupComp2D", 2, base_val, interval, num_pt, ref_axis_id)
        return self.rt.commands.SetupComp2D(axis_id, start_idx, *arrays, self._table())

    @builtin()
    def SetupComp3D(
        self, axis_id: int, start_idx: int, base_val: int, interval: int, num_pt: int,
        ref_axis_id: int,
    ) -> int:  # fmt: skip
        arrays = self._arrays("SetupComp3D", 3, base_val, interval, num_pt, ref_axis_id)
        return self.rt.commands.SetupComp3D(axis_id, start_idx, *arrays, self._table())
