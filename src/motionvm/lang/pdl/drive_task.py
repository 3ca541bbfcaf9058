"""The PDL drive's data: its configuration, its task slots, the messages it sends, and
`DriveState`, what the phase loop (drive_loop.py) and the run-time namespace of the
generated code (drive_ns.py) see of a drive (`drive_rt.Drive`, which hands itself to them).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol

from motionvm.lang.pdl.drive_axis import AxisConfig, PdlAxis
from motionvm.lang.pdl.drive_sysvars import SysVarStore
from motionvm.lang.pdl.lower import PdlProgram
from motionvm.lang.pdl.rt_memory import Memory

N_TASKS = 4


@dataclass
class DriveConfig:
    """Drive parameters; the defaults are the manual's."""

    phase_rate: int = 15_000
    """Phases per second [1/s] (configurable, 20000 for older drives)."""
    budget: int = 1
    """Statements a task executes per phase."""
    wait_unit_us: int = 50
    """`wait` unit [µs]."""
    max_depth: int = 64
    """Nested `call`s and procedure calls per task."""
    stack_words: int = 4096
    """Procedure frame memory per task [long words]."""
    fclk_start: int = 0
    """fclk at reset (tests start it near 2^31 to see the wrap-around)."""
    axis: AxisConfig = field(default_factory=AxisConfig)


class Task:
    """One of the drive's 4 task slots."""

    __slots__ = ("busy_until", "debt", "depth", "gen", "id", "label", "limit", "sp", "wake")

    def __init__(self, tid: int, base: int, words: int) -> None:
        self.id = tid
        self.gen = None
        self.sp = base
        self.limit = base + words
        self.depth = 0
        self.wake = 0
        self.busy_until = 0
        self.debt = 0
        self.label = ""


@dataclass
class Message:
    """One printl/prints/retprintl message as the host receives it."""

    phase: int
    task: int
    mode1: int
    mode2: int
    text: str


class DriveState(Protocol):
    """What the phase loop and the generated code's namespace use of a drive."""

    program: PdlProgram
    config: DriveConfig
    mem: Memory
    sysvars: SysVarStore
    tasks: list[Task]
    axis: PdlAxis
    lock_owner: int | None
    phase: int
    _cur: int  # the task that ran last (the phase loop's round-robin position)
    _left: int  # phases it has left of its turn

    def kill(self, n: int) -> None:
        """Stop task n."""

    def print_message(self, t: Task, k: int, args: tuple) -> None:
        """Send the message of printl format k with its arguments."""

    def fault(self, t: Task, exc: BaseException) -> None:
        """Report a task's fault; the drive keeps running."""

    def _stop(self, t: Task) -> None:
        """End task t."""

    def _sync_axis(self) -> None:
        """Copy the axis's state into the system variables."""

    def _refresh_inputs(self) -> None:
        """Latch the inputs into the state bits."""
