"""One command line, parsed and guarded: argv -> a command -> its exit code.

`run_command(argv, dispatch)` parses `argv` with the command line's parser, calls
`dispatch(args)` and turns what can go wrong into exit codes and one message: a bad
command line (3), an interrupt (130), output piped into a reader that went away (0), a
bug of motionvm (4, with the traceback). `motionvm.cli.main` dispatches to every
command; a test worker (`workers.py`) runs its cases' `run` commands through it too.
"""

from __future__ import annotations

import argparse
import sys
import traceback
from collections.abc import Callable

from motionvm.cli.colour import coloured
from motionvm.cli.colour import wanted as colour_wanted
from motionvm.cli.exits import EXIT_INTERNAL, EXIT_INTERRUPTED, EXIT_OK, EXIT_USAGE, UsageError
from motionvm.cli.interrupts import forget_unhandled_interrupt, interrupted_by
from motionvm.cli.options import build_parser


def run_command(argv: list[str] | None, dispatch: Callable[[object], int]) -> int:
    code = _guarded(argv, dispatch)
    try:  # flushed here, not at exit: a reader gone by now (`| head`) is no error
        sys.stdout.flush()
    except BrokenPipeError:
        from motionvm.cli.run import stdout_gone

        stdout_gone()
    return code


def subcommand_parser(parser: argparse.ArgumentParser, args) -> argparse.ArgumentParser:
    """The parser of the subcommand `args` were parsed for (`parser` without one)."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return action.choices.get(getattr(args, "cmd", None), parser)
    return parser


def _guarded(argv: list[str] | None, dispatch: Callable[[object], int]) -> int:
    try:
        return _parsed(argv, dispatch)
    except KeyboardInterrupt:
        forget_unhandled_interrupt()
        print("motionvm: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED


def _parsed(argv: list[str] | None, dispatch: Callable[[object], int]) -> int:
    parser = build_parser()
    try:
        args, rest = parser.parse_known_args(argv)
        # files may come after options too: `run a.hmpl --machine m.toml app.gdl`
        stray = [a for a in rest if a.startswith("-") and a != "-"]
        if stray or (rest and not hasattr(args, "files")):
            # the usage of the command given (`motionvm run: error: ...`), not motionvm's
            subcommand_parser(parser, args).error(
                f"unrecognized arguments: {' '.join(stray or rest)}"
            )
        if rest:
            args.files = list(args.files) + rest
    except SystemExit as exc:  # argparse already printed its message
        return EXIT_OK if exc.code == 0 else EXIT_USAGE
    try:
        return dispatch(args)
    except UsageError as exc:
        text = exc.rendered()
        print(coloured(text) if colour_wanted() else text, file=sys.stderr)
        return EXIT_USAGE
    except BrokenPipeError:  # output piped into e.g. `head`: stop quietly
        from motionvm.cli.run import stdout_gone

        stdout_gone()
        return EXIT_OK
    except Exception as exc:  # noqa: BLE001 — a bug of ours, reported as such
        if interrupted_by(exc):  # Ctrl-C inside an import: the import machinery wraps it
            raise KeyboardInterrupt from None
        print(
            "motionvm: internal error (a bug in motionvm, not in your program); please file an issue "
            "with this output and the program attached:",
            file=sys.stderr,
        )
        traceback.print_exc()
        return EXIT_INTERNAL
