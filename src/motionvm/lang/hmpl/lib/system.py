"""HMPL built-ins of manual chapter 2 that need no axis, and the task functions of chapter 16.

Sleep, RunScheduler and MutexLock are blocking: generator methods that yield to the
kernel (`None` = next cycle, int = the cycle to wake at). Decisions where the manual is
silent: Sleep(ms) waits ceil(ms / cycle) cycles (at least one); a task started by
StartTask gets its first slice in the next cycle. The owners of the 8 mutexes are kept
by the run time (`rt.mutex_owner`), which frees a task's mutexes when it stops. A task
function that fails returns the code of table 18.1.1.1 (a bad task id 0x107, a running
task 0x108, an unknown function 0x109, a task without a program or main 0x10A) and
stores it for GetSystemLastErr; StopTask of a stopped task succeeds (0). The bus and
system-state functions (IsSystemInit ..., GetECATSt) are in bus.py.
"""

from __future__ import annotations

import math
import zlib

from motionvm import __version__
from motionvm.lang.hmpl.lib.base import Library, builtin
from motionvm.motion import axis_status as st
from motionvm.runtime.errors import RuntimeFault, TaskExit

FIRMWARE_VERSION = f"motionvm {__version__}"
FIRMWARE_DATE = "2026/11/25"
MODEL_NUMBER = "MVM-SIM-64"

# Timer object layout (ctypes_.TIMER): int32 start [ms] at 0, int32 flags at 4
_PREV_IN, _RUNNING, _Q = 1, 2, 4


