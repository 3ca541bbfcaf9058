"""The run-time API of generated PDL code: every name `lower*.py` emits, bound to one drive.

`runtime_namespace(drive)` returns the globals dict the compiled module runs in. The
generated code calls only the names of this module:

    _M _H _F            long/short/float views of the drive memory
    _S _ST _MEND        system variable slots, state bytes, memory size [words]
    _FS                 one-float scratch view: rounds promoted floats to float32
    _w32 _w16 _rnd      integer wrapping and float->integer rounding
    _mod _divi _sign _sin _cos _sqrt _shift _bitset _bitclr _bittog _unsign
    _memcpy _memset _memmin _memmax _memsum _fill _wbl
    _ldl _stl _ldf _stf pointer access;  _oob index fault
    _sw _set _tog _stv  system variable write, state set/toggle/read through an address
    _print _lock _unlock _kill _push _pop _enter _land _Exit
"""

from __future__ import annotations

from motionvm.lang.pdl import rt_builtins as bi
from motionvm.lang.pdl.drive_task import DriveState, Task
from motionvm.lang.pdl.rt_memory import round_int, w16, w32
from motionvm.runtime.errors import RuntimeFault, TaskExit


def _rnd(x: float, bits: int = 32) -> int:
    return round_int(x, bits)


def runtime_namespace(drive: DriveState) -> dict[str, object]:
    """The globals of the compiled program, for one drive."""
    mem = drive.mem
    store = drive.sysvars
    mf = bi.MemFunctions(mem)
    cfg = drive.config
    zeros = memoryview(bytearray(4 * cfg.stack_words)).cast("i")
    kinds = mem.kinds

    def oob(name: str, index: int) -> int:
        raise RuntimeFault(
            f"index {index} of '{name}' is out of range: it leaves the drive's memory "
            f"({mem.user_words:,} long words of user variables)"
        )

    def push(t: Task) -> None:
        t.depth += 1
        if t.depth > cfg.max_depth:
            raise RuntimeFault(
                f"stack overflow: more than {cfg.max_depth} nested calls (a 'call' without "
                "'ret', or recursion without an end?)"
            )

    def pop(t: Task) -> None:
        t.depth -= 1

    def enter(t: Task, frame_kinds: bytes, n_params: int) -> None:
        bp = t.sp
        sp = bp + len(frame_kinds)
        if t.depth >= cfg.max_depth:
            raise RuntimeFault(
                f"stack overflow: more than {cfg.max_depth} nested calls (recursion without an end?)"
            )
        if sp > t.limit:
            raise RuntimeFault(
                f"stack overflow: procedure frames need more than the task's "
                f"{cfg.stack_words} stack words"
            )
        t.sp = sp
        t.depth += 1
        kinds[bp:sp] = frame_kinds
        if sp > bp + n_params:
            mem.M[bp + n_params : sp] = zeros[: sp - bp - n_params]

    def land(table: dict[int, int], offset: int, label: str) -> int:
        pc = table.get(offset)
        if pc is None:
            raise RuntimeFault(
                f"'goto {label}[{offset}]' does not land on the start of a statement after "
                f"'{label}' (valid offsets: {', '.join(map(str, sorted(table))) or 'none'})"
            )
        return pc

    def kill(t: Task, n: int) -> None:
        if n == t.id:
            raise TaskExit()
        if not 0 <= n < len(drive.tasks):
            raise RuntimeFault(f"'kill {n}': there is no task {n} (tasks are 0..3)")
        drive.kill(n)

    def lock(t: Task) -> None:
        if drive.lock_owner is None:
            drive.lock_owner = t.id

    def unlock(t: Task) -> None:
        if drive.lock_owner == t.id:
            drive.lock_owner = None

    ns: dict[str, object] = {
        "_M": mem.M,
        "_H": mem.H,
        "_F": mem.F,
        "_S": store.S,
        "_ST": store.ST,
        "_MEND": mem.size,
        "_FS": memoryview(bytearray(4)).cast("f"),
        "_w32": w32,
        "_w16": w16,
        "_rnd": _rnd,
        "_mod": bi.c_mod,
        "_divi": bi.divi,
        "_sign": bi.sign,
        "_sin": bi.f_sin,
        "_cos": bi.f_cos,
        "_sqrt": bi.f_sqrt,
        "_shift": bi.shift,
        "_bitset": bi.bitset,
        "_bitclr": bi.bitclr,
        "_bittog": bi.bittog,
        "_unsign": bi.unsign,
        "_memcpy": mf.memcpy,
        "_memset": mf.memset,
        "_memmin": mf.memmin,
        "_memmax": mf.memmax,
        "_memsum": mf.memsum,
        "_fill": mem.fill,
        "_wbl": mem.write_block,  # writes a list-backed array back (lower_cache.py)
        "_ldl": mem.load_long,
        "_stl": mem.store_long,
        "_ldf": mem.load_float,
        "_stf": mem.store_float,
        "_oob": oob,
        "_sw": store.write,
        "_set": store.set_state,
        "_tog": store.toggle_state,
        "_stv": store.state_value,
        "_print": drive.print_message,
        "_lock": lock,
        "_unlock": unlock,
        "_kill": kill,
        "_push": push,
        "_pop": pop,
        "_enter": enter,
        "_land": land,
        "_Exit": TaskExit,
        "__builtins__": {
            "range": range,
            "max": max,
            "min": min,
            "abs": abs,
            "ValueError": ValueError,
            "Exception": Exception,
        },
    }
    ns.update(drive.program.tables)
    return ns
