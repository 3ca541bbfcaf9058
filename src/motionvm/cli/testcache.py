"""The cache folder of `motionvm test` (`.motionvm_cache/` in the working directory):
which cases failed last (`--lf`); the stored outcomes of cases are cli/resultcache.py's. Written atomically (a temporary file renamed into
place), read forgivingly: a missing, unreadable or malformed cache is an empty one.
"""

from __future__ import annotations

import contextlib
import json
import os
import tempfile
from collections.abc import Iterable
from pathlib import Path

CACHE_DIR = ".motionvm_cache"
_LAST_FAILED = "lastfailed.json"


def cache_dir() -> Path:
    return Path.cwd() / CACHE_DIR


def read_last_failed() -> set[str]:
    """The ids of the cases that failed (or were errors) when they last ran."""
    try:
        data = json.loads((cache_dir() / _LAST_FAILED).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return set()
    if not isinstance(data, list):
        return set()
    return {i for i in data if isinstance(i, str)}


def update_last_failed(ran: Iterable[str], failed: Iterable[str]) -> None:
    """Forget the cases that ran, remember those of them that failed; cases that did not
    run keep their entry. An unwritable folder is ignored (the cache is a convenience)."""
    ran_ids = set(ran)
    ids = (read_last_failed() - ran_ids) | set(failed)
    with contextlib.suppress(OSError):
        write_atomic(_LAST_FAILED, json.dumps(sorted(ids), indent=1) + "\n")


def write_atomic(name: str, text: str) -> None:
    """Write `text` to the cache file `name`, atomically; OSError if it cannot."""
    folder = cache_dir()
    folder.mkdir(exist_ok=True)
    ignore = folder / ".gitignore"
    if not ignore.exists():
        ignore.write_text("# made by motionvm test\n*\n", encoding="utf-8")
    target = folder / name
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
