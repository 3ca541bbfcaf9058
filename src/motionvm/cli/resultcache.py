"""The results cache of `motionvm test` (`.motionvm_cache/results/` in the working
directory): the outcome of each case's run, keyed by what could change it, so that an
unchanged case is judged again from its stored outcome instead of run.

The key is a hash of the case's command lines, the name and bytes of every file in its
folder (not sub-folders) and of every file its arguments name elsewhere, and motionvm's
version with a hash of its own sources (an edited motionvm runs everything again). What
is stored is the run's outcome, not the verdict: expectations are judged anew. Only
finished runs are stored: a killed, timed-out, flooded or interrupted run never is.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import json
import shutil
from pathlib import Path

from motionvm.cli.cases import Case
from motionvm.cli.exits import EXIT_INTERRUPTED
from motionvm.cli.testcache import cache_dir, write_atomic
from motionvm.cli.workers import Outcome

_RESULTS = "results"


@functools.lru_cache(maxsize=1)
def _motionvm_digest() -> str:
    import motionvm

    h = hashlib.sha256(motionvm.__version__.encode())
    root = Path(motionvm.__file__).parent
    for path in sorted(root.rglob("*")):
        if path.suffix in (".py", ".json", ".pyx", ".so") and path.is_file():
            h.update(path.relative_to(root).as_posix().encode() + b"\0")
            h.update(path.read_bytes())
    return h.hexdigest()


def _file_digest(path: Path, memo: dict[Path, str]) -> str:
    if path not in memo:
        memo[path] = hashlib.sha256(path.read_bytes()).hexdigest()
    return memo[path]


def case_key(case: Case, memo: dict[Path, str]) -> str | None:
    """The key of `case`'s outcome (None: a file could not be read; not cached)."""
    folder = Path(case.folder)
    h = hashlib.sha256(_motionvm_digest().encode())
    h.update(json.dumps([case.command, case.argv, case.restart]).encode())
    try:
        files = {p for p in folder.iterdir() if p.is_file() and not p.name.startswith(".")}
        for arg in (*case.argv, *case.restart):
            p = folder / arg
            if p.is_file():
                files.add(p.resolve())
        for p in sorted(files):
            h.update(str(p).encode() + b"\0" + _file_digest(p, memo).encode())
    except OSError:
        return None
    return h.hexdigest()


def cacheable(outcome: Outcome) -> bool:
    """Only a run that finished by itself is kept."""
    return not (
        outcome.timed_out
        or outcome.crashed is not None
        or outcome.flooded
        or outcome.returncode is None
        or outcome.returncode == EXIT_INTERRUPTED
    )


def load(key: str) -> Outcome | None:
    try:
        data = json.loads((cache_dir() / _RESULTS / f"{key}.json").read_text(encoding="utf-8"))
        return Outcome(
            int(data["returncode"]), str(data["stdout"]), str(data["stderr"]),
            float(data["wall_time"]),
        )  # fmt: skip
    except (OSError, ValueError, KeyError, TypeError):
        return None


def store(key: str, outcome: Outcome) -> None:
    """Keep `outcome` under `key` if it is cacheable (an unwritable folder is ignored)."""
    if not cacheable(outcome):
        return
    data = {
        "returncode": outcome.returncode,
        "stdout": outcome.stdout,
        "stderr": outcome.stderr,
        "wall_time": outcome.wall_time,
    }
    with contextlib.suppress(OSError):
        (cache_dir() / _RESULTS).mkdir(parents=True, exist_ok=True)
        write_atomic(f"{_RESULTS}/{key}.json", json.dumps(data))


def clear() -> None:
    """`--cache-clear`: forget every stored outcome and the last failures."""
    shutil.rmtree(cache_dir(), ignore_errors=True)
