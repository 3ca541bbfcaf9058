"""Machine files (TOML): what the simulated machine is. Only the controller section so far.

```toml
[controller]
cycle_time_ms = 1.0     # controller cycle [ms], 0.125 .. 100
task_slice = 2000       # loop back-edges a task may run per cycle before it yields
data_dir = "data"       # folder for persistent data (user table), relative to this file
```
A bad file is reported as `FILE:LINE: error: MESSAGE` naming the key (exit code 3).
"""

from __future__ import annotations

import re
import tomllib
from dataclasses import dataclass
from pathlib import Path


class MachineFileError(Exception):
    """A machine file that cannot be used; the message names file, line and key."""


@dataclass(frozen=True)
class MachineConfig:
    cycle_time: float = 0.001  # [s]
    task_slice: int = 2000
    data_dir: Path | None = None
    path: Path | None = None


DEFAULT_MACHINE = MachineConfig()

_KNOWN = {"controller": {"cycle_time_ms", "task_slice", "data_dir"}}


def _line_of(text: str, section: str, key: str | None) -> int:
    lines = text.splitlines()
    in_sec = section == ""
    for i, line in enumerate(lines, 1):
        s = line.strip()
        if s.startswith("["):
            in_sec = s.strip("[]").strip() == section
            if key is None and in_sec:
                return i
            continue
        if in_sec and key is not None and re.match(rf"{re.escape(key)}\s*=", s):
            return i
    return 1


def load_machine(path: str | Path) -> MachineConfig:
    """Read and validate a machine file."""
    p = Path(path)
    try:
        text = p.read_text("utf-8")
    except OSError as exc:
        raise MachineFileError(f"{p}: error: cannot read machine file: {exc.strerror}") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        m = re.search(r"line (\d+)", str(exc))
        line = m.group(1) if m else "1"
        raise MachineFileError(f"{p}:{line}: error: invalid TOML: {exc}") from None

    def bad(section: str, key: str | None, msg: str) -> MachineFileError:
        return MachineFileError(f"{p}:{_line_of(text, section, key)}: error: {msg}")

    for sec, val in data.items():
        if sec not in _KNOWN:
            raise bad(sec, None, f"unknown section [{sec}] (known: {', '.join(sorted(_KNOWN))})")
        if not isinstance(val, dict):
            raise bad("", sec, f"'{sec}' must be a table")
        for key in val:
            if key not in _KNOWN[sec]:
                raise bad(sec, key, f"unknown key '{key}' in [{sec}] (known: {', '.join(sorted(_KNOWN[sec]))})")
    ctl = data.get("controller", {})
    cycle_ms = ctl.get("cycle_time_ms", 1.0)
    if isinstance(cycle_ms, bool) or not isinstance(cycle_ms, (int, float)) or not 0.125 <= cycle_ms <= 100:
        raise bad("controller", "cycle_time_ms", f"cycle_time_ms = {cycle_ms!r}: must be a number from 0.125 to 100")
    slice_ = ctl.get("task_slice", 2000)
    if isinstance(slice_, bool) or not isinstance(slice_, int) or not 1 <= slice_ <= 10_000_000:
        raise bad("controller", "task_slice", f"task_slice = {slice_!r}: must be an integer from 1 to 10000000")
    data_dir = ctl.get("data_dir")
    if data_dir is not None and not isinstance(data_dir, str):
        raise bad("controller", "data_dir", f"data_dir = {data_dir!r}: must be a string (a folder)")
    return MachineConfig(
        cycle_time=cycle_ms / 1000.0,
        task_slice=slice_,
        data_dir=(p.parent / data_dir) if data_dir else None,
        path=p,
    )
