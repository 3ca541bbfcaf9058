"""The object dictionary of an EtherCAT slave (CoE): SDO access, PDO mapping, forced PDOs.

An `ObjectDictionary` holds `Obj` entries by (index, subindex). Each entry reads and
writes its value through a getter and a setter on the slave's own state (a drive's
attributes, an I/O module's channels), so the dictionary is a view, never a copy.

- SDO (`sdo_read`, `sdo_write`): any object; the length the master names must be the
  object's size (a visible string: 1..64 bytes, padded with NUL or cut); a refused
  access raises `SdoAbort` with its CiA 301 abort code: 0x06020000 no such object,
  0x06090011 no such subindex, 0x06070010 length mismatch, 0x06010002 write to a
  read-only object, 0x06010001 read of a write-only object, 0x06090030 a value outside
  the object's range (or refused by the object's own check).
- PDO (`pdo_read`, `pdo_write`, `force`, `release`): only objects mapped into the
  RxPDO (outputs of the master, written by it) or the TxPDO (inputs, read by it):
  `map_rx`, `map_tx`. A PDO write goes to an RxPDO object as the master's cyclic write
  would, so the master's own next write overwrites it; a *forced* value (`force`) is
  applied by the slave itself at the start of each of its cycles (`apply_forced`), after
  the master wrote, until `release`. Writing or forcing a TxPDO object aborts with
  0x06010002 (the master cannot write an input), an unmapped object with 0x06040041.
- `on_write`, if set, is called after every write and force/release (the owner of the
  cyclic exchange wakes up, e.g. a resting axis).

Slaves are found by id in a `SlaveDirectory` (the bus, in bus order): the drives of the
axes are slaves 0..N-1; I/O modules register theirs after them with `add`.
"""

from __future__ import annotations

import struct
from collections.abc import Callable, Iterable
from dataclasses import dataclass

# ---- CiA 301 SDO abort codes ------------------------------------------------------------
ABORT_UNSUPPORTED = 0x06010000
ABORT_WRITE_ONLY = 0x06010001
ABORT_READ_ONLY = 0x06010002
ABORT_NO_OBJECT = 0x06020000
ABORT_NOT_MAPPABLE = 0x06040041
ABORT_LENGTH = 0x06070010
ABORT_NO_SUBINDEX = 0x06090011
ABORT_VALUE = 0x06090030
ABORT_GENERAL = 0x08000000

STRING_MAX = 64
"""Longest visible string an SDO moves here [bytes] (HMPL's Data_t holds 65 bytes)."""


class SdoAbort(Exception):
    """An object access the slave refuses, with its CiA 301 abort code."""

    NO_OBJECT = ABORT_NO_OBJECT
    NO_SUBINDEX = ABORT_NO_SUBINDEX
    READ_ONLY = ABORT_READ_ONLY
    RANGE = ABORT_VALUE

    def __init__(self, code: int, message: str):
        super().__init__(f"SDO abort 0x{code:08X}: {message}")
        self.code = code


_FORMATS = {"i8": "<b", "u8": "<B", "i16": "<h", "u16": "<H", "i32": "<i", "u32": "<I",
            "i64": "<q", "u64": "<Q"}  # fmt: skip
SIZES = {name: struct.calcsize(fmt) for name, fmt in _FORMATS.items()}
RANGES = {
    name: (
        (-(1 << (8 * n - 1)), (1 << (8 * n - 1)) - 1) if name[0] == "i" else (0, (1 << 8 * n) - 1)
    )
    for name, n in SIZES.items()
}


@dataclass(frozen=True, slots=True)
class Obj:
    """One object entry: name, data type ("i8" ... "u64", "str"), access and its value.

    `get()` gives the value (an int, or `str` for a visible string); `set(value)` stores
    a value already range-checked (None: read-only). `check(value)` may refuse a value in
    range with a message (ValueError)."""

    name: str
    dtype: str
    get: Callable[[], int | str]
    set: Callable[[int], None] | None = None
    check: Callable[[int], None] | None = None

    @property
    def writable(self) -> bool:
        return self.set is not None

    @property
    def bits(self) -> int:
        """Size in a PDO mapping entry [bits]."""
        return 8 * SIZES[self.dtype] if self.dtype != "str" else 8 * STRING_MAX


def _hex(index: int, sub: int) -> str:
    return f"0x{index:04X}:{sub}"


