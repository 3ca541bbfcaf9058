"""The command line's grammar: subcommands and options of `motionvm` (argparse)."""

from __future__ import annotations

import argparse
import math
import re

from motionvm import __version__, compiled_build
from motionvm.cli.exits import EXIT_CODES_HELP

_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?|[-+]?(?:inf|nan)"
_DURATION = re.compile(rf"\s*({_NUMBER})\s*([a-z]*)\s*")
_UNITS = {"": (1, 1), "s": (1, 1), "ms": (1, 1000), "min": (60, 1), "h": (3600, 1)}
"""Unit -> (factor, divisor) to seconds: 350ms is 350 / 1000 = 0.35, not 350 * 0.001."""
DURATION_FORMS = "seconds (1.5), or a number with ms, s, min or h (150ms, 2s, 1min)"


def duration(text: str) -> float:
    """A duration option's value [s]: `1.5` (seconds), `150ms`, `2s`, `1min`, `1h`.

    argparse reports the ArgumentTypeError as `argument --until: MESSAGE` (exit 3)."""
    m = _DURATION.fullmatch(text.lower())
    if m is None:
        raise argparse.ArgumentTypeError(f"'{text}' is not a duration: expected {DURATION_FORMS}")
    if m.group(2) not in _UNITS:
        raise argparse.ArgumentTypeError(
            f"'{text}': unknown unit '{m.group(2)}' (expected ms, s, min or h, or none for seconds)"
        )
    factor, divisor = _UNITS[m.group(2)]
    seconds = float(m.group(1)) * factor / divisor
    if not math.isfinite(seconds) or seconds < 0:
        raise argparse.ArgumentTypeError(
            f"'{text}' is not a duration: a time must be finite and non-negative"
        )
    return seconds


