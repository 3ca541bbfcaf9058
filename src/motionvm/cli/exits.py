"""The command line's exit codes and its usage error."""

from __future__ import annotations

EXIT_OK, EXIT_RUNTIME, EXIT_COMPILE, EXIT_USAGE, EXIT_INTERNAL = 0, 1, 2, 3, 4
EXIT_TIMEOUT = 124
"""The run had not finished at `--timeout` (as timeout(1) exits)."""
EXIT_INTERRUPTED = 130


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
