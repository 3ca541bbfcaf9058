"""HMPL literals that used to be internal errors: compile errors (exit 2) at the literal."""

from __future__ import annotations

import pytest


def test_a_hex_escape_without_digits_is_a_compile_error(cli):
    for cmd in ("check", "run"):
        r = cli(cmd, "a.hmpl", a__hmpl='void main() { Print("\\x"); }\n')
        assert r.code == 2
        assert r.stderr.splitlines()[0] == (
            "a.hmpl:1:21: error: \\x used with no following hex digits"
        )


@pytest.mark.parametrize(("digits", "shown"), [(5000, "5000"), (30, "30")])
def test_an_integer_constant_of_thousands_of_digits_is_too_large(cli, digits, shown):
    text = "void main() { long long a = " + "9" * digits + "; }\n"
    r = cli("check", "a.hmpl", a__hmpl=text)
    assert r.code == 2
    first = r.stderr.splitlines()[0]
    assert first.startswith("a.hmpl:1:29: error: integer constant '")
    assert first.endswith("is too large (the limit is 18446744073709551615)")
    assert len(first) < 200


def test_a_char_constant_hex_escape_without_digits_is_one_error(cli):
    r = cli("check", "a.hmpl", a__hmpl="void main() { char c = '\\x'; Print(\"%d\", c); }\n")
    assert r.code == 2
    errors = [line for line in r.stderr.splitlines() if ": error: " in line]
    assert errors == ["a.hmpl:1:24: error: \\x used with no following hex digits"]
