"""The protocol every language's run side implements to live on the controller's cycle.

A *cycle client* is one part of a run that the controller steps: the HMPL run time
(system variables before the tasks), the PDL drives (their 15 kHz phases up to the
start of the cycle, before the tasks), a GDL application (its procedures after the
motion step), a scope recorder (a sample of the state the cycle left). The controller
calls, each cycle:

    begin_cycle()   before the tasks run (latch inputs, update system variables, run
                    the drives' firmware up to this cycle)
    ...tasks, motion...
    end_cycle()     after the motion step (event procedures, sampling)

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

Every other capability a client may offer is declared here too, with its default
(`PassiveClient`, the base every client derives from); the controller reads them as
attributes, never by probing for a name:

    observes_motion         True (the default) if a hook reads the state of a moving axis
                            (positions, velocities, drive objects). Only while no client
                            observes motion may the controller jump while axes move,
                            advancing them in closed form (sim/jumps.py); otherwise axes
                            jump only while they rest. A class constant, or a property
                            (asked at every jump) where the answer changes.
    touches_axes            True (the default) if a hook reads or writes anything of an
                            axis or its drive. While no hooked client touches axes, the
                            motion kernel may defer the cycles of moving axes that
                            nobody else reads (motion/deferred.py). A class constant.
    samples_skipped_cycles  False by default; True for a recorder whose `end_cycle` is
                            called for every cycle a jump passes that it samples
                            (`next_sample`), after the axes were advanced to it.
    next_sample(cycle)      a recorder's: the first cycle >= `cycle` whose end it
                            records (the default: `cycle`, every cycle). A jump
                            advances the axes in closed form between those cycles, so
                            a recorder of every N-th cycle costs a jump 1/N of the
                            cycle-by-cycle walk.
    clock_driven            False by default; True if `begin_cycle` only writes values
                            computed from the clock's cycle, so that such a jump calls it
                            too, for the recorder to see them.
    has_work(hook)          True by default. An idle client costs no call: it may answer
                            False for "begin_cycle" or "end_cycle" while that hook would do
                            nothing, and must then call `work_changed()` as soon as the
                            answer may differ.
    watch_work(callback)    the controller's: `work_changed()` calls `callback()`.
    work_changed()          tell the controller that `has_work` may answer differently.

The controller calls only the hooks with work; it takes its hook lists again at its next
point of taking them after a `work_changed()`: before the begin hooks and before the end
hooks of a cycle (as it does when a client comes or goes). So work that appears between
cycles, while the tasks run or in the motion step is done in the same cycle as if the
hook were called every cycle; a hook must not gain begin work from another client's
`begin_cycle`, nor end work from an earlier client's `end_cycle` (it would start a cycle
late). A client that keeps `PassiveClient`'s `begin_cycle`, `end_cycle` or `next_event`
(it has nothing to do there) costs no call of it either.
"""

from __future__ import annotations

from collections.abc import Callable
from types import MethodType
from typing import Protocol, runtime_checkable

BEGIN, END = "begin_cycle", "end_cycle"
"""The two hooks, as `has_work` names them."""


@runtime_checkable
class CycleClient(Protocol):
    """A run side stepped by the controller's cycle (see the module docstring); every
    client derives from `PassiveClient`, which gives each capability its default."""

    observes_motion: bool
    samples_skipped_cycles: bool
    clock_driven: bool

    def begin_cycle(self) -> None: ...

    def end_cycle(self) -> None: ...

    def busy(self) -> bool: ...

    def next_sample(self, cycle: int) -> int: ...

    def next_event(self) -> int | None: ...

    def still_running(self) -> list: ...

    def has_work(self, hook: str) -> bool: ...

    def watch_work(self, callback: Callable[[], None]) -> None: ...

    def work_changed(self) -> None: ...


class PassiveClient:
    """A client with no work of its own, and the default of every capability: the base
    of every client (a client overrides what it offers)."""

    observes_motion = True
    """True if a hook reads the state of moving axes (see the module docstring)."""

    touches_axes = True
    """True if a hook reads or writes an axis or its drive (see the module docstring)."""

    samples_skipped_cycles = False
    """True if `end_cycle` must see every cycle a jump passes (a recorder)."""

    clock_driven = False
    """True if `begin_cycle` only writes values of the clock's cycle."""

    def begin_cycle(self) -> None:
        """Nothing before the tasks."""

    def end_cycle(self) -> None:
        """Nothing after the motion step."""

    def busy(self) -> bool:
        return False

    def next_sample(self, cycle: int) -> int:
        """A recorder's next sampled cycle from `cycle` on (`samples_skipped_cycles`)."""
        return cycle

    def next_event(self) -> int | None:
        return None

    def still_running(self) -> list:
        return []

    def has_work(self, hook: str) -> bool:
        """False while the hook `hook` (BEGIN or END) has nothing to do: the controller
        leaves it out until `work_changed()` (see the module docstring)."""
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


def is_default(bound: Callable, default: Callable) -> bool:
    """True if the bound method `bound` is `PassiveClient`'s `default` (not overridden by
    the client's class, nor replaced on the instance)."""
    return isinstance(bound, MethodType) and bound.__func__ is default


def motion_observation(client: PassiveClient) -> bool | None:
    """`client.observes_motion` if it is a constant of its class; None if it may change
    (a property, or set on the instance): then it is asked at every jump."""
    declared = type(client).observes_motion
    if isinstance(declared, property) or "observes_motion" in vars(client):
        return None
    return bool(declared)


def hooks_touch_axes(clients: list) -> bool:
    """True if a client of `clients` that touches axes (`touches_axes`) has a hook the
    cycle calls (`active_hooks`) or samples skipped cycles."""
    for c in clients:
        if c.touches_axes and (c.samples_skipped_cycles or active_hooks([c], BEGIN)
                               or active_hooks([c], END)):  # fmt: skip
            return True
    return False


def hooked_clients(clients: list, name: str) -> list:
    """The clients, in order, whose `name` hook (BEGIN or END) the cycle must call:
    not a `PassiveClient`'s inherited no-op, and its client has work for it now
    (`has_work`)."""
    begin = name == BEGIN
    noop = PassiveClient.begin_cycle if begin else PassiveClient.end_cycle
    return [
        c
        for c in clients
        if not is_default(c.begin_cycle if begin else c.end_cycle, noop) and c.has_work(name)
    ]


def active_hooks(clients: list, name: str) -> list:
    """The bound `name` methods of `hooked_clients(clients, name)`: what the cycle calls."""
    return [getattr(c, name) for c in hooked_clients(clients, name)]
