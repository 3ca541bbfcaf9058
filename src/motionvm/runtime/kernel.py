"""The cooperative task scheduler: up to 64 tasks as Python generators on the cycle clock.

Each cycle the kernel resumes every ready task once, in task-id order. A task runs
until it yields: `None` means "resume me next cycle" (a slice used up, RunScheduler,
a wait that polls, such as Till or MutexLock); an int is the cycle to wake at (Sleep).
Two negative ints also mean "next cycle" and tell the controller more (`EVENT_WAIT`,
`EVENT_POLL`): the task polls a condition that can change only in a cycle the
controller computes, never in one it jumps over (an axis's status flag, an input),
so the clock may jump past it while nothing it tests changes (`quiet`).
Two more (`STATUS_WAIT`, `STATUS_POLL`) say the condition depends on nothing but the
answers of axis status flags: with a `recorder`, the kernel keeps the flags such a
poll read (`Task.record`), and the task need not be resumed while they answer the same
(`Task.record_holds`), whatever other tasks did since. A task that can yield neither
any more (`Kernel.end_records`: it entered a loop it never leaves that has no such
poll) records nothing from its next slice on.
A task ends when its generator returns, raises `TaskExit`, or faults; a fault stops
only that task and is reported through `on_fault`. No wall clock, no threads: the
same program gives the same schedule every run.
"""

from __future__ import annotations

from collections.abc import Callable, Generator
from dataclasses import dataclass

from motionvm.runtime.clock import Clock
from motionvm.runtime.errors import TaskExit

MAX_TASKS = 64

NOBODY: frozenset = frozenset()
"""`Kernel.wake_horizon`'s answer when no task it left out reads the flag asked about."""

EVENT_WAIT = -2
"""Yielded on entering a wait on a condition that only a computed cycle can change."""
EVENT_POLL = -1
"""Yielded by such a wait after its condition was evaluated again and still is false,
with nothing else run since the last yield (a quiet poll)."""
STATUS_WAIT = -4
"""EVENT_WAIT of a condition that depends only on the answers of status flags."""
STATUS_POLL = -3
"""EVENT_POLL of a condition that depends only on the answers of status flags."""


@dataclass
class Task:
    """One task slot; `gen` is None while the task is stopped."""

    id: int
    gen: Generator | None = None
    wake_cycle: int = 0
    name: str = ""
    starts: int = 0  # how many times the task was started
    context: object = None  # language run time's per-task data (e.g. the memory stack)
    event_wait: bool = False  # the last yield was EVENT_WAIT or EVENT_POLL (or STATUS_*)
    record: list | None = None
    """After a STATUS_WAIT or STATUS_POLL: the flags the task read in that slice, as
    (object, attribute, value), the condition's last evaluation among them; else None."""
    records: bool = True
    """False once the task can never again yield STATUS_WAIT or STATUS_POLL
    (`Kernel.end_records`): its slices need no record of the flags they read."""
    watch: Callable[[], bool] | None = None
    """After an EVENT_WAIT or EVENT_POLL whose condition also tests an axis's position:
    the position test alone (called: true if the wait's condition may hold now), which
    the controller's jumps also ask how far the axis may be advanced before it holds
    (`cycles(k)`: motion/position_watch.py, sim/jumps.py); else None."""

    @property
    def running(self) -> bool:
        return self.gen is not None

    def record_holds(self) -> bool:
        """True if the task waits on a status condition whose flags all answer what they
        answered when it polled: polled again now, it would find it false again."""
        record = self.record
        if not record or not self.event_wait:
            return False
        for read in record:
            if read is None or getattr(read[0], read[1]) != read[2]:
                return False
        return True


