"""The HMPL side of the controller's servers: Native ASCII calls, variables, the ASCII agent.

`HmplComm` is a cycle client (after the HMPL run time) that the session attaches to
the controller's communication hub (comm/hub.py) as its
- `NativeTable`: a Native ASCII request calls the built-in of the program's namespace
  (`b_NAME`, the same object a task calls, with the same checks and error codes).
  Arguments are literals: numbers for `int`/`double` parameters (converted as C
  converts them), strings for `char *` inputs, named constants (HMPL_ABS, PI) as
  values. Out-parameters (manual `[out]`) are left out of the request: the reply is the
  return value (`OK` for void) followed by each out-parameter's value (a `char *` as a
  C string literal, any other pointer as its first element). Built-ins that wait (Sleep,
  Till, MutexLock, the client functions) only make sense inside a task and are refused.
  `HIMC_GPI(n)` and `HIMC_GPO(n)` read the I/O, `HIMC_GPO(n, v)` sets an output.
  `native_is_query` says which calls only read the machine (for a read-only server):
  the `Get...` and `Is...` built-ins, ReadSDO/ReadPDO (and their *Ex), `HIMC_GPI(n)`,
  `HIMC_GPO(n)`, and the math and string functions.
- `VariableTable` and variable requests: system and global variables by name
  (`system_dtest0`, `count`, `table[3]`), read and written as an assignment would.
- `AsciiAgentPort`: START_ASCII_AGENT's parser runs here, one received line at a time,
  as a task would run it (its loops yield at their slice, Sleep waits), with its own
  stack, under the id of the task that started the agent. A fault in the parser is
  reported like a task's and stops the agent (the client gets `ERR ...`).
"""

from __future__ import annotations

import collections
import json
import math
import re
from functools import lru_cache
from importlib import resources

from motionvm.comm.hub import CommHub, RequestError
from motionvm.lang.hmpl import ctypes_ as ct
from motionvm.lang.hmpl.catalog import builtin_signatures, constants
from motionvm.lang.hmpl.cmemory import TaskStack, shadow_pattern, wrap_scalar
from motionvm.lang.hmpl.lib import implemented_builtins
from motionvm.lang.hmpl.scope_source import READ_ONLY, HmplSource
from motionvm.runtime.clients import PassiveClient
from motionvm.runtime.errors import RuntimeFault, TaskExit
from motionvm.runtime.kernel import Task
from motionvm.runtime.scope import ScopeError
from motionvm.source.suggest import did_you_mean

SCRATCH_SIZE = 16 * 1024
"""Bytes for a Native ASCII call's strings and out-parameters."""
AGENT_STACK_SIZE = 64 * 1024
"""The ASCII agent's stack [bytes] (a task's size)."""
RES_SIZE = 2048
"""Bytes of the `res` buffer the parser writes its answer into."""
OUT_SIZE = 1024
"""Bytes reserved for each out-parameter."""
QUERIES = frozenset(
    """ReadSDO ReadSDOEx ReadPDO ReadPDOEx HIMC_GPI StringLen IsStringEqual StrFindChar
    StrFindCharEx StrFindStr sin cos tan asin acos atan atan2 abs fabs ceil floor ldexp exp
    pow log log10 sqrt cbrt hypot""".split()
)
"""Built-ins that only read, besides every `Get...` and `Is...` one."""
_CO_GENERATOR = 0x20
"""`co_flags` bit of a generator function (inspect.CO_GENERATOR, without importing inspect)."""
NO_AGENT = "ERR no ASCII agent is running (the program calls START_ASCII_AGENT)"


def _literal(value: object) -> object:
    """A host's Python argument as a Native ASCII literal: a str is a C string (bytes)."""
    if isinstance(value, str):
        return value.encode("utf-8")
    if isinstance(value, bool):
        return int(value)
    return value


@lru_cache(maxsize=1)
def _param_dirs() -> dict[str, list[str]]:
    """Built-in name -> the direction ("in", "out") of each parameter (manual [in]/[out])."""
    data = resources.files("motionvm.data").joinpath("hmpl_api.json").read_text("utf-8")
    return {e["name"]: [p.get("dir", "in") for p in e["params"]] for e in json.loads(data)}


def _stack(mem, size: int, name: str) -> TaskStack:
    base = mem.alloc_static(size, name)
    mem.shadow[base : base + size] = bytes(size)  # nothing valid until a frame is pushed
    return TaskStack(mem, base, size)


