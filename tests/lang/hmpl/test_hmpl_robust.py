"""Bad input never produces a traceback: mutated golden programs compile to diagnostics or
run to faults reported in the user's terms, never to an internal error."""

from __future__ import annotations

import random
from pathlib import Path

from motionvm.api import Simulation
from motionvm.lang.hmpl.compiler import TaskFile, compile_tasks
from motionvm.source.diagnostics import CompileError, DiagnosticSink

PROGRAMS = Path(__file__).resolve().parents[2] / "programs" / "hmpl"
INSERTS = [
    "*",
    "&",
    "(",
    ")",
    "{",
    "}",
    ";",
    "int",
    "[",
    "]",
    "=",
    "0",
    "x",
    '"s"',
    "->",
    ".",
    "double",
    ",",
    "++",
    "return",
    "break",
    "Timer",
    "Data_t",
    "-1",
    "(char)",
    "~",
    "!",
]


def _mutants(seed: int, count: int):
    files = sorted(PROGRAMS.rglob("*.hmpl"))
    rnd = random.Random(seed)
    for _ in range(count):
        toks = rnd.choice(files).read_text(encoding="utf-8").split(" ")
        for _ in range(rnd.randint(1, 3)):
            i = rnd.randrange(len(toks))
            op = rnd.random()
            if op < 0.4:
                del toks[i]
            elif op < 0.7:
                toks.insert(i, rnd.choice(INSERTS))
            else:
                toks[i] = toks[rnd.randrange(len(toks))]
        yield " ".join(toks)


def test_mutated_programs_never_crash_the_compiler():
    for src in _mutants(seed=11, count=250):
        sink = DiagnosticSink()
        compile_tasks([TaskFile(0, "mutant.hmpl", src)], sink)  # must not raise


def test_mutated_programs_fault_in_user_terms(tmp_path):
    ran = 0
    for src in _mutants(seed=5, count=150):
        try:
            sim = Simulation([TaskFile(0, "mutant.hmpl", src)], data_dir=tmp_path)
        except CompileError:
            continue
        ran += 1
        sim.run(until=0.05)
        for fault in sim.faults:
            assert "internal error" not in fault, (fault, src)
            assert fault.startswith("mutant.hmpl:"), (fault, src)
    assert ran > 20
