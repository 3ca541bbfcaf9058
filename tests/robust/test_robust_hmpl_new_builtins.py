"""The built-ins of position trigger, compensation, filters, drive objects, controller
variables and communication (manual chapters 12, 14, 15, 17, 21), and of axis groups,
GPIO and analog I/O (chapters 8, 9, 10), called from HMPL the way a careless program
calls them: ids out of range, NaN and infinities (also where an int is due: C converts),
null, wild and too-short pointers, arrays of NaN or huge values, lengths that lie. Each
call returns a value or stops its task with a runtime error; never an internal error.
Generated from a fixed seed, bounded in count."""

from __future__ import annotations

import json
import random
import re
from functools import cache
from importlib import resources

from motionvm.api import Simulation

CHAPTERS = ("12.", "14.", "15.", "17.", "21.")
GROUP_IO_CHAPTERS = ("8.", "9.", "10.")
CALLS_PER_BUILTIN = 2
INTS = ["0", "1", "-1", "7", "64", "65535", "2147483647", "-2147483648", "0x6040", "0x60FE",
        "0x830000e3"]  # fmt: skip
DOUBLES = ["0.0", "-1.0", "1e308", "-1e308", "1.0/0.0", "-1.0/0.0", "0.0/0.0", "5e-324", "5.0"]
POINTERS = ["0", "buf", "&iv", "&dv", "small", "(buf + 1020)", "(char *)12345678"]
GROUP_IO_POINTERS = [*POINTERS, "nanv", "hugev", "infv", "nanv", "hugev"]
PRELUDE = """char buf[1024]; char small[2]; int iv; double dv;
void main() {
    Enable(0); Enable(1);
    StringPrint(buf, "127.0.0.1");
"""
GROUP_IO_PRELUDE = """char buf[1024]; char small[2]; int iv; double dv;
double nanv[10]; double hugev[10]; double infv[10];
void main() {
    int k;
    for (k = 0; k < 10; k++) { nanv[k] = 0.0 / 0.0; hugev[k] = 1e308; infv[k] = -1.0 / 0.0; }
    Enable(0); Enable(1); Enable(2); Till(IsEnabled(0) && IsEnabled(1) && IsEnabled(2));
    SetupGroup(0, 0, 1, 2);
    StringPrint(buf, "127.0.0.1");
    LineRel2D(0, 5.0, 3.0); JogGroup(0, 1, 10.0);
"""


@cache
def builtins(chapters: tuple[str, ...] = CHAPTERS) -> list[tuple[str, str, list[str]]]:
    """(name, return type, parameter types) of each built-in of `chapters`."""
    data = resources.files("motionvm.data").joinpath("hmpl_api.json").read_text("utf-8")
    out = []
    for e in json.loads(data):
        if not e["section"].startswith(chapters) or e["name"] == "START_ASCII_AGENT":
            continue
        m = re.match(r"\s*(\w+)[\s*]+\w+\s*\((.*)\)", e["prototype"])
        params = [p.strip() for p in m.group(2).split(",") if p.strip() not in ("", "void")]
        out.append(
            (e["name"], m.group(1), [p.rsplit(" ", 1)[0] + "*" * p.count("*") for p in params])
        )
    return out


def argument(rng: random.Random, ptype: str, pointers: list[str] = POINTERS) -> str:
    if "*" in ptype:
        value = rng.choice(pointers)
        base = ptype.replace("*", "").replace("const", "").strip()
        return value if value == "0" else f"({base} *){value}"
    return rng.choice(DOUBLES if "double" in ptype else INTS)


def group_io_argument(rng: random.Random, ptype: str) -> str:
    """Also a double where an int is due (ids and counts of NaN, 1e308, 5e-324)."""
    if "*" not in ptype and rng.random() < 0.3:
        return rng.choice(DOUBLES)
    return argument(rng, ptype, GROUP_IO_POINTERS)


def internal_errors(chapters, prelude, arg) -> list[str]:
    rng = random.Random(15)
    bad = []
    for name, ret, params in builtins(chapters):
        for _ in range(CALLS_PER_BUILTIN):
            call = f"{name}({', '.join(arg(rng, p) for p in params)})"
            line = f"    {call};\n" if ret == "void" else f"    iv = (int){call};\n"
            text = prelude + line + line + '    Print("done");\n}\n'
            with Simulation.from_source(text) as sim:
                sim.run(until=0.02)
                internal = [f for f in sim.faults if "internal error" in str(f)]
                if internal:
                    bad.append(f"{call}: {internal[0]}")
    return bad


def test_hostile_calls_return_or_stop_their_task_never_an_internal_error():
    bad = internal_errors(CHAPTERS, PRELUDE, argument)
    assert not bad, "\n".join(bad[:10])


def test_hostile_group_and_io_calls_return_or_stop_their_task_never_an_internal_error():
    # group 0 of axes 0, 1, 2 is enabled and moving when the calls come
    bad = internal_errors(GROUP_IO_CHAPTERS, GROUP_IO_PRELUDE, group_io_argument)
    assert not bad, "\n".join(bad[:10])
