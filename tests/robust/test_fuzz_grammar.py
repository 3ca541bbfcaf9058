"""Grammar-aware fuzzing of the three compilers and their run times: whole programs
generated from each grammar (nesting, long expressions, extreme literals, every
statement form; a fifth of them slightly damaged) must end with exit 0, 1 or 2 and
never an internal error or a traceback, within a time budget. Bounded by the hypothesis
profile: `ci` (default) runs 25 programs per language, `thorough` 300."""

from __future__ import annotations

import os
import random
import time

import pytest
from grammar_fuzz import GDL_SCENARIO, GdlGen, HmplGen, PdlGen, damage
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

settings.register_profile(
    "fuzz-ci", max_examples=25, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)  # fmt: skip
settings.register_profile(
    "fuzz-thorough", max_examples=300, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)  # fmt: skip
PROFILE = settings.get_profile(
    "fuzz-thorough" if os.environ.get("HYPOTHESIS_PROFILE") == "thorough" else "fuzz-ci"
)
BUDGET_S = 30.0  # CPU seconds one program may take, compile and run


def _check(outcome, text: str, seconds: float) -> None:
    assert outcome.code in (0, 1, 2), (outcome.code, outcome.stderr[-2000:], text[:3000])
    assert "internal error" not in outcome.stderr, (outcome.stderr[-2000:], text[:3000])
    assert seconds < BUDGET_S, (seconds, text[:3000])


def _source(gen, seed: int) -> str:
    r = random.Random(seed)
    text = gen(r).program()
    if r.random() < 0.2:
        text = damage(text, r)
    return text


@pytest.mark.filterwarnings("ignore:The recursion limit will not be reset")
@PROFILE
@given(seed=st.integers(0, 2**32 - 1))
def test_hmpl_programs_never_crash(cli, seed):
    text = _source(HmplGen, seed)
    t0 = time.process_time()
    r = cli("run", "--until", "0.05s", "a.hmpl", a__hmpl=text)
    _check(r, text, time.process_time() - t0)


@pytest.mark.filterwarnings("ignore:The recursion limit will not be reset")
@PROFILE
@given(seed=st.integers(0, 2**32 - 1))
def test_pdl_programs_never_crash(cli, seed):
    text = _source(PdlGen, seed)
    t0 = time.process_time()
    r = cli("run", "--until", "0.05s", "a.pdl", a__pdl=text)
    _check(r, text, time.process_time() - t0)


@pytest.mark.filterwarnings("ignore:The recursion limit will not be reset")
@PROFILE
@given(seed=st.integers(0, 2**32 - 1))
def test_gdl_programs_never_crash(cli, seed):
    text = _source(GdlGen, seed)
    t0 = time.process_time()
    r = cli(
        "run",
        "--scenario",
        "s.toml",
        "--until",
        "0.05s",
        "a.gdl",
        a__gdl=text,
        s__toml=GDL_SCENARIO,
    )
    _check(r, text, time.process_time() - t0)
