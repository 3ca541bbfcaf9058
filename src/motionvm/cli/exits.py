"""The command line's exit codes and its usage error."""

from __future__ import annotations

EXIT_OK, EXIT_RUNTIME, EXIT_COMPILE, EXIT_USAGE, EXIT_INTERNAL = 0, 1, 2, 3, 4
EXIT_TIMEOUT = 124
"""The run had not finished at `--timeout` (as timeout(1) exits), or it never can: what
every task left waits on, nothing left in the run can change."""
EXIT_INTERRUPTED = 130

EXIT_CODES_HELP = f"""\
exit codes:
  {EXIT_OK:<3}  ok
  {EXIT_RUNTIME:<3}  a task stopped with a runtime error
  {EXIT_COMPILE:<3}  compile errors (nothing runs)
  {EXIT_USAGE:<3}  bad command line, machine file, scenario or scope request
  {EXIT_INTERNAL:<3}  an internal error of motionvm (a bug; please report it)
  {EXIT_TIMEOUT:<3}  the run had not finished at --timeout, or can never end
  {EXIT_INTERRUPTED:<3}  interrupted (Ctrl-C)"""
"""The exit-code table of `motionvm --help` and `motionvm run --help`."""


class UsageError(Exception):
    """A bad command line, machine file, scenario or scope request: exit code 3.

    `located` messages already name a file, line and column (`FILE:LINE:COL: error: ...`,
    one line per problem of a file) and are printed as they are; others get the
    `motionvm: error:` prefix.
    """

    def __init__(self, message: str, *, located: bool = False) -> None:
        super().__init__(message)
        self.located = located

    def rendered(self) -> str:
        return str(self) if self.located else f"motionvm: error: {self}"
