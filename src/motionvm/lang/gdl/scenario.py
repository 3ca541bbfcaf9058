"""A GDL application's part of a scenario file: initial values and timed input changes.

The one reader of scenario files is `sim/scenario.py`; it offers this module
(`ScenarioEntries`) the [initial] keys and events the machine does not know, which are
checked against the application here:

```toml
until = 2.0                          # optional: end of the run [s] (--until wins)

[initial]                            # values before t=0; not events, nothing runs
"STATUS OF photocell{1}" = "ON"

[[event]]
at = 0.100                           # simulated time [s], rounded up to a whole cycle
set = "STATUS OF start_button"       # or force = "..." / release = "..." (f access only)
value = "ON"                         # ON/OFF (or true/false), an integer, a set constant
during = "fan_control"               # optional: inject while this procedure runs,
line = 41                            #   just before its instruction on this line
```

`set` accepts any state variable except an INTEGER$CONSTANT: it is how the machine
changes an object. A reference without subscript on an array means every element.
Events of one cycle are applied in file order. A bad file is one `ScenarioError` that
lists every problem of it, each as `FILE:LINE:COL: error: event N: MESSAGE` pointing at
the key (an event's header for a key that is missing).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from motionvm.lang.gdl.app import App, ObjectInfo
from motionvm.lang.gdl.lexer import tokenize
from motionvm.lang.gdl.objects import INT_LIMIT, StateSpec
from motionvm.sim.scenario import ScenarioEntry
from motionvm.sim.scenario import load_scenario as read_scenario
from motionvm.source.diagnostics import DiagnosticSink, TooManyErrors
from motionvm.source.suggest import did_you_mean
from motionvm.source.toml_places import TomlProblems

EVENT_KEYS = {"at", "set", "force", "release", "value", "during", "line"}


@dataclass(frozen=True, slots=True)
class Target:
    """A resolved `KW OF object[{i}]`: the elements it covers."""

    obj: ObjectInfo
    spec: StateSpec
    elements: tuple[int, ...]


@dataclass(frozen=True, slots=True)
class Event:
    """One timed action of the scenario."""

    number: int
    at: float
    """Simulated time [s]; the client rounds it up to a whole cycle of its controller."""
    action: str  # 'set' | 'force' | 'release'
    target: Target
    value: object
    during: str | None
    line: int | None
    where: str = ""
    """`FILE:LINE:COL` of the event's `[[event]]` header ("": not from a file)."""


@dataclass(frozen=True, slots=True)
class Scenario:
    """A loaded scenario: initial values, events in file order, optional end time."""

    initial: tuple[tuple[Target, object], ...]
    events: tuple[Event, ...]
    until: float | None


def parse_target(app: App, text: str) -> Target:
    """Resolve `KW OF name` or `KW OF name{i}`; raises ValueError with the reason."""
    sink = DiagnosticSink()
    try:
        toks = tokenize("<scenario>", text, sink)
    except TooManyErrors:
        toks = []
    if sink.has_errors:
        raise ValueError(f"'{text}': {sink.errors()[0].message}")
    words = [t.text for t in toks[:-1]]
    if (
        len(words) not in (3, 6)
        or words[1] != "OF"
        or (len(words) == 6 and (words[3], words[5]) != ("{", "}"))
        or toks[0].kind != "keyword"
    ):
        raise ValueError(f"'{text}' is not 'KEYWORD OF object' or 'KEYWORD OF object{{i}}'")
    obj = app.objects.get(words[2].lower())
    if obj is None:
        hint = did_you_mean(words[2], [o.name for o in app.objects.values()])
        raise ValueError(f"unknown object '{words[2]}'{hint}")
    spec = obj.type.state(words[0])
    if spec is None:
        hint = did_you_mean(words[0], [s.keyword for s in obj.type.states])
        raise ValueError(f"{obj.type.name} has no state variable {words[0]}{hint}")
    if len(words) == 3:
        return Target(obj, spec, tuple(obj.elements))
    index = toks[4].value
    if obj.size is None or not isinstance(index, int) or not 1 <= index <= obj.size:
        limit = f"1..{obj.size}" if obj.size else "none: it is not an array"
        raise ValueError(f"index {words[4]} of {obj.name} is outside {limit}")
    return Target(obj, spec, (index,))


