"""Counting executed bytecodes and Python calls per function, for the bytecode benches.

`OpcodeCount.trace` is a `sys.settrace` function (opcode events) that keeps two counters
keyed by (file name, function name): calls and bytecodes. Set it and clear it with
`sys.settrace` around what to count (a builtin call, so nothing of the counting itself
is counted).
A tracing count is free of the noise of a shared machine, unlike CPU time.
"""

from __future__ import annotations

import collections
from pathlib import Path


class OpcodeCount:
    """Calls and executed bytecodes by (file name, function name)."""

    def __init__(self) -> None:
        self.calls: collections.Counter = collections.Counter()
        self.ops: collections.Counter = collections.Counter()

    def trace(self, frame, event, _arg):
        code = frame.f_code
        key = (Path(code.co_filename).name, code.co_name)
        if event == "call":
            self.calls[key] += 1
            frame.f_trace_opcodes = True
            frame.f_trace_lines = False
        elif event == "opcode":
            self.ops[key] += 1
        return self.trace

    @property
    def total(self) -> int:
        """All bytecodes counted."""
        return sum(self.ops.values())
