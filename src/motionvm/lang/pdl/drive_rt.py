"""The simulated PDL drive: 4 tasks on the 15 kHz phase clock, memory, axis, messages.

Scheduling (manual §1.1.1): time advances in phases of 1/15000 s;
`fclk` counts them as a wrapping signed 32-bit value. The runnable tasks (started,
not ended, not sleeping) take turns in increasing task number; task n keeps the CPU
for max(task_prior[n], 1) consecutive phases. A task holding `lock` gets every phase
until `unlock`. In its phase a task runs `config.budget` statements (default 1) and
yields; straight-line code between back-edges is charged as a whole and an overdraft
is paid by sitting out the next phases of that task (lower_body). `sleep` (ms) takes
the task out of the runnable set; `wait` (50 µs units) keeps it in and burns its
phases; `till` re-tests its condition once per phase of the task.

Host side (mpi.dll's RunFuncPdlN / killTask): `start(label)` runs a `_label` on the
lowest idle task, `kill(n)` stops task n. `#task/n` entries start at `reset()`.
A fault stops only its task:
`FILE:LINE:COL: runtime error in task N at t=S.ssssss s: MESSAGE` (drive_faults.py).
"""

from __future__ import annotations

from collections.abc import Callable

from motionvm.lang.coverage import bind
from motionvm.lang.pdl.drive_axis import PdlAxis
from motionvm.lang.pdl.drive_loop import run_phases
from motionvm.lang.pdl.drive_ns import runtime_namespace
from motionvm.lang.pdl.drive_sysvars import SYS_BASE, SysVarStore
from motionvm.lang.pdl.drive_task import N_TASKS, DriveConfig, Message, Task
from motionvm.lang.pdl.lower import PdlProgram
from motionvm.lang.pdl.lower_body import SLEEP
from motionvm.lang.pdl.rt_memory import Memory, round_int
from motionvm.lang.pdl.rt_print import format_message
from motionvm.lang.pdl.symbols import USER_MEMORY_WORDS
from motionvm.lang.pdl.sysvars import lookup
from motionvm.runtime.errors import RuntimeFault, TaskExit


