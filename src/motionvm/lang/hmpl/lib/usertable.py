"""HMPL User Table built-ins (manual chapter 11): `system_user_table[512000]` and its saved copy.

The table lives in program memory at `rt.user_table_addr` (512000 doubles, 8-byte
aligned), so `system_user_table[i]` in HMPL and these functions see the same values.
SaveUserTable copies a range of it into the controller's "disk", the file
`rt.data_dir / "user_table.bin"`; LoadUserTable copies a range back.

File format (little-endian), 4,096,016 bytes:

    offset  size  field
    0       4     magic b"MVUT"
    4       2     format version, 1
    6       2     element size, 8
    8       4     element count, 512000
    12      4     CRC-32 (zlib.crc32) of bytes 0-11 followed by the payload
    16      8*N   the whole table image, IEEE doubles

Saving is crash-safe: the new image is written to a temporary file in the same
folder, flushed and fsync'ed, then `os.replace`d over the old file (atomic on POSIX
and Windows) and the folder is fsync'ed. A crash at any point leaves either the old
or the new file, never a mix. A killed save may leave a stale temporary
`user_table.bin.XXXXXXXX.tmp` (4 MB); the next SaveUserTable or LoadUserTable removes
those of earlier runs: files of exactly that pattern in the data folder, last modified
more than STALE_AFTER seconds ago (a younger one may be another run's save in progress).

Return codes (the manual only says non-zero on failure):
- ERR_ARG_OUT_OF_RANGE (0x138F, eERR_HMPL_ARG_OUT_OF_RANGE): an index outside
  [0, 512000), a negative count or a range running past the end. Nothing changes.
- ERR_STORAGE (0x1770, eERR_HMPL_EXEC_FAILED): LoadUserTable finds no saved file, or a
  damaged one (bad size, magic, version or checksum) - the table is left unchanged -
  or SaveUserTable cannot write the file - the old file is left unchanged.
Decisions where the manual is silent:
- A count of 0 is a successful no-op (the array pointer is not looked at).
- GetTableValue has no error return; an index out of range gives NaN.
- Saving a range keeps the rest of the saved image; with no saved file (or a damaged
  one, which is replaced) the rest of the image is zeros, so loading a range never
  saved gives 0.0.
- Input/output arrays too small for `num_data` doubles are a RuntimeFault (a bad
  pointer, as for any C array access), and nothing is copied.

Run-time attributes used: `rt.mem`, `rt.user_table_addr`, `rt.data_dir` (a Path).
"""

from __future__ import annotations

import contextlib
import os
import re
import struct
import tempfile
import time
import zlib
from pathlib import Path
from typing import BinaryIO

from motionvm.lang.hmpl.lib.base import Library, builtin
from motionvm.runtime.errors import RuntimeFault

TABLE_LEN = 512_000
"""Elements in system_user_table."""
FILE_NAME = "user_table.bin"
MAGIC = b"MVUT"
VERSION = 1
_HEADER = struct.Struct("<4sHHII")
_IMAGE_BYTES = TABLE_LEN * 8

ERR_ARG_OUT_OF_RANGE = 0x138F  # eERR_HMPL_ARG_OUT_OF_RANGE
ERR_STORAGE = 0x1770  # eERR_HMPL_EXEC_FAILED

STALE_AFTER = 60.0
"""[s] A temporary file untouched this long is a killed save's leftover."""
_TEMP_NAME = re.compile(re.escape(FILE_NAME) + r"\.[a-z0-9_]{8}\.tmp")
"""The names `write_atomic` gives its temporaries (tempfile.mkstemp, 8 random characters)."""


def encode_image(image: bytes) -> bytes:
    """The file bytes for a table image of TABLE_LEN doubles."""
    prefix = _HEADER.pack(MAGIC, VERSION, 8, TABLE_LEN, 0)[:12]
    crc = zlib.crc32(image, zlib.crc32(prefix))
    return prefix + struct.pack("<I", crc) + image


def decode_image(data: bytes) -> bytearray | None:
    """The table image in file bytes `data`, or None if they are not a valid file."""
    if len(data) != _HEADER.size + _IMAGE_BYTES:
        return None
    magic, version, elem_size, count, crc = _HEADER.unpack_from(data)
    if (magic, version, elem_size, count) != (MAGIC, VERSION, 8, TABLE_LEN):
        return None
    image = memoryview(data)[_HEADER.size :]
    if zlib.crc32(image, zlib.crc32(data[:12])) != crc:
        return None
    return bytearray(image)


def _write_all(f: BinaryIO, data: bytes) -> None:
    """Write `data` to `f` (a seam for the crash tests)."""
    f.write(data)


def write_atomic(path: Path, data: bytes) -> None:
    """Replace `path` by a file holding `data`: all of it or, after a crash, the old file."""
    folder = path.parent
    folder.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=path.name + ".", suffix=".tmp", dir=folder)
    try:
        with os.fdopen(fd, "wb") as f:
            _write_all(f, data)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
    _fsync_folder(folder)


