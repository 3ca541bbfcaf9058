"""C arithmetic three ways: each random typed integer expression is computed by the
compiler's constant folding, by the generated code at run time, and by gcc (-fwrapv, with
UBSan telling which expressions C leaves undefined: those are compared only between the
two HMPL forms). All three must agree, bit for bit and in signedness.

Batches of 250 expressions; the `ci` profile runs 20 batches (5,000 expressions), the
`thorough` one 200. Without gcc the gcc side is skipped with a notice.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

sys.path.insert(0, str(Path(__file__).resolve().parent))
from c_arith_gen import C_FIRST_LINE, c_program, hmpl_program, make_batch  # noqa: E402
from hmpl_run import run_hmpl  # noqa: E402

settings.register_profile(
    "carith-ci", max_examples=20, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)  # fmt: skip
settings.register_profile(
    "carith-thorough", max_examples=200, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)  # fmt: skip
PROFILE = settings.get_profile(
    "carith-thorough" if os.environ.get("HYPOTHESIS_PROFILE") == "thorough" else "carith-ci"
)
BATCH = 250
GCC = shutil.which("gcc")
_UB = re.compile(r":(\d+):\d+: runtime error: ")


def run_gcc(src: str, tmp: Path) -> tuple[list[str], set[int]]:
    """gcc's values and the indexes of the expressions UBSan found undefined."""
    c = tmp / "diff.c"
    c.write_text(src, encoding="utf-8")
    exe = tmp / "diff"
    subprocess.run(
        [GCC, "-O0", "-fwrapv", "-fsanitize=undefined,float-cast-overflow", "-w", "-o", exe, c],
        check=True,
        capture_output=True,
    )
    r = subprocess.run([exe], capture_output=True, text=True, check=True, timeout=60)
    undefined = {int(m.group(1)) - C_FIRST_LINE for m in _UB.finditer(r.stderr)}
    return r.stdout.splitlines(), undefined


def check_batch(seed: int, tmp: Path) -> None:
    batch = make_batch(seed, BATCH)
    got = [line.split() for line in run_hmpl(hmpl_program(batch))]
    assert len(got) == BATCH
    for k, (folded, runtime) in enumerate(got):
        assert folded == runtime, f"folded {folded} != run time {runtime}: {batch.exprs[k][1]}"
    if GCC is None:
        return
    want, undefined = run_gcc(c_program(batch), tmp)
    for k, (_, runtime) in enumerate(got):
        if k not in undefined:
            assert runtime == want[k], f"HMPL {runtime} != gcc {want[k]}: {batch.exprs[k][2]}"


@pytest.mark.filterwarnings("ignore:The recursion limit will not be reset")
@PROFILE
@given(seed=st.integers(0, 2**32 - 1))
def test_folded_runtime_and_gcc_agree(seed, tmp_path_factory):
    check_batch(seed, tmp_path_factory.mktemp("carith"))


def test_gcc_present_or_noticed():
    if GCC is None:
        pytest.skip("gcc not found: the differential test compares folded and run-time values only")


def test_ring_operations_convert_a_narrower_negative_operand():
    """A negative narrower signed operand of |, ^, & converts to the unsigned type first."""
    src = """unsigned long long u; int m; unsigned a; char c;
void main() {
    u = 0; m = -1; a = 1; c = -1;
    Print("%d %u %d", (u | m) > 0, (a ^ c) / 2, (u ^ m) > 0);
    Print("%d %u %d", (0ull | -1) > 0, (1u ^ (char)-1) / 2, (0ull ^ -1) > 0);
}
"""
    assert run_hmpl(src) == ["1 2147483647 1", "1 2147483647 1"]
