"""Optional compiled build of the motion cycle (everything else: pyproject.toml).

The .py files are the only source of the code. Next to each module of
motionvm/compiled_build.py's `MODULES` a Cython `.pxd` file declares its hot class as
an extension type with typed attributes, or types the objects its functions read (an
"augmenting" .pxd); Cython compiles the .py file with it. Where Cython or a C compiler
is missing, or MOTIONVM_PURE=1 is set, or a module fails to compile, the package installs
and runs as pure Python, unchanged. The modules are compiled together or not at all
(each compiled module imports the others' extension types).

Bit-identical results: C double arithmetic is Python's float arithmetic as long as no
multiply-add is contracted (-ffp-contract=off) and no fast-math flag is set; annotations
do not type anything (annotation_typing=False), only the .pxd files do.

Compiling takes about half a minute on 2 cores; a message on stderr says so first (pip
shows it with -v). Cython translates the modules in parallel processes (where they fork:
Linux), then the C compiler builds them in parallel, the largest first, without
debugging information. An in-place build (`pip install -e .`) that the record says was
made from the sources now there, the same way, is reused, not compiled again: `pip
install -e '.[test]'` after `pip install -e .` takes seconds; after an edit of one
module only that one is compiled again (of all of them after an edit of a .pxd file:
each module's C code depends on the declarations it cimports).
"""

from __future__ import annotations

import importlib.util
import json
import os
import shutil
import sys
from pathlib import Path

from setuptools import setup
from setuptools.command.build_ext import build_ext

_spec = importlib.util.spec_from_file_location(
    "motionvm_compiled_build", Path(__file__).parent / "src/motionvm/compiled_build.py"
)
build_info = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(build_info)  # (not `import motionvm`: nothing is built yet)

SRC = Path(__file__).resolve().parent / "src" / "motionvm"


def build_description() -> str:
    """How this file compiles, as the build's record keeps it."""
    import Cython

    return build_info.build_description(Cython.__version__)


