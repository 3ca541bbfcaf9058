"""The EtherCAT slaves of the machine: the axes' drives, then the I/O modules.

Slave ids follow bus order: the drives of axes 0..N-1 are slaves 0..N-1, and every
`[[slave]]` table of the machine file adds one I/O slave after them, in file order
(io/config.py). A `Slave` has a `kind` ("drive", "digital" or "analog"), one or more
`Module`s (its slots: a slave without slots has one) holding its channels, its EtherCAT
state, and `objects`, a place for its CoE object dictionary (None until one is attached).

Channels of a module, numbered from 1 like the controller's (`GetSlvGPI(1, 3)` is the
3rd input of slave 1):
- digital: `inputs` (pin levels) and `outputs` (states), 0 or 1;
- analog: `ai` and `ao` words of `bits` bits (io/analog.py), with their conversion
  types `ai_type`/`ao_type` and, per AO, a binding to a controller variable (manual
  10.4, `AoBinding`).

`slv_slot_id` of the manual's functions is the slave id OR-ed with a slot id
`HMPL_SLOT_n = n << SLOT_SHIFT`; slot 0 (none given) and slot 1 are the first module.
"""

from __future__ import annotations

from dataclasses import dataclass, field

SLOT_SHIFT = 16
"""HMPL_SLOT_n is n << SLOT_SHIFT (the manual gives no number for it)."""
N_SLOTS = 8
"""HMPL_SLOT_1 .. HMPL_SLOT_8 exist."""
DRIVE, DIGITAL, ANALOG = "drive", "digital", "analog"
STATE_OP = 8
STATE_LOST = 1
"""The state a lost slave reports: it is back in Init (no process data)."""


@dataclass
class AoBinding:
    """An analog output bound to a controller variable (manual 10.4)."""

    var_id: int = -1
    """The controller variable (SetSlvAOMonitor); -1 while none is chosen."""
    enabled: bool = False
    scale: float = 1.0
    offset: float = 0.0


@dataclass
class Module:
    """One slot of a slave: its channels."""

    inputs: list[int] = field(default_factory=list)
    outputs: list[int] = field(default_factory=list)
    ai: list[int] = field(default_factory=list)
    """Analog input words."""
    ao: list[int] = field(default_factory=list)
    """Analog output words."""
    ai_type: list[int] = field(default_factory=list)
    ao_type: list[int] = field(default_factory=list)
    ao_bind: list[AoBinding] = field(default_factory=list)
    bits: int = 16

    @classmethod
    def create(
        cls, inputs: int = 0, outputs: int = 0, ai: int = 0, ao: int = 0, bits: int = 16
    ) -> Module:
        return cls(
            [0] * inputs,
            [0] * outputs,
            [0] * ai,
            [0] * ao,
            [0] * ai,
            [0] * ao,
            [AoBinding() for _ in range(ao)],
            bits,
        )


@dataclass
class Slave:
    """One EtherCAT slave (see the module docstring)."""

    slave_id: int
    kind: str
    modules: list[Module] = field(default_factory=lambda: [Module()])
    name: str = ""
    """Its name in the machine file (`name = "..."`), "" if none."""
    axis: int | None = None
    """The axis whose drive it is (kind "drive")."""
    online: bool = True
    """False once it left the bus (a `slave_lost` fault): it then stays in Init."""
    objects: object | None = None
    """Its CoE object dictionary, once one is attached."""

    def module(self, slot: int) -> Module | None:
        """Slot `slot` (0 or 1: the first), or None if the slave has no such slot."""
        i = max(slot, 1) - 1
        return self.modules[i] if i < len(self.modules) else None


class SlaveBus:
    """Every slave of the machine, by slave id."""

    def __init__(self, slaves: list[Slave]) -> None:
        self.slaves = slaves

    def __len__(self) -> int:
        return len(self.slaves)

    def get(self, slave_id: int) -> Slave | None:
        if 0 <= slave_id < len(self.slaves):
            return self.slaves[slave_id]
        return None

    def address(self, slv_slot_id: int) -> tuple[Slave, Module] | None:
        """The slave and module of a `slv_slot_id` (slave | HMPL_SLOT_n); None if either
        does not exist."""
        slot, slave_id = divmod(slv_slot_id, 1 << SLOT_SHIFT)
        if slv_slot_id < 0 or slot > N_SLOTS:
            return None
        slave = self.get(slave_id)
        if slave is None:
            return None
        module = slave.module(slot)
        return None if module is None else (slave, module)
