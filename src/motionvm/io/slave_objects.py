"""The CoE object dictionary of an EtherCAT I/O slave (CiA 401 objects).

`build(slave)` gives the `ObjectDictionary` (drives/dictionary.py) of one I/O `Slave`
(io/slaves.py); the I/O system registers it in the motion kernel's `SlaveDirectory`
after the drives, so the slave id of ReadSDO ... ReleasePDO is the one of GetSlaveNum,
GetSlvGPI and the `slvS.*` channels. Every entry reads and writes the slave's own
channel lists: the dictionary is a view, and a chapter 9/10 function and an object
access see the same state.

Objects (channels of every slot in slot order, numbered from 1 as the manual numbers
them; an object exists only if the slave has such channels):
- 0x1008 device name (the `name` of the machine file, or "motionvm digital I/O" /
  "motionvm analog I/O"), 0x1018 identity (vendor id 0: none is assigned to a simulated
  module; product code 0x401, revision 0x00010000, serial number the slave id);
- 0x6000 digital inputs, 8-bit groups (u8, read-only): sub k holds inputs 8k-7 .. 8k,
  input 8k-7 in bit 0;
- 0x6200 digital outputs, 8-bit groups (u8, read-write), laid out the same way; a bit
  of a channel the slave does not have must be 0 (abort 0x06090030);
- 0x6401 analog inputs (read-only) and 0x6411 analog outputs (read-write), one
  subindex per channel: the channel's word (GetSlvAIRaw/SetSlvAORaw's word) as an
  INTEGER16 (an INTEGER32 for channels wider than 16 bits), so a 16-bit word 0xFFFF
  reads -1, and a written value is stored as its `bits` low bits (it must fit them,
  signed or not). An array holds at most 254 channels: further ones have no object.

Default PDO mapping: every input object in the TxPDO, every output object in the
RxPDO. A forced output (ForceWritePDO) is applied again by the slave after every
cycle's writes of the controller (`IOSystem.end_cycle`), so it is what GetSlvGPO and
GetSlvAORaw read and what the pin and a wire carry until ReleasePDO; an AO bound to a
controller variable (10.4) is overwritten by its binding unless it is forced.
"""

from __future__ import annotations

from motionvm.drives.dictionary import Obj, ObjectDictionary
from motionvm.io.slaves import ANALOG, Slave

VENDOR_ID = 0x00000000
"""No vendor id is assigned to a simulated I/O module."""
PRODUCT_CODE = 0x00000401
REVISION = 0x00010000

DIGITAL_INPUTS = 0x6000
DIGITAL_OUTPUTS = 0x6200
ANALOG_INPUTS = 0x6401
ANALOG_OUTPUTS = 0x6411
MAX_SUBS = 254
"""Entries of an array object (subindex 1..254)."""


class _Channels:
    """One kind of channel over every slot of a slave: (list, index) by number - 1."""

    def __init__(self, lists: list[list[int]]) -> None:
        self.where = [(values, i) for values in lists for i in range(len(values))]

    def __len__(self) -> int:
        return len(self.where)

    def get(self, n: int) -> int:
        values, i = self.where[n]
        return values[i]

    def set(self, n: int, value: int) -> None:
        values, i = self.where[n]
        values[i] = value


def _byte_obj(name: str, ch: _Channels, k: int, writable: bool) -> Obj:
    first = 8 * k
    count = min(8, len(ch) - first)

    def get() -> int:
        v = 0
        for b in range(count):
            v |= (ch.get(first + b) & 1) << b
        return v

    def set_(value: int) -> None:
        for b in range(count):
            ch.set(first + b, (value >> b) & 1)

    def check(value: int) -> None:
        if value >> count:
            raise ValueError(f"the slave has {len(ch)} channels: bits {count}..7 must be 0")

    return Obj(
        f"{name} {first + 1}..{first + count}",
        "u8",
        get,
        set_ if writable else None,
        check if writable else None,
    )


def _word_obj(name: str, ch: _Channels, n: int, bits: int, writable: bool) -> Obj:
    width = 16 if bits <= 16 else 32
    dtype = f"i{width}"
    mask = (1 << bits) - 1
    sign = 1 << (width - 1)

    def get() -> int:
        w = ch.get(n) & ((1 << width) - 1)
        return w - (1 << width) if w & sign else w

    def set_(value: int) -> None:
        ch.set(n, value & mask)

    def check(value: int) -> None:
        if not -(1 << (bits - 1)) <= value <= mask:
            raise ValueError(f"a {bits}-bit channel holds {-(1 << (bits - 1))}..{mask}")

    return Obj(
        f"{name} {n + 1}", dtype, get, set_ if writable else None, check if writable else None
    )


def build(slave: Slave) -> ObjectDictionary:
    """The object dictionary of the I/O slave `slave` (see the module docstring)."""
    d = ObjectDictionary(f"slave {slave.slave_id}")
    const = lambda name, dtype, value: Obj(name, dtype, lambda: value)  # noqa: E731
    default = "motionvm analog I/O" if slave.kind == ANALOG else "motionvm digital I/O"
    d.add(0x1008, 0, const("Manufacturer device name", "str", slave.name or default))
    d.add_record(0x1018, "Identity", [
        const("Vendor ID", "u32", VENDOR_ID),
        const("Product code", "u32", PRODUCT_CODE),
        const("Revision number", "u32", REVISION),
        const("Serial number", "u32", slave.slave_id),
    ])  # fmt: skip
    mods = slave.modules
    tx: list[tuple[int, int]] = []
    rx: list[tuple[int, int]] = []
    for index, values, writable in (
        (DIGITAL_INPUTS, [m.inputs for m in mods], False),
        (DIGITAL_OUTPUTS, [m.outputs for m in mods], True),
    ):
        ch = _Channels(values)
        if not len(ch):
            continue
        name = "Digital output" if writable else "Digital input"
        n = min((len(ch) + 7) // 8, MAX_SUBS)
        d.add_record(
            index, name + "s 8-bit", [_byte_obj(name + "s", ch, k, writable) for k in range(n)]
        )
        (rx if writable else tx).extend((index, k) for k in range(1, n + 1))
    for index, values, writable in (
        (ANALOG_INPUTS, [m.ai for m in mods], False),
        (ANALOG_OUTPUTS, [m.ao for m in mods], True),
    ):
        ch = _Channels(values)
        if not len(ch):
            continue
        name = "Analog output" if writable else "Analog input"
        bits = mods[0].bits
        n = min(len(ch), MAX_SUBS)
        d.add_record(index, name + "s", [_word_obj(name, ch, k, bits, writable) for k in range(n)])
        (rx if writable else tx).extend((index, k) for k in range(1, n + 1))
    d.map_tx(tx)
    d.map_rx(rx)
    return d
