"""Hostile Native ASCII requests: every reply is a value or a clear `ERR ...`, never an
internal error, and the server keeps answering.

The generated part calls every built-in a request may call with literals a careless
client sends (infinities, numbers beyond any type, strings for numbers, too many or
too few arguments); it runs the requests the way the server does (parse, then execute
at a cycle boundary) without sockets, so hundreds take well under a second. The served
part sends raw bytes over loopback.
"""

from __future__ import annotations

import random
import sys
from pathlib import Path

import pytest

from motionvm.api import Simulation
from motionvm.comm import native
from motionvm.lang.hmpl.catalog import builtin_signatures
from motionvm.lang.hmpl.lib import implemented_builtins

sys.path.insert(0, str(Path(__file__).parents[1] / "comm"))
from comm_helpers import LineClient, served  # noqa: E402

PROGRAM = """int count = 5; double g; int arr[4]; char s[8];
void main() { Print("ready"); }
"""
HOSTILE = ["0", "1", "-1", "7", "1e999", "-1e999", "1.5", "9" * 40, "0x7fffffffffffffff",
           "-0x8000000000000001", '"abc"', '""', "'A'", "HMPL_ABS", "PI", "banana",
           "0x6040", "2147483648", "1e-320", "1e308"]  # fmt: skip
"""Literals a careless client sends as arguments."""
CASES = 6
"""Generated requests per built-in."""


@pytest.fixture(scope="module")
def hub():
    sim = Simulation.from_source(PROGRAM)
    sim.run(until=0.005)
    yield sim.controller.comm
    sim.close()


def ask(hub, line: str) -> str:
    req = native.handle_line(line)
    return req if isinstance(req, str) else native.execute(hub, req)


def test_hostile_arguments_to_every_built_in_get_a_reply_not_an_internal_error(hub):
    rng = random.Random(15)
    sigs = builtin_signatures()
    names = sorted(
        n for n, blocking in implemented_builtins().items() if n in sigs and not blocking
    )
    names.remove("EStop")  # stops every axis: harmless, but later requests see it
    bad = []
    for name in names:
        n_params = len(sigs[name].params)
        for _ in range(CASES):
            n = max(0, n_params + rng.choice([0, 0, 0, -1, 1, 4]))
            line = f"{name}({', '.join(rng.choice(HOSTILE) for _ in range(n))})"
            reply = ask(hub, line)
            if "internal error" in reply:
                bad.append(f"{line} -> {reply}")
    assert not bad, "\n".join(bad[:10])


TOO_LARGE = f"ERR integer constant '{'9' * 400}' is too large (the limit is 18446744073709551615)"


@pytest.mark.parametrize(
    ("line", "reply"),
    [
        ("IsInPos(1e999)", "ERR argument 'axis_id' of IsInPos (int) is an integer; it cannot take inf"),
        ("GetConfigVar(-1e999)",
         "ERR argument 'hcv_id' of GetConfigVar (int) is an integer; it cannot take -inf"),
        ("HIMC_GPO(1e999, 1)", "ERR the I/O number of HIMC_GPO is an integer; it cannot take inf"),
        ("count = 1e999", "ERR 'count' is an integer variable: it cannot hold inf"),
        ("system_ltest0 = -1e999", "ERR 'system_ltest0' is an integer variable: it cannot hold -inf"),
        ("g = " + "9" * 400, TOO_LARGE),  # no C type holds it, not even a double's constant
        ("SetAxisVsf(0, " + "9" * 400 + ", 0.5)", TOO_LARGE),
        ("SetupGroup(0, 0, 1e999)", "ERR SetupGroup: axis id inf is not an integer"),
        ("SetupGroup(0, 0, -1e999, 1)", "ERR SetupGroup: axis id -inf is not an integer"),
        ("f('\\400')", "ERR octal escape '\\400' is out of range (at most \\377)"),
        ('f("\\777")', "ERR octal escape '\\777' is out of range (at most \\377)"),
    ],
)  # fmt: skip
def test_values_no_parameter_or_variable_holds_are_refused_by_name(hub, line, reply):
    assert ask(hub, line) == reply


def test_the_refused_values_change_nothing(hub):
    assert ask(hub, "count = 5") == "OK"
    ask(hub, "count = 1e999")
    assert ask(hub, "count") == "5"
    assert ask(hub, "count = 1e9") == "OK"  # a finite double is truncated as C converts it
    assert ask(hub, "count") == "1000000000"


HOSTILE_LINES = [
    b"IsInPos(\x00)",
    b"\xff\xfe\xfd(1)",
    b"IsInPos(" + b"(" * 500 + b")",
    b"StringLen(" + b",".join([b"1"] * 300) + b")",
    b"g = " + b"9" * 1000,
    b"count = 1e999",
    b'StringLen("\\q")',
    b'StringLen("\\x")',
    b"main = 3",
    b"StringLen(count)",
    b"IsInPos(0",
    b"=",
    b"count = = 1",
    b"  ;  ",
]


def test_a_served_controller_answers_hostile_lines_and_keeps_answering():
    with served(PROGRAM) as (_sim, srv):
        client = LineClient(srv.ports["native-ascii"])
        try:
            for line in HOSTILE_LINES:
                client.send(line + b"\r\n")
                reply = client.line()
                assert reply.startswith("ERR ") and "internal" not in reply, (line, reply)
            assert client.ask("count") == "5"
        finally:
            client.close()


@pytest.mark.parametrize(
    ("requests", "reply"),
    [
        (["arr[3] = 9", "arr[3]"], "9"),
        (["arr[0x2] = -4", "arr[2]"], "-4"),
        (["darr[1] = 2.5;", "darr[1]"], "2.5"),
        (["arr[4]"], "ERR variable 'arr[4]': index 4 is out of range for arr[4] (0..3)"),
        (["arr[1.5]"], "ERR expected 'arr[INDEX]' with an integer index >= 0"),
        (["arr[-1]"], "ERR expected 'arr[INDEX]' with an integer index"),
        (["arr["], "ERR expected 'arr[INDEX]' with an integer index"),
        (["arr[1](2)"], "ERR 'arr[1]' is an array element: it can be read or written, not called"),
        (["arr[1][2]"], "ERR expected '(' or '=' after 'arr[1]'"),
    ],
)
def test_array_elements_are_read_and_written_by_index(requests, reply):
    """The variable requests take `table[3]` (they said so, but '[' did not parse)."""
    sim = Simulation.from_source("int arr[4]; double darr[2];\nvoid main() { }\n")
    try:
        sim.run(until=0.002)
        hub = sim.controller.comm
        for line in requests[:-1]:
            assert ask(hub, line) == "OK"
        assert ask(hub, requests[-1]) == reply
    finally:
        sim.close()
