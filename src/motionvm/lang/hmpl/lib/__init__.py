"""The HMPL built-in functions, one module per chapter group of the manual."""

from __future__ import annotations

import importlib

from motionvm.lang.hmpl.lib.base import Library

# modules holding Library subclasses, in registration order
_MODULES = (
    "motionvm.lang.hmpl.lib.system",
    "motionvm.lang.hmpl.lib.strings",
    "motionvm.lang.hmpl.lib.mathlib",
    "motionvm.lang.hmpl.lib.usertable",
    "motionvm.lang.hmpl.lib.bus",
    "motionvm.lang.hmpl.lib.axis",
    "motionvm.lang.hmpl.lib.errors",
    "motionvm.lang.hmpl.lib.homing",
    "motionvm.lang.hmpl.lib.touchprobe",
    "motionvm.lang.hmpl.lib.sync",
    "motionvm.lang.hmpl.lib.gantry",
    "motionvm.lang.hmpl.lib.compensation",
    "motionvm.lang.hmpl.lib.filters",
    "motionvm.lang.hmpl.lib.comm",
    "motionvm.lang.hmpl.lib.objects",
    "motionvm.lang.hmpl.lib.config",
    "motionvm.lang.hmpl.lib.trigger",
    "motionvm.lang.hmpl.lib.gpio",
    "motionvm.lang.hmpl.lib.analog",
    "motionvm.lang.hmpl.lib.group",
)


def library_classes() -> list[type[Library]]:
    """Every Library subclass of the modules above, in a fixed order."""
    out: list[type[Library]] = []
    for modname in _MODULES:
        try:
            mod = importlib.import_module(modname)
        except ModuleNotFoundError as exc:  # a library still being written
            if exc.name != modname:
                raise
            continue
        for obj in vars(mod).values():
            if (
                isinstance(obj, type)
                and issubclass(obj, Library)
                and obj is not Library
                and obj.__module__ == modname
            ):
                out.append(obj)
    return out


def implemented_builtins() -> dict[str, bool]:
    """HMPL name -> blocking, for every built-in that has an implementation."""
    out: dict[str, bool] = {}
    for cls in library_classes():
        for hname, (_attr, blocking) in cls.builtin_methods().items():
            out[hname] = blocking
    return out


def implemented_names() -> frozenset[str]:
    """Every built-in motionvm implements: the libraries' and the names the compiler itself
    handles (`catalog.COMPILER_HANDLED`). `motionvm builtins` and the reference use this."""
    from motionvm.lang.hmpl.catalog import COMPILER_HANDLED

    return frozenset(implemented_builtins()) | COMPILER_HANDLED