def parse_value(target: Target, raw: object) -> object:
    """Convert a TOML value to the state variable's kind; raises ValueError."""
    spec = target.spec
    ref = f"{spec.keyword} OF {target.obj.name}"
    if spec.kind == "digital":
        if isinstance(raw, bool):
            return raw
        if isinstance(raw, str) and raw.upper() in ("ON", "OFF"):
            return raw.upper() == "ON"
        raise ValueError(f"{ref} takes ON or OFF, not {raw!r}")
    if spec.kind == "int":
        value = raw
        if isinstance(raw, str) and raw.strip().lstrip("-").isdigit():
            value = int(raw)
        if not isinstance(value, int) or isinstance(value, bool):
            raise ValueError(f"{ref} takes an integer, not {raw!r}")
        if abs(value) > INT_LIMIT or not spec.lo <= value <= spec.hi:
            raise ValueError(f"{ref} = {value} is outside {spec.lo}..{spec.hi}")
        return value
    if isinstance(raw, str) and raw.upper() in spec.values:
        return raw.upper()
    raise ValueError(f"{ref} takes one of {', '.join(spec.values)}, not {raw!r}")


def _seconds(value: object, key: str = "at") -> float:
    """`value` of `key` as seconds: finite and >= 0 (nan and inf too are refused);
    raises ValueError naming key and value."""
    if not isinstance(value, int | float) or isinstance(value, bool) or not 0 <= value < math.inf:
        raise ValueError(f"'{key}' must be a number of seconds >= 0, not {value!r}")
    return float(value)


def _event(app: App, index: int, raw: object, problems: TomlProblems) -> Event | None:
    """The `index`-th (from 0) event; None after adding its problems (each at its key)."""
    number = index + 1
    found = len(problems.items)

    def bad(key: str | None, message: str) -> None:
        problems.in_array("event", index, key, f"event {number}: {message}")

    if not isinstance(raw, dict):
        bad(None, "an event is a table")
        return None
    for key in sorted(set(raw) - EVENT_KEYS):
        bad(key, f"unknown key '{key}' (keys: {', '.join(sorted(EVENT_KEYS))})")
    actions = [a for a in ("set", "force", "release") if a in raw]
    at = None
    if "at" not in raw:
        bad(None, "missing 'at'")
    else:
        try:
            at = _seconds(raw["at"])
        except ValueError as exc:
            bad("at", str(exc))
    target = value = None
    if len(actions) != 1:
        bad(actions[1] if actions else None, "give exactly one of set, force, release")
    else:
        action = actions[0]
        key = action
        try:
            target = parse_target(app, str(raw[action]))
            if action == "set" and target.obj.type.name == "INTEGER$CONSTANT":
                raise ValueError(f"{target.obj.name} is an INTEGER$CONSTANT: it never changes")
            if action != "set" and not target.spec.forceable:
                raise ValueError(
                    f"{target.spec.keyword} of {target.obj.type.name} cannot be "
                    f"forced (access {target.spec.access}, no 'f')"
                )
            if action != "release":
                if "value" not in raw:
                    key = None
                    raise ValueError("missing 'value'")
                key = "value"
                value = parse_value(target, raw["value"])
        except ValueError as exc:
            bad(key, str(exc))
    during, line = raw.get("during"), raw.get("line")
    if (during is None) != (line is None):
        bad("during" if during is not None else "line", "'during' and 'line' go together")
    elif during is not None:
        proc = app.procedure(str(during))
        if proc is None:
            bad("during", f"unknown procedure '{during}'")
        else:
            during = proc.name
        if not isinstance(line, int) or isinstance(line, bool):
            bad("line", "'line' must be a line number")
    if len(problems.items) > found or target is None or at is None:
        return None
    where = problems.where(problems.array_place("event", index, None))
    return Event(number, at, actions[0], target, value, during, line, where)


class ScenarioEntries:
    """Takes the scenario entries of one application (a `sim.scenario.ScenarioTaker`):
    the [initial] keys and events the machine does not know, checked against the
    application; `scenario(until)` is what was taken."""

    def __init__(self, app: App) -> None:
        self.app = app
        self.initial: list[tuple[Target, object]] = []
        self.events: list[Event] = []

    def take_scenario_entry(self, entry: ScenarioEntry) -> bool:
        problems = entry.problems
        if entry.index is None:
            ref = str(entry.key)
            try:
                target = parse_target(self.app, ref)
                self.initial.append((target, parse_value(target, entry.value)))
            except ValueError as exc:
                problems.at("initial", ref, f"[initial]: {exc}")
            return True
        event = _event(self.app, entry.index, entry.value, problems)
        if event is not None:
            self.events.append(event)
        return True

    def scenario(self, until: float | None) -> Scenario:
        return Scenario(tuple(self.initial), tuple(self.events), until)


def load_scenario(path: str, app: App) -> Scenario:
    """A scenario file of this application alone (no machine around it: every entry
    is the application's); ScenarioError lists every problem of it."""
    entries = ScenarioEntries(app)
    loaded = read_scenario(path, lambda name: None, None, (entries,))
    return entries.scenario(loaded.until)
