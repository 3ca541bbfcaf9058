"""Test cases of `motionvm test`: which files are cases, what they expect, how they run.

A case is one program file (`X.hmpl`, `X.pdl` or `X.gdl`; a stem without a dot) that
carries expectations, either

- `X.out` beside it: the exact expected stdout, and exit code 0; or
- inline directives in its comments (`//` in HMPL and PDL, `| ... |` in GDL):

  `expect: LINE`               the next stdout line is exactly LINE
  `expect regex: PATTERN`      the next stdout line fully matches the regex PATTERN
  `expect runtime error: TEXT` the run exits 1 and a stderr line contains TEXT
  `error: [FILE:]LINE:COL: TEXT`  a compile error there whose message contains TEXT
                               (exit 2, nothing runs); FILE defaults to the file
                               that holds the comment
  `args: ARG...`               extra `motionvm run` options (shell quoting), e.g. --until 2
  `task N: FILE`               HMPL: FILE runs as task N (the program is task 0);
                               these directives replace the `X.taskK.hmpl` files

Run inputs follow the file names (the program's folder is the working directory):
`X.taskK.hmpl` (K = 1, 2, ...) are the tasks after an HMPL program; `X.toml` is the
machine file (`--machine`) of an HMPL or PDL program and the scenario (`--scenario`) of
a GDL program; `X.NAME.gdl` files are a GDL application linked after the program;
`X.scenario.toml` is the scenario of an HMPL program (shared with that application, if
any); `X.NAME.pdl` files are
programs the machine file puts on drives. Files whose stem has a dot are never cases of
their own.
"""

from __future__ import annotations

import re
import shlex
from dataclasses import dataclass, field
from pathlib import Path

PROGRAM_SUFFIXES = (".hmpl", ".pdl", ".gdl")

_KINDS = r"expect regex|expect runtime error|expect|error|args|task\s+(?P<task>\d+)"
_SLASH = re.compile(rf"//\s*(?P<kind>{_KINDS}):(?: (?P<text>.*)|$)")
_BAR = re.compile(rf"\|\s*(?P<kind>{_KINDS}):(?: (?P<text>.*?))?\s*\|")
_ERROR_AT = re.compile(r"(?:(?P<file>[^:\s]+):)?(?P<line>\d+):(?P<col>\d+): (?P<text>.+)")


class CaseError(Exception):
    """A case that cannot run as written: a malformed directive, a missing task file."""


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
    compile_errors: tuple[tuple[str, int, int, str], ...] = ()
    """(file, line, col, text) of each expected compile error."""

    @property
    def exit_code(self) -> int:
        if self.compile_errors:
            return 2
        return 1 if self.runtime_errors else 0


@dataclass(frozen=True)
class Case:
    """One program with expectations, ready to run: `motionvm run ARGV` in `folder`."""

    id: str
    """The case's name in reports: its path as given, `/`-separated."""
    folder: str
    """Absolute path of the working directory of the run."""
    argv: tuple[str, ...]
    """The arguments after `motionvm run`."""
    expect: Expectations = field(default_factory=Expectations)
    problem: str | None = None
    """Why the case cannot run (a malformed directive): it is reported as an error."""


def is_case_file(path: Path) -> bool:
    """A program whose stem has no dot (`X.task1.hmpl`, `X.cell.gdl` are companions)."""
    return path.suffix in PROGRAM_SUFFIXES and "." not in path.stem


def _directives(path: Path) -> list[tuple[int, str, str, str | None]]:
    """(line, kind, text, task number) of every directive in the comments of `path`."""
    pattern = _BAR if path.suffix == ".gdl" else _SLASH
    out = []
    text = path.read_text(encoding="utf-8", errors="replace")
    for lineno, line in enumerate(text.splitlines(), 1):
        for m in pattern.finditer(line):
            kind = " ".join(m.group("kind").split())
            out.append((lineno, kind, m.group("text") or "", m.group("task")))
            if pattern is _SLASH:
                break  # `//` runs to the end of the line
    return out


def _natural(path: Path) -> tuple:
    return tuple(int(s) if s.isdigit() else s for s in re.split(r"(\d+)", path.name))


def task_files(program: Path) -> list[str]:
    """An HMPL program's task files `X.task1.hmpl`, `X.task2.hmpl`, ... in task order."""
    if program.suffix != ".hmpl":
        return []
    pattern = re.compile(rf"{re.escape(program.stem)}\.task(\d+)\.hmpl")
    found = {}
    for p in program.parent.iterdir():
        m = pattern.fullmatch(p.name)
        if m:
            found[int(m.group(1))] = p.name
    numbers = sorted(found)
    if numbers != list(range(1, len(numbers) + 1)):
        raise CaseError(f"{program.name}: task files must be numbered 1, 2, ...: {numbers}")
    return [found[n] for n in numbers]


def gdl_companions(program: Path) -> list[str]:
    """The GDL files `X.NAME.gdl` linked after the program, in natural order."""
    return [p.name for p in sorted(program.parent.glob(f"{program.stem}.*.gdl"), key=_natural)]


