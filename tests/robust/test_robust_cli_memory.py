"""`motionvm.cli.main` called in a loop (as a test suite or a fuzzer does) frees each
run's program memory when the run ends: the memory of a run is held in reference
cycles, and a full garbage collection can come too late (memory grew by the program's
memory, about 25 MB, with every run)."""

from __future__ import annotations

import gc

import pytest

from motionvm.lang.hmpl.cmemory import Memory

PROGRAMS = {
    "ok": 'void main() { Print("x"); }\n',
    "fault": "void main() { int z = 0; z = 1 / z; }\n",
    "until": "void main() { while (1) Sleep(1); }\n",
}


def live_memories() -> int:
    return sum(1 for o in gc.get_objects() if isinstance(o, Memory) and not o.buf.closed)


@pytest.mark.parametrize("cmd", ["run", "scope"])
def test_each_run_frees_its_memory_when_it_ends(cli, cmd):
    gc.collect()
    before = live_memories()
    gc.disable()
    try:
        for name, text in PROGRAMS.items():
            argv = ("run", "--until", "0.01") if cmd == "run" else ("scope", "--list")
            cli(*argv, f"{name}.hmpl", **{f"{name}__hmpl": text})
            assert live_memories() == before, name
    finally:
        gc.enable()
