"""Running a compiler pass that recurses deeply: on a helper thread with a large C stack
and a high Python recursion limit, so that legal programs with deep nesting or long
expressions compile (each front end still enforces its own documented limits with a
located error; this only makes sure Python's limits are not the ones a user meets).

Recursive descent, the lowerings and CPython's own `compile()` recurse once per level
of nesting of a program (a 10,000-term `a + a + ...` is 10,000 levels deep). CPython's
default limit (1,000 frames) and the main thread's C stack (8 MB, used by `compile()`)
are far below what such programs need.
"""

from __future__ import annotations

import contextvars
import sys
import threading
from collections.abc import Callable
from typing import TypeVar

T = TypeVar("T")

STACK_BYTES = 512 * 1024 * 1024
"""C stack of the helper thread [bytes] (reserved address space; pages are touched only
as deep as the recursion goes)."""
RECURSION_LIMIT = 400_000
"""Python frames allowed while a deep pass runs."""

_lock = threading.Lock()  # one deep pass at a time: the recursion limit is process-wide


def run_deep(fn: Callable[..., T], *args, **kwargs) -> T:
    """`fn(*args, **kwargs)` with room to recurse; its result, or its exception re-raised.

    Called from a thread that is already a deep pass, it runs `fn` directly."""
    if getattr(_state, "inside", False):
        return fn(*args, **kwargs)
    result: list = []
    error: list[BaseException] = []
    context = contextvars.copy_context()  # the caller's context variables hold there too

    def target() -> None:
        _state.inside = True
        try:
            result.append(context.run(fn, *args, **kwargs))
        except BaseException as exc:  # noqa: BLE001 - handed to the caller
            error.append(exc)

    with _lock:
        old_limit = sys.getrecursionlimit()
        old_stack = threading.stack_size()
        try:
            threading.stack_size(STACK_BYTES)
            worker = threading.Thread(target=target, name="motionvm-deep-pass", daemon=True)
        finally:
            threading.stack_size(old_stack)
        sys.setrecursionlimit(max(old_limit, RECURSION_LIMIT))
        try:
            worker.start()
            worker.join()
        finally:
            sys.setrecursionlimit(old_limit)
    if error:
        raise error[0]
    return result[0]


_state = threading.local()
