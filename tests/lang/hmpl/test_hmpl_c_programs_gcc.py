"""The C-feature golden programs (tests/programs/hmpl/c/) are C as well: gcc compiles
them (with `Print` a printf that ends the line) and must print what their `// expect:`
lines say (read by the case model of `motionvm test`, `motionvm.cli.cases`), so the
expectations are C's meaning and not only HMPL's. Skipped without gcc.
"""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

from motionvm.cli.cases import expectations_of

PROGRAMS = Path(__file__).resolve().parents[2] / "programs" / "hmpl" / "c"
GCC = shutil.which("gcc")
# block_prototypes calls a function after the block of its prototype: C89's implicit
# declaration, hence gnu89 (which also has compound literals and designators)
C_PROGRAMS = [
    "brace_elision",
    "compound_literals",
    "line_directive",
    "block_prototypes",
    "switch_case_in_block",
    "forward_typedef",
]
PRELUDE = '#include <stdio.h>\n#define Print(...) (printf(__VA_ARGS__), printf("\\n"))\n'


def expected_lines(program: Path) -> list[str]:
    found = expectations_of(program)
    assert found is not None, f"{program.name} has no expectations"
    assert all(kind == "text" for kind, _ in found[0].stdout)
    return [line for _, line in found[0].stdout]


@pytest.mark.skipif(GCC is None, reason="gcc not found")
@pytest.mark.parametrize("stem", C_PROGRAMS)
def test_gcc_prints_what_the_program_expects(stem, tmp_path):
    text = (PROGRAMS / f"{stem}.hmpl").read_text(encoding="utf-8")
    c = tmp_path / f"{stem}.c"
    # `#line 1`: the line numbers stay those of the .hmpl file
    c.write_text(PRELUDE + "#line 1\n" + text.replace("void main()", "int main()"))
    exe = tmp_path / stem
    subprocess.run([GCC, "-std=gnu89", "-w", "-o", exe, c], check=True, capture_output=True)
    # main() has no return statement: its exit status means nothing in C89
    out = subprocess.run([exe], capture_output=True, text=True, check=False, timeout=60)
    assert out.stdout.splitlines() == expected_lines(PROGRAMS / f"{stem}.hmpl")
