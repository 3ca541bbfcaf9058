"""SaveUserTable/LoadUserTable remove the 4 MB temporaries that killed saves left behind."""

from __future__ import annotations

import os
import time
from pathlib import Path

import pytest

from motionvm.lang.hmpl.cmemory import Memory
from motionvm.lang.hmpl.lib.usertable import FILE_NAME, TABLE_LEN, UserTableLib


class _Runtime:
    """What the User Table uses of the HMPL run time."""

    def __init__(self, data_dir: Path) -> None:
        self.mem = Memory(1 << 23)
        self.user_table_addr = self.mem.alloc_static(8 * TABLE_LEN, "system_user_table")
        self.data_dir = data_dir


@pytest.fixture
def data(tmp_path) -> Path:
    folder = tmp_path / "data"
    folder.mkdir()
    return folder


@pytest.fixture
def lib(data) -> UserTableLib:
    return UserTableLib(_Runtime(data))


def _temp(folder: Path, name: str, age: float) -> Path:
    """A file `name` last modified `age` seconds ago."""
    path = folder / name
    path.write_bytes(b"\0" * 4096)
    then = time.time() - age
    os.utime(path, (then, then))
    return path


STALE = FILE_NAME + ".k3j_9x0q.tmp"  # the name tempfile.mkstemp gives a save's temp file


def test_a_save_removes_a_stale_temp_file(data, lib):
    stale = _temp(data, STALE, 3600)
    assert lib.SaveUserTable(0, 10) == 0
    assert not stale.exists()
    assert sorted(p.name for p in data.iterdir()) == [FILE_NAME]


def test_a_load_removes_a_stale_temp_file(data, lib):
    assert lib.SaveUserTable(0, 10) == 0
    stale = _temp(data, STALE, 3600)
    assert lib.LoadUserTable(0, 10) == 0
    assert not stale.exists()


def test_a_failed_load_removes_it_too(data, lib):
    stale = _temp(data, STALE, 3600)
    assert lib.LoadUserTable(0, 10) != 0  # nothing saved yet
    assert not stale.exists()


def test_a_recent_temp_file_may_be_another_runs_save_and_stays(data, lib):
    young = _temp(data, FILE_NAME + ".abcdefgh.tmp", 5)
    assert lib.SaveUserTable(0, 10) == 0
    assert young.exists()


def test_only_our_own_pattern_is_removed(data, lib, tmp_path):
    others = [
        _temp(data, name, 3600)
        for name in (
            "notes.tmp",
            FILE_NAME + ".tmp",
            FILE_NAME + ".my-backup.tmp",
            FILE_NAME + ".abcdefgh.bak",
            "other.bin.abcdefgh.tmp",
        )
    ]
    outside = _temp(tmp_path, STALE, 3600)  # not in the data folder
    assert lib.SaveUserTable(0, 10) == 0
    assert lib.LoadUserTable(0, 10) == 0
    assert all(p.exists() for p in others)
    assert outside.exists()


def test_a_folder_named_like_a_temp_file_is_left_alone(data, lib):
    folder = data / STALE
    folder.mkdir()
    then = time.time() - 3600
    os.utime(folder, (then, then))
    assert lib.SaveUserTable(0, 10) == 0
    assert folder.is_dir()
