"""The host API: run programs from Python (tests, HMIs, CI scripts) without the CLI.

    sim = Simulation.from_files(["main.hmpl", "conveyor.hmpl"], machine="m.toml")
    sim.on_event(lambda kind, payload: print(kind, payload))   # SendEvent / SendMsgEvent
    sim.run(until=2.0)
    print(sim.messages, sim.read("system_dtest0"))

A thin face over `motionvm.session`, the assembler the command line uses too: the
same files and machine give the same `messages` as the CLI's stdout lines (HMPL
tasks, PDL drives and GDL applications alike). Everything runs on simulated time;
the same inputs give the same results every run.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

from motionvm.lang.hmpl.compiler import TaskFile
from motionvm.lang.hmpl.lvalues import view_code
from motionvm.session import CompileFailed, RunResult, RunSpec, Session, SessionError, Source
from motionvm.sim.machine import MachineConfig
from motionvm.source.diagnostics import CompileError

__all__ = ["CompileError", "RunResult", "SessionError", "Simulation"]


class Simulation:
    """One controller running a set of programs (HMPL tasks, PDL drives, a GDL application).

    Raises `CompileError` (with every diagnostic) if a program does not compile and
    `SessionError` for a bad machine file, scenario or file name.
    """

    def __init__(
        self,
        tasks: Sequence[TaskFile] = (),
        machine: MachineConfig | str | Path | None = None,
        data_dir: str | Path | None = None,
        *,
        sources: Sequence[Source] = (),
        scenario: str | None = None,
        stamp: bool = False,
        skip: bool = True,
        forces: Sequence[str] = (),
        shuffle_seed: int | None = None,
    ) -> None:
        """`tasks` place HMPL task files explicitly; `sources` are files of any language
        (HMPL ones take the free task ids in order). GDL: `scenario` file, `forces`
        (`REF = VALUE` texts applied at t=0), `shuffle_seed`. `skip=False` steps every
        cycle (the same results, slower)."""
        self.messages: list[str] = []
        """Every message line the programs printed, as the CLI prints them."""
        self.faults: list[str] = []
        """Every runtime fault report, as the CLI prints them on stderr."""
        self.diagnostics: list[str] = []
        """Compile warnings and notes, rendered."""
        spec = RunSpec(
            [Source(t.path, t.text, t.task) for t in tasks] + list(sources),
            machine=machine,
            data_dir=data_dir,
            scenario=scenario,
            stamp=stamp,
            skip=skip,
            gdl_forces=tuple(forces),
            shuffle_seed=shuffle_seed,
        )
        self._report_to = self.diagnostics
        try:
            self.session = Session(spec, emit=self.messages.append, report=self._report)
        except CompileFailed as exc:
            raise CompileError(exc.diagnostics) from None
        self._report_to = self.faults
        self.controller = self.session.controller
        self.runtime = self.session.hmpl
        """The HMPL run time (None without HMPL files)."""
        self.session.boot()

    def _report(self, line: str) -> None:
        self._report_to.append(line)

    @classmethod
    def from_files(cls, paths: Sequence[str | Path], **kw) -> Simulation:
        """Files of any language; HMPL files become tasks 0, 1, 2, ... in the order given.
        `machine=` takes a machine file's path or a loaded `MachineConfig`."""
        return cls(sources=[Source(str(p)) for p in paths], **kw)

    @classmethod
    def from_source(cls, text: str, name: str = "program.hmpl", **kw) -> Simulation:
        """One HMPL program given as text, as task 0."""
        return cls([TaskFile(0, name, text)], **kw)

    def on_event(self, callback: Callable[[str, object], None]) -> None:
        """Call `callback(kind, payload)` for each SendEvent ('event', id) and SendMsgEvent ('msg', text)."""
        self._hmpl().event_callbacks.append(callback)

    def run(self, until: float | None = None, timeout: float | None = None) -> RunResult:
        """Run until every part has finished, or until `until` seconds of simulated time,
        or until `timeout` seconds (a run that should have finished by then). Returns why
        it stopped (`reason`: "finished", "until", "timeout") and what still ran."""
        return self.session.run(until, timeout=timeout)

    def step(self, cycles: int = 1) -> None:
        """Run exactly `cycles` controller cycles."""
        self.session.step(cycles)

    @property
    def fault_count(self) -> int:
        """Runtime faults of tasks, drive tasks and procedures so far (the CLI exits 1
        if any); `faults` holds their reports and the warnings of the run."""
        return self.session.fault_count

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return self.controller.sim_time

    def _hmpl(self):
        if self.runtime is None:
            raise KeyError("this simulation runs no HMPL program")
        return self.runtime

    def read(self, name: str, index: int = 0):
        """Value of an HMPL global or system variable (element `index` of an array)."""
        rt = self._hmpl()
        prog = rt.program
        sym = prog.sysvars.get(name) or prog.globals_.get(name)
        if sym is None:
            raise KeyError(f"no global or system variable '{name}'")
        if sym.storage == "pyglobal":
            return rt.ns[sym.pyname]
        if sym.storage == "pylist":
            return rt.ns[sym.pyname][index]
        t = sym.type
        elem = getattr(t, "elem", t)
        return rt.mem.load(sym.addr + index * elem.size, view_code(elem))

    def set_input(self, index: int, value: bool) -> None:
        """Set controller general-purpose input `index` (HIMC_GPI); IndexError if none."""
        self.controller.io.set_input(index, value)

    def output(self, index: int) -> int:
        """Controller general-purpose output `index` (HIMC_GPO); IndexError if none."""
        return self.controller.io.output(index)
