"""The scope channels of a loaded HMPL program: its system and global variables.

`system_timeInMs` [ms], `system_fclk`, `system_ltest0..9`, `system_dtest0..9`,
`system_mtest[i]`, `system_user_table[i]`, and any global variable of the program by
name (`count`; `table[3]` for an array element) [raw]. The HMPL run time offers this
source through `HmplRuntime.scope_sources()`; the Native ASCII server reads and writes the
same variables through `HmplSource.for_native`, whose errors speak of variables.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable
from functools import partial

from motionvm.lang.hmpl.cmemory import wrap_scalar
from motionvm.runtime.scope import RAW_UNIT, ChannelSource, ScopeError

READ_ONLY = frozenset({"system_timeInMs", "system_fclk"})
"""System variables the controller sets every cycle: a host's write is refused."""
_ELEMENT = re.compile(r"([A-Za-z_]\w*)(?:\[(\d+)\])?")
# Array elements offered as suggestions, per array (system_user_table has 512000).
_SUGGESTED_ELEMENTS = 10


class HmplSource(ChannelSource):
    """System variables and global variables of a loaded HMPL program (an `HmplRuntime`)."""

    noun = "scope channel"
    """What an error calls a name."""
    use = "record"
    """What one does with an array's element."""
    numbers_only = "the scope records numbers"

    def __init__(self, runtime) -> None:
        self.runtime = runtime
        self.program = runtime.program

    @classmethod
    def for_native(cls, runtime) -> HmplSource:
        """The same variables for Native ASCII requests: its errors name a variable."""
        source = cls(runtime)
        source.noun, source.use = "variable", "read or write"
        source.numbers_only = "Native ASCII reads and writes numbers only"
        return source

    def _symbol(self, base: str):
        return self.program.sysvars.get(base) or self.program.globals_.get(base)

    def resolve(self, name: str) -> tuple[Callable[[], float], str] | None:
        m = _ELEMENT.fullmatch(name)
        if m is None:
            return None
        base, index = m.group(1), m.group(2)
        sym = self._symbol(base)
        if sym is None:
            return None
        t = sym.type
        elem_t = getattr(t, "elem", None)
        if index is None:
            if elem_t is not None:
                raise ScopeError(
                    f"{self.noun} '{name}' is an array of {t.n}; "
                    f"{self.use} one element, e.g. '{base}[0]'"
                )
            return self._scalar(name, sym, t, sym.addr), self._unit(base)
        if elem_t is None:
            raise ScopeError(f"{self.noun} '{name}': '{base}' is not an array")
        i = int(index)
        if t.n is not None and i >= t.n:
            raise ScopeError(
                f"{self.noun} '{name}': index {i} is out of range for {base}[{t.n}] (0..{t.n - 1})"
            )
        if sym.storage == "pylist" and elem_t.is_scalar:  # an array kept as a Python list
            ns, pyname = self.runtime.ns, sym.pyname
            return (lambda: ns[pyname][i]), self._unit(base)
        return self._scalar(name, sym, elem_t, sym.addr + i * elem_t.size), self._unit(base)

    def _scalar(self, name: str, sym, t, addr: int) -> Callable[[], float]:
        if not (t.is_arith or t.is_pointer):
            raise ScopeError(f"{self.noun} '{name}' is a {t}; {self.numbers_only}")
        if sym.storage == "const":
            value = sym.const_value
            return lambda: value
        if sym.storage == "pyglobal":
            return partial(self.runtime.ns.get, sym.pyname, 0)
        if sym.storage != "static":
            raise ScopeError(f"{self.noun} '{name}' is not a global variable")
        kind = "i64" if t.is_pointer else t.code
        size = t.size
        if addr % size == 0:
            return partial(getattr(self.runtime.mem, kind).__getitem__, addr // size)
        return partial(self.runtime.mem.load, addr, kind)

    def write(self, name: str, value: float) -> bool:
        """Store `value` in the global, system variable or array element `name` now, as
        an assignment of the program would (integers wrap to the variable's width);
        False if `name` is not one of ours, ValueError for a constant or a non-number."""
        m = _ELEMENT.fullmatch(name)
        sym = None if m is None else self._symbol(m.group(1))
        if sym is None:
            return False
        self.resolve(name)  # the same checks (an element of an array, in range, a number)
        if sym.storage == "const":
            raise ValueError(f"'{name}' is a constant")
        if self.read_only(name):
            raise ValueError(f"'{name}' is read-only (the controller sets it every cycle)")
        t, index = sym.type, m.group(2)  # type: ignore[union-attr]
        elem_t = t if index is None else t.elem
        kind = "i64" if elem_t.is_pointer else elem_t.code
        stored = _converted(name, kind, value)
        if sym.storage == "pyglobal":
            self.runtime.ns[sym.pyname] = stored
        elif sym.storage == "pylist":
            self.runtime.ns[sym.pyname][int(index)] = stored
        else:
            addr = sym.addr + int(index or 0) * elem_t.size
            self.runtime.mem.store(addr, kind, stored)
        return True

    def read_only(self, name: str) -> bool:
        """The system variables the controller sets every cycle (the clock's)."""
        return name in READ_ONLY

    @staticmethod
    def _unit(base: str) -> str:
        return "ms" if base == "system_timeInMs" else RAW_UNIT

    def channel_names(self) -> Iterable[str]:
        for table in (self.program.sysvars, self.program.globals_):
            for base, sym in table.items():
                n = getattr(sym.type, "n", None)
                if getattr(sym.type, "elem", None) is None:
                    yield base
                else:
                    yield from (f"{base}[{i}]" for i in range(min(n or 1, _SUGGESTED_ELEMENTS)))


def _converted(name: str, kind: str, value: float):
    """`value` as a variable of `kind` holds it; ValueError for a value no assignment
    can store (an infinity or NaN into an integer, an integer beyond a double's range)."""
    try:
        return wrap_scalar(kind, value)
    except (OverflowError, ValueError):
        what = "a double" if kind[0] == "f" else "an integer variable"
        shown = (
            f"an integer of {value.bit_length()} bits"
            if isinstance(value, int) and value.bit_length() > 64
            else repr(value)
        )
        raise ValueError(f"'{name}' is {what}: it cannot hold {shown}") from None
