"""HMPL behind the language interface (`motionvm.lang.interface`): files as tasks, one
program for all of them, its run side (tasks, Native ASCII, E-stop), and what tools see."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from functools import lru_cache
from typing import Any

from motionvm.lang.index import Completion, SourceIndex
from motionvm.lang.interface import (
    CallError,
    CompileRequest,
    CompileResult,
    DebugThread,
    Language,
    LanguageInputError,
    LineTable,
    NameDoc,
    RunContext,
    RunSide,
    Source,
    Symbol,
    visible_completions,
)
from motionvm.lang.tools import nodes
from motionvm.source.diagnostics import Diagnostic, DiagnosticSink


def place_tasks(sources: Sequence[Source]):
    """HMPL sources as tasks: explicit ids first, the others take 0, 1, 2, ... in order.
    LanguageInputError for an id out of range or given twice, or too many files."""
    from motionvm.lang.hmpl.compiler import N_TASKS, TaskFile

    placed: dict[int, Source] = {}
    for s in sources:
        if s.task is None:
            continue
        if not 0 <= s.task < N_TASKS:
            raise LanguageInputError(f"task {s.task}: task ids are 0..{N_TASKS - 1}")
        if s.task in placed:
            raise LanguageInputError(
                f"task {s.task} given twice ({placed[s.task].path} and {s.path})"
            )
        placed[s.task] = s
    nxt = 0
    for s in sources:
        if s.task is not None:
            continue
        while nxt in placed:
            nxt += 1
        if nxt >= N_TASKS:
            raise LanguageInputError(f"more than {N_TASKS} task files")
        placed[nxt] = s
        nxt += 1
    return [TaskFile(t, s.path, s.text) for t, s in sorted(placed.items())]


class HmplSide(RunSide):
    """An HMPL program on the controller: its run time (tasks) and its communication
    client (Native ASCII table, variables, ASCII agent)."""

    def __init__(self, language: Language, runtime, comm) -> None:
        self.language = language
        self.runtime = runtime
        """The program's run time (`rtapi.HmplRuntime`)."""
        self.comm = comm

    def boot(self) -> None:
        self.runtime.boot()

    @property
    def fault_count(self) -> int:
        return self.runtime.faults

    def scope_sources(self) -> list:
        return self.runtime.scope_sources()

    def on_event(self, callback: Callable[[str, object], None]) -> None:
        self.runtime.event_callbacks.append(callback)

    def builtin_names(self) -> frozenset[str]:
        from motionvm.lang.hmpl.lib import implemented_builtins

        return frozenset(implemented_builtins())

    def call(self, name: str, args: Sequence[object]) -> object:
        """As a task's call (`rtcomm.HmplComm.call_builtin`): `str` arguments are C
        strings; with out-parameters (left out of `args`) the value is the tuple
        (return value, each out-parameter's value)."""
        from motionvm.comm.hub import RequestError

        try:
            return self.comm.call_builtin(name, list(args))
        except RequestError as exc:
            raise CallError(str(exc)) from None

    def close(self) -> None:
        self.runtime.close()

    def debug_threads(self) -> list[DebugThread]:
        return [
            DebugThread(("task", t.id), f"task {t.id}", t.gen)
            for t in self.runtime.kernel.tasks
            if t.gen is not None
        ]

    def thread_of(self, root) -> DebugThread | None:
        current = self.runtime.kernel.current
        if current is not None and current.gen is not None and current.gen.gi_frame is root:
            return DebugThread(("task", current.id), f"task {current.id}", current.gen)
        return super().thread_of(root)

    def frame_variables(self, frame) -> dict[str, object]:
        """Locals kept as Python locals (`v_NAME`); those whose address is taken live in the
        task's stack memory and are not shown."""
        return {k[2:]: v for k, v in frame.f_locals.items() if k.startswith("v_")}

    def variable(self, frame, name: str) -> object:
        for key, space in (("v_" + name, frame.f_locals), ("g_" + name, frame.f_globals)):
            if key in space:
                value = space[key]
                if isinstance(value, int | float | list):
                    return value
        raise KeyError(name)

    def global_variables(self, frame) -> dict[str, object]:
        """Globals kept in the namespace (`g_NAME`: scalars and arrays of numbers)."""
        return {
            k[2:]: v
            for k, v in frame.f_globals.items()
            if k.startswith("g_") and isinstance(v, int | float | list)
        }


