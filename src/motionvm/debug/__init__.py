"""The debug engine: breakpoints, stepping, inspection and time travel over a session.

One layer above `session` (which never imports it) and below the faces (`dap/`, the API,
the studio); it reaches the languages only through `motionvm.lang`. See engine.py.
"""

from motionvm.debug.engine import BreakpointSpec, DebugEngine, Frame
from motionvm.debug.expressions import ExpressionError
from motionvm.debug.positions import Breakpoint, Position, Stop

__all__ = [
    "Breakpoint",
    "BreakpointSpec",
    "DebugEngine",
    "ExpressionError",
    "Frame",
    "Position",
    "Stop",
]
