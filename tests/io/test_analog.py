"""Analog I/O (manual chapter 10): every row of table 10.1.1, HMPL_DAC_SIGNED, the
functions' errors, and the AO bound to a controller variable (10.4)."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from motionvm.api import Simulation
from motionvm.io.analog import (
    DAC_SIGNED,
    RANGES,
    raw_of_word,
    value_of_word,
    word_of_raw,
    word_of_value,
)

N10_P10 = 1

UNSIGNED_ROWS = [(65535, 10.0), (49152, 5.0), (32768, 0.0), (16384, -5.0), (0, -10.0)]
SIGNED_ROWS = [(32767, 10.0), (16384, 5.0), (0, 0.0), (-16384, -5.0), (-32768, -10.0)]


@pytest.mark.parametrize(("raw", "value"), UNSIGNED_ROWS)
def test_the_manuals_unsigned_table(raw, value):
    assert value_of_word(word_of_raw(raw, 16), 16, N10_P10) == value
    assert raw_of_word(word_of_value(value, 16, N10_P10), 16, N10_P10) == raw


@pytest.mark.parametrize(("raw", "value"), SIGNED_ROWS)
def test_the_manuals_signed_table(raw, value):
    t = DAC_SIGNED | N10_P10
    assert value_of_word(word_of_raw(raw, 16), 16, t) == value
    assert raw_of_word(word_of_value(value, 16, t), 16, t) == raw


# every conversion type of table 10.1.1: low end, middle, high end, unsigned and signed
@pytest.mark.parametrize(
    ("range_type", "lo", "hi"),
    [(1, -10, 10), (2, 0, 10), (3, -5, 5), (4, 0, 5), (5, 0, 20), (6, 4, 20), (7, -20, 20)],
)
def test_every_conversion_of_table_10_1_1(range_type, lo, hi):
    assert RANGES[range_type] == (lo, hi)
    mid = (lo + hi) / 2
    for t, rows in (
        (range_type, [(0, lo), (32768, mid), (65535, hi), (49152, (mid + hi) / 2)]),
        (range_type | DAC_SIGNED, [(-32768, lo), (0, mid), (32767, hi), (-16384, (lo + mid) / 2)]),
    ):
        for raw, value in rows:
            assert value_of_word(word_of_raw(raw, 16), 16, t) == value, (t, raw)
            assert raw_of_word(word_of_value(value, 16, t), 16, t) == raw, (t, value)


def test_none_converts_nothing_and_values_beyond_the_range_clamp():
    assert value_of_word(1234, 16, 0) == 0.0
    assert word_of_value(11.0, 16, N10_P10) == 65535 and word_of_value(-11.0, 16, N10_P10) == 0
    assert word_of_value(float("nan"), 16, N10_P10) == 32768
    assert value_of_word(4095, 12, 2) == 10.0 and value_of_word(2048, 12, 2) == 5.0


@given(st.integers(0, 7).filter(bool), st.booleans(), st.integers(0, 65535))
def test_word_value_word_round_trips(range_type, signed, word):
    t = range_type | (DAC_SIGNED if signed else 0)
    assert word_of_value(value_of_word(word, 16, t), 16, t) == word


MACHINE = """
axes = 2
[[slave]]
kind = "analog"
ai = 2
ao = 2
[[slave]]
kind = "analog"
ai = 1
ao = 1
bits = 12
[[wire]]
from = "slv2.ao1"
to = "slv3.ai1"
"""


def run(tmp_path, body: str) -> list[str]:
    m = tmp_path / "m.toml"
    m.write_text(MACHINE)
    sim = Simulation.from_source(f"void main() {{ {body} }}", machine=str(m))
    sim.run(until=5.0)
    assert not sim.faults, sim.faults
    return sim.messages


def test_example_1_raw_output(tmp_path):
    """10.1.1 example 1, on slave 2 (the machine's analog slave), channel 1."""
    out = run(tmp_path, 'SetSlvAORaw(2, 1, 0xFFFF); Print("%d", GetSlvAORaw(2, 1));')
    assert out == ["65535"]


def test_example_3_types_and_converted_values(tmp_path):
    out = run(
        tmp_path,
        """
        SetSlvAOType(2, 1, HMPL_DAC_N10_P10); SetSlvAO(2, 1, 10);
        SetSlvAIType(3, 1, HMPL_DAC_N10_P10); Sleep(2);
        Print("%f %d %f", GetSlvAO(2, 1), GetSlvAORaw(2, 1), GetSlvAI(3, 1));
        Print("%d %d", GetSlvAOType(2, 1), GetSlvAIType(3, 1));
        SetSlvAO(2, 1, 0); SetSlvAOType(2, 1, HMPL_DAC_NONE); SetSlvAIType(3, 1, HMPL_DAC_NONE);
        Print("%d %d %d", GetSlvAORaw(2, 1), GetSlvAOType(2, 1), SetSlvAO(2, 1, 1.0));
        """,
    )
    # the 12-bit input of slave 3 takes the 16-bit word as wired, clamped to 4095
    assert out == ["10.000000 65535 10.000000", "1 1", "32768 0 -1"]


def test_signed_raw_values(tmp_path):
    out = run(
        tmp_path,
        """
        SetSlvAOType(2, 2, HMPL_DAC_SIGNED | HMPL_DAC_N10_P10); SetSlvAO(2, 2, -5);
        Print("%d %f", GetSlvAORaw(2, 2), GetSlvAO(2, 2));
        SetSlvAORaw(2, 2, -32768); Print("%f", GetSlvAO(2, 2));
        """,
    )
    assert out == ["-16384 -5.000000", "-10.000000"]


def test_bad_slaves_channels_and_types(tmp_path):
    out = run(
        tmp_path,
        """
        Print("%x %x %x", SetSlvAORaw(0, 1, 1), SetSlvAORaw(2, 3, 1), SetSlvAOType(2, 1, 8));
        Print("%d %d %f", GetSlvAIType(9, 1), GetSlvAIRaw(2, 0), GetSlvAI(2, 5));
        Print("%x", SetSlvAOMonitor(2, 1, HMPL_AXIS_15 | HMPL_REF_POS));
        """,
    )
    assert out == ["138f 138f 138f", "-1 0 0.000000", "138f"]


def test_an_output_bound_to_a_controller_variable(tmp_path):
    out = run(
        tmp_path,
        """
        SetSlvAOType(2, 1, HMPL_DAC_N10_P10);
        Print("%d", IsSlvAOBound(2, 1));
        SetSlvAOMonitor(2, 1, HMPL_AXIS_1 | HMPL_POS_FB);
        Print("%d", IsSlvAOBound(2, 1));
        SetSlvAOParam(2, 1, 1, 0.1, -2.0);
        Print("%d %f %f", IsSlvAOBound(2, 1), GetSlvAOScale(2, 1), GetSlvAOOffset(2, 1));
        Enable(1); Sleep(10); MoveAbs(1, 50); Till(IsInPos(1)); Sleep(2);
        Print("%.3f", GetSlvAO(2, 1));
        SetSlvAOParam(2, 1, 0, 1, 0); MoveAbs(1, 0); Till(IsInPos(1)); Sleep(2);
        Print("%d %.3f", IsSlvAOBound(2, 1), GetSlvAO(2, 1));
        """,
    )
    assert out == ["0", "0", "1 0.100000 -2.000000", "3.000", "0 3.000"]