class OptionalBuildExt(build_ext):
    """Build the extensions all or none: a failure leaves the pure-Python package. A
    build records what it compiled (motionvm/compiled_build.py, `RECORD`)."""

    def run(self) -> None:
        if self.extensions and self._reuse():
            return
        if self.extensions:
            print(
                f"motionvm: compiling the motion cycle ({len(self.extensions)} modules, "
                "Cython and the C compiler; about half a minute) ...",
                file=sys.stderr,
                flush=True,
            )
        try:
            super().run()
        except Exception as exc:  # no compiler, a compile error: stay pure Python
            self._give_up(exc)
        if self.extensions:
            self._record()
            print("motionvm: the motion cycle is compiled", file=sys.stderr, flush=True)

    def _reuse(self) -> bool:
        """Whether the in-place build is current (its record: the same sources, compiled
        the same way); then it is copied where this build puts its extensions (nothing
        to copy in place) instead of being compiled again."""
        first = self.extensions[0].name
        filename = Path(self.get_ext_filename(first)).name
        suffix = filename[len(first.rsplit(".", 1)[-1]) :]
        if not build_info.reusable(SRC, build_description(), suffix):
            return False
        for ext in self.extensions:
            built = SRC.parent / self.get_ext_filename(ext.name)
            target = Path(self.get_ext_fullpath(ext.name)).resolve()
            if target != built:
                target.parent.mkdir(parents=True, exist_ok=True)
                shutil.copy2(built, target)
        package = self._package_dir()
        if package != SRC:
            shutil.copy2(SRC / build_info.RECORD, package / build_info.RECORD)
        print(
            "motionvm: the motion cycle is compiled already from these sources; reused",
            file=sys.stderr,
            flush=True,
        )
        return True

    def _package_dir(self) -> Path:
        """The package directory the extensions go to (in place or the build tree)."""
        first = build_info.MODULES[0]
        return Path(self.get_ext_fullpath(first)).resolve().parents[first.count(".") - 1]

    def finalize_options(self) -> None:
        super().finalize_options()
        if not self.parallel:  # the C compiles at once on every core (`-j` overrides)
            self.parallel = max(1, min(len(self.extensions or ()), os.cpu_count() or 1))

    def build_extensions(self) -> None:
        self._all = list(self.extensions)
        self._reuse_modules()
        # the largest C file first: the cores finish together
        self.extensions.sort(key=_c_size, reverse=True)
        try:
            super().build_extensions()
        except Exception as exc:
            self._give_up(exc)

    def _reuse_modules(self) -> None:
        """Copy the in-place extensions of the modules the record says are current
        (`reusable_modules`) where this build puts them, and compile only the others."""
        if not self.extensions:
            return
        first = self.extensions[0].name
        filename = Path(self.get_ext_filename(first)).name
        suffix = filename[len(first.rsplit(".", 1)[-1]) :]
        current = build_info.reusable_modules(SRC, build_description(), suffix)
        for ext in [e for e in self.extensions if e.name in current]:
            built = SRC.parent / self.get_ext_filename(ext.name)
            target = Path(self.get_ext_fullpath(ext.name)).resolve()
            if target != built:
                target.parent.mkdir(parents=True, exist_ok=True)
                shutil.copy2(built, target)
            self.extensions.remove(ext)
        if current:
            print(
                f"motionvm: {len(current)} of the {len(self._all)} modules are compiled "
                "already from these sources; reused",
                file=sys.stderr,
                flush=True,
            )

    def _give_up(self, exc: Exception) -> None:
        print(f"motionvm: compiled build skipped ({exc}); pure Python", file=sys.stderr)
        for ext in getattr(self, "_all", self.extensions):  # none half-built: remove them
            path = self.get_ext_fullpath(ext.name)
            if os.path.exists(path):
                os.remove(path)
        self.extensions = []

    def _record(self) -> None:
        """The digest of each compiled module's source, and how they were compiled,
        beside the package's modules (written atomically)."""
        record = {m: build_info.source_digest(f) for m, f in build_info.sources(SRC).items()}
        record[build_info.BUILD_KEY] = build_description()
        record[build_info.DECLARATIONS_KEY] = build_info.declarations_digest(SRC)
        path = self._package_dir() / build_info.RECORD
        tmp = path.with_name(path.name + ".tmp")
        tmp.write_text(json.dumps(record, indent=1) + "\n", "utf-8")
        os.replace(tmp, path)


def _c_size(ext) -> int:
    try:
        return sum(os.path.getsize(f) for f in ext.sources)
    except OSError:
        return 0


def _cython_processes(n: int) -> int:
    """Processes for Cython: one per core, where a process pool forks (Linux); elsewhere
    a new process would run this file again."""
    import multiprocessing

    if sys.platform != "linux" or multiprocessing.get_start_method() != "fork":
        return 0
    return max(0, min(n, os.cpu_count() or 1))


def extensions() -> list:
    if os.environ.get("MOTIONVM_PURE", "") not in ("", "0"):
        return []
    if sys.implementation.name != "cpython":
        return []
    try:
        from Cython.Build import cythonize
        from setuptools import Extension
    except ImportError:
        return []
    exts = [
        Extension(m, [f"src/{m.replace('.', '/')}.py"], extra_compile_args=list(build_info.FLAGS))
        for m in build_info.MODULES
    ]
    try:
        return cythonize(
            exts,
            compiler_directives=dict(build_info.DIRECTIVES),
            include_path=["src"],
            quiet=True,
            nthreads=_cython_processes(len(exts)),
        )
    except Exception as exc:  # a Cython error: stay pure Python
        print(f"motionvm: cythonize failed ({exc}); pure Python", file=sys.stderr)
        return []


setup(ext_modules=extensions(), cmdclass={"build_ext": OptionalBuildExt})
