"""C initializers three ways: random nested arrays and structs, each given a random
initializer that writes some sub-objects' braces and elides others (C89 6.5.7) and leaves
some trailing values out, as a variable (file scope and local) and as a compound literal
(C99). The values HMPL prints must be the ones the generator computed by C's rules, and
(when gcc is installed) the ones gcc's program prints.

Batches of 12 declarations; the `ci` profile runs 8 batches, the `thorough` one 100.
"""

from __future__ import annotations

import os
import random
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

sys.path.insert(0, str(Path(__file__).resolve().parent))
from hmpl_run import run_hmpl  # noqa: E402

settings.register_profile(
    "cinit-ci", max_examples=8, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)  # fmt: skip
settings.register_profile(
    "cinit-thorough", max_examples=100, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)  # fmt: skip
PROFILE = settings.get_profile(
    "cinit-thorough" if os.environ.get("HYPOTHESIS_PROFILE") == "thorough" else "cinit-ci"
)
GCC = shutil.which("gcc")
BATCH = 12


@dataclass
class Type:
    """'int', an array (`n` of `elem`) or a struct (`name`, `members`)."""

    kind: str
    n: int = 0
    elem: Type | None = None
    name: str = ""
    members: tuple[Type, ...] = ()

    def subs(self) -> list[Type]:
        if self.kind == "array":
            assert self.elem is not None
            return [self.elem] * self.n
        return list(self.members)

    def leaves(self, path: str) -> list[str]:
        """The access paths of the scalars, in memory order."""
        if self.kind == "int":
            return [path]
        if self.kind == "array":
            assert self.elem is not None
            return [x for i in range(self.n) for x in self.elem.leaves(f"{path}[{i}]")]
        return [x for i, m in enumerate(self.members) for x in m.leaves(f"{path}.m{i}")]

    def spelled(self) -> tuple[str, str]:
        """(base, dimensions) of a declaration: `struct S1`, `[2][3]`."""
        dims, t = "", self
        while t.kind == "array":
            assert t.elem is not None
            dims += f"[{t.n}]"
            t = t.elem
        return ("int" if t.kind == "int" else f"struct {t.name}"), dims


class Gen:
    def __init__(self, r: random.Random) -> None:
        self.r = r
        self.structs: list[Type] = []
        self.next_value = 0

    def type(self, depth: int, aggregate: bool = False) -> Type:
        r = self.r
        if not aggregate and (depth == 0 or r.random() < 0.35):
            return Type("int")
        if r.random() < 0.5:
            return Type("array", n=r.randint(1, 3), elem=self.type(depth - 1))
        members = tuple(self.type(depth - 1) for _ in range(r.randint(1, 3)))
        t = Type("struct", name=f"S{len(self.structs)}", members=members)
        self.structs.append(t)
        return t

    def value(self) -> int:
        self.next_value += 1
        return self.next_value * 7 % 1000 - 300

    def braced(self, t: Type) -> tuple[str, list[int]]:
        """`{...}` for `t` with sub-objects braced or elided at random; trailing ones
        may be left out (zero)."""
        parts: list[str] = []
        values: list[int] = []
        subs = t.subs()
        keep = self.r.randint(1, len(subs))
        for k, s in enumerate(subs):
            if k >= keep:
                values.extend([0] * len(s.leaves("")))
                continue
            text, vals = self.item(s, first_of_elided=False)
            parts.append(text)
            values.extend(vals)
        return "{" + ", ".join(parts) + "}", values

    def flat(self, t: Type) -> tuple[str, list[int]]:
        """`t`'s values without its braces (all of them: an elided list is complete)."""
        parts: list[str] = []
        values: list[int] = []
        for k, s in enumerate(t.subs()):
            text, vals = self.item(s, first_of_elided=k == 0)
            parts.append(text)
            values.extend(vals)
        return ", ".join(parts), values

    def item(self, s: Type, first_of_elided: bool) -> tuple[str, list[int]]:
        if s.kind == "int":
            v = self.value()
            return str(v), [v]
        # a brace list first in an elided list would belong to the enclosing sub-object
        if not first_of_elided and self.r.random() < 0.5:
            return self.braced(s)
        return self.flat(s)


def make_batch(seed: int) -> tuple[str, str, list[int]]:
    """(HMPL program, C program, expected values)."""
    r = random.Random(seed)
    g = Gen(r)
    decls: list[str] = []
    body: list[str] = []
    expected: list[int] = []
    for k in range(BATCH):
        t = g.type(3, aggregate=True)
        init, values = g.braced(t)
        base, dims = t.spelled()
        where = r.choice(["file", "local", "literal"])
        if where == "literal":
            paths = t.leaves(f"(({base}{dims}){init})")
        else:
            (decls if where == "file" else body).append(f"{base} v{k}{dims} = {init};")
            paths = t.leaves(f"v{k}")
        body.extend(f'Print("%d", {p});' for p in paths)
        expected.extend(values)
    structs = []
    for s in g.structs:  # members come first: a struct is defined after what it holds
        fields = []
        for i, m in enumerate(s.members):
            mb, md = m.spelled()
            fields.append(f"{mb} m{i}{md};")
        structs.append(f"struct {s.name} {{ {' '.join(fields)} }};")
    text = "\n".join(structs + decls) + "\nvoid main() {\n" + "\n".join(body) + "\n}\n"
    c_text = (
        '#include <stdio.h>\n#define Print(...) (printf(__VA_ARGS__), printf("\\n"))\n'
        + text.replace("void main()", "int main(void)")
    )
    return text, c_text, expected


def run_gcc(src: str, tmp: Path) -> list[str]:
    c = tmp / "init.c"
    c.write_text(src, encoding="utf-8")
    exe = tmp / "init"
    subprocess.run(
        [GCC, "-std=c99", "-pedantic-errors", "-O0", "-o", exe, c], check=True, capture_output=True
    )
    return subprocess.run([exe], capture_output=True, text=True, check=True).stdout.splitlines()


@pytest.mark.filterwarnings("ignore:The recursion limit will not be reset")
@PROFILE
@given(seed=st.integers(0, 2**32 - 1))
def test_elided_initializers_agree_with_c(seed, tmp_path_factory):
    text, c_text, expected = make_batch(seed)
    got = run_hmpl(text)
    assert got == [str(v) for v in expected], text
    if GCC is not None:
        assert run_gcc(c_text, tmp_path_factory.mktemp("cinit")) == got, text


def test_gcc_present_or_noticed():
    if GCC is None:
        pytest.skip("gcc not found: the initializer test compares with its own C rules only")


def test_the_generator_elides_and_truncates():
    """The batches exercise what they claim: elided braces and left-out values."""
    text, _, expected = make_batch(1)
    assert 0 in expected
    flat_arrays = [ln for ln in text.splitlines() if "][" in ln and "= {" in ln and "{{" not in ln]
    assert flat_arrays or "}, " in text
