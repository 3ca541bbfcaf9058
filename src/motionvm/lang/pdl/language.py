"""PDL behind the language interface (`motionvm.lang.interface`): programs on drives (the
machine file's, or one file on the next free axis), their run side, and what tools see."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from motionvm.lang.index import Completion, SourceIndex
from motionvm.lang.interface import (
    CompileRequest,
    CompileResult,
    DebugThread,
    Language,
    LanguageInputError,
    LanguageOption,
    LineTable,
    NameDoc,
    RunContext,
    RunSide,
    Source,
    Symbol,
    visible_completions,
)
from motionvm.lang.tools import statement_lines
from motionvm.source.diagnostics import Diagnostic, DiagnosticSink, TooManyErrors


class PdlSide(RunSide):
    """PDL drives on the machine's axes (`machine_drives.PdlDrives`)."""

    def __init__(self, language: Language, drives) -> None:
        self.language = language
        self.drives = drives
        """The cycle client running the drives (`machine_drives.PdlDrives`)."""

    def boot(self) -> None:
        from motionvm.lang.pdl.machine_drives import PdlStartError

        try:
            self.drives.boot()
        except PdlStartError as exc:  # a standalone drive refused a --start label
            raise LanguageInputError(str(exc), located=True) from None

    @property
    def fault_count(self) -> int:
        return len(self.drives.faults)

    def scope_sources(self) -> list:
        return self.drives.scope_sources()

    def debug_threads(self) -> list[DebugThread]:
        return [
            DebugThread(("drive", axis_id, task.id), f"drive {axis_id} task {task.id}", task.gen)
            for axis_id, drive in self.drives.drives
            for task in drive.tasks
            if task.gen is not None
        ]

    def frame_variables(self, frame) -> dict[str, object]:
        """None: a PDL program's variables are the drive's globals (the generated code's
        locals are its memory views)."""
        return {}

    def global_variables(self, frame) -> dict[str, object]:
        """The globals of the program of the drive running `frame`, as KMI reads them
        (an array as a list)."""
        drive = self._drive_of(frame)
        if drive is None:
            return {}
        return {name: _value(drive, g) for name, g in drive.program.globals.items()}

    def global_channel(self, frame, name: str) -> str:
        """`driveN.name`: the global of the program of the drive running `frame`."""
        drive = self._drive_of(frame)
        for axis_id, d in self.drives.drives:
            if d is drive and name.partition("[")[0] in drive.program.globals:
                return f"drive{axis_id}.{name}"
        return name

    def variable(self, frame, name: str) -> object:
        drive = self._drive_of(frame)
        g = drive.program.globals.get(name) if drive is not None else None
        if g is None:
            raise KeyError(name)
        return _value(drive, g)

    def _drive_of(self, frame):
        """The drive one of whose tasks runs or holds `frame` (or its callers)."""
        outer = set()
        f = frame
        while f is not None:
            outer.add(f)
            f = f.f_back
        for _axis_id, drive in self.drives.drives:
            for task in drive.tasks:
                gen = task.gen
                while gen is not None:
                    if getattr(gen, "gi_frame", None) in outer:
                        return drive
                    gen = getattr(gen, "gi_yieldfrom", None)
        return None


def _value(drive, g) -> object:
    """A global of a drive's program: its value, or its elements' (an array)."""
    if g.size == 1:
        return drive.read(g.name)
    return [drive.read(g.name, i) for i in range(g.size)]


