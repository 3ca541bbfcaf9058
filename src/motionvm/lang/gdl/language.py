"""GDL behind the language interface (`motionvm.lang.interface`): the files of a run form
one application; its run side takes the scenario's GDL entries and ends a run inclusively."""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
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
from motionvm.source.deep import run_deep
from motionvm.source.diagnostics import Diagnostic, DiagnosticSink, TooManyErrors


class GdlSide(RunSide):
    """A GDL application on the controller (`client.GdlApplication`)."""

    def __init__(self, language: Language, client) -> None:
        from motionvm.lang.gdl.scenario import ScenarioEntries

        self.language = language
        self.client = client
        """The application's cycle client (`client.GdlApplication`)."""
        self._entries = ScenarioEntries(client.app)

    @property
    def fault_count(self) -> int:
        return self.client.error_count

    def scope_sources(self) -> list:
        return self.client.scope_sources()

    def takes_scenario(self) -> bool:
        return True

    def take_scenario_entry(self, entry) -> bool:
        return self._entries.take_scenario_entry(entry)

    def scenario_loaded(self, until: float | None) -> None:
        self.client.use_scenario(self._entries.scenario(until))

    def end_time(self, end: float | None) -> float | None:
        """Inclusive: the events due at the end time still apply."""
        return self.client.run_until(end)

    def finish(self) -> None:
        self.client.finish()

    def thread_of(self, root) -> DebugThread | None:
        """A procedure runs to its end within one cycle: its frame is its thread."""
        name = root.f_code.co_name
        if name.startswith("p_") and root.f_code.co_filename.lower().endswith(".gdl"):
            return DebugThread(("procedure", name[2:]), f"procedure {name[2:]}")
        return None

    def frame_variables(self, frame) -> dict[str, object]:
        return {}


_UNUSED = "applies to GDL applications; no .gdl file was given"


class Gdl(Language):
    name = "GDL"
    language_id = "gdl"
    suffixes = (".gdl",)
    accepts_text = True
    fold_case = True
    run_modules = ("motionvm.lang.gdl.compiler", "motionvm.lang.gdl.client")
    directive_comment = ("|", "|")
    links_files = True
    case_toml_option = "--scenario"
    options = (
        LanguageOption("forces", "--force", _UNUSED),
        LanguageOption("shuffle_seed", "--shuffle-order", _UNUSED),
    )

    def compile(self, sources: Sequence[Source], request: CompileRequest) -> CompileResult:
        from motionvm.lang.coverage import active as coverage_active
        from motionvm.lang.gdl.compiler import compile_app
        from motionvm.source.cache import CompileCache

        paths = [s.path for s in sources]
        _once_each(paths)
        texts = {s.path: s.text for s in sources if s.text is not None}
        sink = DiagnosticSink()
        # (a check keeps nothing; a compile with coverage probes is neither read nor kept)
        no_cache = request.check_only or coverage_active()
        cache = None if no_cache else CompileCache.open("gdl")
        app = compile_app(paths, sink=sink, texts=texts, cache=cache)
        order = {p: i for i, p in enumerate(paths)}
        diagnostics = sorted(
            sink.items, key=lambda d: (order.get(d.pos.file, -1), d.pos.line, d.pos.col)
        )
        return CompileResult(app, diagnostics)

    def dump(
        self, path: str, stage: str, options: Mapping[str, Any]
    ) -> tuple[str, list[Diagnostic]]:
        from motionvm.lang.gdl.compiler import compile_app
        from motionvm.lang.gdl.dump import dump_ast, dump_tokens
        from motionvm.lang.gdl.lower import emit_python

        sink = DiagnosticSink()
        if stage == "py":
            app = compile_app([path], sink=sink)
            items = sorted(sink.items, key=lambda d: (d.pos.line, d.pos.col))
            return ("" if app is None else emit_python(app)), items
        try:
            # the parser and the printer recurse per level of nesting, as the compile does
            text = run_deep(dump_tokens if stage == "tokens" else dump_ast, path, sink)
        except OSError as exc:
            raise LanguageInputError(f"error: cannot read {path}: {exc.strerror or exc}") from None
        except TooManyErrors:  # the errors are the dump: the lexer gave up on the file
            text = ""
        return text, list(sink.items)

    def python_source(self, program: object) -> str:
        from motionvm.lang.gdl.lower import emit_python

        return emit_python(program)

    def attach(self, controller, program: object, context: RunContext) -> GdlSide:
        from motionvm.lang.gdl.client import GdlApplication
        from motionvm.lang.gdl.motors import GdlMachineError
        from motionvm.sim.scenario import ScenarioError

        try:
            client = GdlApplication(
                controller,
                program,
                emit=context.emit,
                report=context.report,
                forces=context.options.get("forces", ()),
                shuffle_seed=context.options.get("shuffle_seed"),
                motor_axes=context.machine.gdl_motors,
                stamp=context.stamp,
            )
        except ScenarioError as exc:  # a --force text
            raise LanguageInputError(*exc.messages, located=exc.located) from None
        except GdlMachineError as exc:
            raise LanguageInputError(str(exc), located=True) from None
        controller.add_client(client)
        return GdlSide(self, client)

    # ---------------------------------------------------------------- tools

    def _tree(self, path: str, text: str | None):
        from motionvm.lang.gdl.lexer import tokenize
        from motionvm.lang.gdl.parser import parse_tokens
        from motionvm.source.files import SourceFile

        sink = DiagnosticSink()
        try:
            text = SourceFile.read(path).text if text is None else text
        except OSError:
            return None
        try:  # the parser recurses per level of nesting, as the compile does
            return run_deep(lambda: parse_tokens(tokenize(path, text, sink), path, sink))
        except TooManyErrors:  # a file the lexer gives up on has no statements to show
            return None

    def line_table(self, path: str, text: str | None = None) -> LineTable:
        from motionvm.lang.gdl import nodes as n

        kinds = (n.Assign, n.OperatorCall, n.If, n.While, n.Return)
        tree = self._tree(path, text)
        return (
            statement_lines(tree, kinds, path, n.If)
            if tree is not None
            else LineTable(path, frozenset())
        )

    def symbols(self, path: str, text: str | None = None) -> list[Symbol]:
        from motionvm.lang.gdl.editing import symbols

        return symbols(path, text)

    def index(self, path: str, text: str) -> SourceIndex:
        from motionvm.lang.gdl.editing import build_index

        return build_index(path, text)

    def docs(self) -> Mapping[str, NameDoc]:
        from motionvm.lang.gdl.editing import docs

        return docs()

    def inside_comment_or_literal(self, text: str, offset: int) -> bool:
        from motionvm.lang.gdl.lexer import inside_comment_or_literal

        return inside_comment_or_literal(text, offset)

    def completions(self, index: SourceIndex, line: int, col: int) -> list[Completion]:
        from motionvm.lang.gdl.editing import completions

        return completions(index, line, col, visible_completions)


LANGUAGE = Gdl()


def _once_each(paths: Sequence[str]) -> None:
    """LanguageInputError for a file given twice: its modules would clash with
    themselves (`name 'cell' is already used by the module at cell.gdl:2:8`)."""
    seen: dict[str, str] = {}
    for path in paths:
        key = os.path.realpath(path)
        if key in seen:
            also = "" if seen[key] == path else f" (also as {seen[key]})"
            raise LanguageInputError(
                f"{path}: given twice{also}; an application takes each of its .gdl files once"
            )
        seen[key] = path
