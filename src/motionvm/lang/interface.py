"""The language interface: what every language offers the session, the debugger and the tools.

Each language package (`lang/hmpl`, `lang/pdl`, `lang/gdl`) exports one `Language` object
from its `language.py`; the registry (`motionvm.lang`) lists them in run order. Everything
above `lang/` -- the session, the API, the command line, the debugger, the language server,
the studio -- reaches a language only through this interface and loops over the registry:

- who it is: `name`, `language_id`, `suffixes`;
- the compiler: `stages` and `dump` (what each stage makes of a file), `check` (the
  diagnostics of files, nothing runs), `compile` (a program, or None after errors);
- the run: `attach(controller, program, context) -> RunSide`, the language's run side
  on the controller's one cycle. A run side counts its faults (the reports are
  `runtime.fault_position.Fault` records, whatever the language), offers its scope
  sources, takes the scenario entries it understands and states its end-of-run rule;
- what tools see inside a program: `line_table` (which lines hold statements:
  breakpoints, coverage), `symbols` (declarations with their places: outline,
  go to definition, rename) and `docs` (built-ins, constants, keywords: hover, completion);
- what an editor asks of a file's (unsaved) text: `index` (every name resolved to its
  declaration: definition, references, rename), `hover`, `completions`, `signature`
  (`motionvm.lang.index` holds their types and the text helpers they share).

A language's options on the command line (`--start`, `--force`, ...) are declared as
`LanguageOption`s; the session checks that a given option has a language to take it.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from motionvm.lang.index import (
    Completion,
    Signature,
    SourceIndex,
    Symbol,
    call_at,
    param_spans,
    resolve,
    snippet_of,
    token_end,
    word_at,
)
from motionvm.source.diagnostics import Diagnostic

if TYPE_CHECKING:
    from motionvm.runtime.scope import ChannelSource
    from motionvm.sim.machine import MachineConfig
    from motionvm.sim.scenario import ScenarioEntry


class LanguageInputError(Exception):
    """Input a language cannot use that is not a compile error: a start label a program
    lacks, a `--force` text, a machine with too few axes (the CLI's exit code 3).
    `messages`: one complete line each; `located`: each starts `FILE:LINE:COL: error:`."""

    def __init__(self, *messages: str, located: bool = False) -> None:
        super().__init__("\n".join(messages))
        self.messages = list(messages)
        self.located = located


class CallError(ValueError):
    """A host's call of a built-in that cannot be made (`RunSide.call`): an unknown or
    unimplemented name, a wrong number or kind of arguments, a built-in that waits and
    so only runs inside a task. A call the built-in itself refuses is no CallError: it
    returns the manual's error code, as it does to a program."""


@dataclass(frozen=True)
class Source:
    """One program file of a run."""

    path: str
    text: str | None = None
    """The source text, for a program that is not in a file (languages with
    `accepts_text`); None: read the file."""
    task: int | None = None
    """The task it runs as, for a language that places files as tasks (None: the next
    free one)."""


@dataclass(frozen=True)
class LanguageOption:
    """A run option that only one language takes (`RunSpec.options[key]`)."""

    key: str
    """Its key in `RunSpec.options` (`starts`, `forces`, `shuffle_seed`)."""
    flag: str
    """Its name on the command line (`--start`)."""
    unused: str
    """What is wrong when no file of the language was given, after the flag
    ("applies to a PDL program given as a file; none was given")."""


@dataclass(frozen=True)
class CompileRequest:
    """What a language's `compile` is given besides its files."""

    machine: MachineConfig
    """The run's machine (programs it names: PDL drive programs)."""
    options: Mapping[str, Any] = field(default_factory=dict)
    check_only: bool = False
    """`motionvm check`: each file on its own, nothing will run (no bytecode needed)."""
    alone: bool = False
    """The language's files are all the run has and there is no machine file."""


@dataclass
class CompileResult:
    """A compile's outcome: the program (None after an error) and every diagnostic, in
    the order to report them."""

    program: object | None
    diagnostics: list[Diagnostic] = field(default_factory=list)


@dataclass(frozen=True)
class RunContext:
    """What a run side is attached with."""

    machine: MachineConfig
    emit: Callable[[str], None]
    """Receives every message line the program prints."""
    report: Callable[[str], None]
    """Receives every fault report (a `Fault`) and note."""
    stamp: bool = False
    """Prefix each message with the simulated time and its source."""
    options: Mapping[str, Any] = field(default_factory=dict)
    data_dir: Path | None = None
    """Folder of persistent data (None: the machine's or the default)."""
    alone: bool = False
    """As `CompileRequest.alone`."""


@dataclass(frozen=True)
class NameDoc:
    """Documentation of one name of the language (hover, completion, signature help)."""

    name: str
    kind: str
    """"builtin", "constant", "keyword", "variable", "type", "error"."""
    signature: str = ""
    """The prototype (`int MoveAbs(int axis_id, double pos)`) or the value (`= 3`)."""
    summary: str = ""
    """One paragraph: what it is for."""
    params: tuple[tuple[str, str], ...] = ()
    """(name, description with its unit) of each parameter, in order."""
    returns: str = ""
    section: str = ""
    """Where the manual describes it."""
    value: float | None = None
    """A constant's value."""
    implemented: bool = True
    """A built-in that motionvm runs (False: described by the manual only)."""

    def markdown(self) -> str:
        """The hover text."""
        out = []
        if self.signature:
            out.append(f"```\n{self.signature}\n```")
        if self.summary:
            out.append(self.summary)
        if self.params:
            out.append("\n".join(f"- `{n}`: {d}" for n, d in self.params))
        if self.returns:
            out.append(f"Returns: {self.returns}")
        if self.section:
            out.append(f"Manual {self.section}")
        return "\n\n".join(out)


@dataclass(frozen=True)
class LineTable:
    """The lines of one file that hold a statement: where a breakpoint can stop and what
    coverage counts."""

    file: str
    lines: frozenset[int]
    branches: frozenset[int] = frozenset()
    """The lines of `if` statements (coverage counts both arms of each)."""

    def next_line(self, line: int) -> int | None:
        """The first statement line at or after `line` (a breakpoint moves there)."""
        after = [n for n in self.lines if n >= line]
        return min(after) if after else None


@dataclass(frozen=True)
class DebugThread:
    """A task, drive task or procedure as a debugger shows it (a thread)."""

    key: tuple
    """Its identity across the run (`("task", 3)`, `("drive", 1, 0)`), stable while the
    program runs and from one run of the same files to the next."""
    name: str
    """`task 3`, `drive 1 task 0`, `procedure fan_control`."""
    generator: object | None = None
    """The running task's generator (its suspended frames); None: not suspended."""


class RunSide:
    """One language's part of a run, attached to the controller (`Language.attach`).

    The defaults say: nothing to boot, no faults, no scope channels, no scenario entries,
    the run ends when the caller says, no threads to show a debugger."""

    language: Language

    def boot(self) -> None:
        """Power on: start what starts by itself (once, before the first cycle).
        LanguageInputError for a start the program refuses."""

    @property
    def fault_count(self) -> int:
        """Faults of its tasks, drive tasks or procedures so far."""
        return 0

    def scope_sources(self) -> list[ChannelSource]:
        """Its scope channels (its variables), in the order they are offered."""
        return []

    def takes_scenario(self) -> bool:
        """Whether a scenario's entries the machine does not know may be its own."""
        return False

    def take_scenario_entry(self, entry: ScenarioEntry) -> bool:
        """Take one [initial] entry or event the machine did not know: True if it is
        this language's (its problems added to `entry.problems`), False if not."""
        return False

    def scenario_loaded(self, until: float | None) -> None:
        """Every entry of the scenario was offered; `until` is its end time (or None)."""

    def end_time(self, end: float | None) -> float | None:
        """The end time [s] to give the controller for a run asked to end at `end`."""
        return end

    def finish(self) -> None:
        """After the run: notes of what never happened."""

    def on_event(self, callback: Callable[[str, object], None]) -> None:
        """Call `callback(kind, payload)` for each event the program sends (default: none)."""

    def builtin_names(self) -> frozenset[str]:
        """The built-ins a host may `call` (default: none)."""
        return frozenset()

    def call(self, name: str, args: Sequence[object]) -> object:
        """Call built-in `name` from the host, between cycles, with the checks and
        argument conversions of a program's call; its value (see the language's
        run side). CallError if it cannot be called."""
        raise CallError(f"{self.language.name} has no built-ins to call")

    def close(self) -> None:
        """Free its memory; nothing runs afterwards."""

    # ---------------------------------------------------------------- debugging

    def debug_threads(self) -> list[DebugThread]:
        """Its tasks that run now (a suspended generator each)."""
        return []

    def thread_of(self, root) -> DebugThread | None:
        """The thread whose outermost frame of the user's code is `root` (a Python frame
        running now), None if it is not this language's."""
        for thread in self.debug_threads():
            gen = thread.generator
            if gen is not None and getattr(gen, "gi_frame", None) is root:
                return thread
        return None

    def frame_variables(self, frame) -> dict[str, object]:
        """The user's local variables of a frame of generated code, by their names in the
        source."""
        return {k: v for k, v in frame.f_locals.items() if not k.startswith("_")}

    def global_variables(self, frame) -> dict[str, object]:
        """The user's global variables seen from a frame, by their names in the source."""
        return {}

    def global_channel(self, frame, name: str) -> str:
        """The run's name (a scope channel, what `Variables` writes) of the global `name`
        seen from `frame`: the name itself unless the language qualifies it."""
        return name

    def variable(self, frame, name: str) -> object:
        """One variable seen from a frame: a local, else a global (KeyError: neither)."""
        local = self.frame_variables(frame)
        if name in local:
            return local[name]
        return self.global_variables(frame)[name]


_LITERAL = re.compile(r"-?0[xX][0-9A-Fa-f]+|-?\d+")


def visible_completions(index: SourceIndex, line: int, col: int) -> list[Completion]:
    """A completion of each declaration of `index` visible at 1-based (line, col): file
    level ones, and the locals and parameters of the function around it declared before."""
    scope = index.enclosing(line, ("function", "procedure"))
    out = []
    seen = set()
    for s in index.symbols:
        if s.kind in ("member", "task"):
            continue
        if s.container is not None and s.kind not in ("object", "procedure"):
            if scope is None or s.container != scope.name:
                continue
            if s.kind not in ("parameter", "label") and (
                (s.line, s.col) > (line, col) or (s.end_line and line > s.end_line)
            ):
                continue
        if (s.name, s.kind) in seen:
            continue
        seen.add((s.name, s.kind))
        snippet = (
            snippet_of(s.name, s.detail) if s.kind in ("function",) and "(" in s.detail else ""
        )
        out.append(Completion(s.name, s.kind, s.detail, snippet))
    return out


class Language:
    """One language of motionvm (see the module docstring); subclassed once per language."""

    name: str = ""
    """"HMPL", "PDL", "GDL"."""
    language_id: str = ""
    """The editor's language id ("hmpl")."""
    suffixes: tuple[str, ...] = ()
    """File suffixes, lower case, with the dot."""
    stages: tuple[str, ...] = ("tokens", "ast", "py")
    """What `dump` shows."""
    accepts_text: bool = False
    """A program may be given as text instead of a file."""
    places_tasks: bool = False
    """Files run as numbered tasks (`Source.task`)."""
    options: tuple[LanguageOption, ...] = ()
    run_modules: tuple[str, ...] = ()
    """The modules of its compiler and run side, which a worker process imports before
    the clock of a run starts."""
    directive_comment: tuple[str, str] = ("//", "")
    """How a one-line comment opens and closes ("": at the end of the line): the comments
    that hold the expectations of a test case (`// expect: 42`, `| expect: 42 |`)."""
    links_files: bool = False
    """Several files form one program, linked in the order given (a test case `X` links
    its companions `X.NAME<suffix>` after it)."""
    case_toml_option: str = "--machine"
    """What a test case's `X.toml` beside `X<suffix>` is: `--machine` or `--scenario`."""

    # ---------------------------------------------------------------- compiling

    def has_programs(self, sources: Sequence[Source], machine: MachineConfig) -> bool:
        """Whether a run has anything of this language: files, or programs the machine
        names."""
        return bool(sources)

    def place(
        self, machine: MachineConfig, sources: Sequence[Source], request: CompileRequest
    ) -> MachineConfig:
        """The machine with this language's files placed on it (default: unchanged).
        LanguageInputError if they cannot be."""
        return machine

    def compile(self, sources: Sequence[Source], request: CompileRequest) -> CompileResult:
        raise NotImplementedError

    def check(self, sources: Sequence[Source]) -> list[Diagnostic]:
        """The diagnostics of `sources`, each file on its own; nothing runs."""
        from motionvm.sim.machine import DEFAULT_MACHINE

        request = CompileRequest(DEFAULT_MACHINE, check_only=True, alone=True)
        machine = self.place(DEFAULT_MACHINE, sources, request)
        request = CompileRequest(machine, check_only=True, alone=True)
        return self.compile(sources, request).diagnostics

    def dump(
        self, path: str, stage: str, options: Mapping[str, Any]
    ) -> tuple[str, list[Diagnostic]]:
        """What compiler stage `stage` (one of `stages`) makes of the file: the text to
        print ("" after errors) and the diagnostics."""
        raise NotImplementedError

    def python_source(self, program: object) -> str:
        """The generated Python of a compiled program (`ast.unparse`)."""
        return program.python_source()  # type: ignore[attr-defined]

    # ---------------------------------------------------------------- running

    def attach(self, controller, program: object, context: RunContext) -> RunSide:
        """The run side of `program` on `controller`, added to its cycle.
        LanguageInputError for options or a machine it cannot run with."""
        raise NotImplementedError

    # ---------------------------------------------------------------- tools

    def line_table(self, path: str, text: str | None = None) -> LineTable:
        """The statement lines of a file (`text`: its unsaved contents)."""
        raise NotImplementedError

    def symbols(self, path: str, text: str | None = None) -> list[Symbol]:
        """The declarations of a file, in source order."""
        raise NotImplementedError

    def docs(self) -> Mapping[str, NameDoc]:
        """The language's documented names (built-ins, constants, keywords) by name."""
        return {}

    # ---------------------------------------------------------------- editing

    fold_case: bool = False
    """Names are case-insensitive."""

    def index(self, path: str, text: str) -> SourceIndex:
        """Every name of a file's text resolved to its declaration. Default: the name
        tokens are the words of `symbols`' names, resolved by scope (`index.resolve`)."""
        from motionvm.lang.index import words

        symbols = self.symbols(path, text)
        names = {self._key(s.name) for s in symbols}
        found = [w for w in words(text) if self._key(w[0]) in names]
        return resolve(path, text, symbols, found, fold=self.fold_case)

    def _key(self, name: str) -> str:
        return name.lower() if self.fold_case else name

    def doc_of(self, name: str) -> NameDoc | None:
        """The documentation of a name of the language (`docs`), case folded if names are."""
        docs = self.docs()
        found = docs.get(name)
        if found is None and self.fold_case:
            found = docs.get(name.upper()) or docs.get(name.lower())
        return found

    def literal_doc(self, word: str) -> str | None:
        """Markdown about a literal (an error code), or None."""
        return None

    def hover(self, index: SourceIndex, line: int, col: int) -> str | None:
        """Markdown about what is under 1-based (line, col): a declaration as written, a
        documented name, a literal; None: nothing to say."""
        occ = index.at(line, col)
        if occ is not None and occ.symbol is not None:
            s = occ.symbol
            where = f" (in {s.container})" if s.container else ""
            return f"```\n{s.detail or s.name}\n```\n\n{s.kind}{where}, line {s.line}"
        text = index.line_text(line)
        lit = word_at(text, col, _LITERAL)
        if lit is not None:
            said = self.literal_doc(lit[0])
            if said:
                return said
        w = word_at(text, col)
        if w is None:
            return None
        doc = self.doc_of(w[0])
        return doc.markdown() if doc is not None else None

    def inside_comment_or_literal(self, text: str, offset: int) -> bool:
        """Whether character `offset` of `text` lies inside a comment or a string (or
        another literal) of this language: an editor offers no completion there.
        Default: never."""
        return False

    def completions(self, index: SourceIndex, line: int, col: int) -> list[Completion]:
        """What may be written at 1-based (line, col). Default: the documented names and
        the file's declarations visible there."""
        return self.doc_completions() + visible_completions(index, line, col)

    def doc_completions(self) -> list[Completion]:
        """A completion of each documented name (built-ins with a snippet of their
        arguments)."""
        out = []
        for doc in self.docs().values():
            kind = {"builtin": "function", "type": "type", "error": "constant"}.get(
                doc.kind, doc.kind
            )
            snippet = snippet_of(doc.name, doc.signature) if doc.kind == "builtin" else ""
            out.append(Completion(doc.name, kind, doc.signature, snippet, doc.markdown()))
        return out

    def signature(self, index: SourceIndex, line: int, col: int) -> tuple[Signature, int] | None:
        """The call around 1-based (line, col): the callee's signature and the index of the
        argument being written; None outside a call of a known function."""
        call = call_at(index.lines, line, col)
        if call is None:
            return None
        name, arg = call
        doc = self.doc_of(name)
        if doc is not None and doc.signature and "(" in doc.signature:
            return Signature(doc.signature, param_spans(doc.signature), doc.summary), arg
        for s in index.symbols:
            if self._key(s.name) == self._key(name) and s.kind in ("function", "procedure"):
                label = s.detail or s.name
                return Signature(label, param_spans(label)), arg
        return None

    def token_end(self, line_text: str, col: int) -> int:
        """1-based column just after the token at 1-based `col` (a diagnostic's range)."""
        return token_end(line_text, col)

    def __repr__(self) -> str:
        return f"<language {self.name}>"
