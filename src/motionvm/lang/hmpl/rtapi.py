"""The HMPL run time: loads a compiled program into a namespace and runs its tasks.

It owns the program's memory, the namespace generated code runs in (helpers, memory
views, built-ins bound as `b_NAME`), one memory stack per task, the 8 mutexes of
MutexLock/MutexUnlock (released when their task stops), message output, and fault
reports `FILE:LINE:COL: runtime error in task N at t=S.mmm s: MESSAGE` (the place of the
deepest frame of the user's code, the controller's simulated time). HIMC_GPI/HIMC_GPO read and write
the controller's digital I/O (`controller.io.gpio`, io/gpio.py; numbered from 1); the axis built-ins call the
motion commands (`commands`, motion/commands/) on the controller's motion kernel.
"""

from __future__ import annotations

import math
import os
import sys
import traceback
from collections.abc import Callable
from pathlib import Path
from types import CodeType

from motionvm.io.commands import IOCommands
from motionvm.lang.coverage import bind
from motionvm.lang.hmpl.cmemory import Memory, TaskStack
from motionvm.lang.hmpl.compiler import N_TASKS, STACK_SIZE, STATIC_SIZE
from motionvm.lang.hmpl.lib import library_classes
from motionvm.lang.hmpl.program import CompiledProgram
from motionvm.lang.hmpl.rthelpers import make_helpers
from motionvm.motion.commands import MotionCommands
from motionvm.motion.position_watch import PositionWatch
from motionvm.runtime.clients import PassiveClient
from motionvm.runtime.clock import stamp_prefix
from motionvm.runtime.errors import RuntimeFault
from motionvm.runtime.fault_position import Fault, user_frames
from motionvm.runtime.kernel import Kernel, Task

N_MUTEXES = 8
# Python's own frames per HMPL call are few; this bounds HMPL recursion depth.
RECURSION_LIMIT = 6000


_AXIS_SAFE_LIBS = frozenset({
    "motionvm.lang.hmpl.lib.system", "motionvm.lang.hmpl.lib.strings",
    "motionvm.lang.hmpl.lib.mathlib", "motionvm.lang.hmpl.lib.axis",
})  # fmt: skip
"""The built-in libraries that touch no axis, or only through the motion commands'
`MotionKernel.axis` (the axis chapter's commands and getters) and the status flags."""


def reads_axes(codes: list, libs: list) -> bool:
    """True if the generated code `codes` ((file, code object) pairs) may read or change
    an axis otherwise than through the built-ins of `_AXIS_SAFE_LIBS` (a built-in of
    another library, a Till on a position): `Kernel.reads_axes` (motion/deferred.py)."""
    allowed = {"b_" + name for lib in libs if type(lib).__module__ in _AXIS_SAFE_LIBS
               for name in lib.builtin_methods()}  # fmt: skip
    stack = [code for _fname, code in codes]
    while stack:
        code = stack.pop()
        for name in code.co_names:
            if name == "_till_pos" or (name.startswith("b_") and name not in allowed):
                return True
        stack.extend(c for c in code.co_consts if isinstance(c, CodeType))
    return False


def _plain_to_gen(fn: Callable[[], object]):
    """Run a function that never blocks as a task body."""
    fn()
    return
    yield  # pragma: no cover — makes this a generator


