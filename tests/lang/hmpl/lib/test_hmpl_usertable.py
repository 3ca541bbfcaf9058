"""UserTableLib: the chapter 11 examples, index ranges, the file format and crash safety."""

from __future__ import annotations

import math
import os
import struct
import subprocess
import sys
import textwrap
import zlib
from pathlib import Path

import pytest

from motionvm.lang.hmpl.cmemory import Memory
from motionvm.lang.hmpl.lib import usertable
from motionvm.lang.hmpl.lib.usertable import (
    ERR_ARG_OUT_OF_RANGE,
    ERR_STORAGE,
    FILE_NAME,
    TABLE_LEN,
    UserTableLib,
    decode_image,
    encode_image,
)
from motionvm.runtime.errors import RuntimeFault


class FakeRuntime:
    """The parts of the HMPL run time the User Table uses."""

    def __init__(self, data_dir: Path) -> None:
        self.mem = Memory(1 << 23)
        self.user_table_addr = self.mem.alloc_static(8 * TABLE_LEN, "system_user_table")
        self.data_dir = data_dir

    def table(self, index: int) -> float:
        """system_user_table[index] as HMPL code reads it."""
        return self.mem.f64[self.user_table_addr // 8 + index]

    def set_table(self, index: int, value: float) -> None:
        self.mem.f64[self.user_table_addr // 8 + index] = value


@pytest.fixture
def rt(tmp_path) -> FakeRuntime:
    return FakeRuntime(tmp_path / "data")


@pytest.fixture
def lib(rt) -> UserTableLib:
    return UserTableLib(rt)


def doubles(rt, values: list[float]) -> int:
    addr = rt.mem.alloc_static(8 * len(values))
    rt.mem.write_bytes(addr, struct.pack(f"<{len(values)}d", *values))
    return addr


def read_doubles(rt, addr: int, n: int) -> list[float]:
    return list(struct.unpack(f"<{n}d", rt.mem.read_bytes(addr, 8 * n)))


def test_registered_names():
    assert set(UserTableLib.builtin_methods()) == {
        "SetUserTable",
        "GetUserTable",
        "SetTableValue",
        "GetTableValue",
        "SaveUserTable",
        "LoadUserTable",
    }


def test_set_and_get_user_table_manual_example(rt, lib):
    data = doubles(rt, [-2.0, 0.0, 2.0, 6.0, 4.0])
    assert lib.SetUserTable(1, 5, data) == 0
    assert [rt.table(i) for i in range(7)] == [0.0, -2.0, 0.0, 2.0, 6.0, 4.0, 0.0]
    out = rt.mem.alloc_static(8 * 3)
    assert lib.GetUserTable(3, 3, out) == 0
    assert read_doubles(rt, out, 3) == [2.0, 6.0, 4.0]


def test_table_value(rt, lib):
    assert lib.SetTableValue(0, 1.5) == 0
    assert lib.SetTableValue(TABLE_LEN - 1, -7.25) == 0
    assert rt.table(0) == 1.5 and rt.table(TABLE_LEN - 1) == -7.25
    rt.set_table(10, 3.0)
    assert lib.GetTableValue(10) == 3.0
    assert lib.GetTableValue(TABLE_LEN - 1) == -7.25


@pytest.mark.parametrize("index", [-1, TABLE_LEN, TABLE_LEN + 5, -(2**31)])
def test_table_value_out_of_range(rt, lib, index):
    assert lib.SetTableValue(index, 1.0) == ERR_ARG_OUT_OF_RANGE
    assert math.isnan(lib.GetTableValue(index))


@pytest.mark.parametrize(
    "start, n",
    [(-1, 1), (TABLE_LEN, 0), (TABLE_LEN - 2, 3), (0, -1), (0, TABLE_LEN + 1), (5, 2**31 - 1)],
)
def test_ranges_out_of_range(rt, lib, start, n):
    arr = doubles(rt, [9.0] * 4)
    assert lib.SetUserTable(start, n, arr) == ERR_ARG_OUT_OF_RANGE
    assert lib.GetUserTable(start, n, arr) == ERR_ARG_OUT_OF_RANGE
    assert lib.SaveUserTable(start, n) == ERR_ARG_OUT_OF_RANGE
    assert lib.LoadUserTable(start, n) == ERR_ARG_OUT_OF_RANGE
    assert read_doubles(rt, arr, 4) == [9.0] * 4
    assert not (rt.data_dir / FILE_NAME).exists()


def test_whole_table_and_empty_ranges(rt, lib):
    arr = rt.mem.alloc_static(8 * TABLE_LEN)
    assert lib.GetUserTable(0, TABLE_LEN, arr) == 0
    assert lib.SetUserTable(TABLE_LEN - 1, 1, doubles(rt, [1.0])) == 0
    assert lib.SetUserTable(7, 0, 0) == 0  # nothing to copy: the pointer is not used
    assert lib.SaveUserTable(7, 0) == 0
    assert not (rt.data_dir / FILE_NAME).exists()


def test_too_small_arrays_fault(rt, lib):
    small = doubles(rt, [1.0, 2.0])
    with pytest.raises(
        RuntimeFault, match=r"SetUserTable: input array has 2 doubles \(16 bytes\).* 3 needed"
    ):
        lib.SetUserTable(0, 3, small)
    with pytest.raises(RuntimeFault, match="GetUserTable: output array has 2 doubles"):
        lib.GetUserTable(0, 3, small)
    assert read_doubles(rt, small, 2) == [1.0, 2.0]
    with pytest.raises(RuntimeFault, match="null input"):
        lib.SetUserTable(0, 1, 0)
    assert rt.table(0) == 0.0


def test_save_and_load_manual_example(rt, lib):
    rt.set_table(3, 2.0)
    rt.set_table(4, 6.0)
    rt.set_table(5, 4.0)
    assert lib.SaveUserTable(3, 3) == 0
    rt.set_table(3, 999.0)
    rt.set_table(4, 777.0)
    rt.set_table(5, 888.0)
    assert lib.LoadUserTable(3, 3) == 0
    assert [rt.table(i) for i in (3, 4, 5)] == [2.0, 6.0, 4.0]


def test_saved_table_survives_a_restart(rt, lib, tmp_path):
    rt.set_table(100, 1.25)
    assert lib.SaveUserTable(100, 1) == 0
    rt2 = FakeRuntime(rt.data_dir)  # the controller restarts: RAM is zero
    assert rt2.table(100) == 0.0
    assert UserTableLib(rt2).LoadUserTable(0, TABLE_LEN) == 0
    assert rt2.table(100) == 1.25


def test_saving_a_range_keeps_the_rest_of_the_file(rt, lib):
    rt.set_table(1, 1.0)
    rt.set_table(2, 2.0)
    assert lib.SaveUserTable(1, 2) == 0
    rt.set_table(1, 10.0)
    rt.set_table(2, 20.0)
    assert lib.SaveUserTable(2, 1) == 0  # element 1 keeps its saved 1.0
    rt.set_table(1, -1.0)
    rt.set_table(2, -1.0)
    assert lib.LoadUserTable(1, 2) == 0
    assert (rt.table(1), rt.table(2)) == (1.0, 20.0)
    assert lib.LoadUserTable(50, 1) == 0  # never saved: zero
    assert rt.table(50) == 0.0


def test_load_without_a_file_fails_and_changes_nothing(rt, lib):
    rt.set_table(3, 5.0)
    assert lib.LoadUserTable(0, 10) == ERR_STORAGE
    assert rt.table(3) == 5.0


def test_file_format(rt, lib):
    rt.set_table(0, 1.0)
    rt.set_table(TABLE_LEN - 1, -2.0)
    lib.SaveUserTable(0, TABLE_LEN)
    data = (rt.data_dir / FILE_NAME).read_bytes()
    assert len(data) == 16 + 8 * TABLE_LEN
    assert struct.unpack_from("<4sHHI", data) == (b"MVUT", 1, 8, TABLE_LEN)
    (crc,) = struct.unpack_from("<I", data, 12)
    assert crc == zlib.crc32(data[:12] + data[16:])
    assert struct.unpack_from("<d", data, 16) == (1.0,)
    assert struct.unpack_from("<d", data, len(data) - 8) == (-2.0,)
    assert decode_image(data) == bytearray(data[16:])
    assert encode_image(bytes(data[16:])) == data


def _corruptions(data: bytes) -> dict[str, bytes]:
    flip = bytearray(data)
    flip[16 + 8 * 3] ^= 0x01
    bad_magic = b"XXXX" + data[4:]
    bad_version = data[:4] + struct.pack("<H", 2) + data[6:]
    return {
        "empty": b"",
        "truncated": data[: len(data) // 2],
        "longer": data + b"\0",
        "payload bit": bytes(flip),
        "magic": bad_magic,
        "version": bad_version,
    }


def test_corrupt_file_fails_to_load_and_changes_nothing(rt, lib):
    rt.set_table(3, 2.0)
    lib.SaveUserTable(0, 10)
    path = rt.data_dir / FILE_NAME
    good = path.read_bytes()
    rt.set_table(3, 42.0)
    for name, data in _corruptions(good).items():
        path.write_bytes(data)
        assert lib.LoadUserTable(0, 10) == ERR_STORAGE, name
        assert rt.table(3) == 42.0, name


def test_save_replaces_a_corrupt_file(rt, lib):
    path = rt.data_dir / FILE_NAME
    rt.data_dir.mkdir()
    path.write_bytes(b"garbage")
    rt.set_table(8, 8.0)
    assert lib.SaveUserTable(8, 1) == 0
    rt.set_table(8, 0.0)
    assert lib.LoadUserTable(0, 10) == 0
    assert rt.table(8) == 8.0


class SimulatedCrash(BaseException):
    """Stands for the process dying: nothing after it runs."""


def _half_then(exc: BaseException):
    def write_half(f, data: bytes) -> None:
        f.write(data[: len(data) // 2])
        f.flush()
        raise exc

    return write_half


@pytest.mark.parametrize("exc", [SimulatedCrash(), OSError(28, "No space left on device")])
def test_failure_mid_save_keeps_the_old_file(rt, lib, monkeypatch, exc):
    rt.set_table(3, 2.0)
    assert lib.SaveUserTable(0, 10) == 0
    path = rt.data_dir / FILE_NAME
    old = path.read_bytes()
    rt.set_table(3, 99.0)
    monkeypatch.setattr(usertable, "_write_all", _half_then(exc))
    if isinstance(exc, OSError):
        assert lib.SaveUserTable(0, 10) == ERR_STORAGE
    else:
        with pytest.raises(SimulatedCrash):
            lib.SaveUserTable(0, 10)
    assert path.read_bytes() == old
    assert sorted(p.name for p in rt.data_dir.iterdir()) == [FILE_NAME]  # temp file removed
    monkeypatch.undo()
    assert lib.LoadUserTable(0, 10) == 0
    assert rt.table(3) == 2.0


def test_process_killed_mid_save_keeps_the_old_file(rt, lib):
    """A real crash: a child process dies (os._exit) after writing half of the new file."""
    rt.set_table(3, 2.0)
    assert lib.SaveUserTable(0, 10) == 0
    path = rt.data_dir / FILE_NAME
    old = path.read_bytes()
    child = textwrap.dedent(
        f"""
        import os, sys
        sys.path[:0] = {sys.path!r}
        from pathlib import Path
        from motionvm.lang.hmpl.lib import usertable
        from motionvm.lang.hmpl.cmemory import Memory

        class Rt:
            mem = Memory(1 << 23)
            user_table_addr = mem.alloc_static(8 * usertable.TABLE_LEN)
            data_dir = Path({str(rt.data_dir)!r})

        def write_half(f, data):
            f.write(data[: len(data) // 2])
            f.flush()
            os.fsync(f.fileno())
            os._exit(9)

        usertable._write_all = write_half
        Rt.mem.f64[Rt.user_table_addr // 8 + 3] = 99.0
        usertable.UserTableLib(Rt()).SaveUserTable(0, 10)
        """
    )
    result = subprocess.run([sys.executable, "-c", child], capture_output=True)
    assert result.returncode == 9, result.stderr.decode()
    assert path.read_bytes() == old
    leftovers = [p.name for p in rt.data_dir.iterdir() if p.name != FILE_NAME]
    assert len(leftovers) == 1 and leftovers[0].endswith(".tmp")  # the half-written temp file
    rt.set_table(3, 0.0)
    assert lib.LoadUserTable(0, 10) == 0
    assert rt.table(3) == 2.0
    assert lib.SaveUserTable(0, 10) == 0  # a stale temp file does not get in the way


def test_unwritable_data_dir_fails_cleanly(rt, lib, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    rt.data_dir = blocker / "data"
    assert lib.SaveUserTable(0, 1) == ERR_STORAGE
    assert lib.LoadUserTable(0, 1) == ERR_STORAGE


@pytest.mark.skipif(
    os.name != "posix" or os.geteuid() == 0, reason="needs POSIX permissions, not root"
)
def test_read_only_data_dir_keeps_the_old_file(rt, lib):
    rt.set_table(0, 1.0)
    assert lib.SaveUserTable(0, 1) == 0
    old = (rt.data_dir / FILE_NAME).read_bytes()
    rt.data_dir.chmod(0o500)
    try:
        rt.set_table(0, 2.0)
        assert lib.SaveUserTable(0, 1) == ERR_STORAGE
    finally:
        rt.data_dir.chmod(0o700)
    assert (rt.data_dir / FILE_NAME).read_bytes() == old