def port(text: str) -> int:
    """A TCP port option's value, 0..65535 (0: a free port); argparse reports the
    ArgumentTypeError as `argument --port: MESSAGE` (exit 3)."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a port number") from None
    if not 0 <= value <= 65535:
        raise argparse.ArgumentTypeError(f"{value}: a port is 0..65535")
    return value


class _Formatter(argparse.HelpFormatter):
    """Help whose descriptions are wrapped but whose tables (text of several lines, as
    the exit codes of the epilog) are kept as written."""

    def __init__(self, prog: str) -> None:
        super().__init__(prog, max_help_position=30)

    def _fill_text(self, text: str, width: int, indent: str) -> str:
        if "\n" in text:
            return "".join(indent + line for line in text.splitlines(keepends=True))
        return super()._fill_text(text, width, indent)


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="motionvm",
        description="A virtual motion controller for HMPL, PDL and GDL programs.",
        epilog=EXIT_CODES_HELP
        + "\n\n'motionvm COMMAND --help' describes each command's files and options.",
        formatter_class=_Formatter,
    )
    p.add_argument(
        "--version",
        action="version",
        version=f"motionvm {__version__} (motion cycle: {compiled_build.STATUS})",
        help="print the version, and whether the motion cycle runs compiled, and exit",
    )
    sub = p.add_subparsers(dest="cmd", required=True, metavar="COMMAND")
    r = sub.add_parser(
        "run",
        help="compile and run programs on the simulated machine",
        description="Compile every FILE, then run them on one simulated machine and clock. "
        "Program messages go to stdout, diagnostics to stderr.",
        epilog=EXIT_CODES_HELP,
        formatter_class=_Formatter,
    )
    r.add_argument("files", nargs="*", metavar="FILE", help=_FILES_HELP)
    _machine(r)
    r.add_argument(
        "--until",
        type=duration,
        metavar="TIME",
        help="run this long (simulated time: 1.5, 150ms, 2s, 1min); exit 0, with a note of "
        "what still ran",
    )
    r.add_argument(
        "--timeout",
        type=duration,
        metavar="TIME",
        help="a run that has not finished after this much simulated time fails (exit 124), "
        "naming where each task waits",
    )
    r.add_argument("--stamp", action="store_true", help=STAMP_HELP)
    _task(r)
    r.add_argument("--realtime", action="store_true", help="pace the simulation to the wall clock")
    r.add_argument(
        "--no-skip",
        action="store_true",
        help="step every cycle instead of jumping over idle ones (same output, slower)",
    )
    r.add_argument(
        "--no-progress",
        action="store_true",
        help="no progress bar (shown on a terminal's stderr when a run takes a while)",
    )
    _werror(r)
    _scenario(r)
    _cov_report(r)
    r.add_argument(
        "--scope",
        action="append",
        default=[],
        metavar="CH,CH,...",
        help="record channels each cycle: axis0.ref_pos, system_dtest0, gpo3, a global ...",
    )
    r.add_argument(
        "--scope-out",
        action="append",
        default=[],
        metavar="FILE",
        help="write the recording to FILE: .csv, .png, .svg or .vcd, or - for a .csv table on "
        "stdout after the run's messages (repeatable)",
    )
    r.add_argument("--scope-every", type=int, metavar="N", help="record every N cycles (default 1)")
    r.add_argument(
        "--scope-window",
        metavar="START:END",
        help="write only the samples from START to END seconds (either may be empty; 150ms)",
    )
    r.add_argument(
        "--start",
        action="append",
        default=[],
        metavar="LABEL",
        help="PDL: start a task at this label ('top' = the first statement); repeatable",
    )
    r.add_argument(
        "--force",
        action="append",
        default=[],
        metavar="'REF = V'",
        help="GDL: force a state variable with f access (repeatable)",
    )
    r.add_argument(
        "--shuffle-order",
        type=int,
        metavar="SEED",
        help="GDL: permute the order of procedures sharing an activator",
    )
    c = sub.add_parser(
        "check",
        help="compile only; report errors (exit 0 or 2)",
        description="Compile programs of any language without running them.",
        formatter_class=_Formatter,
    )
    c.add_argument("files", nargs="+", metavar="FILE", help=_FILES_HELP)
    _task(c)
    _werror(c)
    k = sub.add_parser(
        "compile",
        help="compile HMPL programs and show the generated Python",
        description="Compile HMPL tasks; with --emit-python print the Python they become.",
        formatter_class=_Formatter,
    )
    k.add_argument("files", nargs="+", metavar="FILE", help="HMPL files, tasks in the order given")
    k.add_argument("--emit-python", action="store_true", help="print the generated Python code")
    _task(k)
    _werror(k)
    _add_builtins_parser(sub)
    e = sub.add_parser(
        "errors",
        help="explain an HMPL error code (manual chapter 18)",
        description="The name and meaning of an error code a built-in returned; axis "
        "(0x83XXCCCC) and group (0x82XXCCCC) codes name their axis or group XX.",
        formatter_class=_Formatter,
    )
    e.add_argument(
        "code",
        nargs="?",
        metavar="CODE",
        help="hex (0x83000136), decimal (2197815606 or the signed -2097151690) or a name "
        "(eERR_AXIS_CMD_INVALID_STATE); none: list every code",
    )
    d = sub.add_parser(
        "dump",
        help="show a compiler stage: tokens, AST or generated Python",
        description="Print what one compiler stage makes of a file of any language.",
        formatter_class=_Formatter,
    )
    d.add_argument(
        "--stage",
        choices=["tokens", "ast", "py"],
        required=True,
        help="tokens (after preprocessing), ast (the syntax tree) or py (the generated Python)",
    )
    d.add_argument("file", metavar="FILE", help="a .hmpl, .pdl or .gdl file")
    d.add_argument(
        "--task-id",
        type=int,
        default=0,
        metavar="N",
        help="HMPL: the task id the preprocessor sees as _TASKID_ (default 0)",
    )
    s = sub.add_parser(
        "scope",
        help="list the scope channels a run of FILES offers",
        description="Compile FILES on the machine as 'run' would, without running them, and "
        "list every channel --scope can record, one per line with its unit.",
        formatter_class=_Formatter,
    )
    s.add_argument("--list", action="store_true", help="list the channels (the only action)")
    s.add_argument("files", nargs="*", metavar="FILE", help=_FILES_HELP)
    _machine(s)
    _scenario(s)
    _task(s)
    add_test_parser(sub)
    add_serve_parser(sub)
    add_lsp_parser(sub)
    add_debug_parser(sub)
    add_studio_parser(sub)
    return p


def add_lsp_parser(sub) -> None:
    """`motionvm lsp`: the language server (motionvm/lsp)."""
    s = sub.add_parser(
        "lsp",
        help="a Language Server Protocol server for editors (stdin/stdout, or --tcp PORT)",
        description="Serve the Language Server Protocol for .hmpl, .pdl and .gdl files: "
        "diagnostics as 'motionvm check' reports them, hover, completion, signature help, "
        "definition, references, rename and document symbols. Speaks on stdin/stdout "
        "unless --tcp is given.",
        formatter_class=_Formatter,
    )
    s.add_argument(
        "--tcp", type=port, metavar="PORT", help="listen on 127.0.0.1:PORT instead of stdin/stdout"
    )
    s.add_argument(
        "--stdio", action="store_true", help="speak on stdin/stdout (the default; editors pass it)"
    )


STAMP_HELP = (
    "prefix every stdout line with the simulated time and its source: [t=S.SSSSSS][task N], "
    "[t=...][drive A task N], [t=...][gdl PROC] (GDL's event trace: [t=...][gdl])"
)
_FILES_HELP = ".hmpl tasks (first = task 0), .pdl drive programs, .gdl application files"


def _add_builtins_parser(sub) -> None:
    b = sub.add_parser(
        "builtins",
        help="the HMPL built-ins: one described, or all listed with whether each is implemented",
        description="Without NAME, one line per built-in: name, implemented or not, manual "
        "section, prototype. With NAME, its purpose, parameters, return value and remarks. "
        "With a glob ('Move*') or a word that names no built-in (home), the built-ins it "
        "finds in names and purposes, the closest names first.",
        formatter_class=_Formatter,
    )
    b.add_argument(
        "name",
        nargs="?",
        metavar="NAME",
        help="describe this built-in (MoveAbs), or list those a glob ('Move*') or a word finds",
    )
    b.add_argument("--missing", action="store_true", help="only the built-ins not implemented")
    b.add_argument(
        "--chapter", type=int, metavar="N", help="only the built-ins of manual chapter N (2-21)"
    )
    b.add_argument("--json", action="store_true", help="print JSON instead of text")


def add_test_parser(sub) -> None:
    """`motionvm test`: run programs that carry expectations (see cli/cases.py)."""
    t = sub.add_parser(
        "test",
        help="run programs that carry expectations; report like pytest",
        formatter_class=_Formatter,
    )
    t.add_argument(
        "files", nargs="*", metavar="PATH", help="files or folders (default: the current folder)"
    )
    t.add_argument(
        "-k",
        metavar="EXPR",
        help="only cases whose path matches EXPR: words (contained in the path), and, or, "
        "not, parentheses ('(hmpl or pdl) and not slow')",
    )
    t.add_argument("-x", "--exitfirst", action="store_true", help="stop at the first failure")
    t.add_argument("-q", "--quiet", action="count", default=0, help="less output")
    t.add_argument("-v", "--verbose", action="count", default=0, help="one line per case")
    t.add_argument(
        "-j", "--jobs", type=int, metavar="N", help="worker processes (default: one per CPU)"
    )
    t.add_argument(
        "--case-timeout",
        type=duration,
        default=60.0,
        metavar="TIME",
        help="wall-clock time limit of one case (default 60 s; 90, 500ms, 2min)",
    )
    t.add_argument("--junitxml", metavar="FILE", help="also write a JUnit XML report")
    t.add_argument(
        "--lf",
        "--last-failed",
        dest="last_failed",
        action="store_true",
        help="only the cases that failed last time (all if none did); kept in "
        ".motionvm_cache/ in the current folder",
    )
    t.add_argument(
        "--repeat",
        type=int,
        default=1,
        metavar="N",
        help="run each case N times; a case whose runs print or exit differently fails "
        "(not deterministic); the results cache is not used",
    )
    t.add_argument(
        "--cache-clear",
        action="store_true",
        help="forget the stored results and last failures (.motionvm_cache/) first: "
        "every case runs",
    )
    t.add_argument(
        "--durations",
        type=int,
        metavar="N",
        help="list the N slowest cases (0: all) with their wall-clock times",
    )
    t.add_argument(
        "--collect-only",
        action="store_true",
        help="list the cases that would run, run none",
    )
    t.add_argument(
        "--update",
        action="store_true",
        help="rewrite each X.out file whose case's stdout differs with the actual stdout "
        "(when the run otherwise met its expectations)",
    )
    _cov_report(t)
    t.add_argument("--dask", metavar="ADDRESS", help="run the cases on the Dask cluster at ADDRESS")


def add_serve_parser(sub) -> None:
    """`motionvm serve`: a run paced to the wall clock with the TCP servers (cli/serve.py)."""
    s = sub.add_parser(
        "serve",
        help="run programs in real time with the TCP servers listening (Native/User ASCII, Modbus)",
        description="Compile every FILE and run them paced to the wall clock, with the "
        "Native ASCII, User ASCII and Modbus TCP servers listening on the machine file's "
        "[comm] address and ports (default 127.0.0.1: 3999, 4000, 502; port 0 picks a "
        "free port). Stops at --until or Ctrl-C.",
    )
    s.add_argument("files", nargs="*", metavar="FILE", help="program files (.hmpl, .pdl, .gdl)")
    _machine(s)
    s.add_argument(
        "--until", type=duration, metavar="TIME", help="stop after this much time (1.5, 2s, 1min)"
    )
    s.add_argument("--stamp", action="store_true", help=STAMP_HELP)
    s.add_argument(
        "--task",
        action="append",
        default=[],
        metavar="N=FILE",
        help="put the HMPL file FILE on task N (repeatable)",
    )
    _werror(s)


def _cov_report(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--cov-report",
        action="append",
        default=[],
        metavar="FORMAT:PATH",
        help="write the line and branch coverage of the programs: lcov:PATH (LCOV), "
        "xml:PATH (Cobertura) or json:PATH (repeatable)",
    )


def _machine(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--machine", metavar="FILE.toml", help="machine file (default: the built-in machine)"
    )


def _scenario(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--scenario", metavar="FILE.toml", help="a scenario file: timed input changes and faults"
    )


def _task(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--task",
        action="append",
        default=[],
        metavar="N=FILE",
        help="put the HMPL file FILE on task N (repeatable; other files fill the free ids)",
    )


def _werror(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--Werror", dest="werror", action="store_true", help="treat compiler warnings as errors"
    )


def add_debug_parser(sub) -> None:
    """`motionvm debug`: the Debug Adapter Protocol server (dap/server.py)."""
    d = sub.add_parser(
        "debug",
        help="a Debug Adapter Protocol server (VS Code, nvim-dap, ...) on stdin/stdout",
        description="Serve the Debug Adapter Protocol on stdin/stdout (or on "
        "127.0.0.1:PORT with --port): an editor launches programs with the launch "
        "arguments program, machine, scenario, stopOnEntry, noDebug and cwd, sets "
        "breakpoints, steps one controller cycle (stepCycle), steps back and goes to any "
        "time (goToTime).",
    )
    d.add_argument(
        "--port",
        type=port,
        metavar="N",
        help="listen on 127.0.0.1:N for one client instead (0: a free port, printed on stderr)",
    )


def add_studio_parser(sub) -> None:
    """`motionvm studio`: the browser studio (motionvm/studio)."""
    s = sub.add_parser(
        "studio",
        help="a local page to edit, run, watch, debug and scrub programs (127.0.0.1)",
        description="Serve a page on 127.0.0.1 to edit FILES, run them on the machine, "
        "watch the scope, the axes, the I/O and the path, set breakpoints, force inputs and "
        "scrub back through the run. Prints the page's address (with its access token) on "
        "stderr and opens it in the browser; Ctrl-C ends it.",
        formatter_class=_Formatter,
    )
    s.add_argument("files", nargs="*", metavar="FILE", help=_FILES_HELP)
    _machine(s)
    _scenario(s)
    s.add_argument(
        "--port", type=port, default=0, metavar="N", help="listen on 127.0.0.1:N (0: a free port)"
    )
    s.add_argument(
        "--no-browser", action="store_true", help="print the address only, open no browser"
    )
