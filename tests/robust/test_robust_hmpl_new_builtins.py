"""The built-ins of position trigger, compensation, filters, drive objects, controller
variables and communication (manual chapters 12, 14, 15, 17, 21) called from HMPL the
way a careless program calls them: ids out of range, NaN and infinities, null, wild and
too-short pointers, lengths that lie. Each call returns a value or stops its task with
a runtime error; never an internal error. Generated from a fixed seed, bounded in count."""

from __future__ import annotations

import json
import random
import re
from functools import cache
from importlib import resources

from motionvm.api import Simulation

CHAPTERS = ("12.", "14.", "15.", "17.", "21.")
CALLS_PER_BUILTIN = 2
INTS = ["0", "1", "-1", "7", "64", "65535", "2147483647", "-2147483648", "0x6040", "0x60FE",
        "0x830000e3"]  # fmt: skip
DOUBLES = ["0.0", "-1.0", "1e308", "-1e308", "1.0/0.0", "-1.0/0.0", "0.0/0.0", "5e-324", "5.0"]
POINTERS = ["0", "buf", "&iv", "&dv", "small", "(buf + 1020)", "(char *)12345678"]
PRELUDE = """char buf[1024]; char small[2]; int iv; double dv;
void main() {
    Enable(0); Enable(1);
    StringPrint(buf, "127.0.0.1");
"""


@cache
def builtins() -> list[tuple[str, str, list[str]]]:
    """(name, return type, parameter types) of each built-in of CHAPTERS."""
    data = resources.files("motionvm.data").joinpath("hmpl_api.json").read_text("utf-8")
    out = []
    for e in json.loads(data):
        if not e["section"].startswith(CHAPTERS) or e["name"] == "START_ASCII_AGENT":
            continue
        m = re.match(r"\s*(\w+)[\s*]+\w+\s*\((.*)\)", e["prototype"])
        params = [p.strip() for p in m.group(2).split(",") if p.strip() not in ("", "void")]
        out.append(
            (e["name"], m.group(1), [p.rsplit(" ", 1)[0] + "*" * p.count("*") for p in params])
        )
    return out


def argument(rng: random.Random, ptype: str) -> str:
    if "*" in ptype:
        value = rng.choice(POINTERS)
        base = ptype.replace("*", "").replace("const", "").strip()
        return value if value == "0" else f"({base} *){value}"
    return rng.choice(DOUBLES if "double" in ptype else INTS)


def test_hostile_calls_return_or_stop_their_task_never_an_internal_error():
    rng = random.Random(15)
    bad = []
    for name, ret, params in builtins():
        for _ in range(CALLS_PER_BUILTIN):
            call = f"{name}({', '.join(argument(rng, p) for p in params)})"
            line = f"    {call};\n" if ret == "void" else f"    iv = (int){call};\n"
            text = PRELUDE + line + line + '    Print("done");\n}\n'
            with Simulation.from_source(text) as sim:
                sim.run(until=0.02)
                internal = [f for f in sim.faults if "internal error" in str(f)]
                if internal:
                    bad.append(f"{call}: {internal[0]}")
    assert not bad, "\n".join(bad[:10])
