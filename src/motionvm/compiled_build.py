"""Whether the motion cycle runs compiled or as pure Python, chosen once per process.

The package's `setup.py` may compile the modules of the motion cycle and of its
closed-form advance (`MODULES`) with Cython, each from its own `.py` file and the `.pxd` file next to it that
types its hot class; the `.py` files are the only source of the code. It then records
the SHA-256 of each module's `.py` and `.pxd` in `compiled_sources.json` beside this
file. `choose` (run by the package's `__init__`, before anything imports those modules)
keeps the compiled modules only if all of them are there and each was built from the
source now beside it. Otherwise (a source edited since, a build half there, or
`MOTIONVM_PURE=1` in the environment) all of them load from their `.py` files: the
compiled modules import each other's types, so it is all or none; an install that
ships the extensions without their sources uses them as they are. The results are the
same bit for bit either way (the build keeps C's floating-point operations those of
Python: no contracted multiply-add, no fast math); only the speed differs.
`motionvm --version` says which one runs (`STATUS`).
"""

from __future__ import annotations

import hashlib
import importlib.machinery
import importlib.util
import json
import os
import sys
from pathlib import Path

MODULES = (
    "motionvm.drives.mechanics",
    "motionvm.drives.sensors",
    "motionvm.drives.cia402",
    "motionvm.motion.profile",
    "motionvm.motion.axis_cycle",
    "motionvm.motion.axis_coast",
)
"""The modules the compiled build compiles (setup.py reads this list)."""

RECORD = "compiled_sources.json"
"""The build's record of what it compiled: {module: SHA-256 of its .py and .pxd}, and
under BUILD_KEY how (setup.py's Cython version, compiler flags and directives)."""

BUILD_KEY = "build"

FLAGS = ("-O2", "-g0", "-ffp-contract=off", "-fno-fast-math")
"""The C compiler's flags: no contracted multiply-add, no fast math (the same floats);
no debugging information (Python's own `-g` costs a third of the compile time)."""

DECLARATIONS_KEY = "declarations"
"""The record's digest of every compiled module's .pxd (`declarations_digest`)."""

DIRECTIVES = {"language_level": 3, "annotation_typing": False}
"""Cython's directives: annotations type nothing, only the .pxd files do."""


def build_description(cython_version: str) -> str:
    """How setup.py compiles, as its record keeps it: a build made with another Cython,
    other flags or directives is compiled again, not reused."""
    return json.dumps({"cython": cython_version, "flags": FLAGS, "directives": DIRECTIVES})


STATUS = "pure Python"
"""What `choose` found: "compiled", "pure Python", or "pure Python (why)"."""


def source_digest(py_file: Path) -> str:
    """SHA-256 of a compiled module's source: its .py file, then its .pxd file."""
    h = hashlib.sha256(py_file.read_bytes())
    pxd = py_file.with_suffix(".pxd")
    if pxd.exists():
        h.update(pxd.read_bytes())
    return h.hexdigest()


def sources(root: Path) -> dict[str, Path]:
    """The .py file of each compiled module in the package at `root`."""
    return {m: root.joinpath(*m.split(".")[1:]).with_suffix(".py") for m in MODULES}


def _has_extension(py_file: Path) -> bool:
    stem = py_file.with_suffix("")
    return any(
        stem.with_name(stem.name + s).exists() for s in importlib.machinery.EXTENSION_SUFFIXES
    )


def why_pure(root: Path, environ=os.environ) -> str | None:
    """None if the compiled modules of the package at `root` can be used; else why not
    ("" if there is no compiled build at all)."""
    files = sources(root)
    built = [m for m, f in files.items() if _has_extension(f)]
    if not built:
        return ""
    if not all(f.exists() for f in files.values()):
        return None  # an install without the sources: the compiled modules are all there is
    if environ.get("MOTIONVM_PURE", "") not in ("", "0"):
        return "MOTIONVM_PURE is set"
    if len(built) != len(files):
        return "the compiled build is incomplete"
    try:
        record = json.loads((root / RECORD).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return f"{RECORD} is missing or unreadable"
    for m, f in files.items():
        if record.get(m) != source_digest(f):
            where = f.relative_to(root.parent).as_posix()
            return f"{where} changed since it was compiled; pip install again to compile it"
    return None


def reusable(root: Path, build: str, ext_suffix: str) -> bool:
    """Whether the package at `root` holds a compiled build that a new build would only
    repeat: every module's extension with `ext_suffix` (this Python's), a record whose
    digests are those of the sources now beside them, made the same way (`build`, as
    setup.py describes its compile). setup.py then reuses it instead of compiling."""
    files = sources(root)
    try:
        record = json.loads((root / RECORD).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return False
    if not isinstance(record, dict) or record.get(BUILD_KEY) != build:
        return False
    for m, f in files.items():
        if not f.with_name(f.stem + ext_suffix).exists():
            return False
        if not f.exists() or record.get(m) != source_digest(f):
            return False
    return True


def declarations_digest(root: Path) -> str:
    """SHA-256 of the .pxd files of all the compiled modules of the package at `root`: a
    module's C code depends on the declarations of those it cimports, not only its own."""
    h = hashlib.sha256()
    for f in sources(root).values():
        pxd = f.with_suffix(".pxd")
        h.update(pxd.read_bytes() if pxd.exists() else b"-")
        h.update(b"\0")
    return h.hexdigest()


def reusable_modules(root: Path, build: str, ext_suffix: str) -> set[str]:
    """The modules of the package at `root` whose extension (`ext_suffix`) a new build
    would only repeat: the record says they were made the same way (`build`) from the
    source now beside them, with every module's declarations (.pxd) as they are now.
    setup.py compiles only the others (one edited module: one compile)."""
    try:
        record = json.loads((root / RECORD).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return set()
    if not isinstance(record, dict) or record.get(BUILD_KEY) != build:
        return set()
    try:
        if record.get(DECLARATIONS_KEY) != declarations_digest(root):
            return set()
    except OSError:
        return set()
    return {
        m
        for m, f in sources(root).items()
        if f.exists()
        and f.with_name(f.stem + ext_suffix).exists()
        and record.get(m) == source_digest(f)
    }


class _SourceFinder:
    """A meta path finder that loads the compiled modules from their .py files."""

    def __init__(self, files: dict[str, Path]) -> None:
        self.files = files

    def find_spec(self, name, path=None, target=None):
        f = self.files.get(name)
        return None if f is None else importlib.util.spec_from_file_location(name, f)


def choose() -> str:
    """Pick compiled or pure Python for this process (see the module docstring); sets and
    returns `STATUS`. Call it before any of `MODULES` is imported."""
    global STATUS
    root = Path(__file__).parent
    reason = why_pure(root)
    if reason is None:
        STATUS = "compiled"
    else:
        if reason:  # an extension is there that must not load
            sys.meta_path.insert(0, _SourceFinder(sources(root)))
        STATUS = f"pure Python ({reason})" if reason else "pure Python"
    return STATUS
