"""The protocol every language's run side implements to live on the controller's cycle.

A *cycle client* is one part of a run that the controller steps: the HMPL run time
(system variables before the tasks), the PDL drives (their 15 kHz phases after the
motion step), a GDL application (its procedures after the motion step), a scope
recorder (a sample of the state the cycle left). The controller calls, each cycle:

    begin_cycle()   before the tasks run (latch inputs, update system variables)
    ...tasks, motion...
    end_cycle()     after the motion step (drive firmware, event procedures, sampling)

and between cycles asks each client

    busy()          True while the client has work that keeps the run going (a task or
                    a procedure that will still run, a program on a drive, a scenario
                    event still to come). The run ends when no client is busy, no task
                    runs and no axis moves.
    next_event()    the earliest cycle at which the client must be stepped because
                    something of it can change there; None if nothing of it changes
                    until another part acts. The controller jumps the clock over the
                    cycles before the earliest next event of all clients, tasks and
                    axes; returning the current cycle means "step every cycle".
    still_running() what keeps it busy, as `runtime.waits.Waiting` items (which task,
                    where it waits), for the notes of a run that `--until` or
                    `--timeout` ended.

A jump must give byte-identical results to stepping, so a client that cannot tell
when it changes next returns the current cycle.

A client may also declare `observes_motion = False`: none of its hooks reads the state
of a moving axis (positions, velocities, drive objects). Only then may the controller
jump while axes move, advancing them in closed form (motion/axis_coast.py). A client
without the attribute counts as observing motion: axes then jump only while they rest.
Two more declarations serve recorders: `samples_skipped_cycles = True` (its `end_cycle`
is called for every cycle a jump passes, after the axes were advanced to it) and
`clock_driven = True` (its `begin_cycle` only writes values computed from the clock's
cycle, so such a jump calls it too, for the recorder to see them).

An idle client costs no call: a client may answer `has_work(hook)` ("begin_cycle" or
"end_cycle") False while that hook would do nothing, and must then call `work_changed()`
as soon as the answer may differ. The controller calls only the hooks with work; it
takes its hook lists again at its next point of taking them after a `work_changed()`:
before the begin hooks and before the end hooks of a cycle (as it does when a client
comes or goes). So work that appears between cycles, while the tasks run or in the
motion step is done in the same cycle as if the hook were called every cycle; a hook
must not gain begin work from another client's `begin_cycle`, nor end work from an
earlier client's `end_cycle` (it would start a cycle late).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol, runtime_checkable


@runtime_checkable
class CycleClient(Protocol):
    """A run side stepped by the controller's cycle (see the module docstring)."""

    def begin_cycle(self) -> None: ...

    def end_cycle(self) -> None: ...

    def busy(self) -> bool: ...

    def next_event(self) -> int | None: ...

    def still_running(self) -> list: ...


class PassiveClient:
    """A client with no work of its own: a base for clients that only observe."""

    observes_motion = True
    """True if a hook reads the state of moving axes (see the module docstring)."""

    def begin_cycle(self) -> None:
        """Nothing before the tasks."""

    def end_cycle(self) -> None:
        """Nothing after the motion step."""

    def busy(self) -> bool:
        return False

    def next_event(self) -> int | None:
        return None

    def still_running(self) -> list:
        return []

    def has_work(self, hook: str) -> bool:
        """False while the hook `hook` ("begin_cycle" or "end_cycle") has nothing to do:
        the controller leaves it out until `work_changed()` (see the module docstring)."""
        return True

    _on_work_changed: Callable[[], None] | None = None

    def watch_work(self, callback: Callable[[], None]) -> None:
        """The controller's: call `callback()` when `has_work` may answer differently."""
        self._on_work_changed = callback

    def work_changed(self) -> None:
        """Tell the controller that `has_work` may answer differently now (any thread)."""
        callback = self._on_work_changed
        if callback is not None:
            callback()


def active_hooks(clients: list, name: str) -> list:
    """The bound `name` methods ("begin_cycle" or "end_cycle") of `clients`, in order,
    leaving out a `PassiveClient`'s inherited no-op and a hook whose client has no work
    for it now (`has_work`): what the cycle must call."""
    noop = getattr(PassiveClient, name)
    hooks = []
    for c in clients:
        hook = getattr(c, name)
        if getattr(hook, "__func__", None) is noop:
            continue
        has_work = getattr(c, "has_work", None)
        if has_work is None or has_work(name):
            hooks.append(hook)
    return hooks
