"""Random typed C integer expressions for the differential arithmetic test, rendered as
HMPL and as C: each leaf is a constant (the folded form) or a global variable holding the
same value (the run-time form). Every operator of C's integer arithmetic, casts between
the ten integer types (HMPL's `long` is 32 bits: `int` in the C text), casts of doubles
to integers and the conditional operator. Division, remainder and shift operands are
shaped so that C defines them (no zero or -1 divisor, counts 0..31); what C still leaves
undefined (a double out of the target's range, ...) is left out of the gcc comparison.
"""

from __future__ import annotations

import random
from dataclasses import dataclass, field

# (HMPL name, C name, bits, signed)
INT_TYPES = [
    ("char", "signed char", 8, True),
    ("unsigned char", "unsigned char", 8, False),
    ("short", "short", 16, True),
    ("unsigned short", "unsigned short", 16, False),
    ("int", "int", 32, True),
    ("unsigned int", "unsigned int", 32, False),
    ("long", "int", 32, True),
    ("unsigned long", "unsigned int", 32, False),
    ("long long", "long long", 64, True),
    ("unsigned long long", "unsigned long long", 64, False),
]
# plain literals: (text, HMPL type of the literal, C type)
LITERALS = [
    ("0", "int", "int"),
    ("1", "int", "int"),
    ("7", "int", "int"),
    ("255", "int", "int"),
    ("5u", "unsigned int", "unsigned int"),
    ("0xffffffff", "unsigned int", "unsigned int"),
    ("0x80000000", "unsigned int", "unsigned int"),
    ("0x7fffffff", "int", "int"),
    ("2147483648", "long long", "long long"),
    ("4294967295", "long long", "long long"),
    ("1ul", "unsigned long", "unsigned int"),
    ("3ll", "long long", "long long"),
    ("0xffffffffffffffff", "unsigned long long", "unsigned long long"),
    ("9223372036854775807", "long long", "long long"),
]
DOUBLES = [0.0, -0.5, 2.5, -2.5, 255.9, 256.0, -128.7, 32768.6, -32769.5, 65535.5, 1e10,
           -1e10, 2147483647.5, 4294967295.0, -2147483648.9, 1.8e19, -9.3e18, 123.456]  # fmt: skip
ARITH = ["+", "-", "*", "&", "|", "^"]
COMPARE = ["<", "<=", ">", ">=", "==", "!="]


def _literal(value: int) -> str:
    """A decimal constant text with this value in both languages (a long long or ULL)."""
    if value == -(1 << 63):
        return "(-9223372036854775807LL - 1)"
    if value < 0:
        return f"({value}LL)"
    if value >= 1 << 63:
        return f"{value}ULL"
    return f"{value}LL"


@dataclass
class Batch:
    """Expressions with their leaves; render() gives the two programs."""

    leaves: list[tuple[str, str, str]] = field(
        default_factory=list
    )  # (hmpl type, c type, value text)
    exprs: list[tuple[str, str, str]] = field(default_factory=list)  # (folded, run-time, C)


