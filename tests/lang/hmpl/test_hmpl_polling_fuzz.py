"""Random polling loops against their plain spin: the same output, cycle for cycle.

A generator builds loop bodies from the statements a scan loop is made of, nested:
local updates from inputs, counters, `if`/`else`, `switch`, block-scope declarations,
global writes, output writes, `continue`, a rare `break`, reads of the time. Each
program runs looping on `1` (a polling loop: it ends its slice at a fixed point, and
when its quiet iterations read only inputs and variables the clock may jump past it)
and on `yes()` (a user's function: the loop keeps its plain spin), under the same random
input changes, stepping and skipping; everything printed, the globals and the outputs
must be the same.
"""

from __future__ import annotations

import os
import random

from hypothesis import given, settings
from hypothesis import strategies as st

from motionvm.api import Simulation

PROFILE = settings.get_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))

PROGRAM = """
int hits;
int yes() { return 1; }
void main() {
    int x = 0, y = 0, n = 0, prev = -1, p = 0;
    while (FOREVER) {
BODY
        if (x != prev && p < 40) {
            p++;
            Print("%d x=%d y=%d n=%d hits=%d", system_timeInMs, x, y, n, hits);
        }
        prev = x;
    }
    Print("%d left x=%d n=%d", system_timeInMs, x, n);
}
"""
CYCLES = 40


class Bodies:
    """Random statements of a scan loop (`block`), at most `depth` deep."""

    def __init__(self, r: random.Random) -> None:
        self.r = r
        self.decls = 0

    def value(self) -> str:
        return self.r.choice([
            "GetGPI(1)", "GetGPI(2)", "y", "x & 3", "n % 4", "GetGPI(1) * 2 + GetGPI(2)",
            "GetGPO(3)", "HIMC_GPI(2)", "y + GetGPI(1)", "system_timeInMs % 3",
        ])  # fmt: skip

    def cond(self) -> str:
        return self.r.choice([
            "x > y", "GetGPI(1)", "!GetGPI(2)", "n < 50", "(x ^ y) & 1", "GetGPO(3)",
            "x == 2", "hits > 3",
        ])  # fmt: skip

    def stmt(self, depth: int) -> str:
        r = self.r
        kinds = ["x", "y", "x", "n", "hits", "gpo", "decl"]
        if depth > 0:
            kinds += ["if", "if", "switch"]
        kind = r.choice(kinds)
        if kind in ("x", "y"):
            return f"{kind} = {self.value()};"
        if kind == "n":
            return "n++;"
        if kind == "hits":
            return "hits++;"
        if kind == "gpo":
            return f"SetGPO(3, {self.value()} & 1);"
        if kind == "decl":
            self.decls += 1
            return f"{{ int z{self.decls} = {self.value()}; y = z{self.decls} + 1; }}"
        if kind == "if":
            then = self.block(depth - 1)
            if r.random() < 0.15:
                then += " continue;"
            elif r.random() < 0.05:
                then += " break;"
            text = f"if ({self.cond()}) {{ {then} }}"
            if r.random() < 0.4:
                text += f" else {{ {self.block(depth - 1)} }}"
            return text
        return (f"switch (x & 3) {{ case 0: {self.block(depth - 1)} break; "
                f"case 1: {self.block(depth - 1)} "
                f"default: {self.block(depth - 1)} }}")  # fmt: skip

    def block(self, depth: int) -> str:
        return " ".join(self.stmt(depth) for _ in range(self.r.randint(1, 3)))


def _run(src: str, toggles: list[tuple[int, int, int]], skip: bool):
    sim = Simulation.from_source(src, skip=skip, stamp=True)
    for cycle, gpi, value in toggles:
        sim.run(until=cycle * 0.001 + 0.0005)
        sim.set_input(gpi, bool(value))
    sim.run(until=CYCLES * 0.001)
    gpio = sim.controller.io.gpio
    return sim.messages, sim.faults, sim.read("hits"), tuple(gpio.outputs)


@PROFILE
@given(seed=st.integers(0, 2**32 - 1))
def test_a_random_polling_loop_runs_as_its_spin(seed):
    r = random.Random(seed)
    body = Bodies(r).block(2)
    src = PROGRAM.replace("BODY", body)
    toggles = sorted((r.randrange(1, CYCLES - 1), r.choice([1, 2]), r.randint(0, 1))
                     for _ in range(r.randint(1, 6)))  # fmt: skip
    spun = _run(src.replace("FOREVER", "yes()"), toggles, False)
    for skip in (False, True):
        assert _run(src.replace("FOREVER", "1"), toggles, skip) == spun, (skip, body, toggles)
