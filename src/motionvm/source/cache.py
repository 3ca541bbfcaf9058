"""The on-disk cache of compiled programs: content-digest keys, atomic entries, a size bound.

Like Python's `__pycache__`, but one folder per user: `$MOTIONVM_CACHE_DIR`, else the
user cache folder (`$XDG_CACHE_HOME/motionvm`, `~/.cache/motionvm`; `%LOCALAPPDATA%` on
Windows). `MOTIONVM_NO_CACHE=1` turns it off. A language builds a key from every input
of a compile (`digest`, `package_digest`) and stores plain data under it: an entry is
written to a temporary file and renamed into place, so a reader sees a whole entry or
none; an entry that is truncated, corrupt or of another format reads as missing (the
program is compiled again). Beyond MAX_BYTES the least recently used entries go.

Entries are pickles read back by an unpickler that builds only motionvm's own classes
and plain containers: an entry holds data (symbols, types, diagnostics, marshalled code
objects), never a reference to other code.
"""

from __future__ import annotations

import hashlib
import io
import os
import pickle
import sys
import tempfile
import zlib
from functools import lru_cache
from pathlib import Path

from motionvm.source.files import SourceFile

MAX_BYTES = 200 * 1024 * 1024
"""The cache folder's size bound [bytes]."""
_MAGIC = b"MVMC\x01"
_SUFFIX = ".mvc"
_PACKAGE = Path(__file__).resolve().parent.parent
_SAFE_BUILTINS = frozenset({"set", "frozenset", "bytearray", "complex", "range", "slice"})


def cache_dir() -> Path | None:
    """The cache folder, or None when caching is off."""
    if os.environ.get("MOTIONVM_NO_CACHE", "") not in ("", "0"):
        return None
    given = os.environ.get("MOTIONVM_CACHE_DIR")
    if given:
        return Path(given)
    if sys.platform == "win32" and os.environ.get("LOCALAPPDATA"):
        return Path(os.environ["LOCALAPPDATA"]) / "motionvm" / "cache"
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "motionvm"


def digest(*parts: str | bytes) -> str:
    """The hex digest of `parts` (each length-prefixed: no two lists share a digest)."""
    h = hashlib.blake2b(digest_size=20)
    for p in parts:
        b = p.encode("utf-8", "surrogatepass") if isinstance(p, str) else p
        h.update(len(b).to_bytes(8, "little"))
        h.update(b)
    return h.hexdigest()


@lru_cache(maxsize=8)
def package_digest(folders: tuple[str, ...], modules_of: tuple[str, ...] = ("",)) -> str:
    """The digest of every source and data file under `folders` of the motionvm package
    (paths relative to it), of the modules directly in `modules_of` ("": the package's
    own, with its version) and of the interpreter's code format: any change of a
    compiler, its data or Python changes it."""
    parts: list[str | bytes] = [sys.implementation.cache_tag or sys.version]
    for folder, deep in [(f, True) for f in folders] + [(f, False) for f in modules_of]:
        for root, dirs, files in os.walk(_PACKAGE / folder):
            dirs[:] = sorted(d for d in dirs if d != "__pycache__") if deep else []
            for name in sorted(files):
                if name.endswith((".py", ".json", ".toml")) and (deep or name.endswith(".py")):
                    path = Path(root, name)
                    parts += [path.relative_to(_PACKAGE).as_posix(), path.read_bytes()]
    return digest(*parts)


def include_digests(files) -> list[tuple[str, str]]:
    """(path, digest of its text) of each file (`SourceFile`) an `#include` read: an
    entry is used only while every one still reads the same (`includes_unchanged`)."""
    return [(sf.path, digest(sf.text)) for sf in files]


def includes_unchanged(includes) -> bool:
    """Whether each (path, text digest) of `include_digests` still reads the same."""
    for path, text_digest in includes:
        try:
            if digest(SourceFile.read(path).text) != text_digest:
                return False
        except OSError:
            return False
    return True


class _DataUnpickler(pickle.Unpickler):
    """Builds motionvm's classes and plain containers only."""

    def find_class(self, module: str, name: str):
        if module.startswith("motionvm.") or (module == "builtins" and name in _SAFE_BUILTINS):
            return super().find_class(module, name)
        raise pickle.UnpicklingError(f"{module}.{name} is not cached data")


class CompileCache:
    """The cache entries of one kind of program (`kind`: "hmpl") in one folder."""

    def __init__(self, folder: Path, kind: str, max_bytes: int = MAX_BYTES) -> None:
        self.folder = folder
        self.kind = kind
        self.max_bytes = max_bytes

    @classmethod
    def open(cls, kind: str) -> CompileCache | None:
        """The cache of `kind` in the configured folder; None when caching is off."""
        folder = cache_dir()
        return None if folder is None else cls(folder, kind)

    def _path(self, key: str) -> Path:
        return self.folder / f"{self.kind}-{key}{_SUFFIX}"

    def load(self, key: str) -> object | None:
        """The entry stored under `key`, or None (missing, unreadable, corrupt)."""
        path = self._path(key)
        try:
            data = path.read_bytes()
        except OSError:
            return None
        if not data.startswith(_MAGIC):
            return None
        try:
            value = _DataUnpickler(io.BytesIO(zlib.decompress(data[len(_MAGIC) :]))).load()
        except Exception:  # noqa: BLE001 - any damage means: not cached
            return None
        try:
            os.utime(path)  # recently used: evicted last
        except OSError:
            pass
        return value

    def store(self, key: str, value: object) -> None:
        """Store `value` under `key` atomically, then keep the folder within its bound.
        A folder that cannot be written, or a value that cannot be pickled (too deeply
        nested for the interpreter's limits), leaves the cache as it was (nothing is
        raised)."""
        try:
            data = _MAGIC + zlib.compress(pickle.dumps(value, protocol=5), 1)
        except Exception:  # noqa: BLE001 - what cannot be kept is compiled again next time
            return
        try:
            self.folder.mkdir(parents=True, exist_ok=True)
            fd, tmp = tempfile.mkstemp(prefix=".tmp-", suffix=_SUFFIX, dir=self.folder)
            try:
                with os.fdopen(fd, "wb") as f:
                    f.write(data)
                os.replace(tmp, self._path(key))
            except BaseException:
                os.unlink(tmp)
                raise
        except OSError:
            return
        self._evict()

    def _evict(self) -> None:
        """Remove the least recently used entries until the folder is within its bound."""
        entries = []
        try:
            with os.scandir(self.folder) as it:
                for e in it:
                    if e.name.endswith(_SUFFIX) and not e.name.startswith(".tmp-"):
                        st = e.stat()
                        entries.append((st.st_mtime_ns, st.st_size, e.path))
        except OSError:
            return
        total = sum(size for _, size, _ in entries)
        for _, size, path in sorted(entries):
            if total <= self.max_bytes:
                break
            try:
                os.unlink(path)
            except OSError:
                continue
            total -= size
