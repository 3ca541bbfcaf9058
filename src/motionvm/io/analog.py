"""Analog data conversion of manual table 10.1.1: raw channel words <-> values.

A conversion type (`range_type` of SetSlvAIType/SetSlvAOType) is one of the ranges
below, optionally OR-ed with `DAC_SIGNED`:

| type | value | range |
|---|---|---|
| HMPL_DAC_NONE | 0 | no conversion: only the Raw functions apply |
| HMPL_DAC_N10_P10 | 1 | -10 .. 10 |
| HMPL_DAC_P0_P10 | 2 | 0 .. 10 |
| HMPL_DAC_N5_P5 | 3 | -5 .. 5 |
| HMPL_DAC_P0_P5 | 4 | 0 .. 5 |
| HMPL_DAC_P0_P20 | 5 | 0 .. 20 |
| HMPL_DAC_P4_P20 | 6 | 4 .. 20 |
| HMPL_DAC_N20_P20 | 7 | -20 .. 20 |
| HMPL_DAC_SIGNED | 8 | the high bit is the sign: raw words are two's complement |

A channel of `bits` bits holds one word, 0 .. 2^bits - 1. Unsigned, raw 0 is the low
end of the range, 2^(bits-1) its middle, 2^bits - 1 its high end; signed, the lowest
word -2^(bits-1) is the low end, 0 the middle, 2^(bits-1) - 1 the high end. In between
the value is linear in the raw word with one step of half-range / 2^(bits-1), and the
highest word reads as the high end itself: that is how the manual's two tables for a
16-bit +-10 V channel read (65535 -> 10, 49152 -> 5, 32768 -> 0, 16384 -> -5, 0 -> -10;
signed 32767 -> 10, 16384 -> 5, 0 -> 0, -16384 -> -5, -32768 -> -10), and ranges the
manual gives no rows for map the same way. A value is converted to the nearest raw
word, clamped to the channel's words.
"""

from __future__ import annotations

import math

DAC_NONE = 0
DAC_SIGNED = 8
RANGES: dict[int, tuple[float, float]] = {
    1: (-10.0, 10.0),
    2: (0.0, 10.0),
    3: (-5.0, 5.0),
    4: (0.0, 5.0),
    5: (0.0, 20.0),
    6: (4.0, 20.0),
    7: (-20.0, 20.0),
}
"""Range type -> (low end, high end) of table 10.1.1."""
TYPE_NAMES = {
    0: "HMPL_DAC_NONE",
    1: "HMPL_DAC_N10_P10",
    2: "HMPL_DAC_P0_P10",
    3: "HMPL_DAC_N5_P5",
    4: "HMPL_DAC_P0_P5",
    5: "HMPL_DAC_P0_P20",
    6: "HMPL_DAC_P4_P20",
    7: "HMPL_DAC_N20_P20",
}

AXIS_SHIFT = 16
"""HMPL_AXIS_n is n << AXIS_SHIFT (SetSlvAOMonitor's var_id, manual 10.4.1)."""
AXIS_VARIABLES = {
    1: "ref_pos",  # HMPL_REF_POS
    2: "ref_vel",  # HMPL_REF_VEL
    3: "ref_acc",  # HMPL_REF_ACC
    4: "pos_fb",  # HMPL_POS_FB
    5: "vel_fb",  # HMPL_VEL_FB
    6: "acc_fb",  # HMPL_ACC_FB: the change of vel_fb over the last cycle
    7: "coe_trq_fb",  # HMPL_CUR_FB: the drive's torque (current) feedback
}
"""The axis variables an AO can follow, by the low half of var_id (HMPL_REF_POS = 1 ...)."""


def valid_type(range_type: int) -> bool:
    """A range type of table 10.1.1, or one OR-ed with HMPL_DAC_SIGNED (not SIGNED alone)."""
    return range_type in TYPE_NAMES or (range_type & ~DAC_SIGNED) in RANGES


def raw_of_word(word: int, bits: int, range_type: int) -> int:
    """The raw value programs see of a channel word: signed types read two's complement."""
    if range_type & DAC_SIGNED and word >= 1 << (bits - 1):
        return word - (1 << bits)
    return word


def word_of_raw(raw: int, bits: int) -> int:
    """The channel word that holds `raw` (a negative raw is two's complement), clamped to
    the raw values the channel can hold (-2^(bits-1) .. 2^bits - 1)."""
    raw = max(-(1 << (bits - 1)), min((1 << bits) - 1, raw))
    return raw & ((1 << bits) - 1)


def word_of_typed_raw(raw: int, bits: int, range_type: int) -> int:
    """The channel word that holds `raw` as a channel of `range_type` reads it, clamped to
    its raw values: -2^(bits-1) .. 2^(bits-1) - 1 signed, 0 .. 2^bits - 1 unsigned."""
    if range_type & DAC_SIGNED:
        half = 1 << (bits - 1)
        return max(-half, min(half - 1, raw)) & ((1 << bits) - 1)
    return max(0, min((1 << bits) - 1, raw))


def value_of_word(word: int, bits: int, range_type: int) -> float:
    """The converted value of a channel word (0.0 for HMPL_DAC_NONE)."""
    span = RANGES.get(range_type & ~DAC_SIGNED)
    if span is None:
        return 0.0
    lo, hi = span
    half = 1 << (bits - 1)
    if range_type & DAC_SIGNED:
        centred = raw_of_word(word, bits, range_type)
    else:
        centred = word - half
    if centred >= half - 1:
        return hi
    mid = (lo + hi) / 2.0
    return mid + centred * ((hi - lo) / 2.0) / half


def word_of_value(value: float, bits: int, range_type: int) -> int:
    """The channel word nearest to `value`, clamped to the channel (HMPL_DAC_NONE: the
    value rounded, as a raw value)."""
    span = RANGES.get(range_type & ~DAC_SIGNED)
    if span is None:
        return word_of_raw(_round(value), bits)
    lo, hi = span
    half = 1 << (bits - 1)
    if value >= hi:
        centred = half - 1
    else:
        mid = (lo + hi) / 2.0
        centred = max(-half, min(half - 1, _round((value - mid) / ((hi - lo) / 2.0) * half)))
    if range_type & DAC_SIGNED:
        return centred & ((1 << bits) - 1)
    return centred + half


def _round(x: float) -> int:
    """Nearest integer, halves away from zero; NaN is 0, infinities are clamped later."""
    if math.isnan(x):
        return 0
    if math.isinf(x):
        return 1 << 62 if x > 0 else -(1 << 62)
    return int(math.floor(abs(x) + 0.5)) * (1 if x >= 0 else -1)
