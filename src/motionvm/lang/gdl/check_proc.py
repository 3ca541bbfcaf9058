"""GDL compile-time checks on procedures: activator lists and instructions.

Activators must belong to the object's type [T]; global activators expand over the
module's local objects only [T]. Assignments need `w` access, reads need `r` access [T];
an INTEGER$CONSTANT is never assigned [T]; set variables take only constants of their
group, or a variable of the same kind whose values all fit [T]; constants are checked
against static limits (PWM VALUE 0..1000) and dynamic ones (array length, travel
limits, MAX$SPEED) when the compiler can see them [T]; the rest is checked at run time.
"""

from __future__ import annotations

from motionvm.lang.gdl import nodes as n
from motionvm.lang.gdl.app import ObjectInfo, Trigger
from motionvm.lang.gdl.check_expr import KIND_NAMES, ExprChecker, VType, article
from motionvm.lang.gdl.check_scope import Scope
from motionvm.lang.gdl.objects import GLOBAL_ACTIVATORS, INT_LIMIT, StateSpec
from motionvm.source.diagnostics import DiagnosticSink
from motionvm.source.suggest import did_you_mean


def dynamic_limit(obj: ObjectInfo, limit: str | None) -> tuple[int, int, str] | None:
    """The per-object limit of an operator argument: (lo, hi, what it comes from)."""
    if limit == "travel" and "LOWER$TRAVEL$LIMIT" in obj.params:
        lo, hi = obj.params["LOWER$TRAVEL$LIMIT"], obj.params["UPPER$TRAVEL$LIMIT"]
        return int(lo), int(hi), "the travel limits"  # type: ignore[call-overload]
    if limit == "max_speed" and "MAX$SPEED" in obj.params:
        return 0, int(obj.params["MAX$SPEED"]), "MAX$SPEED"  # type: ignore[call-overload]
    return None


