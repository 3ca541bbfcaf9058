"""printl shows a pointer as a non-negative hex word address, whatever the conversion."""

from __future__ import annotations

from motionvm.session import RunSpec, Session, Source

PROGRAM = """\
#long *p, a[4], n;
proc f(long *q) do
printl("q=%ld", q);
end;
#task/0;
p = &a[0];
p = p - 10;
n = -8;
printl("p=0x%ld", p);
printl("%x %08X %u %d", p, p, p, &a[1]);
printl("n=%ld %x", n, n);
p = &a[1];
f(p);
"""


def _run(tmp_path) -> list[str]:
    src = tmp_path / "ptr.pdl"
    src.write_text(PROGRAM)
    lines: list[str] = []
    reports: list[str] = []
    session = Session(RunSpec([Source(str(src))]), emit=lines.append, report=reports.append)
    session.run(timeout=1.0)
    assert session.fault_count == 0, reports
    return lines


def test_a_negative_pointer_prints_as_its_32_bit_hex_address(tmp_path):
    lines = _run(tmp_path)
    assert lines[0] == "p=0xfffffff8"
    assert "-" not in lines[0]


def test_every_integer_conversion_of_a_pointer_is_hex(tmp_path):
    lines = _run(tmp_path)
    # p = &a[0] - 10 (a[0] is word 2), &a[1] is word 3
    assert lines[1] == "fffffff8 FFFFFFF8 fffffff8 3"


def test_plain_integers_keep_their_sign_and_pointer_parameters_print_as_addresses(tmp_path):
    lines = _run(tmp_path)
    assert lines[2] == "n=-8 fffffff8"
    assert lines[3] == "q=3"
