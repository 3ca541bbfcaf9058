"""Run-time fault types shared by every language's run time."""

from __future__ import annotations


class RuntimeFault(Exception):
    """A user program's fault: stops the task that raised it, never the controller.

    The language's run time reports it as
    `FILE:LINE:COL: runtime error in task N at t=S s: MESSAGE`, taking the place from the
    deepest frame of the user's code (fault_position.py).
    """


class TaskExit(BaseException):
    """Raised inside a task to end it at once without an error (StopTask on itself)."""