class Drive:
    """One drive running one compiled PDL program."""

    def __init__(
        self,
        program: PdlProgram,
        config: DriveConfig | None = None,
        on_message: Callable[[Message], None] | None = None,
        on_fault: Callable[[str], None] | None = None,
    ) -> None:
        self.program = program
        self.config = config = config or DriveConfig()
        self.on_message = on_message or (lambda m: None)
        self.on_fault = on_fault or (lambda text: None)
        self.mem = Memory(USER_MEMORY_WORDS, config.stack_words, N_TASKS)
        for word, count, kind in program.kinds:
            self.mem.declare(word, count, kind)
        self.sysvars = SysVarStore()
        self.tasks = [Task(i, self.mem.stack_base(i), config.stack_words) for i in range(N_TASKS)]
        self.axis = PdlAxis(config.phase_rate, config.axis)
        self.lock_owner: int | None = None
        self.phase = 0
        self.faults: list[str] = []
        ns = runtime_namespace(self)
        bind(ns, program.code)
        exec(program.code, ns)  # noqa: S102 — our own generated code
        self._main = ns["_main"]
        self._slot = {
            name: SYS_BASE[name]
            for name in ("fclk", "task_num", "task_prior", "x_ref_pos", "ref_pos")
        }
        self._axis_slots = {
            SYS_BASE[k]: k
            for k in ("X_trg", "X_jvl", "X_stop_m", "X_vel_max", "X_acc", "X_dcc", "X_new_sm_fac")
        }
        for slot in self._axis_slots:
            self.sysvars.hooks[slot] = self._axis_write
        self.lcd = bytearray()
        """Every byte written to `lcdout`, in order."""
        self.sysvars.hooks[SYS_BASE["lcdout"]] = self._lcd_write
        self._bits = {k: lookup(k).address for k in ("x_run", "x_home", "LEFT_LIM", "X_LL")}  # type: ignore[union-attr]
        self.inputs: dict[int, int] = {}
        self._cur = N_TASKS - 1
        self._left = 0
        self.reset()

    # ---------------------------------------------------------------- host API

    @property
    def fclk(self) -> int:
        return self.sysvars.S[self._slot["fclk"]]  # type: ignore[return-value]

    @property
    def sim_time(self) -> float:
        """Simulated time since reset [s]."""
        return self.phase / self.config.phase_rate

    def reset(self) -> None:
        """Drive restart: zero memory, default system values, start the `#task/n` tasks."""
        for t in self.tasks:
            self._stop(t)
        self.mem.clear()
        S = self.sysvars.S
        for i in range(len(S)):
            S[i] = 0.0 if isinstance(S[i], float) else 0
        self.sysvars.ST[:] = bytes(len(self.sysvars.ST))
        ax = self.config.axis
        for name, v in (("X_vel_max", ax.v_max), ("X_acc", ax.acc), ("X_dcc", ax.dcc)):
            S[SYS_BASE[name]] = int(v)
        self.phase = 0
        S[self._slot["fclk"]] = self.config.fclk_start
        self.lock_owner = None
        self._cur, self._left = N_TASKS - 1, 0  # the first phase goes to the lowest task
        self._refresh_inputs()
        for n, pc in sorted(self.program.tasks.items()):
            self._launch(self.tasks[n], pc, f"#task/{n}")

    def start(self, label: str) -> int:
        """Run a `_label` on the lowest idle task (RunFuncPdlN); returns the task number."""
        if not label.startswith("_"):
            raise ValueError(
                f"refused: the host can only run labels starting with '_', not '{label}'"
            )
        pc = self.program.entries.get(label)
        if pc is None:
            raise ValueError(f"refused: the program has no label '{label}'")
        if any(t.gen is not None and t.label == label for t in self.tasks):
            raise ValueError(f"refused: label '{label}' is still running")
        for t in self.tasks:
            if t.gen is None:
                self._launch(t, pc, label)
                return t.id
        raise ValueError(f"refused: all {N_TASKS} tasks are busy")

    def start_top(self, task: int = 0) -> None:
        """Run the program from its first statement on `task` (tests, `--start top`)."""
        t = self.tasks[task]
        if t.gen is not None:
            raise ValueError(f"refused: task {task} is running")
        self._launch(t, 0, "")

    def kill(self, n: int) -> None:
        """Stop task n (killTask, or `kill n;` from another task)."""
        self._stop(self.tasks[n])

    def set_input(self, name: str, value: int) -> None:
        """Drive a digital input state (IN1, X_LL, ...) from outside."""
        sv = lookup(name)
        if sv is None or sv.kind != "state":
            raise KeyError(f"'{name}' is not a state")
        self.inputs[sv.address] = 1 if value else 0
        self.sysvars.ST[sv.address] = 1 if value else 0

    def read(self, name: str, index: int = 0) -> int | float:
        """A user or system variable's value, as KMI reads it."""
        g = self.program.globals.get(name)
        if g is not None:
            if g.type == "short" and not g.pointer:
                return self.mem.H[g.index + index]
            view = self.mem.F if g.type == "float" and not g.pointer else self.mem.M
            return view[g.index + index]
        sv = lookup(name)
        if sv is not None and sv.kind == "state":
            return self.sysvars.ST[sv.address]
        return self.sysvars.S[self.sysvars.slot(name, index)]

    def write(self, name: str, value: float, index: int = 0) -> None:
        """A host (KMI) write: refused for `_ro` variables and outside `_lp` limits."""
        g = self.program.globals.get(name)
        if g is None:
            self.sysvars.write(self.sysvars.slot(name, index), value)
            return
        if g.read_only:
            raise ValueError(f"refused: '{name}' is read-only (_ro)")
        if g.limits is not None and not g.limits[0] <= value <= g.limits[1]:
            raise ValueError(
                f"refused: {value} is outside the _lp limits {g.limits[0]}..{g.limits[1]} of '{name}'"
            )
        if g.type == "short" and not g.pointer:
            self.mem.H[g.index + index] = int(value)
        elif g.type == "float" and not g.pointer:
            self.mem.F[g.index + index] = value
        else:
            self.mem.M[g.index + index] = int(value)

    @property
    def busy(self) -> bool:
        """True while a task runs or the axis moves."""
        return self.axis.moving or any(t.gen is not None for t in self.tasks)

    def next_phase(self) -> int | None:
        """The first phase, from `phase` on, in which something of the drive can change:
        `phase` while the axis moves or a task is runnable (also one that busy-waits or
        pays an overdraft), else the earliest wake-up of a sleeping task (only the lock
        holder's while a task holds the lock); None once every task has ended and the
        axis rests. The phases before it are the ones the phase loop skips."""
        if self.axis.moving:
            return self.phase
        owner = self.lock_owner
        if owner is not None and self.tasks[owner].gen is not None:
            wake = self.tasks[owner].wake
        else:
            wakes = [t.wake for t in self.tasks if t.gen is not None]
            if not wakes:
                return None
            wake = min(wakes)
        return max(wake, self.phase)

    # ---------------------------------------------------------------- internals used by tasks

    def print_message(self, t: Task, k: int, args: tuple) -> None:
        fmt = self.program.formats[k]
        msg = Message(self.phase, t.id, fmt.mode1, fmt.mode2, format_message(fmt, args))
        self.on_message(msg)

    def _axis_write(self, slot: int, value: float) -> None:
        self.axis.write(self._axis_slots[slot], value)
        self._sync_axis()

    def _lcd_write(self, slot: int, value: float) -> None:
        byte = int(value) & 0xFF  # an 8-bit output register: the low byte is sent
        self.sysvars.S[slot] = byte
        self.lcd.append(byte)

    def _launch(self, t: Task, pc: int, label: str) -> None:
        t.sp = self.mem.stack_base(t.id)
        t.depth = 0
        t.debt = 0
        t.wake = t.busy_until = self.phase
        t.label = label
        gen = self._main(t, pc)
        next(gen)
        t.gen = gen

    def _stop(self, t: Task) -> None:
        gen = t.gen
        t.gen = None
        if self.lock_owner == t.id:
            self.lock_owner = None
        if gen is not None:
            try:
                gen.close()
            except BaseException:  # noqa: BLE001, S110 — the task is stopped either way
                pass

    def fault(self, t: Task, exc: BaseException) -> None:
        """Report a task's fault with the user's file and line; the drive keeps running."""
        from motionvm.lang.pdl.drive_faults import describe_fault

        text = describe_fault(self.program, t.id, exc, self.sim_time)
        self.faults.append(text)
        self.on_fault(text)

    def _sync_axis(self) -> None:
        ax = self.axis
        S, ST = self.sysvars.S, self.sysvars.ST
        p = ax.position
        S[self._slot["x_ref_pos"]] = round_int(p)
        S[self._slot["ref_pos"]] = p
        b = self._bits
        ST[b["x_run"]] = 1 if ax.moving else 0
        ST[b["x_home"]] = 1 if ax.home() else 0
        if self.config.axis.left_limit is not None:
            ST[b["LEFT_LIM"]] = ST[b["X_LL"]] = 1 if ax.left_limit() else 0

    def _refresh_inputs(self) -> None:
        ST = self.sysvars.ST
        for bit in range(len(ST)):
            if self.sysvars._is_input[bit]:
                ST[bit] = self.inputs.get(bit, 0)
        self._sync_axis()
        self.sysvars.input_written = False

    # ---------------------------------------------------------------- the phase loop

    def run(self, until: float | None = None) -> bool:
        """Run until every task ended and the axis stopped, or `until` [s]; True if done.

        The drive alone, without a controller or a machine (tests, scripts): a run of
        `motionvm` puts the drive on the controller's clock instead (machine_drives.py)."""
        limit = None if until is None else round(until * self.config.phase_rate)
        return self.run_phases(None if limit is None else max(0, limit - self.phase))

    def run_phases(self, count: int | None) -> bool:
        """Run at most `count` phases (None: no limit); True once the drive is idle."""
        return run_phases(self, count)


__all__ = ["SLEEP", "Drive", "DriveConfig", "Message", "RuntimeFault", "Task", "TaskExit"]