class ObjectDictionary:
    """The objects of one slave, their PDO mapping and the PDO values forced on it."""

    def __init__(self, name: str = "slave") -> None:
        self.name = name
        self.objects: dict[tuple[int, int], Obj] = {}
        self.rx: list[tuple[int, int]] = []
        """RxPDO mapping (the master's outputs), in mapping order."""
        self.tx: list[tuple[int, int]] = []
        """TxPDO mapping (the master's inputs), in mapping order."""
        self.forced: dict[tuple[int, int], int] = {}
        """Forced RxPDO values by (index, subindex) (ForceWritePDO until ReleasePDO)."""
        self.on_write: Callable[[], None] | None = None

    # ---- building -------------------------------------------------------------------

    def add(self, index: int, sub: int, obj: Obj) -> None:
        self.objects[(index, sub)] = obj

    def add_record(self, index: int, name: str, entries: Iterable[Obj]) -> None:
        """A record or array: subindex 0 (u8, read-only) counts the entries 1..n."""
        entries = list(entries)
        n = len(entries)
        self.add(index, 0, Obj(f"{name}: number of entries", "u8", lambda: n))
        for i, e in enumerate(entries, 1):
            self.add(index, i, e)

    def map_rx(self, entries: Iterable[tuple[int, int]]) -> None:
        """Set the RxPDO mapping; ValueError naming an object that cannot be mapped."""
        self.rx = self._mapping(entries, "rxpdo", need_write=True)

    def map_tx(self, entries: Iterable[tuple[int, int]]) -> None:
        self.tx = self._mapping(entries, "txpdo", need_write=False)

    def _mapping(self, entries, what: str, need_write: bool) -> list[tuple[int, int]]:
        out: list[tuple[int, int]] = []
        for key in entries:
            obj = self.objects.get(key)
            if obj is None:
                raise ValueError(f"object {_hex(*key)} does not exist")
            if obj.dtype == "str":
                raise ValueError(f"{obj.name} ({_hex(*key)}) is a string: not mappable")
            if need_write and not obj.writable:
                raise ValueError(f"{obj.name} ({_hex(*key)}) is read-only: not an RxPDO object")
            if key in out:
                raise ValueError(f"{obj.name} ({_hex(*key)}) is mapped twice")
            out.append(key)
        return out

    # ---- lookup ---------------------------------------------------------------------

    def entry(self, index: int, sub: int) -> Obj:
        """The object at `index`:`sub`, or SdoAbort (no object, no subindex)."""
        obj = self.objects.get((index, sub))
        if obj is not None:
            return obj
        if any(i == index for i, _ in self.objects):
            raise SdoAbort(ABORT_NO_SUBINDEX, f"object 0x{index:04X} has no subindex {sub}")
        raise SdoAbort(ABORT_NO_OBJECT, f"object 0x{index:04X} does not exist in {self.name}")

    def read(self, index: int, sub: int = 0) -> int | str:
        """The value of `index`:`sub`, with no length check."""
        return self.entry(index, sub).get()

    def write(self, index: int, sub: int, value: int) -> None:
        """Write `index`:`sub` with no length check; SdoAbort if refused."""
        obj = self.entry(index, sub)
        self._store(obj, index, sub, value)

    def _store(self, obj: Obj, index: int, sub: int, value: int) -> None:
        if obj.set is None:
            raise SdoAbort(ABORT_READ_ONLY, f"{obj.name} ({_hex(index, sub)}) is read-only")
        if obj.dtype == "str" or isinstance(value, bool) or not isinstance(value, int):
            raise SdoAbort(ABORT_VALUE, f"{obj.name} ({_hex(index, sub)}) = {value!r}")
        low, high = RANGES[obj.dtype]
        if not low <= value <= high:
            raise SdoAbort(
                ABORT_VALUE, f"{obj.name} ({_hex(index, sub)}) = {value} is not in {low}..{high}"
            )
        if obj.check is not None:
            try:
                obj.check(value)
            except ValueError as exc:
                raise SdoAbort(ABORT_VALUE, f"{obj.name} ({_hex(index, sub)}): {exc}") from None
        obj.set(value)
        if self.on_write is not None:
            self.on_write()

    # ---- SDO ------------------------------------------------------------------------

    def _check_length(self, obj: Obj, index: int, sub: int, length: int) -> None:
        if obj.dtype == "str":
            ok = 1 <= length <= STRING_MAX
            want = f"1..{STRING_MAX}"
        else:
            ok = length == SIZES[obj.dtype]
            want = str(SIZES[obj.dtype])
        if not ok:
            raise SdoAbort(
                ABORT_LENGTH,
                f"{obj.name} ({_hex(index, sub)}) is {want} bytes long, not {length}",
            )

    def sdo_read(self, index: int, sub: int, length: int) -> bytes:
        """Upload `index`:`sub` as `length` little-endian bytes; SdoAbort if refused."""
        obj = self.entry(index, sub)
        self._check_length(obj, index, sub, length)
        return encode(obj, obj.get(), length)

    def sdo_write(self, index: int, sub: int, length: int, data: bytes) -> None:
        """Download `data` (`length` bytes, little-endian) to `index`:`sub`."""
        obj = self.entry(index, sub)
        if obj.set is None:
            raise SdoAbort(ABORT_READ_ONLY, f"{obj.name} ({_hex(index, sub)}) is read-only")
        self._check_length(obj, index, sub, length)
        self._store(obj, index, sub, decode(obj.dtype, data[:length]))

    # ---- PDO ------------------------------------------------------------------------

    def _mapped(self, index: int, sub: int, rx_only: bool) -> Obj:
        obj = self.entry(index, sub)
        key = (index, sub)
        if key in self.rx:
            return obj
        if key in self.tx:
            if rx_only:
                raise SdoAbort(ABORT_READ_ONLY, f"{obj.name} ({_hex(index, sub)}) is a TxPDO input")
            return obj
        raise SdoAbort(ABORT_NOT_MAPPABLE, f"{obj.name} ({_hex(index, sub)}) is not mapped")

    def pdo_read(self, index: int, sub: int) -> int:
        """The value of a mapped object, as the last cyclic exchange left it."""
        return self._mapped(index, sub, rx_only=False).get()

    def pdo_write(self, index: int, sub: int, value: int) -> None:
        """Write an RxPDO object (the master's next cyclic write may overwrite it)."""
        obj = self._mapped(index, sub, rx_only=True)
        self._store(obj, index, sub, value)

    def force(self, index: int, sub: int, value: int) -> None:
        """Force an RxPDO object to `value` until `release`."""
        obj = self._mapped(index, sub, rx_only=True)
        self._store(obj, index, sub, value)  # checks the value
        self.forced[(index, sub)] = value

    def release(self, index: int, sub: int) -> None:
        """Stop forcing `index`:`sub` (a mapped object that is not forced: nothing to do)."""
        self._mapped(index, sub, rx_only=True)
        self.forced.pop((index, sub), None)
        if self.on_write is not None:
            self.on_write()

    def apply_forced(self) -> None:
        """Store every forced value again (the slave calls it as its cycle starts)."""
        objects = self.objects
        for key, value in self.forced.items():
            objects[key].set(value)

    def pdo_bits(self, mapping: list[tuple[int, int]]) -> list[int]:
        """The mapping's entries as CiA 301 mapping values (index << 16 | sub << 8 | bits)."""
        return [i << 16 | s << 8 | self.objects[(i, s)].bits for i, s in mapping]


