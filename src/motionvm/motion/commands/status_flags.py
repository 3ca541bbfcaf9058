"""The Is* commands of manual 5.4 that answer one status flag of an axis (IsEnabled,
IsMoving, IsInPos, IsErrorStop): the one place that owns their rule.

The rule: axis `axis_id` answers 1 if its flag is set, else 0; while a task runs with a
recorder (`MotionKernel.reads` is a list, runtime/kernel.py), the answer is recorded
as (axis, flag name, value) so a status wait need not be polled while its flags answer
the same. A bad axis id answers 0, stores eERR_HMPL_ARG_OUT_OF_RANGE as the system's
last error and records None (not replayable).

The manual's idioms poll these every cycle (`Till(IsInPos(a))`, a loop over the axes),
so each is built per commands object as a plain closure over `axis_id` with the motion
kernel, its axes and the flag's getter bound in (`StatusFlag`): one call, no method look-up.
"""

from __future__ import annotations

from collections.abc import Callable
from operator import attrgetter


def _query(name: str, flag: str, motion, bad_id: Callable[[int, str], int]) -> Callable[[int], int]:
    """The function `name(axis_id)` that answers `flag` of the axes of `motion`."""
    axes = motion.axes
    get = attrgetter(flag)

    def query(axis_id: int) -> int:
        if axis_id >= 0:
            try:
                a = axes[axis_id]
            except IndexError:
                pass
            else:
                reads = motion.reads
                value = get(a)
                if reads is not None:
                    reads.append((a, flag, value))
                return 1 if value else 0
        return bad_id(axis_id, flag)

    query.__name__ = query.__qualname__ = name
    return query


class StatusFlag:
    """Declares (`IsInPos = StatusFlag("in_pos")`, in a commands class) the command that
    answers axis attribute `flag`. On a commands object it is that object's query
    function (made on first use, then kept as the object's attribute); on the class, a
    method that calls it (for `inspect.signature` and documentation)."""

    def __init__(self, flag: str) -> None:
        if not flag.isidentifier():
            raise ValueError(f"not an axis attribute: {flag!r}")
        self.flag = flag

    def __set_name__(self, owner: type, name: str) -> None:
        self.name = name
        flag = self.flag

        def method(commands, axis_id: int) -> int:
            return self.__get__(commands)(axis_id)

        method.__name__ = method.__qualname__ = name
        method.__doc__ = f"1 if the `{flag}` flag of axis `axis_id` is set, else 0."
        self.method = method

    def __get__(self, commands, owner: type | None = None) -> Callable[[int], int]:
        if commands is None:
            return self.method
        query = commands.__dict__.get(self.name)
        if query is None:
            query = _query(self.name, self.flag, commands.motion, commands._status_of_bad_id)
            commands.__dict__[self.name] = query
        return query
