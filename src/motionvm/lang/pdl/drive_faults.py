"""Turn a task's exception into the one-line report `FILE:LINE: runtime error in task N: MSG`.

The line comes from the deepest traceback frame that runs the program's generated
code (compiled with the user's file name and line numbers, lower.py); Python's own
exceptions from that code get the wording of the drive's fault.
"""

from __future__ import annotations

from motionvm.lang.pdl.lower import PdlProgram
from motionvm.runtime.errors import RuntimeFault

_PYTHON_FAULTS = {
    ZeroDivisionError: "division by zero",
    RecursionError: "stack overflow: procedure calls nested too deep",
    OverflowError: "arithmetic overflow: a value does not fit its variable",
    IndexError: "index out of range: the element is outside the drive's memory",
}


def fault_line(program: PdlProgram, exc: BaseException) -> tuple[str, int]:
    """(file, line) of the PDL statement that raised `exc`."""
    tb = exc.__traceback__
    lineno = 0
    while tb is not None:
        if tb.tb_frame.f_code.co_filename == program.path:
            lineno = tb.tb_lineno
        tb = tb.tb_next
    return program.where(lineno) if lineno else (program.path, 0)


def fault_message(exc: BaseException) -> str:
    """The message part of a fault report."""
    if isinstance(exc, RuntimeFault):
        return str(exc)
    for cls, text in _PYTHON_FAULTS.items():
        if isinstance(exc, cls):
            return text
    return f"internal error ({type(exc).__name__}: {exc}); please report it with the program"


def describe_fault(program: PdlProgram, task: int, exc: BaseException) -> str:
    """`FILE:LINE: runtime error in task N: MESSAGE`."""
    file, line = fault_line(program, exc)
    return f"{file}:{line}: runtime error in task {task}: {fault_message(exc)}"