class SystemLib(Library):
    """Chapter 2 (system, Sleep, events are in strings.py, mutexes, TON/TOF) and chapter 16."""

    # ------------------------------------------------------------ identity and state

    def _write_str(self, addr: int, text: str) -> int:
        self.mem.write_cstr(addr, text.encode("latin-1"), "buffer")
        return 0

    @builtin()
    def GetFirmwareVer(self, ver_buf: int) -> int:
        return self._write_str(ver_buf, FIRMWARE_VERSION)

    @builtin()
    def GetFirmwareDate(self, date_buf: int) -> int:
        return self._write_str(date_buf, FIRMWARE_DATE)

    @builtin()
    def GetFirmwareHash(self, hash_buf: int) -> int:
        h = zlib.crc32(FIRMWARE_VERSION.encode()) << 32 | zlib.crc32(FIRMWARE_DATE.encode())
        self.mem.store(hash_buf, "u64", h)
        return 0

    @builtin()
    def GetModelNum(self, mod_buf: int) -> int:
        return self._write_str(mod_buf, MODEL_NUMBER)

    # ------------------------------------------------------------ waiting

    @builtin(blocking=True)
    def Sleep(self, ms: int):
        if ms <= 0:
            yield None
            return None
        cycles = max(1, math.ceil(ms / self.rt.cycle_ms - 1e-9))
        yield self.rt.kernel.cycle + cycles
        return None

    @builtin(blocking=True)
    def RunScheduler(self):
        yield None

    def _mutex_id(self, mutex_id: int, fn: str) -> int:
        n = len(self.rt.mutex_owner)
        if not 0 <= mutex_id < n:
            raise RuntimeFault(f"{fn}: mutex id {mutex_id} out of range (0..{n - 1})")
        return mutex_id

    @builtin(blocking=True)
    def MutexLock(self, mutex_id: int):
        m = self._mutex_id(mutex_id, "MutexLock")
        owners = self.rt.mutex_owner
        me = self.rt.kernel.current.id
        if owners[m] == me:
            raise RuntimeFault(f"MutexLock: mutex {m} is already locked by this task")
        while owners[m] is not None:
            yield None
        owners[m] = me

    @builtin()
    def MutexUnlock(self, mutex_id: int) -> None:
        m = self._mutex_id(mutex_id, "MutexUnlock")
        owners = self.rt.mutex_owner
        if owners[m] == self.rt.kernel.current.id:
            owners[m] = None

    # ------------------------------------------------------------ timers

    def _timer(self, addr: int) -> tuple[int, int]:
        self.mem.check(addr, 8, "Timer pointer")
        return self.mem.load(addr, "i32"), self.mem.load(addr + 4, "i32")

    @builtin()
    def TON(self, timer_p: int, IN: int, PT: int) -> int:
        """On-delay: Q rises PT ms after IN rises; IN falling resets."""
        start, flags = self._timer(timer_p)
        now = self.rt.time_ms
        if IN:
            if not flags & _RUNNING:
                start, flags = now, flags | _RUNNING
            if now - start >= PT:
                flags |= _Q
        else:
            flags &= ~(_RUNNING | _Q)
        flags = flags | _PREV_IN if IN else flags & ~_PREV_IN
        self.mem.store(timer_p, "i32", start)
        self.mem.store(timer_p + 4, "i32", flags)
        return 1 if flags & _Q else 0

    @builtin()
    def TOF(self, timer_p: int, IN: int, PT: int) -> int:
        """Off-delay: Q follows IN up at once and falls PT ms after IN falls."""
        start, flags = self._timer(timer_p)
        now = self.rt.time_ms
        if IN:
            flags = (flags | _Q) & ~_RUNNING
        elif flags & _Q:
            if not flags & _RUNNING:
                start, flags = now, flags | _RUNNING
            if now - start >= PT:
                flags &= ~(_Q | _RUNNING)
        flags = flags | _PREV_IN if IN else flags & ~_PREV_IN
        self.mem.store(timer_p, "i32", start)
        self.mem.store(timer_p + 4, "i32", flags)
        return 1 if flags & _Q else 0

    # ------------------------------------------------------------ tasks (chapter 16)

    def _task_error(self, code: int) -> int:
        """Store `code` (table 18.1.1.1) as the system's last error and return it."""
        self.rt.commands.motion.system_last_error = code
        return code

    def _bad_task_id(self, task_id: int) -> bool:
        return not 0 <= task_id < len(self.rt.kernel.tasks)

    def _start(self, task_id: int, func_name: str | None) -> int:
        if self._bad_task_id(task_id):
            return self._task_error(st.SYS_NOT_VALID_TASKID)
        if self.rt.kernel.tasks[task_id].running:
            return self._task_error(st.SYS_TASK_IS_RUNNING)
        if task_id not in self.rt.program.tasks:
            return self._task_error(st.SYS_TASK_EMPTY)
        result = self.rt.start_task(task_id, func_name)
        if result:
            # the task has no main (2), or no function of that name without parameters (3)
            return self._task_error(
                st.SYS_TASK_EMPTY if func_name is None else st.SYS_FUNC_NOT_IN_TASK
            )
        return 0

    @builtin()
    def StartTask(self, task_id: int) -> int:
        return self._start(task_id, None)

    @builtin()
    def StartTaskFunc(self, task_id: int, func_name: int) -> int:
        fname = self.mem.read_cstr(func_name, "function name").decode("latin-1")
        return self._start(task_id, fname)

    @builtin()
    def StopTask(self, task_id: int) -> int:
        if self._bad_task_id(task_id):
            return self._task_error(st.SYS_NOT_VALID_TASKID)
        k = self.rt.kernel
        if k.current is not None and k.current.id == task_id:
            k.stop(task_id)
            raise TaskExit()
        if not k.tasks[task_id].running:
            return 0
        k.stop(task_id)
        return 0

    @builtin()
    def StopAllTask(self) -> None:
        if self.rt.kernel.stop_all():
            raise TaskExit()

    @builtin()
    def IsTaskStop(self, task_id: int) -> int:
        if self._bad_task_id(task_id):
            return self._task_error(st.SYS_NOT_VALID_TASKID)
        return 0 if self.rt.kernel.tasks[task_id].running else 1
