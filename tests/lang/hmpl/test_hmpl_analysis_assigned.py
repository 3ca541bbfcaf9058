"""The analysis scan's assigned names: for a function body and for each `for` body in it,
the names that `=`, `++`, `--` or `&` may change (the lowering reads them to keep a
counting loop's counter a plain Python range)."""

from __future__ import annotations

from pathlib import Path

import pytest

from motionvm.lang.hmpl import nodes as n
from motionvm.lang.hmpl.analysis import FuncFacts, scan
from motionvm.lang.hmpl.lower_loops import _fill_assigned
from motionvm.lang.hmpl.parser import parse_file
from motionvm.source.diagnostics import DiagnosticSink

REPO = Path(__file__).resolve().parents[3]

SRC = """
int g;
int f(int a, int b) {
    int s = 0, t = 0, u = 0, v = 0;
    for (int i = 0; i < a; i++) {
        s += i;
        for (int j = 0; j < b; j++) {
            t = j;
            u++;
        }
        int *p = &v;
    }
    g = sizeof(b = 2);
    return s + t + u + v;
}
"""


def functions(path: str, text: str | None = None) -> list[n.FuncDef]:
    tu = parse_file(path, task_id=0, sink=DiagnosticSink(), text=text)
    assert tu is not None
    return [x for x in tu.items if type(x) is n.FuncDef and x.body is not None]


def for_bodies(stmt) -> list:
    """The bodies of the `for` statements in `stmt`, outermost first."""
    out = []
    stack = [stmt]
    while stack:
        x = stack.pop(0)
        if type(x) is n.For:
            out.append(x.body)
            stack.append(x.body)
        elif type(x) is n.Block:
            stack.extend(x.items)
    return out


def test_sets_per_body_nest_outwards() -> None:
    (f,) = functions("a.hmpl", SRC)
    facts = FuncFacts()
    scan(f.body, {}, facts, {})
    outer, inner = for_bodies(f.body)
    assert facts.assigned[id(inner)] == {"t", "u"}  # `j++` is the step, not the body
    assert facts.assigned[id(outer)] == {"s", "t", "u", "j", "v"}
    # the function's own set: every name above, the counters, and what `sizeof` holds
    assert facts.assigned[id(f.body)] == {"s", "t", "u", "j", "v", "i", "g", "b"}


def test_scan_without_facts_leaves_nothing() -> None:
    (f,) = functions("a.hmpl", SRC)
    uses: dict[str, set] = {}
    scan(f.body, uses, None, {})
    assert uses["a"] == {"escape"}


PROGRAMS = sorted(
    str(p.relative_to(REPO))
    for p in (REPO / "tests" / "programs" / "hmpl").rglob("*.hmpl")
    if "errors" not in p.parts
)


@pytest.mark.parametrize("rel", PROGRAMS)
def test_same_sets_as_the_lowerings_own_walk(rel: str) -> None:
    """The scan's sets equal those the loop lowering finds itself for any other body."""
    for f in functions(str(REPO / rel)):
        facts = FuncFacts()
        scan(f.body, {}, facts, {})
        walked: dict[int, set[str]] = {}
        _fill_assigned(f.body, walked)
        assert facts.assigned == walked, f.name
