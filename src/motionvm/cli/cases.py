"""Test cases of `motionvm test`: which files are cases, what they expect, how they run.

A case is one program file (`X.hmpl`, `X.pdl` or `X.gdl`; a stem without a dot) that
carries expectations, either

- `X.out` beside it: the exact expected stdout (and exit code 0, or 1 with `expect
  runtime error:` directives); or
- inline directives in its comments (the comment form of its language: `// ...` in
  HMPL and PDL, `| ... |` on one line in GDL), in the program and its companion files:

  `expect: LINE`               the next stdout line is exactly LINE
  `expect regex: PATTERN`      the next stdout line fully matches the regex PATTERN
  `expect runtime error: TEXT` the run exits 1 and the next runtime error it reports
                               (a stderr line `FILE:LINE:COL: runtime error in ...`)
                               contains TEXT; the run may report no runtime error that
                               is not expected
  `error: [FILE:]LINE:COL: TEXT`  a compile error there whose message contains TEXT
                               (exit 2, nothing runs); FILE defaults to the file
                               that holds the comment
  `warning: [FILE:]LINE:COL: TEXT`  a compile warning there whose message contains TEXT
  `diagnostics: exact`         the listed errors and warnings are every diagnostic the
                               compile reports, and each message is exactly its TEXT
  `check:`                     compile only (`motionvm check`), nothing runs; without
                               `error:` the program must compile, and without any
                               `error:` or `warning:` with no diagnostic at all
  `args: ARG...`               extra `motionvm run` options (shell quoting), e.g. --until 2
  `task N: FILE`               HMPL: FILE runs as task N (the program is task 0);
                               these directives replace the `X.taskK.hmpl` files
  `restart: FILE`              after the run, the controller starts again with FILE as
                               its only task (a power cycle: same data folder, same
                               `args:`); the stdout of both runs is compared as one and
                               each run must end with the expected exit code
  `pending: REASON`            the program needs what motionvm cannot do yet: the case
                               is expected to fail (reported `x`), and fails once it passes

A comment that looks like a directive but does not parse (`expected:`, `error: 12: x`)
makes the case an error, so a misspelt expectation is never silently ignored.

Run inputs follow the file names (the program's folder is the working directory):
`X.taskK.hmpl` (K = 1, 2, ...) are the tasks after an HMPL program; `X.toml` is the
machine file (`--machine`) of an HMPL or PDL program and the scenario (`--scenario`) of
a GDL program; `X.NAME.gdl` files are a GDL application linked after the program;
`X.scenario.toml` is the scenario of an HMPL or PDL program (shared with that
application, if any); `X.NAME.pdl` files are programs the machine file puts on drives.
Files whose stem has a dot are never cases of their own.
"""

from __future__ import annotations

import glob
import re
import shlex
from dataclasses import dataclass, field
from pathlib import Path

from motionvm.cli.directives import CaseError, Directive, comment_form, directives
from motionvm.lang import LANGUAGES, language_of, suffixes

PROGRAM_SUFFIXES = suffixes()
_ERROR_AT = re.compile(r"(?:(?P<file>[^:\s]+):)?(?P<line>\d+):(?P<col>\d+): (?P<text>.+)")

__all__ = ["Case", "CaseError", "CollectError", "Expectations", "collect", "make_case"]


@dataclass(frozen=True)
class Expectations:
    """What a case asks of its run."""

    stdout: tuple[tuple[str, str], ...] = ()
    """Expected stdout lines in order: ('text', LINE) or ('regex', PATTERN)."""
    stdout_file: str | None = None
    """The `.out` file whose text is the exact stdout (then `stdout` is empty)."""
    stdout_text: str = ""
    """The text of `stdout_file`."""
    runtime_errors: tuple[str, ...] = ()
    """Texts of the runtime errors the run reports, in order; no other is allowed."""
    compile_errors: tuple[tuple[str, int, int, str], ...] = ()
    """(file, line, col, text) of each expected compile error."""
    warnings: tuple[tuple[str, int, int, str], ...] = ()
    """(file, line, col, text) of each expected compile warning."""
    exact_diagnostics: bool = False
    """The listed errors and warnings are all there are, their texts whole messages."""

    @property
    def exit_code(self) -> int:
        if self.compile_errors:
            return 2
        return 1 if self.runtime_errors else 0


@dataclass(frozen=True)
class Case:
    """One program with expectations, ready to run: `motionvm COMMAND ARGV` in `folder`."""

    id: str
    """The case's name in reports: its path as given, `/`-separated."""
    folder: str
    """Absolute path of the working directory of the run."""
    argv: tuple[str, ...]
    """The arguments after `motionvm COMMAND`."""
    expect: Expectations = field(default_factory=Expectations)
    problem: str | None = None
    """Why the case cannot run (a malformed directive): it is reported as an error."""
    command: str = "run"
    """`run`, or `check` (compile only)."""
    restart: tuple[str, ...] = ()
    """The arguments of a second `motionvm run` after a power cycle (empty: none)."""
    pending: str | None = None
    """Why the case is expected to fail (None: it must pass)."""