def run_arguments(program: Path) -> list[str]:
    """The `motionvm run` arguments of a program given by its file names (in its folder)."""
    argv = [program.name, *task_files(program)]
    toml = program.with_suffix(".toml")
    if toml.is_file():
        argv += ["--scenario" if program.suffix == ".gdl" else "--machine", toml.name]
    more = gdl_companions(program)
    argv += more
    scenario = program.with_name(f"{program.stem}.scenario.toml")
    if program.suffix == ".hmpl" and scenario.is_file():
        argv += ["--scenario", scenario.name]
    return argv


def expectations_of(program: Path) -> tuple[Expectations, list[str], dict[int, str]] | None:
    """(expectations, extra options, explicit tasks) of a program; None: it is no case.

    Raises CaseError for a malformed directive."""
    stdout: list[tuple[str, str]] = []
    runtime: list[str] = []
    compile_errors: list[tuple[str, int, int, str]] = []
    options: list[str] = []
    tasks: dict[int, str] = {}
    files = [program] + [program.with_name(n) for n in gdl_companions(program)]
    for path in files:
        for lineno, kind, value, task in _directives(path):
            where = f"{path.name}:{lineno}"
            if kind == "expect":
                stdout.append(("text", value))
            elif kind == "expect regex":
                try:
                    re.compile(value)
                except re.error as exc:
                    raise CaseError(f"{where}: bad regex {value!r}: {exc}") from None
                stdout.append(("regex", value))
            elif kind == "expect runtime error":
                if not value.strip():
                    raise CaseError(f"{where}: empty runtime error expectation")
                runtime.append(" ".join(value.split()))
            elif kind == "error":
                m = _ERROR_AT.fullmatch(value.strip())
                if m is None:
                    raise CaseError(f"{where}: want 'error: [FILE:]LINE:COL: TEXT', got {value!r}")
                compile_errors.append(
                    (
                        m.group("file") or path.name,
                        int(m.group("line")),
                        int(m.group("col")),
                        " ".join(m.group("text").split()),
                    )
                )
            elif kind == "args":
                try:
                    options += shlex.split(value)
                except ValueError as exc:
                    raise CaseError(f"{where}: bad args {value!r}: {exc}") from None
            else:
                n = int(task or 0)
                if n == 0 or n in tasks or not value.strip():
                    raise CaseError(f"{where}: bad or repeated task directive")
                tasks[n] = value.strip()
    out_file = program.with_suffix(".out")
    if compile_errors and (stdout or runtime):
        raise CaseError(f"{program.name}: a program with compile errors cannot expect output")
    if out_file.is_file():
        if stdout or compile_errors:
            raise CaseError(
                f"{program.name}: both {out_file.name} and inline stdout or error expectations"
            )
        exp = Expectations(
            stdout_file=out_file.name,
            stdout_text=out_file.read_text(encoding="utf-8"),
            runtime_errors=tuple(runtime),
        )
    elif stdout or runtime or compile_errors:
        exp = Expectations(
            stdout=tuple(stdout),
            runtime_errors=tuple(runtime),
            compile_errors=tuple(compile_errors),
        )
    else:
        return None
    return exp, options, tasks


def _task_arguments(tasks: dict[int, str]) -> list[str]:
    numbers = sorted(tasks)
    if numbers == list(range(1, len(numbers) + 1)):
        return [tasks[n] for n in numbers]
    return [arg for n in numbers for arg in ("--task", f"{n}={tasks[n]}")]


def make_case(program: Path, case_id: str) -> Case | None:
    """The case of one program file (None: it carries no expectation)."""
    folder = str(program.parent.resolve())
    try:
        found = expectations_of(program)
        if found is None:
            return None
        exp, options, tasks = found
        argv = run_arguments(program)
        if tasks:  # `task N:` directives name the tasks; they replace X.taskK.hmpl files
            auto = set(task_files(program))
            argv = [argv[0], *_task_arguments(tasks), *(a for a in argv[1:] if a not in auto)]
    except (CaseError, OSError) as exc:
        return Case(case_id, folder, (), problem=str(exc))
    return Case(case_id, folder, (*options, *argv), exp)


class CollectError(Exception):
    """A path given to `motionvm test` that does not exist or is no program."""


def _display(path: Path) -> str:
    try:
        return path.resolve().relative_to(Path.cwd().resolve()).as_posix()
    except ValueError:
        return path.as_posix()


def collect(paths: list[str]) -> list[Case]:
    """Every case under `paths` (files or folders, recursively), sorted by id."""
    programs: dict[str, Path] = {}
    for given in paths:
        p = Path(given)
        if p.is_dir():
            for f in p.rglob("*"):
                if f.is_file() and is_case_file(f) and not _hidden(f.relative_to(p)):
                    programs[_display(f)] = f
        elif p.is_file():
            if not is_case_file(p):
                raise CollectError(
                    f"{given}: not a program (want X.hmpl, X.pdl or X.gdl; a stem with a "
                    "dot is a companion file)"
                )
            programs[_display(p)] = p
        else:
            raise CollectError(f"{given}: no such file or folder")
    cases = [make_case(programs[i], i) for i in sorted(programs)]
    return [c for c in cases if c is not None]


def _hidden(rel: Path) -> bool:
    """Skip hidden folders and virtual environments (`.git`, `.venv`, `__pycache__`)."""
    return any(part.startswith((".", "__")) for part in rel.parts[:-1])
