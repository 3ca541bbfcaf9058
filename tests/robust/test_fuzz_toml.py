"""Fuzzing the machine file and scenario readers: random TOML built from their keys
(values of every TOML type, deep nesting, NUL characters, huge numbers) and mutations of
the project's own machine files and scenarios must end with exit 0, 1 or 3 (a run that
went, a fault the scenario injected, a located error), never 4 or a traceback. Bounded
by the hypothesis profile: `ci` (default) runs 25 files of each kind, `thorough` 300."""

from __future__ import annotations

import os
import random
import shutil
import time
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

settings.register_profile(
    "toml-ci", max_examples=25, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)  # fmt: skip
settings.register_profile(
    "toml-thorough", max_examples=300, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)  # fmt: skip
PROFILE = settings.get_profile(
    "toml-thorough" if os.environ.get("HYPOTHESIS_PROFILE") == "thorough" else "toml-ci"
)
BUDGET_S = 20.0  # CPU seconds one file may take, load and a short run
ROOT = Path(__file__).resolve().parents[2]
SEEDS = sorted((ROOT / "examples").glob("*.toml")) + sorted(
    (ROOT / "tests" / "programs").rglob("*.toml")
)
MACHINES = [p for p in SEEDS if "[[axis]]" in p.read_text() or "[controller]" in p.read_text()]
SCENARIOS = [p for p in SEEDS if "[[event]]" in p.read_text() or "[initial]" in p.read_text()]
PROGRAM = 'void main() {\n    Sleep(5);\n    Print("done");\n}\n'

MACHINE_KEYS = {
    "": ["axes"],
    "controller": ["cycle_time_ms", "task_slice", "data_dir"],
    "comm": ["modbus_port", "native_port", "user_port", "address", "token", "idle_timeout"],
    "axis": ["type", "counts_per_unit", "max_vel", "max_acc", "max_dec", "kill_dec",
             "sw_left", "sw_right", "hw_left", "hw_right", "drive", "pdl", "pdl_start",
             "gdl", "home_switch"],
    "slave": ["kind", "di", "do", "ai", "ao", "slots", "name"],
    "sensor": ["kind", "axis", "at", "input", "width"],
    "wire": ["from", "to", "gain", "delay_ms"],
    "io": ["gpi", "gpo"],
}  # fmt: skip
SCENARIO_KEYS = ["at", "set", "value", "fault", "axis", "slave", "code", "side"]
NAMES = ["gpi1", "gpo3", "axis0.max_vel", "axis0.pos_fb", "system_timeInMs", "system_ltest0",
         "slv0.di1", "hw_limit", "drive_error", "left", "right", "digital", "analog",
         "servo", "linear", "rotary", "x.pdl", "a.hmpl"]  # fmt: skip
ARRAYS = ["axis", "slave", "sensor", "wire", "event"]


def value(r: random.Random, depth: int = 0) -> str:
    """A random TOML value (text)."""
    k = r.randrange(14 if depth < 3 else 10)
    if k == 0:
        return str(r.choice([0, 1, -1, 7, 2**31, 2**63 - 1, -(2**63), 10**6]))
    if k == 1:
        return r.choice(["0.0", "1.5", "-2.5", "1e308", "-1e-320", "inf", "-inf", "nan", "0.001"])
    if k == 2:
        return r.choice(["true", "false"])
    if k == 3:
        return '"' + r.choice(NAMES) + '"'
    if k == 4:
        return r.choice(['""', '"\\u0000"', '"a\\u0000b"', '"' + "x" * 300 + '"', '"../.."', '"/"'])
    if k == 5:
        return r.choice(["1979-05-27T07:32:00Z", "07:32:00", "1979-05-27"])
    if k == 6:
        return str(r.randint(-(10**20), 10**20))
    if k == 7:
        return "0x" + "f" * r.randint(1, 40)
    if k == 8:
        return '"' + r.choice(NAMES) + "[" + str(r.randint(-2, 99)) + ']"'
    if k == 9:
        return str(r.uniform(-1e6, 1e6))
    if k == 10:
        return "[" + ", ".join(value(r, depth + 1) for _ in range(r.randint(0, 3))) + "]"
    if k == 11:
        keys = r.sample(sum(MACHINE_KEYS.values(), []) + SCENARIO_KEYS, r.randint(0, 3))
        return "{" + ", ".join(f"{key} = {value(r, depth + 1)}" for key in keys) + "}"
    if k == 12:
        n = r.choice([40, 200, 5000])
        return "[" * n + "]" * n
    return "{a = " * 40 + "1" + "}" * 40


