"""The `motionvm` command: run | check | compile | builtins | errors | dump | scope | test | serve.

Parsing arguments and printing only: every run is assembled by `motionvm.session`, the
same code the Python API uses. Exit codes: 0 ok; 1 a task stopped with a runtime
error; 2 compile errors (nothing runs); 3 bad command line, machine file, scenario or
scope request; 4 an internal error of motionvm itself (a bug); 124 the run had not
finished at `--timeout`; 130 interrupted.
"""

from __future__ import annotations

import sys
import traceback

from motionvm.cli.exits import (
    EXIT_COMPILE,
    EXIT_INTERNAL,
    EXIT_INTERRUPTED,
    EXIT_OK,
    EXIT_RUNTIME,
    EXIT_TIMEOUT,
    EXIT_USAGE,
    UsageError,
)
from motionvm.cli.options import build_parser

__all__ = [
    "EXIT_COMPILE",
    "EXIT_INTERNAL",
    "EXIT_INTERRUPTED",
    "EXIT_OK",
    "EXIT_RUNTIME",
    "EXIT_TIMEOUT",
    "EXIT_USAGE",
    "UsageError",
    "main",
]


def main(argv: list[str] | None = None) -> int:
    code = _main(argv)
    try:  # flushed here, not at exit: a reader gone by now (`| head`) is no error
        sys.stdout.flush()
    except BrokenPipeError:
        from motionvm.cli.run import stdout_gone

        stdout_gone()
    return code


def _main(argv: list[str] | None) -> int:
    parser = build_parser()
    try:
        args, rest = parser.parse_known_args(argv)
        # files may come after options too: `run a.hmpl --machine m.toml app.gdl`
        stray = [a for a in rest if a.startswith("-") and a != "-"]
        if stray or (rest and not hasattr(args, "files")):
            parser.error(f"unrecognized arguments: {' '.join(stray or rest)}")
        if rest:
            args.files = list(args.files) + rest
    except SystemExit as exc:  # argparse already printed its message
        return EXIT_OK if exc.code == 0 else EXIT_USAGE
    try:
        return _dispatch(args)
    except UsageError as exc:
        print(exc.rendered(), file=sys.stderr)
        return EXIT_USAGE
    except BrokenPipeError:  # output piped into e.g. `head`: stop quietly
        from motionvm.cli.run import stdout_gone

        stdout_gone()
        return EXIT_OK
    except KeyboardInterrupt:
        print("motionvm: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except Exception:  # noqa: BLE001 — a bug of ours, reported as such
        print(
            "motionvm: internal error (a bug in motionvm, not in your program); please file an issue "
            "with this output and the program attached:",
            file=sys.stderr,
        )
        traceback.print_exc()
        return EXIT_INTERNAL


def _dispatch(args) -> int:
    if args.cmd == "builtins":
        from motionvm.cli.reference import cmd_builtins

        return cmd_builtins(args)
    if args.cmd == "errors":
        from motionvm.cli.reference import cmd_errors

        return cmd_errors(args)
    if args.cmd == "scope":
        from motionvm.cli.run import cmd_scope

        return cmd_scope(args)
    if args.cmd == "dump":
        from motionvm.cli.info import cmd_dump

        return cmd_dump(args)
    if args.cmd == "test":
        from motionvm.cli.test import cmd_test

        return cmd_test(args)
    if args.cmd == "serve":
        from motionvm.cli.serve import cmd_serve

        return cmd_serve(args)
    from motionvm.cli import run

    if args.cmd == "check":
        return run.cmd_check(args)
    if args.cmd == "compile":
        return run.cmd_compile(args)
    return run.cmd_run(args)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
