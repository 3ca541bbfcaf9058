"""Scope channels of PDL drives: `driveN.<name>`, a drive's system variable, state or global.

Names (docs/scope.md): a system variable or state of the drive (`sysvars.py`) in any case, as
the drive's compiler reads them (`drive1.x_ref_pos` [count], `drive1.X_trg`,
`drive1.fclk`, `drive1.x_run` [bool], `drive1.ref_pos[0]`), or a global of the drive's
program (`drive1.p`, `drive1.tab[3]`). N is the drive's number: the id of the axis it
sits on. The PDL run side (machine_drives.PdlDrives) offers one `PdlDriveSource` for
all its drives through `scope_sources()`; the assembler of a run registers it.
"""

from __future__ import annotations

import difflib
import re
from collections.abc import Callable, Iterable
from functools import partial

from motionvm.lang.pdl.sysvars import SYSVARS, lookup
from motionvm.runtime.scope import BIT_UNIT, RAW_UNIT, ChannelSource, ScopeError

_ELEMENT = re.compile(r"([A-Za-z_]\w*)(?:\[(\d+)\])?")
_SUGGESTED_ELEMENTS = 10  # array elements offered as "did you mean" suggestions, per array
_DRIVE = re.compile(r"drive(\d+)\.(.+)")
_UNIT_IN_DOC = re.compile(r"\[([^\]]+)\]\s*$")


class PdlDriveSource(ChannelSource):
    """`driveN.<name>` of PDL drives: system variables and states (any
    case, as the drive's compiler reads them) and the program's global variables.

    `drives` maps a drive number (the axis id in a machine file) to its `Drive`. With
    `bare` set, that drive's names also resolve without the `driveN.` prefix (a
    standalone `motionvm run prog.pdl` has one drive: `x_ref_pos` is `drive0.x_ref_pos`).
    Units: the catalog's (`count`, `count/s`, `count/s²`, `ms`), `bool` for states,
    `raw` for the rest.
    """

    def __init__(self, drives, bare: int | None = None) -> None:
        self.drives = dict(drives)
        self.bare = bare

    def resolve(self, name: str) -> tuple[Callable[[], float], str] | None:
        m = _DRIVE.fullmatch(name)
        if m is None:
            if self.bare is None or _ELEMENT.fullmatch(name) is None:
                return None
            if not self._known(self.drives[self.bare], name):
                return None
            return self._resolve(name, self.bare, name)
        return self._resolve(name, int(m.group(1)), m.group(2))

    @staticmethod
    def _known(drive, ref: str) -> bool:
        base = _ELEMENT.fullmatch(ref)
        if base is None:
            return False
        return base.group(1) in drive.program.globals or lookup(base.group(1)) is not None

    def _resolve(self, name: str, n: int, ref: str) -> tuple[Callable[[], float], str]:
        drive = self.drives.get(n)
        if drive is None:
            have = ", ".join(f"drive{k}" for k in sorted(self.drives)) or "none"
            raise ScopeError(
                f"scope channel '{name}': no PDL drive {n} (PDL drives: {have}; "
                f"driveN is the drive of axis N)"
            )
        m = _ELEMENT.fullmatch(ref)
        if m is None or not self._known(drive, ref):
            known = [k.partition(".")[2] for k in self._names(n, drive)]
            close = [
                f"drive{n}.{c}" if name != ref else c
                for c in difflib.get_close_matches(ref, known, n=4, cutoff=0.6)
            ]
            hint = (
                f"did you mean {', '.join(close)}?"
                if close
                else "drive channels are a PDL system variable, state or global, "
                "e.g. drive1.x_ref_pos"
            )
            raise ScopeError(f"unknown scope channel '{name}'; {hint}")
        base, index = m.group(1), m.group(2)
        g = drive.program.globals.get(base)
        if g is not None:
            size, unit = g.size, RAW_UNIT
        else:
            sv = lookup(base)
            size = sv.size
            if sv.kind == "state":
                if index is not None:
                    raise ScopeError(f"scope channel '{name}': state '{sv.name}' is one bit")
                return partial(drive.sysvars.ST.__getitem__, sv.address), BIT_UNIT
            found = _UNIT_IN_DOC.search(sv.doc)
            unit = found.group(1).replace("^2", "²") if found else RAW_UNIT
        if index is None and size > 1:
            raise ScopeError(
                f"scope channel '{name}' is an array of {size}; record one element, "
                f"e.g. '{name}[0]'"
            )
        i = int(index or 0)
        if i >= size:
            raise ScopeError(
                f"scope channel '{name}': index {i} is out of range for {base}[{size}] "
                f"(0..{size - 1})"
            )
        if g is None:
            return partial(drive.sysvars.S.__getitem__, drive.sysvars.slot(base, i)), unit
        return partial(drive.read, base, i), unit

    def write(self, name: str, value: float) -> bool:
        """A host write of `driveN.<name>` (the drive's KMI write: read-only system
        variables, `_ro` globals and values outside `_lp` limits refused with ValueError;
        a state is set as an input). False if `name` is not one of ours."""
        if self.resolve(name) is None:  # also: a known drive, name and index
            return False
        m = _DRIVE.fullmatch(name)
        n, ref = (int(m.group(1)), m.group(2)) if m is not None else (self.bare, name)
        drive = self.drives[n]
        base, index = _ELEMENT.fullmatch(ref).groups()  # type: ignore[union-attr]
        sv = None if base in drive.program.globals else lookup(base)
        if sv is not None and sv.read_only:
            raise ValueError(f"refused: system variable '{sv.name}' is read-only")
        if sv is not None and sv.kind == "state":
            drive.set_input(base, int(value))
        else:
            drive.write(base if sv is None else sv.name, value, int(index or 0))
        return True

    @staticmethod
    def _names(n: int, drive) -> Iterable[str]:
        for sv in SYSVARS.values():
            if sv.size == 1:
                yield f"drive{n}.{sv.name}"
            else:
                yield from (f"drive{n}.{sv.name}[{i}]" for i in range(sv.size))
        for g in drive.program.globals.values():
            if g.size == 1:
                yield f"drive{n}.{g.name}"
            else:
                yield from (
                    f"drive{n}.{g.name}[{i}]" for i in range(min(g.size, _SUGGESTED_ELEMENTS))
                )

    def channel_names(self) -> Iterable[str]:
        for n, drive in sorted(self.drives.items()):
            for name in self._names(n, drive):
                yield name
                if n == self.bare:
                    yield name.partition(".")[2]
