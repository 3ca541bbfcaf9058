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
"""

from __future__ import annotations

import importlib.util
import json
import os
import sys
from pathlib import Path

from setuptools import setup
from setuptools.command.build_ext import build_ext

_spec = importlib.util.spec_from_file_location(
    "motionvm_compiled_build", Path(__file__).parent / "src/motionvm/compiled_build.py"
)
build_info = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(build_info)  # (not `import motionvm`: nothing is built yet)


class OptionalBuildExt(build_ext):
    """Build the extensions all or none: a failure leaves the pure-Python package. A
    build records what it compiled (motionvm/compiled_build.py, `RECORD`)."""

    def run(self) -> None:
        try:
            super().run()
        except Exception as exc:  # no compiler, a compile error: stay pure Python
            self._give_up(exc)
        if self.extensions:
            self._record()

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
        """The digest of each compiled module's source, beside the package's modules."""
        src_root = Path(__file__).parent / "src" / "motionvm"
        record = {m: build_info.source_digest(f) for m, f in build_info.sources(src_root).items()}
        # the package directory the extensions went to (in place or the build tree)
        first = build_info.MODULES[0]
        package = Path(self.get_ext_fullpath(first)).parents[first.count(".") - 1]
        (package / build_info.RECORD).write_text(json.dumps(record, indent=1) + "\n", "utf-8")


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
    flags = ["-O2", "-ffp-contract=off", "-fno-fast-math"]
    exts = [
        Extension(m, [f"src/{m.replace('.', '/')}.py"], extra_compile_args=flags)
        for m in build_info.MODULES
    ]
    try:
        return cythonize(
            exts,
            compiler_directives={"language_level": 3, "annotation_typing": False},
            include_path=["src"],
            quiet=True,
        )
    except Exception as exc:  # a Cython error: stay pure Python
        print(f"motionvm: cythonize failed ({exc}); pure Python", file=sys.stderr)
        return []


setup(ext_modules=extensions(), cmdclass={"build_ext": OptionalBuildExt})