def encode(obj: Obj, value: int | str, length: int) -> bytes:
    """`value` of `obj`'s type as `length` little-endian bytes (strings padded or cut)."""
    if obj.dtype == "str":
        raw = str(value).encode("latin-1", "replace")[:length]
        return raw + b"\x00" * (length - len(raw))
    return struct.pack(_FORMATS[obj.dtype], value)


def decode(dtype: str, data: bytes) -> int:
    """Little-endian `data` as a value of `dtype` (zero-extended if short)."""
    n = SIZES[dtype]
    data = bytes(data[:n]).ljust(n, b"\x00")
    return struct.unpack(_FORMATS[dtype], data)[0]


def wrap(dtype: str, value: int) -> int:
    """`value` cut to `dtype`'s width, as C converts an int64 to it."""
    n = 8 * SIZES[dtype]
    value &= (1 << n) - 1
    if dtype[0] == "i" and value >> (n - 1):
        value -= 1 << n
    return value


class SlaveDirectory:
    """The slaves of the bus by id, in bus order: the axes' drives first (slaves
    0..N-1), then the I/O modules that `add` their dictionaries."""

    def __init__(self, dictionaries: Iterable[ObjectDictionary] = ()) -> None:
        self._slaves: list[ObjectDictionary] = list(dictionaries)

    def __len__(self) -> int:
        return len(self._slaves)

    def add(self, dictionary: ObjectDictionary) -> int:
        """Append a slave; returns its slave id."""
        self._slaves.append(dictionary)
        return len(self._slaves) - 1

    def get(self, slave_id: int) -> ObjectDictionary | None:
        """Slave `slave_id`'s dictionary, or None if there is no such slave."""
        if 0 <= slave_id < len(self._slaves):
            return self._slaves[slave_id]
        return None