class Gen:
    def __init__(self, rnd: random.Random, batch: Batch) -> None:
        self.r = rnd
        self.b = batch

    def _leaf_var(self, htype: str, ctype: str, text: str) -> str:
        self.b.leaves.append((htype, ctype, text))
        return f"g{len(self.b.leaves) - 1}"

    def _int_value(self, bits: int, signed: bool) -> int:
        lo, hi = (-(1 << (bits - 1)), (1 << (bits - 1)) - 1) if signed else (0, (1 << bits) - 1)
        pick = self.r.random()
        if pick < 0.5:
            return self.r.choice([lo, hi, 0, 1, -1 if signed else 2, lo + 1, hi - 1, hi // 2 + 1])
        return self.r.randint(lo, hi)

    def leaf(self) -> tuple[str, str, str]:
        """(folded HMPL, run-time HMPL, C) texts of one operand."""
        pick = self.r.random()
        if pick < 0.55:
            hname, cname, bits, signed = self.r.choice(INT_TYPES)
            v = _literal(self._int_value(bits, signed))
            var = self._leaf_var(hname, cname, f"({hname}){v}")
            return f"(({hname}){v})", var, f"(({cname}){v})"
        if pick < 0.85:
            text, htype, ctype = self.r.choice(LITERALS)
            var = self._leaf_var(htype, ctype, text)
            # C's unsigned long is 64 bits on gcc's targets, HMPL's 32: 1ul is 1u there
            return text, var, text.replace("ul", "u")
        hname, cname, _, _ = self.r.choice(INT_TYPES)
        d = repr(self.r.choice(DOUBLES))
        var = self._leaf_var("double", "double", d)
        return f"(({hname}){d})", f"(({hname}){var})", f"(({cname}){d})"

    def expr(self, depth: int) -> tuple[str, str, str]:
        if depth <= 0 or self.r.random() < 0.25:
            return self.leaf()
        pick = self.r.random()
        if pick < 0.4:
            op = self.r.choice(ARITH)
            a, b = self.expr(depth - 1), self.expr(depth - 1)
            return _join(lambda x, y: f"({x} {op} {y})", a, b)
        if pick < 0.5:
            op = self.r.choice(["/", "%"])
            a, b = self.expr(depth - 1), self.expr(depth - 1)
            if self.r.random() < 0.5:  # a divisor in 1..127
                return _join(lambda x, y: f"({x} {op} ({y} & 127 | 1))", a, b)
            return _join(lambda x, y: f"({x} {op} -({y} & 127 | 2))", a, b)  # in -127..-2
        if pick < 0.6:
            op = self.r.choice(["<<", ">>"])
            a, b = self.expr(depth - 1), self.expr(depth - 1)
            return _join(lambda x, y: f"({x} {op} ({y} & 31))", a, b)
        if pick < 0.7:
            op = self.r.choice(COMPARE)
            a, b = self.expr(depth - 1), self.expr(depth - 1)
            return _join(lambda x, y: f"({x} {op} {y})", a, b)
        if pick < 0.8:
            op = self.r.choice(["-", "~", "!"])
            a = self.expr(depth - 1)
            return tuple(f"({op}{x})" for x in a)  # type: ignore[return-value]
        if pick < 0.93:
            hname, cname, _, _ = self.r.choice(INT_TYPES)
            f, rt, c = self.expr(depth - 1)
            return f"(({hname}){f})", f"(({hname}){rt})", f"(({cname}){c})"
        a, b, c = self.expr(depth - 1), self.expr(depth - 1), self.expr(depth - 1)
        return tuple(f"({x} ? {y} : {z})" for x, y, z in zip(a, b, c))  # type: ignore[return-value]


def _join(fmt, a, b) -> tuple[str, str, str]:
    return fmt(a[0], b[0]), fmt(a[1], b[1]), fmt(a[2], b[2])


def make_batch(seed: int, count: int, depth: int = 4) -> Batch:
    batch = Batch()
    g = Gen(random.Random(seed), batch)
    for _ in range(count):
        batch.exprs.append(g.expr(depth))
    return batch


def hmpl_program(batch: Batch) -> str:
    """Prints, per expression, its folded value then its run-time value (as unsigned long
    long: the bits and the signedness of the result both show)."""
    decls = [f"{h} g{k};" for k, (h, _, _) in enumerate(batch.leaves)]
    inits = [f"    g{k} = {v};" for k, (_, _, v) in enumerate(batch.leaves)]
    prints = [
        f'    Print("%llu %llu", (unsigned long long){f}, (unsigned long long){rt});'
        for f, rt, _ in batch.exprs
    ]
    return "\n".join(decls + ["void main() {"] + inits + prints + ["}"]) + "\n"


def c_program(batch: Batch) -> str:
    """One printf per expression, expression k on line FIRST_LINE + k."""
    head = ["#include <stdio.h>", "int main(void) {"]
    lines = [f'printf("%llu\\n", (unsigned long long){c});' for _, _, c in batch.exprs]
    return "\n".join(head + lines + ["return 0;", "}"]) + "\n"


C_FIRST_LINE = 3