class Kernel:
    """Schedules tasks; language run times supply generators and per-task hooks."""

    def __init__(self, clock: Clock | None = None, n_tasks: int = MAX_TASKS) -> None:
        self.clock = clock if clock is not None else Clock()
        """The controller's clock; the kernel reads the cycle from it."""
        self.tasks = [Task(i) for i in range(n_tasks)]
        self.active: list[Task] = []
        """The running tasks in id order (a cycle visits only these); read only."""
        self._visits: tuple[Task, ...] = ()  # `_active` as of its last change, for run_cycle
        self.current: Task | None = None
        self.on_fault: Callable[[Task, BaseException], None] = lambda task, exc: None
        self.before_resume: Callable[[Task], None] = lambda task: None
        self.on_stop: Callable[[Task], None] = lambda task: None
        self._changed = False  # a task started or stopped since the last cycle's end
        self.quiet = False
        """True if in the last cycle run no task acted after a task polled an event (so
        every poll saw what the tasks of the cycle left) and no task started or stopped
        from outside."""
        self.event_waits = False
        """True if in the last cycle run a task waited on an event."""
        self.unrecorded_waits = False
        """True if in the last cycle run a task waited on an event without a `record`."""
        self.resumed = True
        """True if the last cycle run resumed a task (False: none was due)."""
        self.reads_axes = True
        """False while no running task can read or change an axis other than through the
        motion commands and status flags (the language run time that starts the tasks
        says so): the motion kernel may then defer moving axes (motion/deferred.py)."""
        self.recorder = None
        """An object whose `reads` list the status flags record while a task runs (the
        motion kernel), or None: no task keeps a `record`."""

    # ------------------------------------------------------------ control

    def start(self, task_id: int, gen: Generator, name: str = "", context: object = None) -> None:
        """Make a stopped task run `gen`, from the next cycle on."""
        t = self.tasks[task_id]
        t.gen = gen
        t.name = name
        t.wake_cycle = self.cycle + (1 if self.current is not None else 0)
        t.context = context
        t.starts += 1
        t.event_wait = False
        t.record = None
        t.records = True
        self._changed = True
        if t not in self.active:
            self.active.append(t)
            self.active.sort(key=lambda x: x.id)
            self._visits = tuple(self.active)

    def stop(self, task_id: int) -> None:
        """Stop a task: close its generator; `on_stop` then releases what it held."""
        t = self.tasks[task_id]
        gen = t.gen
        if gen is None:
            return
        t.gen = None
        if t is not self.current:
            try:
                gen.close()
            except (
                BaseException
            ):  # a finally clause of the user's code faulted; it is stopped anyway
                pass
        self._release(t)

    def stop_all(self) -> bool:
        """Stop every task, the calling one last; True if a task called it (it must then
        raise TaskExit to end its own slice)."""
        me = self.current
        for t in list(self.active):
            if t is not me:
                self.stop(t.id)
        if me is not None:
            self.stop(me.id)
            return True
        return False

    def _release(self, t: Task) -> None:
        self._changed = True
        if t in self.active:
            self.active.remove(t)
            self._visits = tuple(self.active)
        self.on_stop(t)

    @property
    def cycle(self) -> int:
        """The current cycle of the controller's clock."""
        return self.clock.cycle

    @property
    def any_running(self) -> bool:
        return bool(self.active)

    def next_wake(self) -> int | None:
        """The earliest cycle any running task wants to run, or None if none runs."""
        if not self.active:
            return None
        return min(t.wake_cycle for t in self.active)

    def idle_until(self, cycle: int) -> int | None:
        """The first cycle from `cycle` on whose `run_cycle` would resume a task (None:
        no task runs); in the cycles before it `run_cycle` would change nothing of this
        kernel. That needs the last cycle to have left the kernel as a cycle without a
        task due leaves it (no event wait, nothing started or stopped since, `quiet`);
        else the answer is `cycle`."""
        if self.event_waits or self._changed or not self.quiet:
            return cycle
        return self.next_wake()

    def wake_horizon(
        self, cycle: int, status_holds: Callable[[], bool], flag: str
    ) -> tuple[int | None, set | None, list]:
        """Where the clock may jump to as far as the tasks go, for time skipping: the
        earliest wake cycle of the running tasks (`cycle` as soon as one is due), leaving
        out those waiting on an event that would find their condition false again if
        polled now; the objects whose `flag` the tasks left out read (None: they test
        the whole status); and the position watches they wait on (`Task.watch`, each
        false now).

        A task waiting on an event without a `record` is left out only if the last
        cycle was `quiet`, no task started or stopped since, and `status_holds()` (the
        caller's: everything such a task tests is as it was right after the tasks of
        the last computed cycle)."""
        old_ok = None  # the tasks without a record: the whole status as it was
        wake = None
        watched: set | None = NOBODY
        watches = []
        for t in self.active:
            w = t.wake_cycle
            if w > cycle:
                if wake is None or w < wake:
                    wake = w
                continue
            if not t.event_wait:
                return cycle, None, watches
            if t.watch is not None:
                if t.watch():
                    return cycle, None, watches
                watches.append(t.watch)
            record = t.record
            if record is not None:
                for read in record:  # `Task.record_holds`, inline
                    if read is None:
                        return cycle, None, watches
                    obj, attr, value = read
                    if getattr(obj, attr) != value:
                        return cycle, None, watches
                    if attr == flag and watched is not None:
                        if watched is NOBODY:
                            watched = set()
                        watched.add(obj)
            else:
                if old_ok is None:
                    old_ok = self.quiet and not self._changed and status_holds()
                if not old_ok:
                    return cycle, None, watches
                watched = None
        return wake, watched, watches

    def forget_records(self) -> None:
        """Something outside the tasks changed what they test (a debugger wrote a task's
        local variable): no task is passed over by its `record` until it polls again."""
        for t in self.active:
            t.record = None
        self._changed = True

    def end_records(self) -> None:
        """The running task can never again yield STATUS_WAIT or STATUS_POLL (its
        language's code says so: it entered a loop it never leaves, with no such wait
        in it): from its next slice on, no record of the flags it reads is kept, as no
        `Task.record` would ever be taken from it. Until it is started again. (Outside
        a task's slice: nothing.)"""
        t = self.current
        if t is not None:
            t.records = False

    # ------------------------------------------------------------ one cycle

    def run_cycle(self) -> None:
        """Resume every task that is due in this cycle, once, in id order."""
        cycle = self.clock.cycle
        polled = stale = False  # a task polled an event; a task acted after that
        unrecorded = False  # a task polled an event without a record of its reads
        recorder = self.recorder
        before_resume = self.before_resume
        reads = None
        resumed = False
        for t in self._visits:  # a task started in this cycle runs from the next one
            gen = t.gen
            if gen is None or t.wake_cycle > cycle:
                continue
            resumed = True
            self.current = t
            before_resume(t)
            if recorder is not None:
                # (a task that can no longer poll a status keeps no record: `end_records`)
                recorder.reads = reads = [] if t.records else None
            t.record = t.watch = None
            try:
                y = gen.send(None)
            except StopIteration:
                self._finish(t)
                stale = stale or polled
            except TaskExit:
                self._finish(t)
                stale = stale or polled
            except BaseException as exc:
                if isinstance(exc, (KeyboardInterrupt, SystemExit)):
                    raise
                self._finish(t)
                self.on_fault(t, exc)
                stale = stale or polled
            else:
                if y is None:  # the common case first: resume me next cycle
                    if t.gen is gen:
                        t.wake_cycle = cycle + 1
                        t.event_wait = False
                    if polled:
                        stale = True
                elif t.gen is not gen:  # stopped or restarted itself
                    stale = stale or polled
                elif y < 0:  # EVENT_POLL (only polled) or EVENT_WAIT (acted, then polled)
                    t.wake_cycle = cycle + 1
                    t.event_wait = True
                    if y != EVENT_POLL and y != STATUS_POLL:
                        stale = stale or polled
                    polled = True
                    if y <= STATUS_POLL and reads:
                        t.record = reads
                    else:
                        unrecorded = True
                else:
                    t.wake_cycle = max(int(y), cycle + 1)
                    t.event_wait = False
                    stale = stale or polled
            finally:
                self.current = None
                if recorder is not None:
                    recorder.reads = None
        self.event_waits = polled
        self.unrecorded_waits = unrecorded
        self.resumed = resumed
        self.quiet = not stale and not self._changed
        self._changed = False

    def _finish(self, t: Task) -> None:
        if t.gen is not None:
            t.gen = None
            self._release(t)