class HmplRuntime(PassiveClient):
    """One loaded HMPL program on a controller (kernel + clock): a cycle client whose
    `begin_cycle` updates the system variables. Its tasks keep the run going and wake it
    up through the controller's task kernel, so as a client it is never busy and has no
    next event of its own (`PassiveClient`)."""

    observes_motion = False  # its hooks write the clock's system variables only
    touches_axes = False
    clock_driven = True  # `begin_cycle` writes values of the clock only (sim/jumps.py)

    def __init__(
        self,
        controller,
        program: CompiledProgram,
        mem: Memory,
        *,
        emit: Callable[[str], None],
        report: Callable[[str], None],
        data_dir: Path,
        task_slice: int = 2000,
    ) -> None:
        self.controller = controller
        self.kernel: Kernel = controller.kernel
        self.program = program
        self.mem = mem
        self._emit = emit
        self._report = report
        self.data_dir = Path(data_dir)
        self.task_slice = task_slice
        self.events: list[tuple[float, int, str, object]] = []
        self.event_callbacks: list[Callable[[str, object], None]] = []
        self.faults = 0
        self.stamp = False
        self._inputs, self._outputs = controller.io.gpio.inputs, controller.io.gpio.outputs
        self.mutex_owner: list[int | None] = [None] * N_MUTEXES
        """The task id holding each mutex (MutexLock), None while it is free."""
        self.commands = MotionCommands(controller.motion)
        """The motion commands in manual units that the axis built-ins call."""
        self.io_commands = IOCommands(controller.io)
        """The I/O commands (chapters 9, 10) that the GPIO and AIO built-ins call."""
        self.user_files = {fname for fname, _ in program.codes}
        self.stacks = [
            TaskStack(mem, STATIC_SIZE + i * STACK_SIZE, STACK_SIZE) for i in range(N_TASKS)
        ]
        self.user_table_addr = program.sysvars["system_user_table"].addr
        self._time_addr = program.sysvars["system_timeInMs"].addr // 4
        self._fclk_addr = program.sysvars["system_fclk"].addr // 4
        self._clock = controller.clock
        self._i32 = mem.i32
        self._cycle_ms = controller.cycle_time * 1000.0
        self._whole_ms = self._cycle_ms == 1.0
        """What `begin_cycle` reads each cycle, looked up once."""
        self.ns = make_helpers(mem)
        self.ns["__name__"] = "hmpl_program"
        self.ns["_gpi"] = self._gpi
        self.ns["_gpo"] = self._gpo
        self.ns["_gpo_set"] = self._gpo_set
        self.ns["_till_ms"] = self._till_ms
        self.ns["_till_pos"] = self._till_pos
        self.ns["_end_records"] = self.kernel.end_records
        self.libs = [cls(self) for cls in library_classes()]
        for lib in self.libs:
            for hname, (attr, _blocking) in lib.builtin_methods().items():
                self.ns["b_" + hname] = getattr(lib, attr)
        for _fname, code in program.codes:
            bind(self.ns, code)
            exec(code, self.ns)
        self.kernel.before_resume = self._resume_hook()
        self.kernel.reads_axes = reads_axes(program.codes, self.libs)
        self.kernel.on_fault = self._on_fault
        self.kernel.on_stop = self._on_stop
        if sys.getrecursionlimit() < RECURSION_LIMIT:
            sys.setrecursionlimit(RECURSION_LIMIT)

    def close(self) -> None:
        """The run is over: free the program's memory and namespace now, without waiting
        for a full garbage collection (the generated code and its namespace form a cycle).
        The tasks still suspended are closed first, while the names their `finally` and
        `except` clauses use still exist."""
        for t in self.kernel.tasks:
            if t.gen is not None:
                self.kernel.stop(t.id)
        self.ns.clear()
        self.mem.release()

    # ------------------------------------------------------------ clock

    @property
    def cycle(self) -> int:
        return self.kernel.cycle

    @property
    def cycle_ms(self) -> float:
        return self.controller.cycle_time * 1000.0

    @property
    def sim_time(self) -> float:
        """Simulated time [s]."""
        return self.kernel.cycle * self.controller.cycle_time

    @property
    def time_ms(self) -> int:
        """Controller time [ms], as system_timeInMs shows it."""
        return int(round(self.kernel.cycle * self.cycle_ms))

    @property
    def current_task_id(self) -> int:
        t = self.kernel.current
        return t.id if t is not None else -1

    def begin_cycle(self) -> None:
        """Update the system variables of manual 22.2 for this cycle."""
        cycle = self._clock.cycle
        i32 = self._i32
        if cycle <= 0x7FFFFFFF:  # neither value wrapped yet (24 days of 1 ms cycles)
            # 1 ms cycles: no arithmetic (round(cycle * 1.0) is the cycle); an operation on
            # an int wider than 30 bits costs an allocation
            if self._whole_ms:
                i32[self._time_addr] = cycle
            else:
                i32[self._time_addr] = round(cycle * self._cycle_ms) & 0x7FFFFFFF
            i32[self._fclk_addr] = cycle
            return
        # time_ms inlined (the same arithmetic; round of a float is an int)
        i32[self._time_addr] = round(cycle * self._cycle_ms) & 0x7FFFFFFF
        # system_fclk: +1 per controller cycle (22.2), wrapping as a signed 32-bit int
        i32[self._fclk_addr] = ((cycle + 0x80000000) & 0xFFFFFFFF) - 0x80000000

    def estop_input(self, n: int) -> None:
        """The E-stop input `n` rose (io/gpio.py): every task stops, the calling one
        (a task whose SetGPIInvert made it rise) last; the report names the code."""
        from motionvm.motion.axis_status import SYS_EMERGENCY_STOP
        from motionvm.runtime.errors import TaskExit

        if not self.kernel.any_running:
            return
        self._report(
            f"motionvm: {f'E-stop input {n}' if n else 'E-stop'} at t={self.sim_time:.3f} s: "
            "every axis disabled, "
            f"every task stopped (eERR_EMERGENCY_STOP 0x{SYS_EMERGENCY_STOP:08X})"
        )
        if self.kernel.stop_all():
            raise TaskExit()

    def _till_ms(self, limit, strict: bool) -> int | None:
        """The first cycle after this one whose system_timeInMs (as `begin_cycle` sets
        it) is >= `limit` (> if `strict`): where `Till(system_timeInMs >= limit)` wakes
        up. None (poll next cycle) if the time would wrap before it."""
        cycle_ms = self.controller.cycle_time * 1000.0
        x = float(limit)
        cycle = self.kernel.cycle + 1
        if x > 0x7FFFFFFF:
            return None
        if x > 0.0:
            cycle = max(cycle, math.floor((x - 1.0) / cycle_ms) - 1)  # time there < x - 0.5
        while True:
            t = round(cycle * cycle_ms)
            if t > 0x7FFFFFFF:
                return None
            if t > x if strict else t >= x:
                return cycle
            cycle += 1

    def _till_pos(self, axis_id, threshold, rising: bool, code: int) -> int:
        """The yield of `Till(GetPosFb(axis_id) >= threshold)` (rising; falling: <=, and
        the strict forms alike) while its condition is false: `code` (EVENT_WAIT or
        EVENT_POLL), with the position it waits for handed to the controller's jumps
        (`Task.watch`). A bad axis id hands nothing (GetPosFb answers 0 then)."""
        a = self.controller.motion.axis(axis_id)
        if a is not None:
            self.kernel.current.watch = PositionWatch(a, float(threshold), rising)
        return code

    def still_running(self) -> list:
        """Every running task and the line of the user's code where it waits."""
        from motionvm.runtime.waits import Waiting, suspended_at, why_waiting

        out = []
        cycle = self.kernel.cycle
        for t in self.kernel.tasks:
            if t.gen is None:
                continue
            at = suspended_at(t.gen, self.user_files.__contains__)
            if at is None:
                out.append(Waiting(f"task {t.id}", why="not started yet"))
                continue
            asleep = t.wake_cycle > cycle and not t.event_wait
            wake = t.wake_cycle * self.controller.cycle_time if asleep else None
            out.append(Waiting(f"task {t.id}", *at, why=why_waiting(at, wake, t.gen)))
        return out

    def scope_sources(self) -> list:
        """The program's system and global variables as scope channels."""
        from motionvm.lang.hmpl.scope_source import HmplSource

        return [HmplSource(self)]

    # ------------------------------------------------------------ output

    def emit(self, text: str) -> None:
        """One message line from the current task (Print, SendMsgEvent, ...)."""
        if self.stamp:
            text = stamp_prefix(self.sim_time, f"task {self.current_task_id}") + text
        self._emit(text)

    def emit_event(self, kind: str, payload: object) -> None:
        """Deliver a host event (SendEvent id or SendMsgEvent text) to registered callbacks."""
        self.events.append((self.sim_time, self.current_task_id, kind, payload))
        for cb in self.event_callbacks:
            cb(kind, payload)

    # ------------------------------------------------------------ GPIO

    @staticmethod
    def _gpio_index(bits: list[int], i: int, what: str) -> int:
        """Input or output number `i` (from 1, as GetGPI numbers them) as a list index."""
        if not 1 <= i <= len(bits):
            raise RuntimeFault(f"{what}({i}): index out of range (1..{len(bits)})")
        return i - 1

    def _gpi(self, i: int) -> int:
        bits = self._inputs
        return bits[self._gpio_index(bits, i, "HIMC_GPI")]

    def _gpo(self, i: int) -> int:
        bits = self._outputs
        return bits[self._gpio_index(bits, i, "HIMC_GPO")]

    def _gpo_set(self, i: int, v) -> int:
        bits = self._outputs
        bits[self._gpio_index(bits, i, "HIMC_GPO")] = 1 if v else 0
        return 1 if v else 0

    # ------------------------------------------------------------ tasks

    def boot(self) -> None:
        """Initialize globals (once, as at download) and start task 0 and _AUTORUN_ tasks."""
        for tid in sorted(self.program.tasks):
            self.ns[self.program.tasks[tid].init]()
        for tid in sorted(self.program.tasks):
            info = self.program.tasks[tid]
            if info.entry is not None and (tid == 0 or info.autorun):
                self.start_task(tid, None)

    def start_task(self, task_id: int, func_name: str | None) -> int:
        """Start `main` (or `func_name`) of a task; 0 on success, non-zero on failure."""
        info = self.program.tasks.get(task_id)
        if info is None or self.kernel.tasks[task_id].running:
            return 1
        if func_name is None:
            sym = info.functions.get("main")
            if sym is None:
                return 2
        else:
            sym = info.functions.get(func_name) or self.program.tasks.get(0, info).functions.get(
                func_name
            )
            if sym is None or sym.type.params:
                return 3
        fn = self.ns[sym.pyname]
        gen = fn() if sym.is_generator else _plain_to_gen(fn)
        self.stacks[task_id].reset()
        self.kernel.start(task_id, gen, func_name or "main")
        return 0

    def _resume_hook(self) -> Callable[[Task], None]:
        """The kernel's `before_resume`: a task's slice budget and memory stack are the
        generated code's `_budget` and `_stack` while it runs (what it needs bound once)."""
        ns, stacks, budget = self.ns, self.stacks, self.task_slice

        def before_resume(t: Task) -> None:
            ns["_budget"] = budget
            ns["_stack"] = stacks[t.id]

        return before_resume

    def _on_stop(self, t: Task) -> None:
        self.stacks[t.id].reset()
        owners = self.mutex_owner
        for m, owner in enumerate(owners):
            if owner == t.id:
                owners[m] = None

    def _on_fault(self, t: Task, exc: BaseException) -> None:
        self.faults += 1
        where = self._user_location(exc)
        file, line, col = where
        msg = self._fault_message(exc)
        if msg is None:  # no fault of the program: an error of motionvm (or of a host callback)
            msg = "".join(traceback.format_exception_only(type(exc), exc)).strip()
            kind = "internal"
            text = (
                f"{self._place(where)}: internal error in task {t.id}: {msg}\n"
                "  this is a bug in motionvm, not in your program; please file an issue with the program attached"
            )  # fmt: skip
        else:
            kind = "runtime"
            text = f"{self._place(where)}: runtime error in task {t.id} at t={self.sim_time:.3f} s: {msg}"  # fmt: skip
        self._report(
            Fault(
                text,
                file=file,
                line=line,
                col=col,
                time=self.sim_time,
                message=msg,
                language="HMPL",
                task=t.id,
                kind=kind,
            )  # fmt: skip
        )

    def _user_location(self, exc: BaseException) -> tuple[str, int, int]:
        """(file, line, column) of the deepest frame of the user's code (`<motionvm>`, 0,
        0: none)."""
        frames = user_frames(exc.__traceback__, self.user_files.__contains__)
        if not frames:
            return "<motionvm>", 0, 0
        f = frames[-1]
        return f.file, f.line, f.col

    @staticmethod
    def _place(where: tuple[str, int, int]) -> str:
        """`FILE:LINE:COL`, or the file alone when the place is unknown."""
        file, line, col = where
        return f"{file}:{line}:{col}" if line else file

    @staticmethod
    def _fault_message(exc: BaseException) -> str | None:
        if isinstance(exc, RuntimeFault):
            return str(exc)
        if isinstance(exc, RecursionError):
            return "stack overflow: function calls nested too deeply (infinite recursion?)"
        if isinstance(exc, MemoryError):
            return "out of memory"
        if isinstance(exc, IndexError) and "memoryview" in str(exc):
            return "memory access outside the program's memory (bad pointer)"
        return None


def data_dir_default(machine_dir: Path | None) -> Path:
    """The machine's data folder: $MOTIONVM_DATA_DIR, else ./motionvm-data."""
    env = os.environ.get("MOTIONVM_DATA_DIR")
    if env:
        return Path(env)
    return (machine_dir or Path.cwd()) / "motionvm-data"
