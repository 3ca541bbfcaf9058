"""Turn a task's exception into the one-line report
`FILE:LINE:COL: runtime error in task N at t=S.ssssss s: MSG`.

The place comes from the deepest traceback frame that runs the program's generated
code (compiled with the user's file name, line numbers and columns, lower.py); the time
is the drive's phase time, as its message stamps show it; Python's own exceptions from
that code get the wording of the drive's fault.
"""

from __future__ import annotations

from motionvm.lang.pdl.lower import PdlProgram
from motionvm.runtime.errors import RuntimeFault
from motionvm.runtime.fault_position import Fault, user_frames

_PYTHON_FAULTS = {
    ZeroDivisionError: "division by zero",
    RecursionError: "stack overflow: procedure calls nested too deep",
    OverflowError: "arithmetic overflow: a value does not fit its variable",
    IndexError: "index out of range: the element is outside the drive's memory",
}


def fault_place(program: PdlProgram, exc: BaseException) -> tuple[str, int, int]:
    """(file, line, column) of the PDL statement that raised `exc` (line 0: unknown)."""
    frames = user_frames(exc.__traceback__, program.path.__eq__)
    if not frames:
        return program.path, 0, 1
    f = frames[-1]
    if f.line == f.first_line and len(frames) > 1:
        f = frames[-2]  # a procedure's entry (frame set-up) faults at its call
    file, line = program.where(f.line)
    return file, line, f.col


def fault_message(exc: BaseException) -> str:
    """The message part of a fault report."""
    if isinstance(exc, RuntimeFault):
        return str(exc)
    for cls, text in _PYTHON_FAULTS.items():
        if isinstance(exc, cls):
            return text
    return f"internal error ({type(exc).__name__}: {exc}); please report it with the program"


def describe_fault(program: PdlProgram, task: int, exc: BaseException, sim_time: float) -> Fault:
    """`FILE:LINE:COL: runtime error in task N at t=S.ssssss s: MESSAGE` (a `Fault`, its
    parts filled in; kind "internal" for an exception that is no fault of the program);
    `sim_time` [s]: the drive's time of the faulting phase."""
    file, line, col = fault_place(program, exc)
    message = fault_message(exc)
    internal = not isinstance(exc, (RuntimeFault, *_PYTHON_FAULTS))
    return Fault(
        f"{file}:{line}:{col}: runtime error in task {task} at t={sim_time:.6f} s: {message}",
        file=file, line=line, col=col, time=sim_time, message=message, language="PDL",
        task=task, kind="internal" if internal else "runtime",
    )  # fmt: skip
