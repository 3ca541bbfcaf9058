"""The catalog of HMPL built-ins and named constants, read from the package's data files.

`data/hmpl_api.json` is a copy of the manual's function list (324 entries, with
prototypes); this module turns each prototype into a typed signature that the checker
uses for every call, and `motionvm builtins` lists. Constants come from
`data/hmpl_constants.json`; the manual gives no numbers for some enumerations
(BM_*, TM_*, CS_*, HMPL_DAC_*, HMPL_REF_*/HMPL_AXIS_*, HMPL_SLOT_2): those get the
position of the name in its table, counting from 0 (docs/lang/hmpl-semantics.md).
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from functools import lru_cache
from importlib import resources

from motionvm.lang.hmpl import ctypes_ as ct

# Names the language treats specially rather than as plain calls (manual chapter 19).
MACRO_NAMES = frozenset(
    {"_TASKID_", "_AUTORUN_", "Till", "HIMC_GPI", "HIMC_GPO", "START_ASCII_AGENT"}
)
COMPILER_HANDLED = MACRO_NAMES - {"START_ASCII_AGENT"}
"""The special names whose behaviour the compiler itself implements."""


@dataclass(frozen=True, slots=True)
class BuiltinSig:
    """A built-in's typed signature as the manual's prototype gives it."""

    name: str
    ret: ct.CType
    params: tuple[tuple[str, ct.CType], ...]
    variadic: bool
    prototype: str
    section: str
    chapter: str


_PARAM_TYPES: dict[str, ct.CType] = {
    "int": ct.INT,
    "double": ct.DOUBLE,
    "char *": ct.pointer_to(ct.CHAR),
    "double *": ct.pointer_to(ct.DOUBLE),
    "int *": ct.pointer_to(ct.INT),
    "uint16_t": ct.U16,
    "uint8_t *": ct.pointer_to(ct.U8),
    "void *": ct.pointer_to(ct.VOID),
    "int64_t": ct.I64,
    "Timer *": ct.pointer_to(ct.TIMER),
    "uint16_t *": ct.pointer_to(ct.U16),
    "uint64_t *": ct.pointer_to(ct.U64),
    "unsigned short": ct.U16,
    "char": ct.CHAR,
    "void (*)(char *command, char *response)": ct.pointer_to(
        ct.FuncT(0, 1, ct.VOID, (ct.pointer_to(ct.CHAR), ct.pointer_to(ct.CHAR)), False)
    ),
}

_RET_TYPES: dict[str | None, ct.CType] = {
    "int": ct.INT,
    "double": ct.DOUBLE,
    "void": ct.VOID,
    "int64_t": ct.I64,
    None: ct.INT,
}


def _data(name: str):
    return json.loads(resources.files("motionvm.data").joinpath(name).read_text("utf-8"))


@lru_cache(maxsize=1)
def builtin_signatures() -> dict[str, BuiltinSig]:
    """Every built-in of the manual by name, in manual order."""
    out: dict[str, BuiltinSig] = {}
    for e in _data("hmpl_api.json"):
        name = e["name"]
        params: list[tuple[str, ct.CType]] = []
        variadic = False
        for p in e["params"]:
            if p["type"] == "...":
                variadic = True
                continue
            params.append((p["name"], _PARAM_TYPES[p["type"]]))
        proto = e["prototype"]
        if name != e["prototype"].split("(")[0].split()[-1].lstrip("*") and "(" in proto:
            # hmpl_api.json keeps the manual's misspelt prototype (e.g. Idexp); show the real name
            head, _, tail = proto.partition("(")
            proto = re.sub(r"\w+$", name, head) + "(" + tail
        out[name] = BuiltinSig(
            name=name,
            ret=_RET_TYPES[e["returns"]],
            params=tuple(params),
            variadic=variadic,
            prototype=proto,
            section=e["section"],
            chapter=e["chapter"],
        )
    return out


@dataclass(frozen=True, slots=True)
class Constant:
    name: str
    value: int | float
    type: ct.CType
    section: str


# groups whose "names" are descriptions in the manual, not identifiers a program uses
_DESCRIPTIVE_GROUPS = frozenset({"axis_buffer_modes", "ethercat_states", "default_ports"})


@lru_cache(maxsize=1)
def constants() -> dict[str, Constant]:
    """Every named constant usable in a program (PI, HOME_METHOD_1, BM_BUFF, true, ...)."""
    out: dict[str, Constant] = {}
    groups = _data("hmpl_constants.json")["groups"]
    for gname, group in groups.items():
        if gname in _DESCRIPTIVE_GROUPS:
            continue
        for pos, item in enumerate(group["items"]):
            name = item["name"]
            if not re.fullmatch(r"[A-Za-z_]\w*", name) or name in MACRO_NAMES:
                continue
            if name == "TimerInit":
                continue  # an initializer, handled by the compiler
            value = item["value"]
            if value is None:
                value = pos
            if isinstance(value, bool):
                value = int(value)
            if not isinstance(value, (int, float)):
                continue
            typ = ct.DOUBLE if isinstance(value, float) else ct.INT
            out[name] = Constant(name, value, typ, item.get("section", ""))
    return out


@dataclass(frozen=True, slots=True)
class SystemVar:
    """A system variable of manual 22.2 (`n` elements for arrays, 0 for scalars)."""

    name: str
    type: ct.CType
    n: int


def system_variables() -> list[SystemVar]:
    """system_timeInMs, system_fclk, system_user_table[512000], system_ltest0..9, ..."""
    out = [
        SystemVar("system_timeInMs", ct.INT, 0),
        SystemVar("system_fclk", ct.INT, 0),
        SystemVar("system_user_table", ct.DOUBLE, 512000),
    ]
    out += [SystemVar(f"system_ltest{i}", ct.INT, 0) for i in range(10)]
    out += [SystemVar(f"system_dtest{i}", ct.DOUBLE, 0) for i in range(10)]
    out.append(SystemVar("system_mtest", ct.DOUBLE, 10))
    return out
