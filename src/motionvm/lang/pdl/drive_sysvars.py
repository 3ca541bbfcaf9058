"""Where the drive keeps its system variables and states, and what writing them does.

The catalog (`sysvars.py`) names them; here each numeric system
variable gets `size` slots of one Python list `S` (generated code reads `S[k]`), in
catalog order, and each state is one byte of the status array `ST` at its bit address
(`<state>` is that address). Writes go through `SysVarStore.write`, which converts to
the variable's type and runs the drive's reaction (a new `X_trg` starts a move).
"""

from __future__ import annotations

from collections.abc import Callable

from motionvm.lang.pdl import sysvars
from motionvm.lang.pdl.rt_builtins import f32
from motionvm.lang.pdl.rt_memory import round_int, w16, w32
from motionvm.runtime.errors import RuntimeFault


def _layout() -> tuple[dict[str, int], list[sysvars.SysVar], int]:
    bases: dict[str, int] = {}
    owners: list[sysvars.SysVar] = []
    n_states = 0
    for sv in sysvars.SYSVARS.values():
        if sv.kind == "state":
            n_states = max(n_states, sv.address + 1)
            continue
        bases[sv.name] = len(owners)
        owners.extend([sv] * sv.size)
    return bases, owners, n_states


SYS_BASE, SLOT_OWNER, N_STATES = _layout()
"""Slot of each system variable's element 0; the variable owning each slot; state count."""


def state_names() -> dict[int, sysvars.SysVar]:
    """Bit address -> state."""
    return {sv.address: sv for sv in sysvars.SYSVARS.values() if sv.kind == "state"}


class SysVarStore:
    """The values of the system variables (`S`) and states (`ST`) of one drive."""

    def __init__(self) -> None:
        self.S: list[int | float] = [0] * len(SLOT_OWNER)
        for i, sv in enumerate(SLOT_OWNER):
            if sv.kind == "float":
                self.S[i] = 0.0
        self.ST = bytearray(N_STATES)
        self.hooks: dict[int, Callable[[int, int | float], None]] = {}
        """Slot -> reaction to a program's write (called after the value is stored)."""
        self.input_written = False
        """Set when a program writes an input state; the drive refreshes inputs then."""
        self._is_input = bytes(
            1 if (st := state_names().get(b)) is not None and st.is_input else 0
            for b in range(N_STATES)
        )

    def slot(self, name: str, index: int = 0) -> int:
        sv = sysvars.lookup(name)
        if sv is None or sv.kind == "state":
            raise KeyError(name)
        if not 0 <= index < sv.size:
            raise IndexError(f"{sv.name}[{index}] is outside 0..{sv.size - 1}")
        return SYS_BASE[sv.name] + index

    def convert(self, slot: int, value: float) -> int | float:
        kind = SLOT_OWNER[slot].kind
        if kind == "float":
            return f32(float(value))
        if type(value) is float:
            value = round_int(value, 16 if kind == "short" else 32)
        return w16(value) if kind == "short" else w32(value)

    def write(self, slot: int, value: float) -> None:
        """A program's write of a system variable (type conversion, then the reaction)."""
        v = self.convert(slot, value)
        self.S[slot] = v
        hook = self.hooks.get(slot)
        if hook is not None:
            hook(slot, v)

    # ---------------------------------------------------------------- states

    def check_bit(self, bit: int) -> int:
        if not 0 <= bit < N_STATES:
            raise RuntimeFault(f"{bit} is not a state address (valid: 0..{N_STATES - 1})")
        return bit

    def state_value(self, bit: int) -> int:
        """The 0/1 of the state at address `bit` (`<var>` in a condition)."""
        return self.ST[self.check_bit(bit)]

    def set_state(self, bit: int, value: int) -> None:
        self.ST[self.check_bit(bit)] = 1 if value else 0
        if self._is_input[bit]:
            self.input_written = True

    def toggle_state(self, bit: int) -> None:
        self.set_state(bit, not self.ST[self.check_bit(bit)])
