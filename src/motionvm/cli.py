"""The `motionvm` command: run | check | compile | builtins | dump (DESIGN.md's CLI contract).

Exit codes: 0 ok; 1 a task stopped with a runtime error; 2 compile errors (nothing
runs); 3 bad command line or machine file; 4 an internal error of motionvm itself.
"""

from __future__ import annotations

import argparse
import json
import sys
import traceback
from pathlib import Path

EXIT_OK, EXIT_RUNTIME, EXIT_COMPILE, EXIT_USAGE, EXIT_INTERNAL = 0, 1, 2, 3, 4


class UsageError(Exception):
    """A bad command line: message printed, exit code 3."""


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="motionvm", description="A virtual motion controller for HMPL, PDL and GDL programs."
    )
    sub = p.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run", help="compile and run programs on the simulated machine")
    r.add_argument("files", nargs="*", metavar="FILE")
    r.add_argument(
        "--machine", metavar="FILE.toml", help="machine file (default: the built-in machine)"
    )
    r.add_argument(
        "--until", type=float, metavar="SECONDS", help="stop after this much simulated time"
    )
    r.add_argument("--stamp", action="store_true", help="prefix messages with [t=SECONDS][task N]")
    r.add_argument(
        "--task", action="append", default=[], metavar="N=FILE", help="put FILE on task N"
    )
    r.add_argument("--realtime", action="store_true", help="pace the simulation to the wall clock")
    r.add_argument("--scenario", metavar="FILE.toml", help="GDL: timed input changes")
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
        help="write the recording to FILE: .csv, .png, .svg or .vcd (repeatable)",
    )
    r.add_argument("--scope-every", type=int, metavar="N", help="record every N cycles (default 1)")
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
    c = sub.add_parser("check", help="compile only; report errors")
    c.add_argument("files", nargs="+", metavar="FILE")
    c.add_argument("--task", action="append", default=[], metavar="N=FILE")
    k = sub.add_parser("compile", help="compile and show the generated Python")
    k.add_argument("files", nargs="+", metavar="FILE")
    k.add_argument("--emit-python", action="store_true", help="print the generated Python code")
    k.add_argument("--task", action="append", default=[], metavar="N=FILE")
    b = sub.add_parser("builtins", help="list every HMPL built-in and whether it is implemented")
    b.add_argument("--json", action="store_true")
    d = sub.add_parser("dump", help="show a compiler stage")
    d.add_argument("--stage", choices=["tokens", "ast", "py"], required=True)
    d.add_argument("file", metavar="FILE")
    d.add_argument("--task-id", type=int, default=0)
    return p


