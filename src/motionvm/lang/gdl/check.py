"""GDL compile-time checks on declarations and the link of modules into an application.

In order: one name space for modules, procedures and objects [T]; `USE` names an object
of another module with exactly that type; each parameter belongs to its type, appears
once, has the right data type and lies within its limits, mandatory ones present,
LOWER$TRAVEL$LIMIT <= UPPER$TRAVEL$LIMIT [T]; hierarchy: the parent exists and is of an
allowed type, its device is present and not reserved for another type, the channels
are in range and no two children share one [T], and a home input hangs on its axis's
board [T]. Procedures are checked by `check_proc`.
"""

from __future__ import annotations

from pathlib import Path

from motionvm.lang.gdl import nodes as n
from motionvm.lang.gdl.app import App, ObjectInfo, ProcInfo
from motionvm.lang.gdl.check_proc import ProcChecker
from motionvm.lang.gdl.check_scope import Scope
from motionvm.lang.gdl.objects import TYPE_BY_NAME, ParamSpec
from motionvm.source.diagnostics import DiagnosticSink
from motionvm.source.files import SourcePos
from motionvm.source.suggest import did_you_mean

KIND_WORDS = {
    "int": "an integer",
    "digital": "ON or OFF",
    "config": "a configuration keyword",
    "name": "an object name",
    "string": "a string",
    "set": "a set constant",
}


def where(pos: SourcePos) -> str:
    """`file:line:col` with the file's base name, for messages that point elsewhere."""
    return f"{Path(pos.file).name}:{pos.line}:{pos.col}"