class HmplComm(PassiveClient):
    """The program's Native ASCII table, variables and ASCII agent (module docstring)."""

    observes_motion = False
    """Its only hook runs the ASCII agent's parser, which `next_event` wakes at its cycles
    (a line received, its Sleep ended), never in a cycle a jump passes."""

    def __init__(self, rt) -> None:
        self.rt = rt
        self.vars = HmplSource.for_native(rt)
        self.scratch = _stack(rt.mem, SCRATCH_SIZE, "<native ascii>")
        self.agent_stack = _stack(rt.mem, AGENT_STACK_SIZE, "<ascii agent>")
        self.parser = None
        """The agent's parser function (START_ASCII_AGENT), None while none runs."""
        self.parser_task = 0
        self._queue: collections.deque = collections.deque()
        self._current: tuple | None = None  # (generator, reply future, res address)
        self._wake = 0

    def attach(self, hub: CommHub) -> None:
        """Serve `hub`'s Native ASCII requests, variables and User ASCII lines."""
        hub.native = self
        hub.variables = self
        hub.agent = self

    # ------------------------------------------------------------ variables

    def read_variable(self, name: str) -> int | float:
        try:
            found = self.vars.resolve(name)
        except ScopeError as exc:
            raise RequestError(str(exc)) from None
        if found is None:
            names = list(self.vars.channel_names())
            raise RequestError(f"unknown variable '{name}'{did_you_mean(name, names)}")
        return found[0]()

    def write_variable(self, name: str, value: int | float) -> None:
        if name in READ_ONLY:
            raise RequestError(f"{name} is read-only (the controller sets it every cycle)")
        try:
            if not self.vars.write(name, value):
                names = list(self.vars.channel_names())
                raise RequestError(f"unknown variable '{name}'{did_you_mean(name, names)}")
        except (ScopeError, ValueError) as exc:
            raise RequestError(str(exc)) from None

    def native_read(self, name: str) -> str:
        from motionvm.comm.native import format_value

        return format_value(self.read_variable(name))

    def native_write(self, name: str, value: object) -> str:
        value = self._constant(value)
        if not isinstance(value, (int, float)):
            raise RequestError(f"'{name}' takes a number")
        self.write_variable(name, value)
        return "OK"

    def _constant(self, value: object) -> object:
        from motionvm.comm.native import Ident

        if isinstance(value, Ident):
            consts = constants()
            c = consts.get(value.name)
            if c is None:
                hint = did_you_mean(value.name, consts)
                raise RequestError(f"unknown constant '{value.name}'{hint}")
            return c.value
        return value

    # ------------------------------------------------------------ Native ASCII calls

    def native_is_query(self, name: str, args: list) -> bool:
        if name == "HIMC_GPO":
            return len(args) <= 1  # HIMC_GPO(n, v) sets the output
        return name in QUERIES or name.startswith(("Get", "Is"))

    def native_call(self, name: str, args: list) -> str:
        from motionvm.comm.native import format_value

        if name in ("HIMC_GPI", "HIMC_GPO"):
            return self._gpio(name, [self._constant(a) for a in args])
        sig, result, outs = self._call(name, args, "over Native ASCII")
        parts = ["OK" if sig.ret == ct.VOID or result is None else format_value(result)]
        parts += [format_value(self._out_value(addr, ptype)) for addr, ptype in outs]
        return " ".join(parts)

    def call_builtin(self, name: str, args: list) -> object:
        """The host's call of built-in `name` with Python values (the API's
        `Simulation.call`): the value it returns, or with out-parameters (left out of
        `args`) the tuple (return value, each out-parameter's value); a `char *` out
        value is a str. RequestError for a call that cannot be made."""
        sig, result, outs = self._call(name, [_literal(a) for a in args], "from the host")
        if sig.ret == ct.VOID:
            result = None
        if not outs:
            return result
        values = [self._out_value(addr, ptype) for addr, ptype in outs]
        text = [v.decode("utf-8", "replace") if isinstance(v, bytes) else v for v in values]
        return (result, *text)

    def _call(self, name: str, args: list, via: str) -> tuple:
        """Call built-in `name` as a task's call would, arguments converted as C converts
        them: (signature, return value, [(address, type) of each out-parameter]). `via`
        says in a refusal how it was called ("over Native ASCII")."""
        if name == "Till":
            raise RequestError(f"Till waits inside a task; it cannot be called {via}")
        sigs = builtin_signatures()  # the tables are read at the first request (cached)
        sig = sigs.get(name)
        if sig is None:
            raise RequestError(f"unknown function '{name}'{did_you_mean(name, sigs)}")
        blocking = implemented_builtins().get(name)
        if blocking is None:
            raise RequestError(f"{name} (manual {sig.section}) is not implemented")
        if blocking or name == "START_ASCII_AGENT":
            raise RequestError(f"{name} only makes sense inside a task; it cannot be called {via}")
        dirs = _param_dirs().get(name, [])
        ins = [i for i, (_pn, pt) in enumerate(sig.params) if not self._is_out(dirs, i, pt)]
        if len(args) < len(ins) or (len(args) > len(ins) and not sig.variadic):
            want = f"at least {len(ins)}" if sig.variadic else str(len(ins))
            raise RequestError(
                f"{name} takes {want} argument{'s' if want != '1' else ''}, got {len(args)} "
                f"({sig.prototype.strip()})"
            )
        self.scratch.reset()
        call_args: list[object] = []
        outs: list[tuple[int, ct.CType]] = []
        given = iter(args)
        for i, (pname, ptype) in enumerate(sig.params):
            if i in ins:
                call_args.append(self._marshal(next(given), ptype, f"argument '{pname}' of {name}"))
            else:
                addr = self.scratch.push(OUT_SIZE, shadow_pattern(OUT_SIZE))
                outs.append((addr, ptype))
                call_args.append(addr)
        for extra in given:  # only a variadic built-in has more (counted above)
            call_args.append(self._vararg(extra))
        fn = self.rt.ns["b_" + name]
        try:
            result = fn(*call_args)
        except RuntimeFault as exc:
            raise RequestError(str(exc)) from None
        except TaskExit:
            result = None
        except (AttributeError, TypeError):
            raise RequestError(f"{name} only makes sense inside a task") from None
        return sig, result, outs

    @staticmethod
    def _is_out(dirs: list[str], i: int, ptype: ct.CType) -> bool:
        return i < len(dirs) and dirs[i] == "out" and isinstance(ptype, ct.PtrT)

    def _marshal(self, value: object, ptype: ct.CType, what: str) -> object:
        value = self._constant(value)
        if isinstance(ptype, ct.IntT):
            if isinstance(value, (bytes, bytearray)):
                raise RequestError(f"{what} is an integer ({ptype}), got a string")
            return wrap_scalar(ptype.code, _integer(value, f"{what} ({ptype})"))
        if isinstance(ptype, ct.FloatT):
            if isinstance(value, (bytes, bytearray)):
                raise RequestError(f"{what} is a number ({ptype}), got a string")
            return _double(value, f"{what} ({ptype})")
        if isinstance(ptype, ct.PtrT) and isinstance(ptype.target, ct.IntT):
            if ptype.target.size == 1 and isinstance(value, (bytes, bytearray)):
                return self._string(bytes(value))
        if value == 0 and not isinstance(value, (bytes, bytearray)):
            return 0  # a null pointer
        raise RequestError(f"{what} is a pointer ({ptype}); only strings can be given literally")

    def _vararg(self, value: object) -> object:
        value = self._constant(value)
        if isinstance(value, (bytes, bytearray)):
            return self._string(bytes(value))
        return value

    def _string(self, data: bytes) -> int:
        n = len(data) + 1
        addr = self.scratch.push(n, shadow_pattern(n))
        self.rt.mem.write_bytes(addr, data + b"\0")
        return addr

    def _out_value(self, addr: int, ptype: ct.CType) -> object:
        """An out-parameter's value: a `char *` as bytes, any other pointer's first element."""
        target = ptype.target if isinstance(ptype, ct.PtrT) else ct.INT
        mem = self.rt.mem
        if isinstance(target, ct.IntT) and target.size == 1 and target.signed:
            return mem.read_cstr(addr)
        if isinstance(target, (ct.IntT, ct.FloatT)):
            return mem.load(addr, target.code)
        return mem.load(addr, "i64")

    def _gpio(self, name: str, args: list) -> str:
        from motionvm.comm.native import format_value

        rt = self.rt
        if not args or len(args) > (2 if name == "HIMC_GPO" else 1):
            raise RequestError(f"{name} takes the I/O number (and, for HIMC_GPO, a value)")
        if not all(isinstance(a, (int, float)) for a in args):
            raise RequestError(f"{name} takes numbers")
        try:
            index = _integer(args[0], f"the I/O number of {name}")
            if len(args) == 2:
                rt._gpo_set(index, args[1])
                return "OK"
            return format_value((rt._gpi if name == "HIMC_GPI" else rt._gpo)(index))
        except RuntimeFault as exc:
            raise RequestError(str(exc)) from None

    # ------------------------------------------------------------ the ASCII agent

    def start_agent(self, parser, task_id: int) -> None:
        """START_ASCII_AGENT(parser) from task `task_id`."""
        if not callable(parser):
            raise RuntimeFault("START_ASCII_AGENT: the argument is not a function")
        code = getattr(parser, "__code__", None)
        if code is not None and code.co_argcount != 2:
            name = re.sub(r"^(g|t\d+)_", "", parser.__name__)  # the generated name's task prefix
            raise RuntimeFault(
                f"START_ASCII_AGENT: the parser takes (char *cmd, char *res); "
                f"{name} takes {code.co_argcount} parameter{'s' if code.co_argcount != 1 else ''}"
            )
        if self.parser is not None and self.parser is not parser:
            raise RuntimeFault(
                "START_ASCII_AGENT: an ASCII agent is already running "
                "(eERR_HMPL_ASCII_AGENT_RUNNING, 0x1392)"
            )
        self.parser, self.parser_task = parser, task_id
        self.work_changed()

    def has_work(self, hook: str) -> bool:
        """`begin_cycle` has work while an agent runs (runtime/clients.py), not only
        while lines wait: a line arrives in the hub's `begin_cycle` of the cycle that
        starts it."""
        return self.parser is not None

    def accept(self, line: str, reply) -> None:
        if self.parser is None:
            reply.set_result(NO_AGENT)
            return
        self._queue.append((line, reply))

    def busy(self) -> bool:
        return self._current is not None or bool(self._queue and self.parser)

    def next_event(self) -> int | None:
        if self._current is not None:
            return self._wake
        if self._queue and self.parser is not None:
            return self.rt.cycle
        return None

    def begin_cycle(self) -> None:
        if self._current is None:
            if not self._queue or self.parser is None:
                return
            self._start_line(*self._queue.popleft())
        if self.rt.cycle >= self._wake:
            self._resume()

    def _start_line(self, line: str, reply) -> None:
        stack, mem = self.agent_stack, self.rt.mem
        stack.reset()
        data = line.encode("latin-1", "replace") + b"\0"
        cmd = stack.push(len(data), shadow_pattern(len(data)))
        mem.write_bytes(cmd, data)
        res = stack.push(RES_SIZE, shadow_pattern(RES_SIZE))
        parser = self.parser
        if getattr(getattr(parser, "__code__", None), "co_flags", 0) & _CO_GENERATOR:
            gen = parser(cmd, res)
        else:
            gen = _plain(parser, cmd, res)
        self._current = (gen, reply, res)
        self._wake = self.rt.cycle

    def _resume(self) -> None:
        gen, reply, res = self._current  # type: ignore[misc]
        rt, kernel = self.rt, self.rt.kernel
        cycle = rt.cycle
        ns = rt.ns
        ns["_budget"] = rt.task_slice
        ns["_stack"] = self.agent_stack
        me = Task(self.parser_task, name="ascii agent")
        kernel.current = me
        try:
            try:
                y = gen.send(None)
            except (StopIteration, TaskExit):
                self._current = None
                # a `res` the parser left unterminated is its fault, as a task's would be
                reply.set_result(rt.mem.read_cstr(res, "res").decode("latin-1"))
            else:
                self._wake = cycle + 1 if y is None else max(int(y), cycle + 1)
        except Exception as exc:  # noqa: BLE001 — the parser's fault, reported as a task's
            self._current = None
            self.parser = None
            self.work_changed()
            rt._on_fault(me, exc)
            reply.set_result(f"ERR the ASCII agent stopped: {exc}")
        finally:
            kernel.current = None


def _integer(value: object, what: str) -> int:
    """A literal as an integer parameter takes it (C truncates a double); RequestError for
    an infinity or NaN, which no integer holds."""
    if isinstance(value, float) and not math.isfinite(value):
        raise RequestError(f"{what} is an integer; it cannot take {value!r}")
    return int(value)  # type: ignore[call-overload]


def _double(value: object, what: str) -> float:
    """A literal as a double parameter takes it; RequestError for an integer literal beyond
    a double's range."""
    try:
        return float(value)  # type: ignore[arg-type]
    except OverflowError:
        raise RequestError(f"{what} is a double; the integer is out of its range") from None


def _plain(fn, *args):
    """A parser without loops or waits, run as a generator."""
    fn(*args)
    return
    yield  # pragma: no cover — makes this a generator
