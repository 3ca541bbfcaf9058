"""Scenario files for any run: timed input changes and injected faults (TOML), read once
and applied by a cycle client; a GDL application takes the events that name its objects.

```toml
until = 2.0                  # optional: end of the run [s] (--until wins)

[initial]                    # values before the first cycle
gpi3 = 1

[[event]]
at = 0.100                   # simulated time [s], rounded up to a whole cycle
set = "gpi3"                 # an input or variable: gpiN, slvS.diK, slvS.aiK (raw word),
value = 1                    #   an HMPL variable (system_dtest0, a global), ...; ON/OFF too

[[event]]
at = 0.500
fault = "drive"              # drive | encoder_loss | following_error | hw_limit |
axis = 0                     #   slave_lost | estop (io/faults.py)
code = 0x7500                # drive: the alarm's error code (default 0x1000)
```

`set` names are resolved by `resolve(name)` (the session's: the machine's I/O channels
and every language's writable variables, sim/variables.py). An event or [initial] entry
whose name it does not know is offered, as a `ScenarioEntry`, to each `ScenarioTaker` of
the run in turn (a language's run side: a GDL application takes its `KW OF object`
names and `force`/`release`/`during`/`line` events); one that none takes is an error.
This is the one reader of scenario files: each language gets the entries it understands.
Events of one cycle are applied in file order, at the start of the cycle (before every
language's tasks): a program reads an input set at `at = 0.1` in the cycle of 0.1 s. A
bad file is one `ScenarioError` that lists every problem, each as
`FILE:LINE:COL: error: event N: MESSAGE` at its key.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Protocol

from motionvm.io.faults import check_fault, inject_fault
from motionvm.runtime.clients import PassiveClient
from motionvm.runtime.waits import Waiting
from motionvm.source.toml_places import TomlProblems, parse_toml

KEYS = {"at", "set", "value", "fault", "axis", "slave", "code", "side"}
LANGUAGE_KEYS = {"force", "release", "during", "line"}
"""Keys of events that only a language's objects take (GDL's forces and injections)."""

Setter = Callable[[object], None]
Resolver = Callable[[str], Setter | None]


class ScenarioError(Exception):
    """A bad scenario (exit code 3): `messages`, one line per problem; `located`: each
    reads `FILE:LINE:COL: error: ...`."""

    def __init__(self, *messages: str, located: bool = False) -> None:
        super().__init__("\n".join(messages))
        self.messages = list(messages)
        self.located = located


@dataclass(frozen=True)
class Action:
    """One event of the scenario that this client applies."""

    number: int
    at: float
    """[s]"""
    name: str
    """What it sets, or `fault KIND`."""
    apply: Callable[[], None]
    where: str = ""
    """`FILE:LINE:COL` of its `set` key (a write refused at run time is reported there)."""


@dataclass
class Scenario:
    """The events of a scenario file that the machine applies (not a language's)."""

    path: str = ""
    until: float | None = None
    initial: list[Callable[[], None]] = field(default_factory=list)
    actions: list[Action] = field(default_factory=list)


@dataclass(frozen=True)
class ScenarioEntry:
    """An [initial] entry (`index` None: `key` and `value`) or the `index`-th (from 0)
    [[event]] table (`value`: the table) that the machine does not know, offered to the
    run's languages. A taker adds its problems to `problems`, at their keys."""

    key: str | None
    index: int | None
    value: object
    problems: TomlProblems


class ScenarioTaker(Protocol):
    """A part of the run that takes scenario entries of its own (a language's run side)."""

    def take_scenario_entry(self, entry: ScenarioEntry) -> bool:
        """True: the entry is its own (checked, its problems added); False: not its own."""
        ...


def _value(raw: object) -> object:
    """A TOML value as a setter takes it: ON/OFF and booleans as 1/0, numbers as they are."""
    if isinstance(raw, bool):
        return 1 if raw else 0
    if isinstance(raw, str) and raw.upper() in ("ON", "OFF"):
        return 1 if raw.upper() == "ON" else 0
    if isinstance(raw, int | float) and math.isfinite(raw):
        return raw
    raise ValueError(f"value = {raw!r}: must be a number, true/false or ON/OFF")


def _seconds(value: object, key: str) -> float:
    if not isinstance(value, int | float) or isinstance(value, bool) or not 0 <= value < math.inf:
        raise ValueError(f"'{key}' must be a number of seconds >= 0, not {value!r}")
    return float(value)


def load_scenario(
    path: str, resolve: Resolver, io, takers: Sequence[ScenarioTaker] = ()
) -> Scenario:
    """Read a scenario file (see the module docstring); ScenarioError lists every problem.
    Events and [initial] keys `resolve` does not know are offered to `takers`."""
    try:
        raw = Path(path).read_bytes()
    except OSError as exc:
        raise ScenarioError(f"cannot read the scenario {path}: {exc.strerror or exc}") from None
    data, problems = parse_toml(raw, lambda text: TomlProblems(path, text))
    if data is None:
        raise ScenarioError(*problems.headlines(), located=True)
    out = Scenario(path)
    for key in sorted(set(data) - {"until", "initial", "event"}):
        problems.at("", key, f"unknown key '{key}' (keys: event, initial, until)")
    if "until" in data:
        try:
            out.until = _seconds(data["until"], "until")
        except ValueError as exc:
            problems.at("", "until", str(exc))
    table = data.get("initial", {})
    if not isinstance(table, dict):
        problems.at("", "initial", "[initial] must be a table")
        table = {}
    for name, raw_value in table.items():
        try:
            setter = resolve(name)
        except ValueError as exc:
            problems.at("initial", name, f"[initial]: {name}: {exc}")
            continue
        if setter is None:
            if not _offer(takers, ScenarioEntry(name, None, raw_value, problems)):
                problems.at("initial", name, f"[initial]: unknown input or variable '{name}'")
            continue
        try:
            value = _value(raw_value)
        except ValueError as exc:
            problems.at("initial", name, f"[initial]: {name}: {exc}")
            continue
        out.initial.append(lambda s=setter, v=value: s(v))
    events = data.get("event", [])
    if not isinstance(events, list):
        problems.at("", "event", "events are written [[event]]")
        events = []
    for i, ev in enumerate(events):
        if _a_language_event(ev, resolve) and _offer(takers, ScenarioEntry(None, i, ev, problems)):
            continue
        action = _event(i, ev, resolve, io, problems)
        if action is not None:
            out.actions.append(action)
    if problems.items:
        raise ScenarioError(*problems.headlines(), located=True)
    return out


def _offer(takers: Sequence[ScenarioTaker], entry: ScenarioEntry) -> bool:
    """Whether one of `takers` took `entry` (the first that does)."""
    return any(t.take_scenario_entry(entry) for t in takers)


def _a_language_event(ev: object, resolve: Resolver) -> bool:
    """An event that may be a language's: not a fault, and with a language's keys, or
    no `set`, or a `set` the machine does not know."""
    if not isinstance(ev, dict) or "fault" in ev:
        return False
    if "set" not in ev or set(ev) & LANGUAGE_KEYS:
        return True
    return _known(resolve, ev["set"]) is None


def _event(i: int, ev: object, resolve: Resolver, io, problems: TomlProblems):
    """The `i`-th event as an Action, or None after problems."""
    number = i + 1

    def bad(key: str | None, message: str) -> None:
        problems.in_array("event", i, key, f"event {number}: {message}")

    if not isinstance(ev, dict):
        bad(None, "an event is a table")
        return None
    found = len(problems.items)
    for key in sorted(set(ev) - KEYS):
        extra = (
            " (force, release, during and line apply to GDL objects)"
            if key in LANGUAGE_KEYS
            else ""
        )
        bad(key, f"unknown key '{key}' (keys: {', '.join(sorted(KEYS))}){extra}")
    at = None
    if "at" not in ev:
        bad(None, "missing 'at'")
    else:
        try:
            at = _seconds(ev["at"], "at")
        except ValueError as exc:
            bad("at", str(exc))
    if ("fault" in ev) == ("set" in ev):
        bad(None if "fault" not in ev else "set", "give exactly one of set, fault")
        return None
    if "fault" in ev:
        kind = ev["fault"]
        if "value" in ev:
            bad("value", "'value' does not apply to a fault")
        args = {k: ev[k] for k in ("axis", "slave", "code", "side") if k in ev}
        if io is None:
            bad("fault", "fault events need a machine (a run of the scenario with programs)")
            return None
        for key, message in check_fault(io, kind, args):
            bad(key, message)
        if len(problems.items) > found or at is None:
            return None
        return Action(number, at, f"fault {kind}", lambda: inject_fault(io, kind, **args))
    name = ev["set"]
    for key in ("axis", "slave", "code", "side"):
        if key in ev:
            bad(key, f"'{key}' applies to fault events")
    try:
        setter = resolve(name) if isinstance(name, str) else None
    except ValueError as exc:
        bad("set", f"set = {name!r}: {exc}")
        return None
    if setter is None:
        bad(
            "set",
            f"set = {name!r}: unknown input or variable (inputs: gpiN, slvS.diK, slvS.aiK; HMPL variables by name)",
        )
        return None
    if "value" not in ev:
        bad(None, "missing 'value'")
        return None
    try:
        value = _value(ev["value"])
    except ValueError as exc:
        bad("value", str(exc))
        return None
    if len(problems.items) > found or at is None:
        return None
    where = problems.where(problems.array_place("event", i, "set"))
    return Action(number, at, name, lambda: setter(value), where)


def _known(resolve: Resolver, name: object) -> Setter | None:
    """`resolve(name)`, with a read-only name counting as known (its error is reported
    where the event is checked)."""
    try:
        return resolve(str(name))
    except ValueError:
        return lambda value: None


class ScenarioClient(PassiveClient):
    """Applies a scenario's actions at the start of their cycles (a cycle client)."""

    observes_motion = False  # its actions come at their cycles, its next events

    def __init__(self, controller, report: Callable[[str], None] = print) -> None:
        self.controller = controller
        self.report = report
        """Receives a line for each write the run refuses (a value out of range)."""
        self.errors = 0
        """Writes refused so far (each is a fault of the run: exit code 1)."""
        self.scenario = Scenario()
        self._due: list[tuple[int, Action]] = []
        self._next = 0

    def load(self, scenario: Scenario) -> None:
        """Take `scenario`: its [initial] values now, its events at their cycles."""
        self.scenario = scenario
        for apply in scenario.initial:
            apply()
        dt = self.controller.cycle_time
        timed = [(math.ceil(a.at / dt - 1e-9), a) for a in scenario.actions]
        self._due = sorted(timed, key=lambda item: item[0])  # stable: file order in a cycle
        self._next = 0

    def begin_cycle(self) -> None:
        due = self._due
        if self._next >= len(due):
            return
        cycle = self.controller.cycle
        while self._next < len(due) and due[self._next][0] <= cycle:
            action = due[self._next][1]
            self._next += 1
            try:
                action.apply()
            except ValueError as exc:  # a variable that refuses the value now
                self.errors += 1
                self.report(f"{action.where}: error: event {action.number}: {exc}")

    def busy(self) -> bool:
        return self._next < len(self._due)

    def next_event(self) -> int | None:
        return self._due[self._next][0] if self._next < len(self._due) else None

    def still_running(self) -> list:
        if self._next >= len(self._due):
            return []
        action = self._due[self._next][1]
        return [
            Waiting(
                "the scenario", why=f"event {action.number} ({action.name}) at t={action.at:g} s"
            )
        ]
