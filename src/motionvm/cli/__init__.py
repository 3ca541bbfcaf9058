"""The `motionvm` command: run | check | compile | builtins | errors | dump | scope | test |
serve | lsp | debug | studio.

Parsing arguments and printing only: every run is assembled by `motionvm.session`, the
same code the Python API uses. Exit codes: 0 ok; 1 a task stopped with a runtime
error; 2 compile errors (nothing runs); 3 bad command line, machine file, scenario or
scope request; 4 an internal error of motionvm itself (a bug); 124 the run had not
finished at `--timeout`; 130 interrupted.
"""

from __future__ import annotations

import sys

from motionvm.cli.entry import run_command
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
    """The `motionvm` command with `argv` (default: the process's); its exit code.
    With MOTIONVM_PARENT_PID set (a case of `motionvm test --dask`), the process ends
    itself when that process is gone."""
    import os

    parent = os.environ.get("MOTIONVM_PARENT_PID", "")
    if parent.isdigit() and argv is None:
        from motionvm.cli.workers import die_with

        die_with(int(parent), by_signal=False)
    return run_command(argv, _dispatch)


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
    if args.cmd == "lsp":
        from motionvm.lsp import serve

        try:
            serve(args.tcp)
        except OSError as exc:
            if args.tcp is None:
                raise
            raise UsageError(f"--tcp {args.tcp}: {exc.strerror or exc}") from None
        return EXIT_OK
    if args.cmd == "debug":
        from motionvm.cli.debug import cmd_debug

        return cmd_debug(args)
    if args.cmd == "studio":
        from motionvm.cli.studio import cmd_studio

        return cmd_studio(args)
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