def machine_file(r: random.Random) -> str:
    lines = []
    for section in r.sample(list(MACHINE_KEYS), r.randint(1, len(MACHINE_KEYS))):
        for _ in range(r.randint(1, 2) if section in ARRAYS else 1):
            if section:
                lines.append(f"[[{section}]]" if section in ARRAYS else f"[{section}]")
            for key in r.sample(MACHINE_KEYS[section], r.randint(0, len(MACHINE_KEYS[section]))):
                lines.append(f"{key} = {value(r)}")
    return "\n".join(lines) + "\n"


def scenario_file(r: random.Random) -> str:
    lines = []
    if r.random() < 0.5:
        lines.append(f"until = {value(r)}")
    if r.random() < 0.5:
        lines.append("[initial]")
        for name in r.sample(NAMES, r.randint(0, 3)):
            lines.append(f'"{name}" = {value(r)}')
    for _ in range(r.randint(0, 6)):
        lines.append("[[event]]")
        for key in r.sample(SCENARIO_KEYS, r.randint(0, len(SCENARIO_KEYS))):
            lines.append(f"{key} = {value(r)}")
    return "\n".join(lines) + "\n"


def mutate(text: str, r: random.Random) -> str:
    """A few random edits of a real file: a value replaced, lines dropped, repeated or
    swapped, a key renamed, characters inserted."""
    lines = text.splitlines()
    for _ in range(r.randint(1, 4)):
        if not lines:
            break
        i = r.randrange(len(lines))
        k = r.randrange(6)
        if k == 0 and "=" in lines[i]:
            key = lines[i].split("=", 1)[0]
            lines[i] = f"{key}= {value(r)}"
        elif k == 1:
            del lines[i]
        elif k == 2:
            lines.insert(i, lines[i])
        elif k == 3:
            j = r.randrange(len(lines))
            lines[i], lines[j] = lines[j], lines[i]
        elif k == 4 and "=" in lines[i]:
            key, rest = lines[i].split("=", 1)
            lines[i] = f"{r.choice(sum(MACHINE_KEYS.values(), []) + SCENARIO_KEYS)} ={rest}"
        else:
            at = r.randrange(len(lines[i]) + 1)
            lines[i] = (
                lines[i][:at]
                + r.choice(["[", "]", "{", '"', "=", "#", "\\", "\x00", "é"])
                + lines[i][at:]
            )
    return "\n".join(lines) + "\n"


def _folder(tmp: Path) -> None:
    """The files the project's machine files and scenarios name, beside them."""
    for src in SEEDS:
        for p in src.parent.iterdir():
            if p.suffix in (".pdl", ".gdl") and not (tmp / p.name).exists():
                shutil.copy(p, tmp / p.name)


def _check(outcome, text: str, seconds: float) -> None:
    assert outcome.code in (0, 1, 3), (outcome.code, outcome.stderr[-2000:], text[:3000])
    assert "internal error" not in outcome.stderr, (outcome.stderr[-2000:], text[:3000])
    assert seconds < BUDGET_S, (seconds, text[:3000])


@pytest.fixture
def folder_cli(cli, tmp_path):
    _folder(tmp_path)
    return cli


@pytest.mark.filterwarnings("ignore:The recursion limit will not be reset")
@PROFILE
@given(seed=st.integers(0, 2**32 - 1))
def test_machine_files_never_crash(folder_cli, seed):
    r = random.Random(seed)
    text = mutate(r.choice(MACHINES).read_text(), r) if r.random() < 0.5 else machine_file(r)
    t0 = time.process_time()
    out = folder_cli(
        "run", "--until", "0.02", "--machine", "m.toml", "a.hmpl", m__toml=text, a__hmpl=PROGRAM
    )
    _check(out, text, time.process_time() - t0)


@pytest.mark.filterwarnings("ignore:The recursion limit will not be reset")
@PROFILE
@given(seed=st.integers(0, 2**32 - 1))
def test_scenarios_never_crash(folder_cli, seed):
    r = random.Random(seed)
    text = mutate(r.choice(SCENARIOS).read_text(), r) if r.random() < 0.5 else scenario_file(r)
    t0 = time.process_time()
    out = folder_cli(
        "run", "--until", "0.02", "--scenario", "s.toml", "a.hmpl", s__toml=text, a__hmpl=PROGRAM
    )
    _check(out, text, time.process_time() - t0)