class AppChecker:
    """Checks a set of parsed files as one application and builds the `App`."""

    def __init__(self, files: list[n.GdlFile], paths: list[str], sink: DiagnosticSink) -> None:
        self.files = files
        self.paths = paths
        self.sink = sink
        self.names: dict[str, tuple[str, SourcePos]] = {}
        self.objects: dict[str, ObjectInfo] = {}
        self.scopes: list[tuple[n.Module, Scope]] = []

    def run(self) -> App | None:
        modules = [m for f in self.files for m in f.modules]
        for m in modules:
            self._declare_names(m)
        for m in modules:
            self.scopes.append((m, self._build_scope(m)))
        for m, scope in self.scopes:
            for decl in m.objects:
                info = self.objects.get(decl.name.key)
                if info is not None and info.pos == decl.pos:
                    self._check_params(decl, info, scope)
        self._check_hierarchy()
        procs: list[ProcInfo] = []
        for m, scope in self.scopes:
            for p in m.procedures:
                checker = ProcChecker(scope, self.sink)
                triggers = checker.check(p)
                procs.append(ProcInfo(p.name.text, m.name.text, p, len(procs), triggers))
        if self.sink.has_errors:
            return None
        return App(self.paths, [m.name.text for m in modules], self.objects, procs)

    # ------------------------------------------------------------ names

    def _claim(self, name: n.Name, kind: str) -> bool:
        prev = self.names.get(name.key)
        if prev is not None:
            prev_kind, prev_pos = prev
            self.sink.error(
                name.pos,
                f"name '{name.text}' is already used by the {prev_kind} "
                f"at {where(prev_pos)}: module, procedure and object names must be unique "
                "in the whole application",
            )
            return False
        self.names[name.key] = (kind, name.pos)
        return True

    def _declare_names(self, m: n.Module) -> None:
        self._claim(m.name, "module")
        for decl in m.objects:
            if self._claim(decl.name, "object"):
                self.objects[decl.name.key] = ObjectInfo(
                    decl.name.text, TYPE_BY_NAME[decl.type_kw], m.name.text, decl.pos
                )
        for p in m.procedures:
            self._claim(p.name, "procedure")

    def _build_scope(self, m: n.Module) -> Scope:
        scope = Scope(m.name.text, self.objects)
        for decl in m.objects:
            info = self.objects.get(decl.name.key)
            if info is not None and info.pos == decl.pos:
                scope.local[decl.name.key] = info
        for use in m.uses:
            for name in use.names:
                info = self.objects.get(name.key)
                if info is None:
                    hint = did_you_mean(name.text, [o.name for o in self.objects.values()])
                    self.sink.error(
                        name.pos,
                        f"USE of unknown object '{name.text}': no module declares it{hint}",
                    )
                elif name.key in scope.local:
                    self.sink.error(
                        name.pos,
                        f"'{name.text}' is declared in this module; USE "
                        "is only for objects of other modules",
                    )
                elif info.type.name != use.type_kw:
                    self.sink.error(
                        name.pos,
                        f"'{name.text}' is declared with type "
                        f"{info.type.name} at {where(info.pos)}, not {use.type_kw}",
                    )
                else:
                    scope.used[name.key] = info
        return scope

    # ------------------------------------------------------------ parameters

    def _check_params(self, decl: n.ObjectDecl, info: ObjectInfo, scope: Scope) -> None:
        t = info.type
        for pa in decl.params:
            spec = t.param(pa.keyword)
            if spec is None:
                hint = did_you_mean(pa.keyword, [p.keyword for p in t.params])
                extra = (
                    " (objects of this type cannot be arrays)" if pa.keyword == "ARRAY$SIZE" else ""
                )
                self.sink.error(pa.pos, f"{t.name} has no parameter {pa.keyword}{hint}{extra}")
                continue
            if pa.keyword in info.param_pos:
                self.sink.error(
                    pa.pos,
                    f"parameter {pa.keyword} given twice (first at "
                    f"{where(info.param_pos[pa.keyword])})",
                )
                continue
            info.param_pos[pa.keyword] = pa.pos
            value = self._param_value(spec, pa, scope)
            if value is not None:
                info.params[pa.keyword] = value
        for spec in t.params:
            if spec.keyword in info.param_pos:
                continue
            if spec.mandatory:
                self.sink.error(
                    decl.name.pos, f"{t.name} {info.name} needs the parameter {spec.keyword}"
                )
            elif spec.default is not None:
                info.params[spec.keyword] = spec.default
        lower = info.params.get("LOWER$TRAVEL$LIMIT")
        upper = info.params.get("UPPER$TRAVEL$LIMIT")
        if isinstance(lower, int) and isinstance(upper, int) and lower > upper:
            pos = info.param_pos.get("LOWER$TRAVEL$LIMIT", decl.name.pos)
            self.sink.error(
                pos,
                f"LOWER$TRAVEL$LIMIT {lower} is greater than "
                f"UPPER$TRAVEL$LIMIT {upper} of {info.name}",
            )

    def _param_value(self, spec: ParamSpec, pa: n.ParamAssign, scope: Scope) -> object:
        v = pa.value
        where = f"{spec.keyword}"
        if spec.kind == "int" and isinstance(v, n.IntValue):
            if not spec.lo <= v.value <= spec.hi:
                self.sink.error(
                    v.pos, f"{where} = {v.value} is outside the limits {spec.lo}..{spec.hi}"
                )
                return None
            return v.value
        if spec.kind in ("config", "digital") and isinstance(v, n.KeywordValue | n.NameValue):
            word = v.word if isinstance(v, n.KeywordValue) else v.name.text
            allowed = spec.values if spec.kind == "config" else ("ON", "OFF")
            if word not in allowed:
                self.sink.error(v.pos, f"{where} = {word} is not one of {', '.join(allowed)}")
                return None
            return word if spec.kind == "config" else word == "ON"
        if spec.kind == "string" and isinstance(v, n.StringValue):
            return (v.first, v.second if v.second is not None else v.first)
        if spec.kind == "name" and isinstance(v, n.NameValue):
            target = scope.get(v.name.key)
            if target is None:
                self._unknown(v.name, scope)
                return None
            if target.type.name not in spec.types:
                self.sink.error(
                    v.pos,
                    f"{where} must name {' or '.join(spec.types)}; "
                    f"'{target.name}' is {target.type.name}",
                )
                return None
            return target.key
        shown = {
            n.IntValue: "an integer",
            n.KeywordValue: "a keyword",
            n.NameValue: "a name",
            n.StringValue: "a string",
        }[type(v)]
        self.sink.error(v.pos, f"{where} expects {KIND_WORDS[spec.kind]}, found {shown}")
        return None

    def _unknown(self, name: n.Name, scope: Scope) -> None:
        self.sink.error(name.pos, scope.unknown_message(name))

    # ------------------------------------------------------------ hierarchy

    def _check_hierarchy(self) -> None:
        used: dict[tuple[str, str, int], str] = {}
        homes: dict[str, str] = {}
        for info in self.objects.values():
            for spec in info.type.parent_params():
                parent_key = info.params.get(spec.keyword)
                if isinstance(parent_key, str):
                    self._check_channel(info, self.objects[parent_key], used)
            if info.type.name == "STP$MOTOR$AXIS$HOME$INPUT":
                self._check_home(info, homes)

    def _check_channel(
        self, child: ObjectInfo, parent: ObjectInfo, used: dict[tuple[str, str, int], str]
    ) -> None:
        dev = next((d for d in parent.type.devices if child.type.name in d.child_types), None)
        first = child.params.get("CHANNEL")
        if dev is None or not isinstance(first, int):
            return  # logical hierarchy (SYNOPTIC) or an error already reported
        pos = child.param_pos.get("CHANNEL", child.pos)
        config = parent.params.get(dev.config_param)
        if config == "ABSENT":
            self.sink.error(
                pos,
                f"{parent.name} has {dev.config_param} = ABSENT: no "
                f"{child.type.name} can be connected to it",
            )
            return
        if config not in ("PRESENT", child.type.name):
            self.sink.error(
                pos,
                f"{dev.config_param} of {parent.name} is reserved for "
                f"{config}; {child.name} is {child.type.name}",
            )
            return
        count = child.size or 1
        last = first + count - 1
        lo, hi = dev.channels
        if last > hi:
            self.sink.error(
                pos,
                f"channels {first}..{last} of {child.name} exceed the "
                f"{dev.config_param} channels {lo}..{hi} of {parent.name}",
            )
            return
        for ch in range(first, last + 1):
            slot = (parent.key, dev.config_param, ch)
            owner = used.get(slot)
            if owner is not None:
                self.sink.error(
                    pos,
                    f"channel {ch} of {parent.name} ({dev.config_param}) is "
                    f"already used by {owner}",
                )
                return
        for ch in range(first, last + 1):
            used[(parent.key, dev.config_param, ch)] = child.name

    def _check_home(self, home: ObjectInfo, homes: dict[str, str]) -> None:
        axis_key = home.params.get("STPMOTOR$NAME")
        board_key = home.params.get("STEPPERMOTOR$BOARD$NAME")
        if not isinstance(axis_key, str) or not isinstance(board_key, str):
            return
        axis = self.objects[axis_key]
        pos = home.param_pos.get("STPMOTOR$NAME", home.pos)
        if axis.params.get("BOARD$NAME") != board_key:
            parent = axis.params.get("BOARD$NAME")
            shown = self.objects[parent].name if isinstance(parent, str) else "?"
            self.sink.error(
                pos,
                f"axis {axis.name} hangs on {shown}, but the home input "
                f"{home.name} is on {self.objects[board_key].name}: "
                "STEPPERMOTOR$BOARD$NAME must be the axis's parent",
            )
        elif axis_key in homes:
            self.sink.error(pos, f"axis {axis.name} already has the home input {homes[axis_key]}")
        else:
            homes[axis_key] = home.name


def check_app(files: list[n.GdlFile], paths: list[str], sink: DiagnosticSink) -> App | None:
    """Check and link parsed files; the `App`, or None after reporting errors to `sink`."""
    return AppChecker(files, paths, sink).run()
