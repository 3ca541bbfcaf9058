"""Kept function checks (`check_memo`): a check that reuses what earlier checks kept
reports exactly what a check from nothing reports, for every program of the repository
and along seeded random edits; and it does reuse."""

from __future__ import annotations

import random
from pathlib import Path

import pytest

from motionvm.lang import Source
from motionvm.lang.hmpl import check_memo
from motionvm.session import RunSpec, check

ROOT = Path(__file__).resolve().parents[3]
PROGRAMS = sorted(
    p
    for folder in ("tests/programs/hmpl", "examples", "tests/comm/programs")
    for p in (ROOT / folder).rglob("*.hmpl")
    if ".task" not in p.name  # a second task of a program: checked with its first
)


def _check(path: Path, text: str, *, kept: bool) -> list[str]:
    """The diagnostics of `check` on `text` as the file `path`; `kept` false: nothing
    kept before (a check from nothing)."""
    if not kept:
        check_memo.CHECKS.clear()
    found: list = []
    check(RunSpec([Source(str(path), text)]), lambda _line: None, found)
    return [f"{d.severity} {d.pos.file}:{d.pos.line}:{d.pos.col} {d.message}" for d in found]


def _moved(text: str) -> str:
    """`text` with two blank lines before its last function (after its declarations)."""
    lines = text.split("\n")
    at = max((k for k, line in enumerate(lines) if line.startswith(("void ", "int "))), default=0)
    return "\n".join(lines[:at] + ["", ""] + lines[at:])


@pytest.mark.parametrize("path", PROGRAMS, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_program_checks_alike_with_kept_checks(path: Path) -> None:
    text = path.read_text()
    cold = _check(path, text, kept=False)
    assert _check(path, text, kept=True) == cold
    moved = _moved(text)
    assert _check(path, moved, kept=True) == _check(path, moved, kept=False)


BASE = """\
#define N 4
typedef int count_t;
struct Move { int axis; double pos; };
struct Move moves[N];
int total = 0;
int helper(int a);

int waits(int axis) {
    Till(IsInPos(axis));
    return 0;
}

int warns(int axis) {
    int unused = 3;
    if (axis = 2) return 1;
    return 0;
    total++;
}

int errs(int axis) {
    return missing + axis;
}

void statics(void) {
    static char buf[64];
    static int table[8] = {1, 2, 3};
    Print("statics %d", table[0]);
    buf[0] = 'a';
}

int enums(void) {
    enum { RED = 3, GREEN };
    count_t c = GREEN;
    int arr[GREEN];
    arr[0] = c;
    return arr[0];
}

int calls(void) {
    int r = helper(1, 2);
    r += MoveAbs(0);
    r += waits(0);
    Print("calls %d", r);
    return r;
}

int helper(int a) {
    int local_proto(int);
    return a + RED;
}

void main() {
    int k;
    for (k = 0; k < N; k++) moves[k].pos = k;
    Print("main %d", calls() + enums() + warns(0) + errs(0));
    statics();
}
"""

EDITS = [
    "delete",
    "blank",
    "duplicate",
    "number",
    "rename",
    "static",
    "string",
]


def _edit(lines: list[str], rng: random.Random) -> list[str]:
    k = rng.randrange(len(lines))
    kind = rng.choice(EDITS)
    out = list(lines)
    if kind == "delete" and len(out) > 10:
        del out[k]
    elif kind == "blank":
        out.insert(k, "")
    elif kind == "duplicate":
        out.insert(k, out[k])
    elif kind == "number":
        out[k] = out[k].replace("3", str(rng.randrange(-2, 9)), 1)
    elif kind == "rename":
        out[k] = out[k].replace("axis", rng.choice(["axis", "axes", "a"]), 1)
    elif kind == "static":
        out.insert(k, f"    static double big{k}[{rng.choice([1, 100, 400000, 600000])}];")
    else:
        out.insert(k, f'    Print("text {rng.randrange(3)}");')
    return out


@pytest.mark.parametrize("seed", range(6))
def test_random_edits_check_alike_with_kept_checks(tmp_path: Path, seed: int) -> None:
    """Seeded random edits of a program with waits, warnings, errors, static locals,
    string literals, enums and typedefs in bodies, prototypes in a body: after every
    edit, the check that reuses reports what a check from nothing reports."""
    rng = random.Random(seed)
    path = tmp_path / "edited.hmpl"
    lines = BASE.split("\n")
    check_memo.CHECKS.clear()
    reused = 0
    for _ in range(25):
        edited = _edit(lines, rng)
        text = "\n".join(edited)
        before = check_memo.CHECKS.reused
        warm = _check(path, text, kept=True)
        reused += check_memo.CHECKS.reused - before
        kept = dict(check_memo.CHECKS._entries)
        assert warm == _check(path, text, kept=False), text
        check_memo.CHECKS._entries.update(kept)  # the next edit reuses as an editor's would
        if not any(" expected " in line for line in warm):
            lines = edited  # (a syntax error: the next edit starts from the text before)
    assert reused > 0


def test_a_changed_line_reuses_every_other_function(tmp_path: Path) -> None:
    path = tmp_path / "one.hmpl"
    check_memo.CHECKS.clear()
    _check(path, BASE, kept=True)
    before = check_memo.CHECKS.reused
    edited = BASE.replace("int unused = 3;", "int unused = 4;")
    found = _check(path, edited, kept=True)
    assert check_memo.CHECKS.reused - before == BASE.count("\n}") - 1  # all but `warns`
    assert any("unused variable 'unused'" in line for line in found)


def test_moved_functions_report_at_their_new_lines(tmp_path: Path) -> None:
    path = tmp_path / "moved.hmpl"
    check_memo.CHECKS.clear()
    first = _check(path, BASE, kept=True)
    before = check_memo.CHECKS.reused
    moved = BASE.replace("int errs(int axis) {", "\n\n\nint errs(int axis) {")
    found = _check(path, moved, kept=True)
    assert check_memo.CHECKS.reused > before
    (old,) = [line for line in first if "missing" in line]
    (new,) = [line for line in found if "missing" in line]
    old_line, new_line = (int(x.split(":")[1]) for x in (old, new))
    assert new_line == old_line + 3


def test_kept_checks_are_bounded() -> None:
    memo = check_memo.FunctionMemo(limit=3)
    for k in range(10):
        key = check_memo.FunctionKey(bytes([k]) * 16, "f.hmpl", 1, 2, True)
        memo.put(b"env", 0, key, [], [])
    assert len(memo) == 3
