"""The host API: run HMPL programs from Python (tests, HMIs, CI scripts) without the CLI.

    sim = Simulation.from_files(["main.hmpl", "conveyor.hmpl"])
    sim.on_event(lambda kind, payload: print(kind, payload))   # SendEvent / SendMsgEvent
    sim.run(until=2.0)
    print(sim.messages, sim.read("system_dtest0"))

Everything runs on simulated time; the same files give the same results every run.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

from motionvm.lang.hmpl.compiler import TaskFile, compile_tasks
from motionvm.lang.hmpl.lvalues import view_code
from motionvm.lang.hmpl.rtapi import HmplRuntime, data_dir_default
from motionvm.sim.controller import Controller
from motionvm.sim.machine import DEFAULT_MACHINE, MachineConfig
from motionvm.source.diagnostics import CompileError, DiagnosticSink


class Simulation:
    """One controller running one HMPL program (any number of task files)."""

    def __init__(
        self,
        tasks: Sequence[TaskFile],
        machine: MachineConfig = DEFAULT_MACHINE,
        data_dir: str | Path | None = None,
    ) -> None:
        sink = DiagnosticSink()
        prog, mem = compile_tasks(list(tasks), sink)
        if prog is None:
            raise CompileError(sink.errors())
        self.messages: list[str] = []
        self.faults: list[str] = []
        self.controller = Controller(machine.cycle_time, machine=machine)
        folder = (
            Path(data_dir) if data_dir is not None else (machine.data_dir or data_dir_default(None))
        )
        self.runtime = HmplRuntime(
            self.controller,
            prog,
            mem,
            emit=self.messages.append,
            report=self.faults.append,
            data_dir=folder,
            task_slice=machine.task_slice,
        )
        self.controller.clients.append(self.runtime)
        self.runtime.boot()

    @classmethod
    def from_files(cls, paths: Sequence[str | Path], **kw) -> Simulation:
        """Files become tasks 0, 1, 2, ... in the order given."""
        return cls([TaskFile(i, str(p)) for i, p in enumerate(paths)], **kw)

    @classmethod
    def from_source(cls, text: str, name: str = "program.hmpl", **kw) -> Simulation:
        return cls([TaskFile(0, name, text)], **kw)

    def on_event(self, callback: Callable[[str, object], None]) -> None:
        """Call `callback(kind, payload)` for each SendEvent ('event', id) and SendMsgEvent ('msg', text)."""
        self.runtime.event_callbacks.append(callback)

    def run(self, until: float | None = None) -> None:
        """Run until every task stops, or until `until` seconds of simulated time."""
        self.controller.run(until)

    def step(self, cycles: int = 1) -> None:
        for _ in range(cycles):
            self.controller.step()

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return self.controller.sim_time

    def read(self, name: str, index: int = 0):
        """Value of a global or system variable (element `index` of an array)."""
        prog = self.runtime.program
        sym = prog.sysvars.get(name) or prog.globals_.get(name)
        if sym is None:
            raise KeyError(f"no global or system variable '{name}'")
        if sym.storage == "pyglobal":
            return self.runtime.ns[sym.pyname]
        if sym.storage == "pylist":
            return self.runtime.ns[sym.pyname][index]
        t = sym.type
        elem = getattr(t, "elem", t)
        return self.runtime.mem.load(sym.addr + index * elem.size, view_code(elem))

    def set_input(self, index: int, value: bool) -> None:
        """Set controller general-purpose input `index` (HIMC_GPI); IndexError if none."""
        self.controller.io.set_input(index, value)

    def output(self, index: int) -> int:
        """Controller general-purpose output `index` (HIMC_GPO); IndexError if none."""
        return self.controller.io.output(index)
