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

Compiling takes about a minute and a half; a message on stderr says so first (pip shows
it with -v). An in-place build (`pip install -e .`) that the record says was made from
the sources now there, the same way, is reused, not compiled again: `pip install -e
'.[test]'` after `pip install -e .` takes seconds.
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
                "Cython and the C compiler; about a minute and a half) ...",
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

    def build_extensions(self) -> None:
        try:
            super().build_extensions()
        except Exception as exc:
            self._give_up(exc)

    def _give_up(self, exc: Exception) -> None:
        print(f"motionvm: compiled build skipped ({exc}); pure Python", file=sys.stderr)
        for ext in self.extensions:  # none half-built: remove what was built
            path = self.get_ext_fullpath(ext.name)
            if os.path.exists(path):
                os.remove(path)
        self.extensions = []

    def _record(self) -> None:
        """The digest of each compiled module's source, and how they were compiled,
        beside the package's modules (written atomically)."""
        record = {m: build_info.source_digest(f) for m, f in build_info.sources(SRC).items()}
        record[build_info.BUILD_KEY] = build_description()
        path = self._package_dir() / build_info.RECORD
        tmp = path.with_name(path.name + ".tmp")
        tmp.write_text(json.dumps(record, indent=1) + "\n", "utf-8")
        os.replace(tmp, path)


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
        )
    except Exception as exc:  # a Cython error: stay pure Python
        print(f"motionvm: cythonize failed ({exc}); pure Python", file=sys.stderr)
        return []


setup(ext_modules=extensions(), cmdclass={"build_ext": OptionalBuildExt})
