"""What makes a cold PDL compile fast gives what the plain way gives, in linear work.

- the lexer's one-regex match of common tokens (`_COMMON`) gives the tokens, positions
  and messages of its character-by-character way;
- `placing.place` does not enter statements placed before and `finish_locations` fills
  only starts: the code's positions are those of placing with `ast.walk` at every nesting
  level and `ast.fix_missing_locations`, and a deep nest is walked about once per node;
- `clone` copies a tree as `copy.deepcopy` does;
- `gc_held` restores the collector's state.
"""

from __future__ import annotations

import ast
import copy
import gc
import random
import re
import types
from pathlib import Path

import pytest

from motionvm.lang import placing
from motionvm.lang.gc_hold import gc_held
from motionvm.lang.pdl import lexer, lower, lower_base, lower_body
from motionvm.lang.pdl.front import front_end
from motionvm.lang.pdl.lower import lower_program
from motionvm.source import DiagnosticSink

PROGRAMS = Path(__file__).parents[2] / "programs" / "pdl"
SOURCES = sorted(PROGRAMS.glob("chunk/*.pdl")) + sorted(PROGRAMS.glob("run/*.pdl"))

_TRICKY = [
    'x=1;y+=2; z->3 a<>b // c\n/* d\n e */ "s\\"t" #long q;\n',
    "12abc 0x1F 0x 1.5 .5 1..2 12345678901 4294967296 007\n\tloop(3) do end;",
    "a \\\n b\\  \n c \u201cq\u201d \uff1b \u00e9 @= |= %= -- ++ / /= x/y\r\n#include <f.h>\n",
    "   \n  # long x;\n  \v\f;",
]


def _tokens(text: str) -> tuple[list[tuple], list[str]]:
    sink = DiagnosticSink()
    toks = lexer.tokenize("t.pdl", text, sink)
    return [(t.kind, t.text, t.pos.line, t.pos.col, t.value, t.bol, t.end_col) for t in toks], [
        d.headline() for d in sink.items
    ]


def test_common_token_match_gives_the_character_by_character_tokens(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    rng = random.Random(7)
    alphabet = list("abXY_09 \t\r\n\\/*\"'#.;=<>+-%&|@~()[]{},:xX\u201c\uff1b\u00e9") + [
        "//c\n", "/*c*/", "0x1F", "1.5", "#long", "\\\n", "sleep", "+=", "->", "99999999999"
    ]  # fmt: skip
    texts = _TRICKY + [
        "".join(rng.choice(alphabet) for _ in range(rng.randint(0, 80))) for _ in range(400)
    ]
    texts += [p.read_text() for p in SOURCES]
    fast = [_tokens(t) for t in texts]
    monkeypatch.setattr(lexer, "_COMMON", re.compile(r"(?!)"))  # never matches
    slow = [_tokens(t) for t in texts]
    assert fast == slow


def _place_by_walk(stmts: list[ast.stmt], line: int, col: int) -> list[ast.stmt]:
    """The plain way: every node under `stmts` without a location, at every level."""
    for s in stmts:
        for node in ast.walk(s):
            if "lineno" in node._attributes and not hasattr(node, "lineno"):
                node.lineno, node.col_offset = line, col
    return stmts


def _finish_by_fix(module: ast.Module) -> ast.Module:
    ast.fix_missing_locations(module)
    for node in ast.walk(module):
        if "lineno" in node._attributes:
            node.end_lineno, node.end_col_offset = node.lineno, node.col_offset
    return module


def _positions(code: types.CodeType) -> list:
    out = [(code.co_name, code.co_code, list(code.co_positions()))]
    for k in code.co_consts:
        if isinstance(k, types.CodeType):
            out += _positions(k)
    return out


def _compiled(path: Path, promote: bool) -> list:
    sink = DiagnosticSink()
    result = front_end(str(path), sink=sink)
    assert result is not None, [d.headline() for d in sink.items]
    return _positions(lower_program(str(path), result.symbols, promote).code)


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: p.name)
def test_code_positions_are_those_of_placing_every_level(
    path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    fast = [_compiled(path, promote) for promote in (True, False)]
    monkeypatch.setattr(lower_body, "place", _place_by_walk)
    monkeypatch.setattr(lower, "finish_locations", _finish_by_fix)
    assert fast == [_compiled(path, promote) for promote in (True, False)]


class _CountingShapes(dict):
    """`placing.CHILD_FIELDS`, counting the nodes the location walks look at."""

    looked = 0

    def __getitem__(self, key: object) -> tuple[str, ...]:
        _CountingShapes.looked += 1
        return super().__getitem__(key)


def _nest(depth: int) -> str:
    """`depth` loops nested in one another, a statement at each level."""
    opens = "".join(f"loop(2) do\n  a = a + {k};\n" for k in range(depth))
    return "#long a;\n" + opens + "end;\n" * depth + "halt;\n"


@pytest.mark.parametrize("depth", [10, 40, 150])
def test_a_deep_nest_is_walked_about_once_per_node(
    depth: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(placing, "CHILD_FIELDS", _CountingShapes(placing.CHILD_FIELDS))
    sink = DiagnosticSink()
    result = front_end("nest.pdl", sink=sink, text=_nest(depth))
    assert result is not None, [d.headline() for d in sink.items]
    _CountingShapes.looked = 0
    prog = lower_program("nest.pdl", result.symbols)
    nodes = sum(1 for _ in ast.walk(prog.module))
    # Walking again at every enclosing level looked 4.5x as often as there are nodes at
    # depth 10, 2.4x at 40, 1.9x at 150; names and constants are placed without a look.
    assert 0 < _CountingShapes.looked <= nodes // 2, (_CountingShapes.looked, nodes)


def test_clone_copies_as_deepcopy_does() -> None:
    sink = DiagnosticSink()
    result = front_end(str(SOURCES[0]), sink=sink)
    assert result is not None
    module = lower_program(str(SOURCES[0]), result.symbols).module
    assert module is not None
    body = module.body[-1].body  # type: ignore[attr-defined]
    copied = lower_base.clone(body)
    dump = [ast.dump(s, include_attributes=True) for s in body]
    assert [ast.dump(s, include_attributes=True) for s in copied] == dump
    assert dump == [ast.dump(s, include_attributes=True) for s in copy.deepcopy(body)]
    originals = {id(x) for s in body for x in ast.walk(s)}
    for node in (x for s in copied for x in ast.walk(s)):
        assert placing.PLACED not in node.__dict__
        assert id(node) not in originals or not (node._fields or node._attributes)


def test_gc_held_restores_the_collector() -> None:
    assert gc.isenabled()
    with gc_held():
        assert not gc.isenabled()
        with gc_held():
            assert not gc.isenabled()
        assert not gc.isenabled()
    assert gc.isenabled()
    gc.disable()
    try:
        with gc_held():
            pass
        assert not gc.isenabled()
    finally:
        gc.enable()


def test_gc_held_promotes_what_survives_only_when_asked() -> None:
    class Node:
        pass

    def generation_of(obj: object) -> int:
        for g in range(3):
            if any(o is obj for o in gc.get_objects(generation=g)):
                return g
        return -1

    with gc_held():
        kept = Node()
    assert generation_of(kept) == 2  # a compile's program: the oldest generation at once
    with gc_held(promote=False):
        young = Node()
    assert generation_of(young) == 0  # a front end's pass: left young, collected as usual
