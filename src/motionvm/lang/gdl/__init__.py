"""GDL (GD language): compiler front end and event-driven run-time support (RTS).

The language's face is `language.py` (the language interface). Entry points by module:
`compiler.compile_app` (files -> checked `App`), `scenario.load_scenario`, and
`client.GdlApplication` (an application as a client of the controller's cycle); they are
also importable from this package, loaded on first use so that the registry
(`motionvm.lang`) stays cheap to import.
"""

from __future__ import annotations

import importlib

_LAZY = {
    "App": "motionvm.lang.gdl.app",
    "GdlApplication": "motionvm.lang.gdl.client",
    "compile_app": "motionvm.lang.gdl.compiler",
    "load_scenario": "motionvm.lang.gdl.scenario",
}

__all__ = sorted(_LAZY)


def __getattr__(name: str):
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'motionvm.lang.gdl' has no attribute '{name}'")
    return getattr(importlib.import_module(module), name)
