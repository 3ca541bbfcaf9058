"""How HMPL built-ins are written: `Library` classes whose `@builtin` methods are HMPL functions.

Calling convention between generated code and a built-in method:
- C integer arguments arrive as Python ints (already converted to the parameter type),
  `double`/`float` as Python floats.
- Every pointer (`char *`, `double *`, `Timer *`, arrays) arrives as an int address into
  `self.mem` (a `cmemory.Memory`); out-parameters are written with `self.mem.store`.
- Variadic arguments (`...`) arrive after default argument promotions: ints, floats,
  and addresses for strings/pointers.
- The return value is a Python int or float (None for void).
- A fault that should stop the calling task raises `RuntimeFault(message)`.
- A *blocking* built-in (`@builtin(blocking=True)`) is a generator function: it yields
  wait objects to the kernel and returns its result; generated code calls it with
  `yield from`.

A built-in that is a motion command as it stands (ints and doubles in, an int or a
double out: `motionvm.motion.commands`) is declared `Name = command()`; the program's
namespace then binds `b_Name` straight to the run time's `commands.Name`. Built-ins
with pointers, arrays, strings or waits are `@builtin` methods that marshal around the
command.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover
    from motionvm.lang.hmpl.cmemory import Memory


class _Command:
    """A class attribute that is the HMPL built-in and motion (or I/O) command of its name."""

    def __init__(self, commands: str = "commands") -> None:
        self.commands = commands

    def __set_name__(self, owner: type, name: str) -> None:
        self.name = name
        self._hmpl_builtin = (name, False)

    def __get__(self, lib: Library | None, owner: type | None = None) -> Any:
        if lib is None:
            return self
        return getattr(getattr(lib.rt, self.commands), self.name)


def command() -> _Command:
    """Declare (`Name = command()`) the HMPL built-in that is motion command `Name`."""
    return _Command()


def io_command() -> _Command:
    """Declare (`Name = io_command()`) the HMPL built-in that is I/O command `Name`
    (`motionvm.io.commands`, the run time's `io_commands`)."""
    return _Command("io_commands")


def builtin(name: str | None = None, *, blocking: bool = False) -> Callable:
    """Mark a Library method as the HMPL built-in `name` (default: the method's name)."""

    def mark(fn: Callable) -> Callable:
        fn._hmpl_builtin = (name or fn.__name__, blocking)  # type: ignore[attr-defined]
        return fn

    return mark


class Library:
    """A group of built-ins bound to one running program.

    `rt` is the program's run time (`motionvm.lang.hmpl.rtapi.HmplRuntime`); libraries use
    `rt.mem`, `rt.emit(text)`, `rt.sim_time` [s], `rt.cycle`, `rt.data_dir`,
    `rt.current_task_id`, `rt.kernel`, `rt.commands` (the motion commands).
    """

    def __init__(self, rt: Any) -> None:
        self.rt = rt
        self.mem: Memory = rt.mem

    @classmethod
    def builtin_methods(cls) -> dict[str, tuple[str, bool]]:
        """HMPL name -> (method name, blocking) for every @builtin method of the class."""
        found: dict[str, tuple[str, bool]] = {}
        for klass in reversed(cls.__mro__):
            for attr, fn in vars(klass).items():
                mark = getattr(fn, "_hmpl_builtin", None)
                if mark:
                    found[mark[0]] = (attr, mark[1])
        return found