class Hmpl(Language):
    name = "HMPL"
    language_id = "hmpl"
    suffixes = (".hmpl",)
    run_modules = ("motionvm.lang.hmpl.compiler", "motionvm.lang.hmpl.rtapi")
    directive_comment = ("//", "")
    accepts_text = True
    places_tasks = True

    def compile(self, sources: Sequence[Source], request: CompileRequest) -> CompileResult:
        from motionvm.lang.coverage import active as coverage_active
        from motionvm.lang.hmpl.compiler import compile_tasks
        from motionvm.source.cache import CompileCache

        sink = DiagnosticSink()
        files = place_tasks(sources)
        if request.check_only:  # diagnostics only: nothing to keep
            prog, mem = compile_tasks(files, sink, bytecode=False)
        else:
            # (a compile with coverage probes is neither taken from the cache nor kept)
            cache = None if coverage_active() else CompileCache.open("hmpl")
            prog, mem = compile_tasks(files, sink, cache=cache)
        return CompileResult((prog, mem) if prog is not None else None, list(sink.items))

    def dump(
        self, path: str, stage: str, options: Mapping[str, Any]
    ) -> tuple[str, list[Diagnostic]]:
        from motionvm.lang.hmpl import dump
        from motionvm.lang.hmpl.compiler import TaskFile, compile_tasks
        from motionvm.lang.hmpl.parser import parse
        from motionvm.lang.hmpl.preprocess import preprocess

        sink = DiagnosticSink()
        if stage == "py":
            prog, _mem = compile_tasks([TaskFile(0, path)], sink)
            return ("" if prog is None else prog.python_source()), list(sink.items)
        toks = preprocess(path, task_id=options.get("task_id", 0), sink=sink)
        if stage == "tokens":
            text = dump.dump_tokens(toks) + "\n"
        else:
            text = dump.dump_ast(parse(toks, sink)) + "\n"
        return text, list(sink.items)

    def python_source(self, program: object) -> str:
        return program[0].python_source()  # type: ignore[index]

    def attach(self, controller, program: object, context: RunContext) -> HmplSide:
        from motionvm.lang.hmpl.rtapi import HmplRuntime, data_dir_default
        from motionvm.lang.hmpl.rtcomm import HmplComm

        prog, mem = program  # type: ignore[misc]
        machine = context.machine
        data_dir = (
            context.data_dir
            or machine.data_dir
            or data_dir_default(machine.path.parent if machine.path else None)
        )
        runtime = HmplRuntime(
            controller,
            prog,
            mem,
            emit=context.emit,
            report=context.report,
            data_dir=data_dir,
            task_slice=machine.task_slice,
        )
        runtime.stamp = context.stamp
        controller.add_client(runtime)
        comm = HmplComm(runtime)  # Native ASCII, variables, ASCII agent
        comm.attach(controller.comm)
        controller.add_client(comm)
        controller.io.on_estop(runtime.estop_input)  # E-stop input: tasks stop
        return HmplSide(self, runtime, comm)

    # ---------------------------------------------------------------- tools

    def _tree(self, path: str, text: str | None):
        from motionvm.lang.hmpl.parser import parse_file

        return parse_file(path, task_id=0, sink=DiagnosticSink(), text=text)

    def line_table(self, path: str, text: str | None = None) -> LineTable:
        from motionvm.lang.hmpl import nodes as n

        tree = self._tree(path, text)
        kinds = (n.ExprStmt, n.If, n.While, n.DoWhile, n.For, n.Switch, n.Break, n.Continue,
                 n.Return, n.Goto)  # fmt: skip
        lines: set[int] = set()
        branches: set[int] = set()
        for item in tree.items if tree is not None else ():
            if not isinstance(item, n.FuncDef) or item.body is None:
                continue
            for node in nodes(item.body):
                executes = isinstance(node, kinds) or (
                    isinstance(node, n.VarDecl) and node.init is not None
                )
                if executes and node.pos.file == path:
                    lines.add(node.pos.line)
                    if isinstance(node, n.If):
                        branches.add(node.pos.line)
        return LineTable(path, frozenset(lines), frozenset(branches))

    def symbols(self, path: str, text: str | None = None) -> list[Symbol]:
        from motionvm.lang.hmpl import nodes as n

        tree = self._tree(path, text)
        out: list[Symbol] = []

        def add(name: str, kind: str, pos, container: str | None = None, detail: str = ""):
            if pos.file == path:
                out.append(Symbol(name, kind, path, pos.line, pos.col, container, detail))

        for item in tree.items if tree is not None else ():
            decls = item.decls if isinstance(item, n.DeclStmt) else (item,)
            for d in decls:
                if isinstance(d, n.FuncDef):
                    if d.body is None:
                        continue
                    add(d.name, "function", d.pos)
                    for p in d.params:
                        add(p.name, "parameter", p.pos, d.name)
                    for node in nodes(d.body):
                        if isinstance(node, n.VarDecl):
                            add(node.name, "variable", node.pos, d.name)
                        elif isinstance(node, n.Label):
                            add(node.name, "label", node.pos, d.name)
                elif isinstance(d, n.VarDecl):
                    add(d.name, "variable", d.pos)
                elif isinstance(d, n.Typedef):
                    add(d.name, "type", d.pos)
                elif isinstance(d, n.StructDef) and d.tag:
                    add(d.tag, "struct", d.pos)
                    for f in d.fields:
                        add(f.name, "member", f.pos, d.tag)
        out.sort(key=lambda s: (s.line, s.col))
        return out

    def docs(self) -> Mapping[str, NameDoc]:
        return _docs()

    def index(self, path: str, text: str) -> SourceIndex:
        from motionvm.lang.hmpl.editing import build_index

        return build_index(path, text)

    def inside_comment_or_literal(self, text: str, offset: int) -> bool:
        from motionvm.lang.hmpl.lexer import inside_comment_or_literal

        return inside_comment_or_literal(text, offset)

    def completions(self, index: SourceIndex, line: int, col: int) -> list[Completion]:
        from motionvm.lang.hmpl.editing import keyword_completions, member_completions

        members = member_completions(index, line, col)
        if members is not None:
            return members
        return (
            self.doc_completions()
            + keyword_completions()
            + [
                c if c.kind != "struct" else replace(c, label=c.label.split(" ", 1)[1])
                for c in visible_completions(index, line, col)
            ]
        )

    def doc_completions(self) -> list[Completion]:
        return _doc_completions(self)

    def literal_doc(self, word: str) -> str | None:
        from motionvm.lang.hmpl.editing import error_code_doc

        return error_code_doc(word)


