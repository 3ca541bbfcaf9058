"""Compile one HMPL task and run it to its end on a bare controller, returning the
lines it printed (the differential tests compare them with C's); or return the Python
it is lowered to (`python_of`, the lowering tests)."""

from __future__ import annotations

from motionvm.lang.hmpl.compiler import TaskFile, compile_tasks
from motionvm.lang.hmpl.rtapi import HmplRuntime
from motionvm.sim.controller import Controller
from motionvm.source.diagnostics import DiagnosticSink


def run_hmpl(src: str, name: str = "<diff>.hmpl") -> list[str]:
    sink = DiagnosticSink()
    prog, mem = compile_tasks([TaskFile(0, name, src)], sink)
    assert prog is not None, [d.headline() for d in sink.items][:5]
    ctl = Controller(0.001)
    lines: list[str] = []
    faults: list[str] = []
    rt = HmplRuntime(
        ctl, prog, mem, emit=lines.append, report=lambda s: faults.append(str(s)), data_dir="."
    )
    ctl.clients.append(rt)
    rt.boot()
    ctl.run()
    rt.close()
    assert not faults, faults
    return lines


def python_of(body: str) -> str:
    """The Python of a task whose `main` runs `body` (with a local `a`, globals `g` and
    `t` and a function `f` in scope)."""
    src = f"int g; int t;\nint f() {{ return 1; }}\nvoid main() {{\n int a = 0;\n {body}\n}}\n"
    sink = DiagnosticSink()
    prog, _mem = compile_tasks([TaskFile(0, "p.hmpl", src)], sink)
    assert prog is not None, [d.headline() for d in sink.items]
    return prog.python_source()