def is_case_file(path: Path) -> bool:
    """A program whose stem has no dot (`X.task1.hmpl`, `X.cell.gdl` are companions)."""
    return path.suffix in PROGRAM_SUFFIXES and "." not in path.stem


def _natural(path: Path) -> tuple:
    return tuple(int(s) if s.isdigit() else s for s in re.split(r"(\d+)", path.name))


def task_files(program: Path) -> list[str]:
    """The task files `X.task1<suffix>`, `X.task2<suffix>`, ... of a program whose language
    places files as tasks, in task order."""
    lang = language_of(program)
    if lang is None or not lang.places_tasks:
        return []
    pattern = re.compile(rf"{re.escape(program.stem)}\.task(\d+){re.escape(program.suffix)}")
    found = {}
    for p in program.parent.iterdir():
        m = pattern.fullmatch(p.name)
        if m:
            found[int(m.group(1))] = p.name
    numbers = sorted(found)
    if numbers != list(range(1, len(numbers) + 1)):
        raise CaseError(f"{program.name}: task files must be numbered 1, 2, ...: {numbers}")
    return [found[n] for n in numbers]


def linked_files(program: Path) -> list[str]:
    """The files `X.NAME<suffix>` of the languages that link several files into one program
    (a GDL application), passed after the program, in natural order."""
    return [
        p.name
        for lang in LANGUAGES
        if lang.links_files
        for suffix in lang.suffixes
        for p in sorted(program.parent.glob(f"{glob.escape(program.stem)}.*{suffix}"), key=_natural)
    ]


def run_arguments(program: Path) -> list[str]:
    """The `motionvm run` arguments of a program given by its file names (in its folder)."""
    lang = language_of(program)
    argv = [program.name, *task_files(program)]
    toml_option = lang.case_toml_option if lang is not None else "--machine"
    toml = program.with_suffix(".toml")
    if toml.is_file():
        argv += [toml_option, toml.name]
    argv += linked_files(program)
    scenario = program.with_name(f"{program.stem}.scenario.toml")
    if toml_option != "--scenario" and scenario.is_file():
        argv += ["--scenario", scenario.name]
    return argv


@dataclass
class _Found:
    """The directives of a program and its companions, gathered."""

    stdout: list[tuple[str, str]] = field(default_factory=list)
    runtime: list[str] = field(default_factory=list)
    errors: list[tuple[str, int, int, str]] = field(default_factory=list)
    warnings: list[tuple[str, int, int, str]] = field(default_factory=list)
    exact: bool = False
    check: bool = False
    options: list[str] = field(default_factory=list)
    tasks: dict[int, str] = field(default_factory=dict)
    restart: str | None = None
    pending: str | None = None

    def take(self, d: Directive) -> None:
        """Add one directive; CaseError if it is malformed or repeated."""
        where, value = d.where, d.text
        if d.kind == "expect":
            self.stdout.append(("text", value))
        elif d.kind == "expect regex":
            try:
                re.compile(value)
            except re.error as exc:
                raise CaseError(f"{where}: bad regex {value!r}: {exc}") from None
            self.stdout.append(("regex", value))
        elif d.kind == "expect runtime error":
            if not value.strip():
                raise CaseError(f"{where}: empty runtime error expectation")
            self.runtime.append(" ".join(value.split()))
        elif d.kind in ("error", "warning"):
            m = _ERROR_AT.fullmatch(value.strip())
            if m is None:
                raise CaseError(f"{where}: want '{d.kind}: [FILE:]LINE:COL: TEXT', got {value!r}")
            at = (m.group("file") or d.file, int(m.group("line")), int(m.group("col")))
            text = " ".join(m.group("text").split())
            (self.errors if d.kind == "error" else self.warnings).append((*at, text))
        elif d.kind == "diagnostics":
            if value.strip() != "exact":
                raise CaseError(f"{where}: want 'diagnostics: exact', got {value!r}")
            self.exact = True
        elif d.kind == "check":
            self.check = True
        elif d.kind == "args":
            try:
                self.options += shlex.split(value)
            except ValueError as exc:
                raise CaseError(f"{where}: bad args {value!r}: {exc}") from None
        elif d.kind == "restart":
            if self.restart is not None or not value.strip():
                raise CaseError(f"{where}: bad or repeated restart directive")
            self.restart = value.strip()
        elif d.kind == "pending":
            self.pending = value.strip() or "pending"
        else:
            n = int(d.task or 0)
            if n == 0 or n in self.tasks or not value.strip():
                raise CaseError(f"{where}: bad or repeated task directive")
            self.tasks[n] = value.strip()

    def has_expectations(self) -> bool:
        return bool(self.stdout or self.runtime or self.errors or self.warnings or self.check)


