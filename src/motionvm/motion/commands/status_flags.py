"""The Is* commands of manual 5.4 that answer one status flag of an axis (IsEnabled,
IsMoving, IsInPos, IsErrorStop): the one place that owns their rule.

The rule: axis `axis_id` answers 1 if its flag is set, else 0; while a task runs with a
recorder (`MotionKernel.reads` is a list, runtime/kernel.py), the answer is recorded
as (axis, flag name, value) so a status wait need not be polled while its flags answer
the same. A bad axis id answers 0, stores eERR_HMPL_ARG_OUT_OF_RANGE as the system's
last error and records None (not replayable).

The manual's idioms poll these every cycle (`Till(IsInPos(a))`, a loop over the axes),
so each is built per commands object as a plain closure over `axis_id` with the motion
kernel and its axes bound in (`StatusFlag`): one call, no method or flag-name look-up.
"""

from __future__ import annotations

from collections.abc import Callable

# One query per flag, each reading its flag by name (an attribute read, no call: the
# idioms above poll them every cycle).


def _enabled_query(axes: list, motion, bad_id: Callable[[int, str], int]) -> Callable[[int], int]:
    def IsEnabled(axis_id: int) -> int:
        if axis_id >= 0:
            try:
                a = axes[axis_id]
            except IndexError:
                pass
            else:
                reads = motion.reads
                if reads is None:
                    return 1 if a.enabled else 0
                flag = a.enabled
                reads.append((a, "enabled", flag))
                return 1 if flag else 0
        return bad_id(axis_id, "enabled")

    return IsEnabled


def _moving_query(axes: list, motion, bad_id: Callable[[int, str], int]) -> Callable[[int], int]:
    def IsMoving(axis_id: int) -> int:
        if axis_id >= 0:
            try:
                a = axes[axis_id]
            except IndexError:
                pass
            else:
                reads = motion.reads
                if reads is None:
                    return 1 if a.moving else 0
                flag = a.moving
                reads.append((a, "moving", flag))
                return 1 if flag else 0
        return bad_id(axis_id, "moving")

    return IsMoving


def _in_pos_query(axes: list, motion, bad_id: Callable[[int, str], int]) -> Callable[[int], int]:
    def IsInPos(axis_id: int) -> int:
        if axis_id >= 0:
            try:
                a = axes[axis_id]
            except IndexError:
                pass
            else:
                reads = motion.reads
                if reads is None:
                    return 1 if a.in_pos else 0
                flag = a.in_pos
                reads.append((a, "in_pos", flag))
                return 1 if flag else 0
        return bad_id(axis_id, "in_pos")

    return IsInPos


def _error_stop_query(
    axes: list, motion, bad_id: Callable[[int, str], int]
) -> Callable[[int], int]:
    def IsErrorStop(axis_id: int) -> int:
        if axis_id >= 0:
            try:
                a = axes[axis_id]
            except IndexError:
                pass
            else:
                reads = motion.reads
                if reads is None:
                    return 1 if a.error_stop else 0
                flag = a.error_stop
                reads.append((a, "error_stop", flag))
                return 1 if flag else 0
        return bad_id(axis_id, "error_stop")

    return IsErrorStop


_QUERIES = {
    "enabled": _enabled_query,
    "moving": _moving_query,
    "in_pos": _in_pos_query,
    "error_stop": _error_stop_query,
}
"""The query maker of each status flag: (axes, motion kernel, bad-id handler) -> query."""


class StatusFlag:
    """Declares (`IsInPos = StatusFlag("in_pos")`, in a commands class) the command that
    answers axis attribute `flag`. On a commands object it is that object's query
    function (made on first use, then kept as the object's attribute); on the class, a
    method that calls it (for `inspect.signature` and documentation)."""

    def __init__(self, flag: str) -> None:
        if flag not in _QUERIES:
            raise ValueError(f"not an axis status flag: {flag!r}")
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
            motion = commands.motion
            query = _QUERIES[self.flag](motion.axes, motion, commands._status_of_bad_id)
            commands.__dict__[self.name] = query
        return query