@lru_cache(maxsize=1)
def _doc_completions(lang: Language) -> list[Completion]:
    return Language.doc_completions(lang)


@lru_cache(maxsize=1)
def _docs() -> dict[str, NameDoc]:
    """The manual's built-ins (prototype, purpose, parameters, section) and constants."""
    import json
    from importlib import resources

    from motionvm.lang.hmpl.catalog import builtin_signatures, constants
    from motionvm.lang.hmpl.lib import implemented_names

    sigs = builtin_signatures()
    implemented = implemented_names()
    out: dict[str, NameDoc] = {}
    data = json.loads(resources.files("motionvm.data").joinpath("hmpl_api.json").read_text("utf-8"))
    for e in data:
        sig = sigs[e["name"]]
        params = tuple(
            (p["name"], p["desc"] + (f" [{p['unit']}]" if p.get("unit") else ""))
            for p in e["params"]
            if p["type"] != "..."
        )
        out[e["name"]] = NameDoc(
            e["name"], "builtin", sig.prototype, e["purpose"], params, e["returns_desc"],
            sig.section, implemented=e["name"] in implemented,
        )  # fmt: skip
    for c in constants().values():
        out.setdefault(
            c.name,
            NameDoc(c.name, "constant", f"{c.name} = {c.value:g}", section=c.section,
                    value=c.value),
        )  # fmt: skip
    return out


LANGUAGE = Hmpl()
