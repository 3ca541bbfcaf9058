"""The function being lowered, as every part of the HMPL lowering sees it.

One `FunctionContext` per lowered function (or per task's global initializers): the
program and task it belongs to, whether its code is kept (not a check), the current
block scope, the names of the generated Python function (temporaries `_t1`, `_t2`, ...
and locals `v_x`, `v_x_2`, ...), the layout of its stack frame, and what the finished
function must declare (`global` names, whether it is a generator). The parts
(lower_expr.py, lower_access.py, lower_stmt.py, ...) own their own state and share
only this.

    int f(int x) { struct P q; int *p = &x; ... }      (struct P: two ints)
has a frame of 32 bytes: x at offset 0 (its address is taken), q at offset 16, each
followed by a red zone of 8 bytes that no access may touch; `p` is the Python local
`v_p`, and the first temporary made while lowering it is `_t1`.
"""

from __future__ import annotations

import ast

from motionvm.lang.hmpl import ctypes_ as ct
from motionvm.lang.hmpl.cmemory import RED_ZONE, shadow_pattern
from motionvm.lang.hmpl.symbols import FuncSym, Scope
from motionvm.lang.placing import place


class SemanticError(Exception):
    """Abandon lowering of the current statement after reporting to the sink."""


class FunctionContext:
    """What the parts of one function's lowering share."""

    __slots__ = (
        "_ntemp",
        "_pynames",
        "addr_taken",
        "bytecode",
        "frame_size",
        "frame_valid",
        "func",
        "func_assigned",
        "globals_stored",
        "has_yield",
        "in_init",
        "list_bytes",
        "prog",
        "scope",
        "sink",
        "task",
    )

    def __init__(
        self, prog, task: int, scope: Scope, func: FuncSym | None, addr_taken: set[str]
    ) -> None:
        self.prog = prog
        self.sink = prog.sink
        self.task = task
        self.bytecode: bool = prog.bytecode
        """Whether the generated code is compiled; false in a check (`motionvm check`),
        which keeps only the diagnostics: nodes need no location (`at`), loops no
        aliased globals (`lower_walk.alias_globals`)."""
        self.scope = scope
        """The innermost block scope; a part entering a block sets it, and restores it."""
        self.func = func
        """The function lowered, None for a task's global initializers."""
        self.in_init = func is None
        self.addr_taken = addr_taken
        """Names of locals whose address is taken: they live in the frame."""
        self.func_assigned: set[str] = set()
        """Names the function body assigns."""
        self.globals_stored: set[str] = set()
        """Module globals the function assigns: its `global` declaration."""
        self.has_yield = False
        """Set whenever a yield is generated: the function is a generator."""
        self.frame_size = 0
        self.frame_valid = bytearray()
        self.list_bytes = 0
        """Bytes of the local arrays kept as Python lists: charged to the task's stack
        (reserved above the frame, never valid) so that recursion stays bounded."""
        self._ntemp = 0
        self._pynames: set[str] = set()

    def at(self, stmts: list[ast.stmt], pos) -> list[ast.stmt]:
        """`stmts`, every generated node under them without a location placed at the
        user's position `pos` (`placing.place`: what an inner statement placed is not
        entered); left unplaced in a check, whose code is not kept."""
        if self.bytecode:
            col = pos.col - 1
            place(stmts, pos.line, col if col > 0 else 0)
        return stmts

    def fail(self, pos, message: str) -> SemanticError:
        """Report an error at `pos`; the exception abandons the statement."""
        self.sink.error(pos, message)
        return SemanticError(message)

    def temp(self) -> str:
        """A new temporary name: `_t1`, `_t2`, ..."""
        self._ntemp += 1
        return f"_t{self._ntemp}"

    def unique_local(self, base: str) -> str:
        """The Python name of a new local `base`: `v_base`, or `v_base_2`, ... if taken."""
        cand = f"v_{base}"
        k = 1
        while cand in self._pynames:
            k += 1
            cand = f"v_{base}_{k}"
        self._pynames.add(cand)
        return cand

    def local_names(self) -> set[str]:
        """A copy of the Python local names made so far."""
        return set(self._pynames)

    def locals_since(self, before: set[str]) -> set[str]:
        """The Python local names made since `local_names()` gave `before`."""
        return self._pynames - before

    def frame_alloc(self, t: ct.CType) -> int:
        """The offset of a new object of type `t` in the stack frame (8-aligned, followed by
        a red zone that no access may touch)."""
        align = max(8, t.align)
        off = (self.frame_size + align - 1) // align * align
        size = max(t.size, 1)
        self.frame_valid.extend(b"\x00" * (off - len(self.frame_valid)))
        end = (off + size + 7) // 8 * 8
        self.frame_valid.extend(shadow_pattern(size))
        self.frame_valid.extend(b"\x00" * (end - off - size + RED_ZONE))
        self.frame_size = end + RED_ZONE
        return off

    def event_symbol(self, ident: str):
        """The symbol of `ident` for the wait analysis (till_events.py): a variable's, or
        None for a built-in function (a user's function of that name is a FuncSym),
        False if nothing of that name is visible."""
        sym = self.scope.lookup(ident) or self.prog.global_symbol(ident, self.task)
        if sym is None and ident in self.prog.builtins:
            return None
        return sym if sym is not None else False
