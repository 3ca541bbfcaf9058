"""A pointer far outside the program's memory (past its end, or negative) is a runtime
error naming the pointer, for every access width, never an internal error."""

from __future__ import annotations

import pytest


@pytest.mark.parametrize("ctype", ["char", "short", "int", "long long", "double"])
@pytest.mark.parametrize("addr", ["100000001", "100000000", "16777216", "-8", "0x7ffffff0"])
def test_wild_pointer_load_and_store(cli, ctype, addr):
    prog = f"""void main() {{
    {ctype} *p = ({ctype} *){addr};
    {ctype} x = *p;
    Print("%d", (int)x);
}}
"""
    r = cli("run", "a.hmpl", a__hmpl=prog)
    assert r.code == 1 and r.stdout == "", r.stderr
    assert "a.hmpl:3:" in r.stderr and "runtime error in task 0" in r.stderr, r.stderr
    store = prog.replace(f"{ctype} x = *p;", "*p = 1;").replace("(int)x", "0")
    r = cli("run", "a.hmpl", a__hmpl=store)
    assert r.code == 1 and r.stdout == "", r.stderr
    assert "runtime error in task 0" in r.stderr, r.stderr
