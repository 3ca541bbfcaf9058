"""The scope of a GDL module while it is checked: the objects it declares and those it USEs
(built by `check.AppChecker`, read by `check_proc.ProcChecker`)."""

from __future__ import annotations

from motionvm.lang.gdl import nodes as n
from motionvm.lang.gdl.app import ObjectInfo
from motionvm.source.suggest import did_you_mean


class Scope:
    """The objects one module can see: its own, and those it USEs."""

    def __init__(self, module: str, everything: dict[str, ObjectInfo]) -> None:
        self.module = module
        self.everything = everything
        self.local: dict[str, ObjectInfo] = {}
        self.used: dict[str, ObjectInfo] = {}

    def get(self, key: str) -> ObjectInfo | None:
        return self.local.get(key) or self.used.get(key)

    def names(self) -> list[str]:
        return sorted(o.name for o in [*self.local.values(), *self.used.values()])

    def unknown_message(self, name: n.Name) -> str:
        """Why `name` is not visible here: declared elsewhere (needs USE) or unknown."""
        other = self.everything.get(name.key)
        if other is not None:
            return (
                f"'{name.text}' is declared in module {other.module}: add "
                f"'USE {other.type.name} {other.name};' to module {self.module}"
            )
        return f"unknown object '{name.text}'{did_you_mean(name.text, self.names())}"
