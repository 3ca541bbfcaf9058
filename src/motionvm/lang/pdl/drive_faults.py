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
    lines: list[tuple[int, int]] = []
    while tb is not None:
        code = tb.tb_frame.f_code
        if code.co_filename == program.path:
            lines.append((tb.tb_lineno, code.co_firstlineno))
        tb = tb.tb_next
    if not lines:
        return program.path, 0
    lineno, first = lines[-1]
    if lineno == first and len(lines) > 1:
        lineno = lines[-2][0]  # a procedure's entry (frame set-up) faults at its call
    return program.where(lineno)


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
