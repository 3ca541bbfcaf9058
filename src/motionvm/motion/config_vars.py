"""Controller variables by HCV id (manual 17.1.1): a registry that the owners of the
variables fill, read and written by GetConfigVar/SetConfigVar.

An id is 0xCCIIVVVV: CC the class (`SYSTEM` 0x00, `AXIS` 0x83, `GROUP` 0x82), II the
axis or group id (0 for system variables), VVVV the variable. Each class is a
*family*: a set of variables (by VVVV) and a test of which ids II exist (the axes of the
machine, the groups). Whoever owns the variables registers them: the motion kernel the
axis variables (motion/config_axis.py), an HMPL run time the system variables it keeps
in its memory (system_ltest0 ...), the axis groups their table-17.1.1.3 variables. The
ids and names of the manual's tables are package data (data/hcv_ids.json,
`manual_ids()`), so a test can check that every one is registered.

A getter takes the object id II and returns a float; a setter takes II and the value
and raises `AxisCommandError` (the axis's own check: the axis error code), `ValueError`
(eERR_HCV_VALUE_OUT_OF_RANGE) or nothing. A variable without a setter is read-only
(eERR_HCV_IS_READ_ONLY); an id nobody registered is eERR_HCV_ID_NOT_FOUND.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import lru_cache
from importlib import resources

SYSTEM, GROUP, AXIS = 0x00, 0x82, 0x83

HCV_ID_NOT_FOUND = 0x00000001
"""eERR_HCV_ID_NOT_FOUND (table 18.1.1.1): no variable has this id."""
HCV_IS_READ_ONLY = 0x00000003
"""eERR_HCV_IS_READ_ONLY: the variable cannot be written."""
HCV_VALUE_OUT_OF_RANGE = 0x00000004
"""eERR_HCV_VALUE_OUT_OF_RANGE: the value is outside the variable's range."""

Getter = Callable[[int], float]
Setter = Callable[[int, float], None]


@dataclass(frozen=True, slots=True)
class ConfigVar:
    """One variable of a family: its manual name, getter and setter (None: read-only)."""

    name: str
    get: Getter
    set: Setter | None = None


@dataclass
class Family:
    """The variables of one class and the object ids (axes, groups) that exist."""

    exists: Callable[[int], bool]
    variables: dict[int, ConfigVar] = field(default_factory=dict)


class ConfigVarTable:
    """Every registered controller variable (see the module docstring)."""

    def __init__(self) -> None:
        self.families: dict[int, Family] = {SYSTEM: Family(lambda obj: obj == 0)}

    def add_family(self, cls: int, exists: Callable[[int], bool]) -> None:
        """Declare class `cls` (e.g. GROUP) whose object id II exists if `exists(II)`."""
        self.families.setdefault(cls, Family(exists)).exists = exists

    def add(self, cls: int, var: int, name: str, get: Getter, set: Setter | None = None) -> None:
        """Register variable VVVV = `var` of class `cls` (declared with `add_family`)."""
        self.families[cls].variables[var] = ConfigVar(name, get, set)

    def lookup(self, hcv_id: int) -> tuple[ConfigVar, int] | None:
        """(the variable, its object id II) for `hcv_id`, or None if there is none."""
        hcv_id &= 0xFFFFFFFF
        family = self.families.get(hcv_id >> 24)
        if family is None:
            return None
        obj = (hcv_id >> 16) & 0xFF
        var = family.variables.get(hcv_id & 0xFFFF)
        if var is None or not family.exists(obj):
            return None
        return var, obj


def hcv_id(cls: int, obj: int, var: int) -> int:
    """The id 0xCCIIVVVV."""
    return cls << 24 | obj << 16 | var


@lru_cache(maxsize=1)
def manual_ids() -> dict[int, list[tuple[int, str]]]:
    """The manual's tables by class: [(VVVV, name), ...] in table order."""
    text = resources.files("motionvm.data").joinpath("hcv_ids.json").read_text("utf-8")
    out: dict[int, list[tuple[int, str]]] = {}
    for table in json.loads(text)["tables"]:
        for row in table["rows"]:
            raw = row["id"].replace("XX", "00")
            value = int(raw, 16)
            out.setdefault(value >> 24, []).append((value & 0xFFFF, row["name"]))
    return out
