"""Optional compiled build of the motion cycle's hot classes (everything else: pyproject.toml).

The .py files are the only source of the code. Next to four of them a Cython `.pxd`
file declares their hot classes as extension types with typed attributes (an
"augmenting" .pxd); Cython compiles the .py file with it. Where Cython or a C compiler
is missing, or MOTIONVM_PURE=1 is set, or a module fails to compile, the package installs
and runs as pure Python, unchanged. The four modules are compiled together or not at all
(each compiled module imports the others' extension types).

Bit-identical results: C double arithmetic is Python's float arithmetic as long as no
multiply-add is contracted (-ffp-contract=off) and no fast-math flag is set; annotations
do not type anything (annotation_typing=False), only the .pxd files do.
"""

from __future__ import annotations

import os
import sys

from setuptools import setup
from setuptools.command.build_ext import build_ext

COMPILED = [
    "motionvm/drives/mechanics",
    "motionvm/drives/cia402",
    "motionvm/motion/profile",
    "motionvm/motion/axis_cycle",
]


class OptionalBuildExt(build_ext):
    """Build the extensions all or none: a failure leaves the pure-Python package."""

    def run(self) -> None:
        try:
            super().run()
        except Exception as exc:  # no compiler, a compile error: stay pure Python
            self._give_up(exc)

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


def extensions() -> list:
    if os.environ.get("MOTIONVM_PURE") or sys.implementation.name != "cpython":
        return []
    try:
        from Cython.Build import cythonize
        from setuptools import Extension
    except ImportError:
        return []
    flags = ["-O2", "-ffp-contract=off", "-fno-fast-math"]
    exts = [
        Extension(m.replace("/", "."), [f"src/{m}.py"], extra_compile_args=flags)
        for m in COMPILED
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
