"""The object dictionary of the simulated CiA 402 drive and its PDO mapping (drive keys
`rxpdo`, `txpdo`).

`build(drive, config)` gives the `ObjectDictionary` (drives/dictionary.py) of one
`Cia402Drive`: the communication objects of CiA 301 (device type 0x1000, device name
0x1008, hardware/software version 0x1009/0x100A, identity 0x1018, the PDO mappings
0x1600/0x1A00, read-only: the mapping is the machine file's) and the drive profile
objects of CiA 402 (0x603F ... 0x6502, with 0x60FE digital outputs: sub 1 the physical
outputs, sub 2 the bit mask). Every entry reads and writes the drive's own attributes.

The default mapping is the cyclic synchronous one the controller uses:
RxPDO 0x6040 controlword, 0x6060 modes of operation, 0x607A target position, 0x60FF
target velocity, 0x6071 target torque, 0x60B8 touch probe function, 0x60FE:1 digital
outputs; TxPDO 0x603F error code, 0x6041 statusword, 0x6061 modes display, 0x6064
position actual, 0x606C velocity actual, 0x6077 torque actual, 0x60F4 following error,
0x60B9 touch probe status, 0x60BA/0x60BC touch probe 1/2 positive edge, 0x60FD digital
inputs. A machine file changes it per axis with `drive = { rxpdo = [...], txpdo = [...] }`:
each entry an index (`0x607A`, subindex 0) or a string `"0x60FE:1"`. The controller
needs 0x6040 and 0x607A in the RxPDO and 0x6041 and 0x6064 in the TxPDO.
"""

from __future__ import annotations

import re

from motionvm.drives import objects as od
from motionvm.drives.dictionary import Obj, ObjectDictionary

DEVICE_NAME = "motionvm CiA 402 servo drive"
HARDWARE_VERSION = "1.0"
SOFTWARE_VERSION = "1.0"
VENDOR_ID = 0x00000000
"""No vendor id is assigned to a simulated drive."""
PRODUCT_CODE = 0x00000402
REVISION = 0x00010000

DEFAULT_RX = ((0x6040, 0), (0x6060, 0), (0x607A, 0), (0x60FF, 0), (0x6071, 0), (0x60B8, 0),
              (0x60FE, 1))  # fmt: skip
DEFAULT_TX = ((0x603F, 0), (0x6041, 0), (0x6061, 0), (0x6064, 0), (0x606C, 0), (0x6077, 0),
              (0x60F4, 0), (0x60B9, 0), (0x60BA, 0), (0x60BC, 0), (0x60FD, 0))  # fmt: skip
REQUIRED = {"rxpdo": ((0x6040, 0), (0x607A, 0)), "txpdo": ((0x6041, 0), (0x6064, 0))}

_ENTRY = re.compile(
    r"\s*(0[xX][0-9a-fA-F]{1,16}|[0-9]{1,16})\s*(?::\s*(0[xX][0-9a-fA-F]{1,16}|[0-9]{1,16}))?\s*",
    re.ASCII,
)
"""An entry string: index and optional subindex, each hex (0x) or decimal (leading zeros
allowed, `"0x60FE:01"`); 16 digits at most, as no index or subindex needs more."""


def _attr(drive, name: str, dtype: str, attr: str, writable: bool = False, check=None) -> Obj:
    setter = (lambda v: setattr(drive, attr, v)) if writable else None
    return Obj(name, dtype, lambda: getattr(drive, attr), setter, check)


def _check_mode(value: int) -> None:
    if value not in od.MODES:
        raise ValueError(f"mode of operation {value} is not supported (0, 6, 8, 9, 10)")


def build(drive, config: dict | None = None, serial: int = 0) -> ObjectDictionary:
    """The dictionary of `drive`, mapped as `config`'s `rxpdo`/`txpdo` say (default:
    the cyclic synchronous mapping); ValueError naming the key of a bad mapping."""
    d = ObjectDictionary("the drive")
    const = lambda name, dtype, value: Obj(name, dtype, lambda: value)  # noqa: E731
    d.add(0x1000, 0, _attr(drive, "Device type", "u32", "device_type"))
    d.add(0x1008, 0, const("Manufacturer device name", "str", DEVICE_NAME))
    d.add(0x1009, 0, const("Manufacturer hardware version", "str", HARDWARE_VERSION))
    d.add(0x100A, 0, const("Manufacturer software version", "str", SOFTWARE_VERSION))
    d.add_record(0x1018, "Identity", [
        const("Vendor ID", "u32", VENDOR_ID),
        const("Product code", "u32", PRODUCT_CODE),
        const("Revision number", "u32", REVISION),
        const("Serial number", "u32", serial),
    ])  # fmt: skip
    for index, entry in od.DICTIONARY.items():
        check = _check_mode if index == od.MODES_OF_OPERATION else None
        d.add(index, 0, _attr(drive, entry.name, entry.dtype, entry.attr, entry.writable, check))
    d.add_record(0x60FE, "Digital outputs", [
        _attr(drive, "Physical outputs", "u32", "digital_outputs", writable=True),
        _attr(drive, "Bit mask", "u32", "digital_output_mask", writable=True),
    ])  # fmt: skip
    config = config or {}
    for key, default, map_ in (("rxpdo", DEFAULT_RX, d.map_rx), ("txpdo", DEFAULT_TX, d.map_tx)):
        entries = _entries(config, key, default)
        shown = "[" + ", ".join(f"0x{i:04X}" + (f":{s}" if s else "") for i, s in entries) + "]"
        try:
            map_(entries)
        except ValueError as exc:
            raise ValueError(f"drive: {key} = {shown}: {exc}") from None
        for need in REQUIRED[key]:
            if need not in entries:
                raise ValueError(
                    f"drive: {key} = {shown} lacks {d.objects[need].name} "
                    f"(0x{need[0]:04X}), which the controller needs"
                )
    d.add_record(0x1600, "RxPDO mapping", _mapping_objs(d, d.rx))
    d.add_record(0x1A00, "TxPDO mapping", _mapping_objs(d, d.tx))
    return d


def _mapping_objs(d: ObjectDictionary, mapping: list[tuple[int, int]]) -> list[Obj]:
    values = d.pdo_bits(mapping)
    return [Obj(f"Mapping entry {i + 1}", "u32", lambda v=v: v) for i, v in enumerate(values)]


def _entries(config: dict, key: str, default) -> list[tuple[int, int]]:
    raw = config.get(key)
    if raw is None:
        return list(default)
    if not isinstance(raw, list) or not raw:
        raise ValueError(
            f'drive: {key} = {raw!r} must be a list of objects, e.g. [0x6040, 0x607A, "0x60FE:1"]'
        )
    out = []
    for item in raw:
        if isinstance(item, int) and not isinstance(item, bool) and 0 <= item <= 0xFFFF:
            out.append((item, 0))
            continue
        m = _ENTRY.fullmatch(item) if isinstance(item, str) else None
        if m is None:
            raise ValueError(
                f"drive: {key} = {raw!r}: entry {item!r} is not an object index "
                '(0x607A) or "INDEX:SUBINDEX" ("0x60FE:1")'
            )
        index, sub = _number(m.group(1)), _number(m.group(2) or "0")
        if index > 0xFFFF or sub > 0xFF:
            raise ValueError(f"drive: {key} = {raw!r}: entry {item!r} is out of range")
        out.append((index, sub))
    return out


def _number(text: str) -> int:
    """A matched entry number: hex with 0x, else decimal."""
    return int(text[2:], 16) if text[:2].lower() == "0x" else int(text, 10)
