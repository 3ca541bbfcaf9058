"""The on-disk compile cache: its folder, whole entries, data only, a size bound."""

from __future__ import annotations

import os
import pickle
import zlib
from pathlib import Path

from motionvm.source import cache
from motionvm.source.cache import CompileCache, cache_dir
from motionvm.source.files import SourcePos


def test_the_folder_is_the_given_one_else_the_users_cache_folder(monkeypatch, tmp_path):
    monkeypatch.delenv("MOTIONVM_NO_CACHE", raising=False)
    monkeypatch.setenv("MOTIONVM_CACHE_DIR", str(tmp_path / "given"))
    assert cache_dir() == tmp_path / "given"
    monkeypatch.delenv("MOTIONVM_CACHE_DIR")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert cache_dir() == tmp_path / "xdg" / "motionvm"
    monkeypatch.delenv("XDG_CACHE_HOME")
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert cache_dir() == tmp_path / "home" / ".cache" / "motionvm"
    monkeypatch.setenv("MOTIONVM_NO_CACHE", "1")
    assert cache_dir() is None and CompileCache.open("hmpl") is None


def test_an_entry_reads_back_and_leaves_no_temporary_file(tmp_path):
    c = CompileCache(tmp_path / "c", "t")
    value = {"pos": SourcePos("a.hmpl", 3, 4), "codes": [b"\x00" * 10], "s": frozenset({1})}
    c.store("k1", value)
    assert c.load("k1") == value
    assert c.load("k2") is None
    assert [p.name for p in (tmp_path / "c").iterdir()] == ["t-k1.mvc"]


def test_an_entry_naming_other_code_is_not_loaded(tmp_path):
    c = CompileCache(tmp_path, "t")
    c.store("k", {"fine": 1})
    evil = pickle.dumps(os.getcwd)  # a reference to a function outside motionvm
    (tmp_path / "t-k.mvc").write_bytes(b"MVMC\x01" + zlib.compress(evil))
    assert c.load("k") is None


def test_the_least_recently_used_entries_go_beyond_the_bound(tmp_path):
    c = CompileCache(tmp_path, "t", max_bytes=3500)
    blob = os.urandom(1000)  # does not compress
    for k, key in enumerate(["a", "b", "c"]):
        c.store(key, blob)
        os.utime(tmp_path / f"t-{key}.mvc", ns=(k * 10**9, k * 10**9))
    assert c.load("a") == blob  # used last now
    c.store("d", blob)
    assert sorted(p.name for p in tmp_path.glob("*.mvc")) == ["t-a.mvc", "t-c.mvc", "t-d.mvc"]


def test_a_folder_that_cannot_be_written_caches_nothing(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("")
    c = CompileCache(Path(blocker, "sub"), "t")
    c.store("k", 1)  # no exception
    assert c.load("k") is None


def test_the_package_digest_is_kept_per_process():
    assert cache.package_digest(("source",)) == cache.package_digest(("source",))