class ProcChecker(ExprChecker):
    """Checks one procedure in the scope of its module."""

    def __init__(self, scope: Scope, sink: DiagnosticSink) -> None:
        self.scope = scope
        self.sink = sink
        self.triggers: tuple[Trigger, ...] = ()
        self.name = ""

    def check(self, proc: n.Procedure) -> tuple[Trigger, ...]:
        self.name = proc.name.text
        self.triggers = self._activators(proc)
        self._block(proc.body)
        return self.triggers

    # ------------------------------------------------------------ activators

    def _activators(self, proc: n.Procedure) -> tuple[Trigger, ...]:
        out: list[Trigger] = []
        had_error = False
        for entry in proc.activators:
            if isinstance(entry, n.GlobalActivator):
                for obj in self.scope.local.values():
                    for kw in GLOBAL_ACTIVATORS[entry.keyword]:
                        if kw in obj.type.activators:
                            out.append(Trigger(obj.key, kw, None))
                continue
            obj = self._object(entry.obj)
            if obj is None:
                had_error = True
                continue
            if entry.keyword not in obj.type.activators:
                acts = ", ".join(obj.type.activators) or "none"
                self.sink.error(
                    entry.pos,
                    f"{entry.keyword} is not an activator of "
                    f"{obj.type.name} (its activators: {acts})",
                )
                had_error = True
                continue
            if entry.index is not None and not self._const_index(obj, entry.index, entry.obj.pos):
                had_error = True
                continue
            out.append(Trigger(obj.key, entry.keyword, entry.index))
        unique = tuple(dict.fromkeys(out))
        if not unique and not had_error and proc.activators:
            self.sink.error(
                proc.name.pos,
                f"the activator list of procedure {proc.name.text} "
                "is empty after expanding its global activators (no local object "
                "has such an activator)",
            )
        return unique

    # ------------------------------------------------------------ objects and indexes

    def _object(self, name: n.Name) -> ObjectInfo | None:
        obj = self.scope.get(name.key)
        if obj is None:
            self.sink.error(name.pos, self.scope.unknown_message(name))
        return obj

    def _const_index(self, obj: ObjectInfo, index: int, pos: n.SourcePos) -> bool:
        if obj.size is None:
            self.sink.error(pos, f"{obj.name} is not an array: it takes no subscript")
            return False
        if index < 1:
            self.sink.error(
                pos, f"index {index} of {obj.name} is below 1: arrays are indexed from 1"
            )
            return False
        if index > obj.size:
            self.sink.error(
                pos, f"index {index} exceeds the length {obj.size} of {obj.name} (ARRAY$SIZE)"
            )
            return False
        return True

    def _object_ref(self, ref: n.ObjectRef, whole_ok: bool) -> ObjectInfo | None:
        obj = self._object(ref.name)
        if obj is None:
            return None
        if ref.index is None:
            if obj.size is not None and not whole_ok:
                self.sink.error(
                    ref.pos,
                    f"the whole array {obj.name} cannot be used as a "
                    f"value: write {obj.name}{{index}}",
                )
                return None
            return obj
        t = self._expr(ref.index)
        if t.kind not in ("int", "error"):
            self.sink.error(
                ref.index.pos, f"a subscript must be an integer, not {KIND_NAMES[t.kind]}"
            )
        elif t.const is not None:
            if not self._const_index(obj, t.const, ref.index.pos):
                return None
        elif obj.size is None:
            self.sink.error(ref.pos, f"{obj.name} is not an array: it takes no subscript")
            return None
        return obj

    def _state(self, ref: n.StateRef, write: bool) -> tuple[ObjectInfo, StateSpec] | None:
        obj = self._object_ref(ref.obj, whole_ok=write)
        if obj is None:
            return None
        spec = obj.type.state(ref.keyword)
        if spec is None:
            hint = did_you_mean(ref.keyword, [s.keyword for s in obj.type.states])
            what = "operator" if obj.type.operator(ref.keyword) else "state variable"
            extra = " (an operator is called, not assigned or read)" if what == "operator" else ""
            self.sink.error(
                ref.pos, f"{obj.type.name} has no state variable {ref.keyword}{hint}{extra}"
            )
            return None
        if write and not spec.writable:
            if obj.type.name == "INTEGER$CONSTANT":
                msg = (
                    f"an INTEGER$CONSTANT cannot be assigned: {obj.name} keeps the VALUE of "
                    "its declaration"
                )
            else:
                msg = (
                    f"{ref.keyword} of {obj.type.name} is read-only (access {spec.access}): "
                    f"{ref.keyword} OF {obj.name} cannot be assigned"
                )
            self.sink.error(ref.pos, msg)
            return None
        if not write and not spec.readable:
            self.sink.error(
                ref.pos,
                f"{ref.keyword} of {obj.type.name} is write-only (access "
                f"{spec.access}): it cannot be read",
            )
            return None
        return obj, spec

    # ------------------------------------------------------------ instructions

    def _block(self, body: tuple[n.Instr, ...]) -> None:
        for instr in body:
            if isinstance(instr, n.Assign):
                self._assign(instr)
            elif isinstance(instr, n.OperatorCall):
                self._operator(instr)
            elif isinstance(instr, n.If):
                self._condition(instr.cond, "IF")
                self._block(instr.then)
                self._block(instr.orelse)
            elif isinstance(instr, n.While):
                self._condition(instr.cond, "WHILE")
                self._block(instr.body)

    def _condition(self, cond: n.Expr, what: str) -> None:
        t = self._expr(cond)
        if t.kind not in ("digital", "error"):
            self.sink.error(
                cond.pos,
                f"the {what} condition must be digital or boolean, not {KIND_NAMES[t.kind]}",
            )

    def _assign(self, a: n.Assign) -> None:
        found = self._state(a.target, write=True)
        value = self._expr(a.value)
        if found is None or value.kind == "error":
            return
        obj, spec = found
        target = f"{spec.keyword} OF {obj.name}"
        if spec.kind == "int":
            if value.kind != "int":
                self._mismatch(a.value, value, target, "an integer")
            elif value.const is not None:
                self._int_limit(value.const, spec.lo, spec.hi, target, a.value.pos)
        elif spec.kind == "digital":
            if value.kind != "digital":
                self._mismatch(a.value, value, target, "ON/OFF or a boolean expression")
        elif spec.kind == "set":
            self._set_assign(a.value, value, spec, target)
        if any(t.obj == obj.key and t.keyword == spec.keyword for t in self.triggers):
            self.sink.warning(
                a.pos,
                f"procedure {self.name} assigns {target}, one of its own "
                "activators: a change runs it once more",
            )

    def _int_limit(self, value: int, lo: int, hi: int, target: str, pos: n.SourcePos) -> bool:
        """Report a constant outside the integer range or lo..hi; True when it is fine."""
        if abs(value) > INT_LIMIT:
            self.sink.error(
                pos, f"constant {value} exceeds the integer range -{INT_LIMIT}..{INT_LIMIT}"
            )
            return False
        if not lo <= value <= hi:
            self.sink.error(
                pos, f"constant {value} exceeds the static limit {lo}..{hi} of {target}"
            )
            return False
        return True

    def _mismatch(self, node: n.Expr, value: VType, target: str, wanted: str) -> None:
        self.sink.error(node.pos, f"{target} takes {wanted}, not {self._describe(node, value)}")

    @staticmethod
    def _describe(node: n.Expr, value: VType) -> str:
        if isinstance(node, n.DigitalLit):
            return "ON" if node.value else "OFF"
        if isinstance(node, n.SetLit):
            return node.word
        return article(KIND_NAMES[value.kind]) + " value"

    def _set_assign(self, node: n.Expr, value: VType, spec: StateSpec, target: str) -> None:
        group = "{" + ", ".join(spec.values) + "}"
        if value.kind == "setconst" or isinstance(node, n.DigitalLit):
            word = value.values[0] if value.kind == "setconst" else self._describe(node, value)
            if word not in spec.values:
                self.sink.error(node.pos, f"{word} is not in the group {group} of {target}")
        elif value.kind == "set":
            if value.keyword != spec.keyword:
                self.sink.error(
                    node.pos,
                    f"cannot assign {value.keyword} to {target}: a set "
                    "variable takes only a variable of the same kind",
                )
            elif not set(value.values) <= set(spec.values):
                self.sink.error(
                    node.pos,
                    f"{value.keyword} can take values outside the group {group} of {target}",
                )
        else:
            self._mismatch(node, value, target, f"a constant of {group}")

    def _operator(self, call: n.OperatorCall) -> None:
        obj = self._object_ref(call.obj, whole_ok=True)
        args = [self._expr(a) for a in call.args]
        if obj is None:
            return
        op = obj.type.operator(call.keyword)
        if op is None:
            if obj.type.state(call.keyword) is not None:
                msg = f"{call.keyword} OF {obj.name} is a state variable: assign it with '='"
            else:
                names = [o.keyword for o in obj.type.operators]
                msg = (
                    f"{obj.type.name} has no operator {call.keyword}"
                    f"{did_you_mean(call.keyword, names)}"
                )
            self.sink.error(call.pos, msg)
            return
        if len(args) != len(op.args):
            self.sink.error(
                call.pos, f"{op.keyword} takes {len(op.args)} argument(s), {len(args)} given"
            )
            return
        for spec, t, node in zip(op.args, args, call.args, strict=True):
            if t.kind not in ("int", "error"):
                self.sink.error(
                    node.pos,
                    f"argument {spec.name} of {op.keyword} must be an "
                    f"integer, not {KIND_NAMES[t.kind]}",
                )
            elif t.const is not None:
                what = f"argument {spec.name} of {op.keyword}"
                if not self._int_limit(t.const, spec.lo, spec.hi, what, node.pos):
                    continue
                dyn = dynamic_limit(obj, spec.limit)
                if dyn is not None and not dyn[0] <= t.const <= dyn[1]:
                    self.sink.error(
                        node.pos,
                        f"{what} = {t.const} is outside {dyn[2]} {dyn[0]}..{dyn[1]} of {obj.name}",
                    )
