"""Scenario files (TOML): initial values and timed input changes that drive a GDL run.

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
Events of one cycle are applied in file order. Every problem is a `ScenarioError`
naming the file and the event.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass

from motionvm.lang.gdl.app import App, ObjectInfo
from motionvm.lang.gdl.lexer import tokenize
from motionvm.lang.gdl.objects import INT_LIMIT, StateSpec
from motionvm.source.diagnostics import DiagnosticSink, TooManyErrors
from motionvm.source.suggest import did_you_mean

EVENT_KEYS = {"at", "set", "force", "release", "value", "during", "line"}


class ScenarioError(Exception):
    """A bad scenario file (exit code 3)."""


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


def _seconds(at: object, where: str) -> float:
    if not isinstance(at, int | float) or isinstance(at, bool) or not 0 <= at < math.inf:
        raise ScenarioError(f"{where}: 'at' must be a number of seconds >= 0, not {at!r}")
    return float(at)


def _event(app: App, number: int, raw: object, where: str) -> Event:
    if not isinstance(raw, dict):
        raise ScenarioError(f"{where}: an event is a table")
    unknown = sorted(set(raw) - EVENT_KEYS)
    if unknown:
        raise ScenarioError(
            f"{where}: unknown key '{unknown[0]}' (keys: {', '.join(sorted(EVENT_KEYS))})"
        )
    actions = [a for a in ("set", "force", "release") if a in raw]
    if len(actions) != 1:
        raise ScenarioError(f"{where}: give exactly one of set, force, release")
    action = actions[0]
    if "at" not in raw:
        raise ScenarioError(f"{where}: missing 'at'")
    try:
        target = parse_target(app, str(raw[action]))
        if action == "set" and target.obj.type.name == "INTEGER$CONSTANT":
            raise ValueError(f"{target.obj.name} is an INTEGER$CONSTANT: it never changes")
        if action != "set" and not target.spec.forceable:
            raise ValueError(
                f"{target.spec.keyword} of {target.obj.type.name} cannot be "
                f"forced (access {target.spec.access}, no 'f')"
            )
        if action == "release":
            value = None
        elif "value" not in raw:
            raise ValueError("missing 'value'")
        else:
            value = parse_value(target, raw["value"])
    except ValueError as exc:
        raise ScenarioError(f"{where}: {exc}") from None
    during, line = raw.get("during"), raw.get("line")
    if (during is None) != (line is None):
        raise ScenarioError(f"{where}: 'during' and 'line' go together")
    if during is not None:
        proc = app.procedure(str(during))
        if proc is None:
            raise ScenarioError(f"{where}: unknown procedure '{during}'")
        if not isinstance(line, int) or isinstance(line, bool):
            raise ScenarioError(f"{where}: 'line' must be a line number")
        during = proc.name
    return Event(number, _seconds(raw["at"], where), action, target, value, during, line)


def load_scenario(path: str, app: App) -> Scenario:
    """Read and validate a scenario file against the application."""
    try:
        with open(path, "rb") as fh:
            data = tomllib.load(fh)
    except OSError as exc:
        raise ScenarioError(f"{path}: cannot read the scenario: {exc.strerror or exc}") from None
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{path}: not valid TOML: {exc}") from None
    unknown = sorted(set(data) - {"until", "initial", "event"})
    if unknown:
        raise ScenarioError(f"{path}: unknown key '{unknown[0]}' (keys: event, initial, until)")
    until = data.get("until")
    if until is not None and (
        not isinstance(until, int | float) or isinstance(until, bool) or until < 0
    ):
        raise ScenarioError(f"{path}: 'until' must be a number of seconds >= 0")
    initial: list[tuple[Target, object]] = []
    table = data.get("initial", {})
    if not isinstance(table, dict):
        raise ScenarioError(f"{path}: [initial] must be a table")
    for ref, raw in table.items():
        try:
            target = parse_target(app, ref)
            initial.append((target, parse_value(target, raw)))
        except ValueError as exc:
            raise ScenarioError(f"{path}: [initial]: {exc}") from None
    raw_events = data.get("event", [])
    if not isinstance(raw_events, list):
        raise ScenarioError(f"{path}: events are written [[event]]")
    events = [_event(app, i + 1, e, f"{path}: event {i + 1}") for i, e in enumerate(raw_events)]
    return Scenario(tuple(initial), tuple(events), float(until) if until is not None else None)
