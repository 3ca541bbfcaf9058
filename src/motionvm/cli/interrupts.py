"""Signals around the files a run writes: a Ctrl-C while the scope files are written
waits for them, SIGTERM ends a run as an interrupt does (its temporaries removed).

Python raises KeyboardInterrupt wherever the main thread is when SIGINT arrives. During
a run that is what we want (the run stops and what was recorded is written); while the
scope files are written it would abandon them, so `finishing_files` notes a first SIGINT
and raises it only once the files are complete; a second one abandons them at once
(each file's temporary is removed by its atomic write). `terminate_as_exit` turns
SIGTERM into `SystemExit(143)`, so `finally` blocks and atomic writes clean up instead
of the process dying where it stands.
"""

from __future__ import annotations

import contextlib
import os
import signal
import threading
from collections.abc import Iterator

EXIT_TERMINATED = 128 + signal.SIGTERM


def _main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


def interrupted_by(exc: BaseException) -> bool:
    """True if `exc` is, or was raised while handling or because of, a KeyboardInterrupt
    (an import interrupted inside a class body surfaces as a RuntimeError)."""
    seen: set[int] = set()
    e: BaseException | None = exc
    while e is not None and id(e) not in seen:
        if isinstance(e, KeyboardInterrupt):
            return True
        seen.add(id(e))
        e = e.__cause__ or e.__context__
    return False


def forget_unhandled_interrupt() -> None:
    """Call after handling a KeyboardInterrupt, so the process exits with our exit code.

    CPython notes a KeyboardInterrupt that escapes code run by `exec(<string>)` (as
    `dataclasses` and `collections.namedtuple` do while a module is imported) as
    unhandled, even when a caller catches it, and then ends the process by SIGINT at
    exit instead of with the code `sys.exit` was given. The next `exec` of a string
    clears that note."""
    exec("None")  # noqa: S102 — a constant: only its side effect on the interpreter matters


@contextlib.contextmanager
def finishing_files(what: str) -> Iterator[None]:
    """Within the block a first SIGINT is noted on stderr, not raised: the block
    finishes, then KeyboardInterrupt is raised. A second SIGINT raises at once. Does
    nothing outside the main thread or where SIGINT is ignored (a test worker)."""
    if not _main_thread() or signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        yield
        return
    pending: list[int] = []

    def later(signum, frame) -> None:
        if pending:
            raise KeyboardInterrupt
        pending.append(signum)
        # os.write, not print: the interrupted code may be inside a write to stderr
        with contextlib.suppress(OSError):
            os.write(
                2, f"motionvm: interrupted; finishing {what} (Ctrl-C again to abandon)\n".encode()
            )

    old = signal.signal(signal.SIGINT, later)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, old)
    if pending:
        raise KeyboardInterrupt


@contextlib.contextmanager
def terminate_as_exit() -> Iterator[None]:
    """Within the block SIGTERM raises SystemExit(143) (main thread only)."""
    if not _main_thread() or signal.getsignal(signal.SIGTERM) is not signal.SIG_DFL:
        yield
        return

    def stop(signum, frame) -> None:
        raise SystemExit(EXIT_TERMINATED)

    old = signal.signal(signal.SIGTERM, stop)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, old)
