"""Native ASCII request lines -> requests, and reply values -> text (no sockets)."""

from __future__ import annotations

import pytest

from motionvm.comm.hub import RequestError
from motionvm.comm.native import Ident, Request, format_value, parse_request


@pytest.mark.parametrize(
    ("line", "request_"),
    [
        ("MoveAbs(0, 10.5)", Request("call", "MoveAbs", (0, 10.5))),
        ("MoveAbs(0,10.5);", Request("call", "MoveAbs", (0, 10.5))),
        ("  GetFirmwareVer( )  ", Request("call", "GetFirmwareVer", ())),
        ("system_dtest0", Request("read", "system_dtest0")),
        ("system_dtest0 = 1.5", Request("write", "system_dtest0", (1.5,))),
        ("system_ltest3=-0x10", Request("write", "system_ltest3", (-16,))),
        ("F(1e3, .5, 2., -7)", Request("call", "F", (1000.0, 0.5, 2.0, -7))),
        ("F(010, 0b101, 10u)", Request("call", "F", (8, 5, 10))),
        ('Print("a\\tb\\\\ \\"q\\" %d", 3)', Request("call", "Print", (b'a\tb\\ "q" %d', 3))),
        ("F('A', '\\n', HMPL_ABS)", Request("call", "F", (65, 10, Ident("HMPL_ABS")))),
        (
            "F(18446744073709551615, -0xffffffffffffffff)",
            Request("call", "F", (2**64 - 1, 1 - 2**64)),
        ),
    ],
)
def test_lines_parse_to_requests(line, request_):
    assert parse_request(line) == request_


@pytest.mark.parametrize(
    ("line", "message"),
    [
        ("", "empty request"),
        ("(1)", "a request starts with a function or variable name"),
        ("MoveAbs 0 1", "expected '(' or '=' after 'MoveAbs'"),
        ("MoveAbs(0, 1", "missing ')' at the end of the call of 'MoveAbs'"),
        ("MoveAbs(0 1)", "expected ',' or ')' in the call of 'MoveAbs'"),
        ("MoveAbs(0,)", "expected a value, got ')'"),
        ("x = ", "missing value"),
        ("x = 1 2", "unexpected '2' after the value"),
        ('F(-"s")', "a sign before '\"s\"': only numbers have one"),
        ("F(09)", "invalid octal number '09'"),
        ("F(1) 2", "unexpected '2' after the call of 'F'"),
        ("F(#)", "unexpected '#)' at column 3"),
        ("F('ab')", "character literal 'ab' holds 2 characters"),
        (
            'Print("%d", ' + "9" * 400 + ")",  # it printed -1 (its low 32 bits)
            f"integer constant '{'9' * 400}' is too large (the limit is 18446744073709551615)",
        ),
        (
            "x = -0x10000000000000000",
            "integer constant '0x10000000000000000' is too large (the limit is "
            "18446744073709551615)",
        ),
    ],
)
def test_malformed_lines_say_what_is_wrong(line, message):
    with pytest.raises(RequestError) as info:
        parse_request(line)
    assert str(info.value) == message


@pytest.mark.parametrize(
    ("value", "text"),
    [
        (3, "3"),
        (-2097151880, "-2097151880"),
        (0.1, "0.1"),
        (10.5, "10.5"),
        (1e-7, "1e-07"),
        (2.0**60, "1.152921504606847e+18"),
        (float("inf"), "inf"),
        (float("nan"), "nan"),
        (b'a"b\n\x01', '"a\\"b\\n\\x01"'),
    ],
)
def test_values_format_in_the_shortest_exact_form(value, text):
    assert format_value(value) == text
    if isinstance(value, float) and value == value:
        assert float(text) == value