def _gather(program: Path) -> _Found:
    found = _Found()
    files = [program] + [program.with_name(n) for n in linked_files(program)]
    for path in files:
        text = path.read_text(encoding="utf-8", errors="replace")
        for d in directives(text, path.name, comment_form(path)):
            found.take(d)
    return found


def expectations_of(program: Path) -> tuple[Expectations, list[str], dict[int, str]] | None:
    """(expectations, extra options, explicit tasks) of a program; None: it is no case.

    Raises CaseError for a malformed directive."""
    found = _gather(program)
    exp = _expectations(program, found)
    return None if exp is None else (exp, found.options, found.tasks)


def _expectations(program: Path, found: _Found) -> Expectations | None:
    """The expectations of the gathered directives and `X.out`; None: no case."""
    name = program.name
    if found.errors and (found.stdout or found.runtime):
        raise CaseError(f"{name}: a program with compile errors cannot expect output")
    if found.check and (found.stdout or found.runtime or found.restart):
        raise CaseError(f"{name}: a 'check:' program does not run: it cannot expect output")
    out_file = program.with_suffix(".out")
    diagnostics = dict(
        compile_errors=tuple(found.errors),
        warnings=tuple(found.warnings),
        # a `check:` case that lists no diagnostic must compile without any
        exact_diagnostics=found.exact or (found.check and not found.errors + found.warnings),
    )
    if out_file.is_file():
        if found.stdout or found.errors or found.check:
            raise CaseError(
                f"{name}: both {out_file.name} and inline stdout, error or check expectations"
            )
        return Expectations(
            stdout_file=out_file.name,
            stdout_text=out_file.read_text(encoding="utf-8"),
            runtime_errors=tuple(found.runtime),
            **diagnostics,
        )
    if found.has_expectations():
        return Expectations(
            stdout=tuple(found.stdout), runtime_errors=tuple(found.runtime), **diagnostics
        )
    return None


def _task_arguments(tasks: dict[int, str]) -> list[str]:
    numbers = sorted(tasks)
    if numbers == list(range(1, len(numbers) + 1)):
        return [tasks[n] for n in numbers]
    return [arg for n in numbers for arg in ("--task", f"{n}={tasks[n]}")]


def make_case(program: Path, case_id: str) -> Case | None:
    """The case of one program file (None: it carries no expectation)."""
    folder = str(program.parent.resolve())
    try:
        found = _gather(program)
        exp = _expectations(program, found)
        if exp is None:
            return None
        argv = run_arguments(program)
        if found.tasks:  # `task N:` directives name the tasks; they replace X.taskK.hmpl
            auto = set(task_files(program))
            argv = [argv[0], *_task_arguments(found.tasks), *(a for a in argv[1:] if a not in auto)]
    except (CaseError, OSError) as exc:
        return Case(case_id, folder, (), problem=str(exc))
    restart = (*found.options, found.restart) if found.restart else ()
    return Case(
        case_id,
        folder,
        (*found.options, *argv),
        exp,
        command="check" if found.check else "run",
        restart=restart,
        pending=found.pending,
    )


class CollectError(Exception):
    """A path given to `motionvm test` that does not exist or is no program."""


def _display(path: Path) -> str:
    try:
        return path.resolve().relative_to(Path.cwd().resolve()).as_posix()
    except ValueError:
        return path.as_posix()


def collect(paths: list[str], base: Path | None = None) -> list[Case]:
    """Every case under `paths` (files or folders, recursively), sorted by id. Ids are
    paths relative to `base` (default: the working directory, where it contains them)."""
    programs: dict[str, Path] = {}

    def display(f: Path) -> str:
        if base is None:
            return _display(f)
        return f.resolve().relative_to(base.resolve()).as_posix()

    for given in paths:
        p = Path(given)
        if p.is_dir():
            for f in p.rglob("*"):
                if f.is_file() and is_case_file(f) and not _hidden(f.relative_to(p)):
                    programs[display(f)] = f
        elif p.is_file():
            if not is_case_file(p):
                raise CollectError(
                    f"{given}: not a program (want X.hmpl, X.pdl or X.gdl; a stem with a "
                    "dot is a companion file)"
                )
            programs[display(p)] = p
        else:
            raise CollectError(f"{given}: no such file or folder")
    cases = [make_case(programs[i], i) for i in sorted(programs)]
    return [c for c in cases if c is not None]


def _hidden(rel: Path) -> bool:
    """Skip hidden folders and virtual environments (`.git`, `.venv`, `__pycache__`)."""
    return any(part.startswith((".", "__")) for part in rel.parts[:-1])