def remove_stale_temps(folder: Path, now: float | None = None) -> None:
    """Delete the leftover temporaries of killed saves in `folder` (see the module doc);
    anything else, and any error (no folder, no permission), is left alone."""
    now = time.time() if now is None else now
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return
    for entry in entries:
        if not _TEMP_NAME.fullmatch(entry.name):
            continue
        try:
            if not entry.is_file(follow_symlinks=False):
                continue
            if now - entry.stat(follow_symlinks=False).st_mtime < STALE_AFTER:
                continue
            os.unlink(entry.path)
        except OSError:
            continue


def _fsync_folder(folder: Path) -> None:
    """Make the rename durable (POSIX); folders cannot be opened on Windows."""
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


class UserTableLib(Library):
    """Chapter 11: Set/GetUserTable, Set/GetTableValue, Save/LoadUserTable."""

    # ------------------------------------------------------------ helpers

    def _span(self, start_idx: int) -> int:
        """Byte address of element `start_idx`."""
        return self.rt.user_table_addr + 8 * start_idx

    @staticmethod
    def _range_ok(start_idx: int, num_data: int) -> bool:
        return 0 <= start_idx < TABLE_LEN and 0 <= num_data <= TABLE_LEN - start_idx

    def _array(self, func: str, addr: int, num_data: int, what: str) -> None:
        """Fault unless `addr` holds `num_data` doubles (any pointer will do for none)."""
        need = 8 * num_data
        if need == 0:
            return
        if addr == 0:
            raise RuntimeFault(f"{func}: null {what} pointer")
        room = self.mem.extent(addr)
        if room < need:
            raise RuntimeFault(
                f"{func}: {what} array has {room // 8} doubles ({room} bytes) from 0x{addr:x},"
                f" {num_data} needed"
            )

    def _path(self) -> Path:
        return Path(self.rt.data_dir) / FILE_NAME

    def _saved_image(self) -> bytearray | None:
        try:
            data = self._path().read_bytes()
        except OSError:
            return None
        return decode_image(data)

    # ------------------------------------------------------------ RAM table

    @builtin()
    def SetUserTable(self, start_idx: int, num_data: int, input: int) -> int:
        """Copy `num_data` doubles from `input` to the table at `start_idx`; 0 or an error code."""
        if not self._range_ok(start_idx, num_data):
            return ERR_ARG_OUT_OF_RANGE
        self._array("SetUserTable", input, num_data, "input")
        at, n = self._span(start_idx), 8 * num_data
        buf = self.mem.buf
        buf[at : at + n] = buf[input : input + n]
        return 0

    @builtin()
    def GetUserTable(self, start_idx: int, num_data: int, output: int) -> int:
        """Copy `num_data` doubles of the table from `start_idx` to `output`; 0 or an error code."""
        if not self._range_ok(start_idx, num_data):
            return ERR_ARG_OUT_OF_RANGE
        self._array("GetUserTable", output, num_data, "output")
        at, n = self._span(start_idx), 8 * num_data
        buf = self.mem.buf
        buf[output : output + n] = buf[at : at + n]
        return 0

    @builtin()
    def SetTableValue(self, index: int, value: float) -> int:
        if not 0 <= index < TABLE_LEN:
            return ERR_ARG_OUT_OF_RANGE
        self.mem.store(self._span(index), "f64", value)
        return 0

    @builtin()
    def GetTableValue(self, index: int) -> float:
        """Element `index`; NaN if `index` is outside [0, 512000)."""
        if not 0 <= index < TABLE_LEN:
            return float("nan")
        return self.mem.load(self._span(index), "f64")

    # ------------------------------------------------------------ persistent copy

    @builtin()
    def SaveUserTable(self, start_idx: int, num_data: int) -> int:
        """Store elements [start_idx, start_idx+num_data) in the saved file; 0 or an error code."""
        if not self._range_ok(start_idx, num_data):
            return ERR_ARG_OUT_OF_RANGE
        if num_data == 0:
            return 0
        remove_stale_temps(self._path().parent)
        image = self._saved_image() or bytearray(_IMAGE_BYTES)
        lo, hi = 8 * start_idx, 8 * (start_idx + num_data)
        base = self.rt.user_table_addr
        image[lo:hi] = self.mem.buf[base + lo : base + hi]
        try:
            write_atomic(self._path(), encode_image(image))
        except OSError:
            return ERR_STORAGE
        return 0

    @builtin()
    def LoadUserTable(self, start_idx: int, num_data: int) -> int:
        """Copy saved elements [start_idx, start_idx+num_data) to the table; 0 or an error code."""
        if not self._range_ok(start_idx, num_data):
            return ERR_ARG_OUT_OF_RANGE
        remove_stale_temps(self._path().parent)
        image = self._saved_image()
        if image is None:
            return ERR_STORAGE
        lo, hi = 8 * start_idx, 8 * (start_idx + num_data)
        base = self.rt.user_table_addr
        self.mem.buf[base + lo : base + hi] = image[lo:hi]
        return 0