def main(argv: list[str] | None = None) -> int:
    try:
        args = _parser().parse_args(argv)
    except SystemExit as exc:  # argparse already printed its message
        return EXIT_OK if exc.code == 0 else EXIT_USAGE
    try:
        if args.cmd == "builtins":
            return cmd_builtins(args)
        if args.cmd == "dump":
            return cmd_dump(args)
        return _dispatch(args)
    except UsageError as exc:
        print(f"motionvm: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except BrokenPipeError:  # output piped into e.g. `head`: stop quietly
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_OK
    except KeyboardInterrupt:
        print("motionvm: interrupted", file=sys.stderr)
        return EXIT_RUNTIME
    except Exception:  # noqa: BLE001 — a bug of ours, reported as such
        print(
            "motionvm: internal error (a bug in motionvm, not in your program); please file an issue "
            "with this output and the program attached:",
            file=sys.stderr,
        )
        traceback.print_exc()
        return EXIT_INTERNAL


def _dispatch(args) -> int:
    files = list(args.files)
    langs = {Path(f).suffix.lower() for f in files} | {
        Path(t.partition("=")[2]).suffix.lower() for t in args.task
    }
    if not files and not args.task:
        if args.cmd == "run" and getattr(args, "machine", None):
            from motionvm.hmpl_cli import hmpl_command  # the machine's PDL drives alone

            return hmpl_command(args)
        raise UsageError("no input files")
    unknown = langs - {".hmpl", ".pdl", ".gdl"}
    if unknown:
        raise UsageError(f"unknown file type '{sorted(unknown)[0]}' (expected .hmpl, .pdl or .gdl)")
    if langs == {".gdl"}:
        return _gdl(args, files)
    if ".gdl" in langs:
        raise UsageError("GDL files cannot be mixed with HMPL or PDL files in one run")
    if langs == {".pdl"}:
        return _pdl(args, files)
    if ".pdl" in langs:
        raise UsageError(
            "PDL files run on a drive of their own: run them without HMPL files, or put them on "
            'the drives of a machine file (pdl = "x.pdl" in an [[axis]] table, --machine)'
        )
    from motionvm.hmpl_cli import hmpl_command

    return hmpl_command(args)


def _gdl(args, files: list[str]) -> int:
    try:
        from motionvm.lang.gdl import cli as gdl_cli
    except ImportError:
        raise UsageError("the GDL run time is not available yet (issue 5)") from None
    if args.cmd == "check":
        return gdl_cli.main_check(files, sys.stdout, sys.stderr)
    if args.cmd == "run":
        if _scope_request(args) is not None:
            raise UsageError(
                "--scope records HMPL and PDL runs only; a GDL run has no scope channels yet "
                "(its messages and the scenario's timing are its trace)"
            )
        return gdl_cli.main_run(
            files,
            args.scenario,
            args.until,
            sys.stdout,
            sys.stderr,
            args.force or None,
            args.shuffle_order,
        )
    raise UsageError("'compile' supports HMPL files only")


def _pdl(args, files: list[str]) -> int:
    from motionvm.lang.pdl import cli as pdl_cli

    if args.cmd == "check":
        return pdl_cli.main_check(files, sys.stdout, sys.stderr)
    if args.cmd == "run":
        starts = args.start or None
        return pdl_cli.main_run(
            files,
            starts,
            args.until,
            sys.stdout,
            sys.stderr,
            stamp=bool(args.stamp),
            scope=_scope_request(args),
        )
    raise UsageError("'compile' supports HMPL files only (use 'motionvm dump --stage py' for PDL)")


def _scope_request(args):
    """The checked --scope/--scope-out/--scope-every request (None if none); UsageError if bad."""
    from motionvm.sim.scope import ScopeError, ScopeRequest

    try:
        return ScopeRequest.from_options(
            getattr(args, "scope", []),
            getattr(args, "scope_out", []),
            getattr(args, "scope_every", None),
        )
    except ScopeError as exc:
        raise UsageError(str(exc)) from None


def cmd_builtins(args) -> int:
    from motionvm.lang.hmpl.catalog import builtin_signatures
    from motionvm.lang.hmpl.lib import implemented_builtins

    impl = implemented_builtins()
    special = {"_TASKID_", "_AUTORUN_", "Till", "HIMC_GPI", "HIMC_GPO"}
    rows = []
    for name, sig in builtin_signatures().items():
        rows.append(
            {
                "name": name,
                "prototype": sig.prototype,
                "section": sig.section,
                "implemented": name in impl or name in special,
            }
        )
    if args.json:
        json.dump(rows, sys.stdout, indent=1)
        sys.stdout.write("\n")
    else:
        width = max(len(r["name"]) for r in rows)
        for r in rows:
            mark = "yes" if r["implemented"] else "no "
            sys.stdout.write(f"{r['name']:<{width}}  {mark}  {r['section']:<7} {r['prototype']}\n")
        done = sum(r["implemented"] for r in rows)
        sys.stdout.write(f"{done} of {len(rows)} built-ins implemented\n")
    return EXIT_OK


def cmd_dump(args) -> int:
    suffix = Path(args.file).suffix.lower()
    if not Path(args.file).is_file():
        raise UsageError(f"{args.file}: no such file")
    if suffix == ".gdl":
        from motionvm.lang.gdl import cli as gdl_cli

        return gdl_cli.main_dump([args.file], args.stage, sys.stdout, sys.stderr)
    if suffix == ".pdl":
        return _pdl_dump(args.file, args.stage)
    from motionvm.hmpl_cli import dump_stage

    return dump_stage(args.file, args.stage, args.task_id)


def _pdl_dump(path: str, stage: str) -> int:
    from motionvm.lang.pdl import dump
    from motionvm.lang.pdl.front import compile_front
    from motionvm.lang.pdl.preprocess import preprocess
    from motionvm.source.diagnostics import DiagnosticSink, render_diagnostic

    sink = DiagnosticSink()
    if stage == "tokens":
        sys.stdout.write(dump.dump_tokens(preprocess(path, sink)) + "\n")
    elif stage == "ast":
        prog = compile_front(path, sink=sink)
        if prog is not None:
            sys.stdout.write(dump.dump_ast(prog) + "\n")
    else:
        from motionvm.lang.pdl.program import compile_pdl

        prog = compile_pdl(path, sink=sink)
        if prog is not None:
            sys.stdout.write(prog.python_source() + "\n")
    for d in sorted(sink.items, key=lambda d: (d.pos.file, d.pos.line, d.pos.col)):
        print(render_diagnostic(d), file=sys.stderr)
    return EXIT_COMPILE if sink.has_errors else EXIT_OK


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