class Pdl(Language):
    name = "PDL"
    language_id = "pdl"
    suffixes = (".pdl",)
    accepts_text = True
    run_modules = ("motionvm.lang.pdl.machine_drives",)
    directive_comment = ("//", "")
    options = (
        LanguageOption(
            "starts", "--start", "applies to a PDL program given as a file; none was given"
        ),
    )

    def has_programs(self, sources, machine) -> bool:
        return bool(sources) or bool(machine.pdl_drives)

    def place(self, machine, sources: Sequence[Source], request: CompileRequest):
        """Check only: each file on a drive of its own. Else the file (one at most) on
        the next axis whose drive runs no program."""
        from motionvm.sim.machine import PdlDriveSpec

        if request.check_only:
            specs = tuple(PdlDriveSpec(i, Path(s.path)) for i, s in enumerate(sources))
            return dataclasses.replace(machine, pdl_drives=specs)
        if not sources:
            return machine
        if len(sources) > 1:
            given = ", ".join(s.path for s in sources)
            raise LanguageInputError(
                f"at most one .pdl file on the command line, got {len(sources)} ({given}); a "
                'machine file puts programs on several drives (pdl = "x.pdl" in an [[axis]] '
                "table)"
            )
        taken = {d.axis for d in machine.pdl_drives}
        free = [i for i in range(len(machine.axes)) if i not in taken]
        if not free:
            raise LanguageInputError(
                f"{sources[0].path}: every axis of the machine runs a PDL program"
            )
        starts = tuple(request.options.get("starts", ()))
        spec = PdlDriveSpec(free[0], Path(sources[0].path), starts)  # no `where`: --start
        return dataclasses.replace(machine, pdl_drives=(*machine.pdl_drives, spec))

    def compile(self, sources: Sequence[Source], request: CompileRequest) -> CompileResult:
        from motionvm.lang.coverage import active as coverage_active
        from motionvm.lang.pdl.machine_drives import PdlStartError, compile_specs, standalone_spec
        from motionvm.source.cache import CompileCache

        # (a check keeps nothing; a compile with coverage probes is neither read nor kept)
        no_cache = request.check_only or coverage_active()
        cache = None if no_cache else CompileCache.open("pdl")
        machine = request.machine
        texts = {str(Path(s.path)): s.text for s in sources if s.text is not None}
        texts.update({s.path: s.text for s in sources if s.text is not None})
        try:
            if request.alone and not request.check_only:  # one program, the default machine
                specs = standalone_spec(sources[0].path, request.options.get("starts", ()))
            else:
                specs = [(spec, str(spec.path)) for spec in machine.pdl_drives]
            drives, diagnostics = compile_specs(specs, texts, cache)
        except PdlStartError as exc:
            raise LanguageInputError(str(exc), located=True) from None
        return CompileResult(drives, diagnostics)

    def dump(
        self, path: str, stage: str, options: Mapping[str, Any]
    ) -> tuple[str, list[Diagnostic]]:
        from motionvm.lang.pdl import dump
        from motionvm.lang.pdl.front import compile_front
        from motionvm.lang.pdl.preprocess import preprocess
        from motionvm.lang.pdl.program import compile_pdl

        sink = DiagnosticSink()
        text = ""
        if stage == "tokens":
            try:
                text = dump.dump_tokens(preprocess(path, sink)) + "\n"
            except TooManyErrors:  # the errors are the dump: too many for a token list
                pass
        elif stage == "ast":
            prog = compile_front(path, sink=sink)
            if prog is not None:
                text = dump.dump_ast(prog) + "\n"
        else:
            prog = compile_pdl(path, sink=sink)
            if prog is not None:
                text = prog.python_source() + "\n"
        return text, sorted(sink.items, key=lambda d: (d.pos.file, d.pos.line, d.pos.col))

    def python_source(self, program: object) -> str:
        return "\n".join(d.program.python_source() for d in program)  # type: ignore[attr-defined]

    def attach(self, controller, program: object, context: RunContext) -> PdlSide:
        from motionvm.lang.pdl.machine_drives import PdlDrives

        drives = PdlDrives(
            controller,
            program,
            context.machine,
            emit=context.emit,
            report=context.report,
            stamp=context.stamp,
            standalone=context.alone,
        )
        controller.add_client(drives)
        return PdlSide(self, drives)

    # ---------------------------------------------------------------- tools

    def _tree(self, path: str, text: str | None):
        from motionvm.lang.pdl.front import front_end

        result = front_end(path, sink=DiagnosticSink(), text=text)
        return None if result is None else result.program

    def line_table(self, path: str, text: str | None = None) -> LineTable:
        from motionvm.lang.pdl import nodes as n

        kinds = (n.Assign, n.StateAssign, n.IncDec, n.Goto, n.CallLabel, n.ProcCall, n.Simple,
                 n.Delay, n.Kill, n.SetState, n.Print, n.Loop, n.If, n.While, n.Till)  # fmt: skip
        tree = self._tree(path, text)
        return (
            statement_lines(tree, kinds, path, n.If)
            if tree is not None
            else LineTable(path, frozenset())
        )

    def symbols(self, path: str, text: str | None = None) -> list[Symbol]:
        from motionvm.lang.pdl.editing import symbols

        return symbols(path, text)

    def index(self, path: str, text: str) -> SourceIndex:
        from motionvm.lang.pdl.editing import build_index

        return build_index(path, text)

    def docs(self) -> Mapping[str, NameDoc]:
        from motionvm.lang.pdl.editing import docs

        return docs()

    def inside_comment_or_literal(self, text: str, offset: int) -> bool:
        from motionvm.lang.pdl.lexer import inside_comment_or_literal

        return inside_comment_or_literal(text, offset)

    def completions(self, index: SourceIndex, line: int, col: int) -> list[Completion]:
        from motionvm.lang.pdl.editing import completions

        return completions(index, line, col, visible_completions)


LANGUAGE = Pdl()
