"""Random move sequences with random waits print the same with the compiled motion cycle
and with its pure-Python modules (motionvm/compiled_build.py).

The programs and machines of `test_skip_random.py` (two tasks, three axes, every kind of
move and wait, random cycle time, motor delay, counts per mm, limits), each run through
the command line twice in a process of its own: as installed (compiled) and with
`MOTIONVM_PURE=1`. The exit codes, the outputs with `--stamp` times and the messages
(a task's fault, the tasks still waiting at `--timeout`) must be identical. Skipped where the compiled build is not in use.
"""

from __future__ import annotations

import os
import subprocess
import sys

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from skip_util import machine_file
from test_skip_random import AXES, _task, machine, statement

from motionvm import compiled_build

settings.register_profile("compiled-ci", max_examples=6, derandomize=True, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])  # fmt: skip
settings.register_profile("compiled-thorough", max_examples=100, derandomize=True,
                          deadline=None, suppress_health_check=[HealthCheck.too_slow])  # fmt: skip
PROFILE = settings.get_profile("compiled-" + os.environ.get("HYPOTHESIS_PROFILE", "ci"))


def _run(argv: list[str], pure: bool) -> tuple[int, str, str]:
    env = dict(os.environ)
    env.pop("MOTIONVM_PURE", None)
    if pure:
        env["MOTIONVM_PURE"] = "1"
    code = f"import sys; from motionvm.cli import main; sys.exit(main({argv!r}))"
    r = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                       timeout=300)  # fmt: skip
    return r.returncode, r.stdout, r.stderr


@pytest.mark.skipif(compiled_build.STATUS != "compiled", reason="no compiled build in use")
@PROFILE
@given(machine, st.lists(statement, min_size=1, max_size=10), st.lists(statement, max_size=6))
def test_compiled_and_pure_runs_print_the_same(tmp_path_factory, spec, body_0, body_1):
    tmp = tmp_path_factory.mktemp("compiled")
    paths = []
    for i, text in enumerate([_task(body_0, True), _task(body_1, False)]):
        p = tmp / f"t{i}.hmpl"
        p.write_text(text, encoding="utf-8")
        paths.append(str(p))
    argv = ["run", "--stamp", "--no-progress", "--timeout", "60",
            "--machine", machine_file(tmp, spec, AXES), *paths]  # fmt: skip
    compiled = _run(argv, pure=False)
    assert compiled[0] in (0, 1, 124), compiled  # finished, a task faulted, or --timeout
    assert compiled == _run(argv, pure=True)
