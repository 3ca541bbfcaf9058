"""Source files, positions in them, and compiler diagnostics shared by every language."""

from motionvm.source.diagnostics import CompileError, Diagnostic, DiagnosticSink, render_diagnostic
from motionvm.source.files import SourceFile, SourcePos

__all__ = [
    "CompileError",
    "Diagnostic",
    "DiagnosticSink",
    "SourceFile",
    "SourcePos",
    "render_diagnostic",
]
