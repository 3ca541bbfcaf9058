"""The Modbus TCP server's register map: Modbus addresses -> controller state.

| table | addresses | controller | access |
|---|---|---|---|
| coils | 0-7 | outputs 1-8 (coil k is output k+1, HIMC_GPO(k+1)) | read, write |
| discrete inputs | 0-7 | inputs 1-8 (input k+1) | read |
| holding registers | 0-19 | system_ltest0..9, int32, 2 registers each, high word first | read, write |
| holding registers | 100-139 | system_dtest0..9, float64, 4 registers each, high word first | read, write |
| input registers | 1000 + 4N | axis N feedback position [mm or deg], float64, high word first | read |
| input registers | 2000 + 4N | axis N feedback velocity [mm/s or deg/s], float64, high word first | read |

Addresses count from 0 as on the wire. A request any of whose addresses lies outside
the map is refused whole (exception 02, illegal data address). Writing part of a
multi-register value (one register of an int32) changes those 16 bits and keeps the
others. Every function here runs in the simulation thread at a cycle boundary
(comm/hub.py), so a write lands at the next cycle boundary and a read sees the state
the last cycle left.

The manual numbers the controller's inputs and outputs from 1; `gpio_index` is the one
place that turns such a number into the index of the controller's I/O lists.
"""

from __future__ import annotations

import struct

from motionvm.comm.hub import CommHub

ILLEGAL_FUNCTION, ILLEGAL_ADDRESS, ILLEGAL_VALUE = 0x01, 0x02, 0x03
"""Modbus exception codes."""

N_BITS = 8
"""Coils (outputs 1-8) and discrete inputs (inputs 1-8)."""
LTEST_BASE, N_LTEST = 0, 10
DTEST_BASE, N_DTEST = 100, 10
POS_BASE, VEL_BASE, AXIS_STRIDE = 1000, 2000, 4


def gpio_index(number: int) -> int:
    """The index in the controller's input or output list of I/O `number` (from 1)."""
    return number - 1


def _bits(hub: CommHub, table: str, address: int, count: int) -> list[bool] | int:
    if address < 0 or address + count > N_BITS:
        return ILLEGAL_ADDRESS
    bits = hub.io.outputs if table == "c" else hub.io.inputs
    out = []
    for k in range(address, address + count):
        i = gpio_index(k + 1)
        if not 0 <= i < len(bits):
            return ILLEGAL_ADDRESS
        out.append(bool(bits[i]))
    return out


def _holding_words(hub: CommHub, address: int) -> tuple[str, int, list[int]] | None:
    """(variable, first register, its registers) of the variable holding `address`."""
    if LTEST_BASE <= address < LTEST_BASE + 2 * N_LTEST:
        n = (address - LTEST_BASE) // 2
        name = f"system_ltest{n}"
        value = int(hub.variables.read_variable(name)) & 0xFFFFFFFF
        return name, LTEST_BASE + 2 * n, list(struct.unpack(">HH", struct.pack(">I", value)))
    if DTEST_BASE <= address < DTEST_BASE + 4 * N_DTEST:
        n = (address - DTEST_BASE) // 4
        name = f"system_dtest{n}"
        value = float(hub.variables.read_variable(name))
        return name, DTEST_BASE + 4 * n, list(struct.unpack(">HHHH", struct.pack(">d", value)))
    return None


def _input_words(hub: CommHub, address: int) -> list[int] | None:
    """The 4 registers of the axis value holding input register `address`."""
    for base, attr in ((POS_BASE, "pos_fb"), (VEL_BASE, "vel_fb")):
        n = (address - base) // AXIS_STRIDE
        if address >= base and n < len(hub.motion.axes):
            value = float(getattr(hub.motion.axes[n], attr))
            return list(struct.unpack(">HHHH", struct.pack(">d", value)))
    return None


def read(hub: CommHub, function_code: int, address: int, count: int) -> list | int:
    """The values a read request returns, or its exception code."""
    if function_code in (1, 5, 15):
        return _bits(hub, "c", address, count)
    if function_code == 2:
        return _bits(hub, "d", address, count)
    if function_code in (3, 6, 16, 22, 23):
        out = []
        for a in range(address, address + count):
            held = _holding_words(hub, a)
            if held is None:
                return ILLEGAL_ADDRESS
            out.append(held[2][a - held[1]])
        return out
    if function_code == 4:
        out = []
        for a in range(address, address + count):
            words = _input_words(hub, a)
            if words is None:
                return ILLEGAL_ADDRESS
            out.append(words[(a - POS_BASE) % AXIS_STRIDE])
        return out
    return ILLEGAL_FUNCTION


def write(hub: CommHub, function_code: int, address: int, values: list) -> int | None:
    """Apply a write request; None, or its exception code (then nothing is written)."""
    count = len(values)
    if function_code in (5, 15):
        checked = _bits(hub, "c", address, count)
        if isinstance(checked, int):
            return checked
        for k, v in zip(range(address, address + count), values):
            hub.io.outputs[gpio_index(k + 1)] = 1 if v else 0
        return None
    if function_code not in (6, 16, 22, 23):
        return ILLEGAL_FUNCTION
    pending: dict[str, tuple[int, list[int]]] = {}
    for a, v in zip(range(address, address + count), values):
        held = _holding_words(hub, a)
        if held is None:
            return ILLEGAL_ADDRESS
        name, first, words = held
        first, words = pending.setdefault(name, (first, words))
        words[a - first] = int(v) & 0xFFFF
    for name, (_first, words) in pending.items():
        if name.startswith("system_ltest"):
            value: int | float = struct.unpack(">i", struct.pack(">HH", *words))[0]
        else:
            value = struct.unpack(">d", struct.pack(">HHHH", *words))[0]
        hub.variables.write_variable(name, value)
    return None
