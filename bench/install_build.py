"""Benchmark: the install's compile step (setup.py's compiled build of the motion cycle).

Builds the motion cycle from a fresh copy of a source tree (`setup.py build_ext
--inplace`, what `pip install -e .` runs: Cython, then the C compiler) and prints the
wall-clock seconds (what an install waits) and the CPU seconds of the processes. With
`--old DIR` (another checkout, say `git worktree add /tmp/old main`) the two trees'
builds alternate, REPEAT times each, and the medians are compared. Then, for this tree,
the rebuild after one module's source is edited (the other modules are reused).

Needs a Python with Cython (setup.py's build requirement): `--python PY`, e.g.
    python -m venv /tmp/cy && /tmp/cy/bin/pip install Cython==3.1.8 "setuptools>=77" wheel
    python bench/install_build.py --python /tmp/cy/bin/python --old /tmp/old
Prints `RESULT name=value` lines.
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]
REPEAT = 3
_SKIP = shutil.ignore_patterns(
    "__pycache__", "*.c", "*.so", "*.pyd", "*.html", "compiled_sources.json", "node_modules"
)


def copy_tree(root: Path, to: Path) -> Path:
    """The files setup.py reads, without any build output."""
    to.mkdir(parents=True)
    for name in ("setup.py", "pyproject.toml", "README.md", "LICENSE", "MANIFEST.in"):
        if (root / name).exists():
            shutil.copy2(root / name, to / name)
    shutil.copytree(root / "src", to / "src", ignore=_SKIP)
    return to


def _children_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def build(python: str, tree: Path) -> tuple[float, float, str]:
    """(wall s, CPU s, stderr) of an in-place build of `tree`."""
    env = dict(os.environ)
    env.pop("MOTIONVM_PURE", None)
    env.pop("PYTHONPATH", None)
    c0, t0 = _children_cpu(), time.perf_counter()
    r = subprocess.run([python, "setup.py", "-q", "build_ext", "--inplace"], cwd=tree,
                       env=env, capture_output=True, text=True, timeout=1800)  # fmt: skip
    wall, cpu = time.perf_counter() - t0, _children_cpu() - c0
    if r.returncode != 0 or "compiled build skipped" in r.stderr or "failed" in r.stderr:
        print(r.stdout[-2000:], r.stderr[-4000:], file=sys.stderr)
        raise SystemExit(f"the build of {tree} failed")
    built = list((tree / "src").rglob("*.so")) + list((tree / "src").rglob("*.pyd"))
    if len(built) != 6:
        raise SystemExit(f"the build of {tree} made {len(built)} extensions, not 6")
    return wall, cpu, r.stderr


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--python", default=sys.executable, help="a Python with Cython")
    ap.add_argument("--old", type=Path, help="another checkout to compare with")
    ap.add_argument("--repeat", type=int, default=REPEAT)
    args = ap.parse_args()
    check = subprocess.run([args.python, "-c", "import Cython"], capture_output=True)
    if check.returncode:
        raise SystemExit(f"{args.python} has no Cython: see this file's docstring")
    sides = {"new": HERE} | ({"old": args.old.resolve()} if args.old else {})
    times: dict[str, list[tuple[float, float]]] = {k: [] for k in sides}
    with tempfile.TemporaryDirectory(prefix="mvm-build-") as tmp:
        for k in range(args.repeat):
            for side, root in sides.items() if k % 2 == 0 else reversed(sides.items()):
                tree = copy_tree(root, Path(tmp, f"{side}{k}"))
                wall, cpu, _ = build(args.python, tree)
                times[side].append((wall, cpu))
                print(f"{side}: {wall:.1f} s wall, {cpu:.1f} s CPU", flush=True)
                if side == "new" and k == 0:
                    edited = tree / "src/motionvm/drives/sensors.py"
                    edited.write_text(edited.read_text() + "\n# edited\n")
                    one_wall, one_cpu, err = build(args.python, tree)
                    print(f"new, one module edited: {one_wall:.1f} s wall, {one_cpu:.1f} s CPU")
                    print("  " + "\n  ".join(ln for ln in err.splitlines() if "motionvm" in ln))
                shutil.rmtree(tree)
    med = {s: (statistics.median(w for w, _ in v), statistics.median(c for _, c in v))
           for s, v in times.items()}  # fmt: skip
    print(f"cores: {os.cpu_count()}, load average: {os.getloadavg()[0]:.1f}")
    for side, (wall, cpu) in med.items():
        print(f"RESULT install_build_{side}_wall_s={wall:.1f}")
        print(f"RESULT install_build_{side}_cpu_s={cpu:.1f}")
    print(f"RESULT install_build_one_module_edited_wall_s={one_wall:.1f}")
    if "old" in med:
        print(f"RESULT install_build_wall_old_over_new={med['old'][0] / med['new'][0]:.2f}")


if __name__ == "__main__":
    main()
