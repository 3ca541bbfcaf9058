"""PDL, the language of HIWIN mega-fabs servo drives: front end, lowering and run side.

The language's face is `language.py` (the language interface). `front.compile_front` runs
the preprocessor, parser and checker on one file; `program.compile_pdl` lowers it to
Python. The run side: `drive_rt.Drive` (4 tasks on the 15 kHz phase clock,
`drive_loop.py`), its profile `drive_axis.py`, and `machine_drives.PdlDrives`, the cycle
client that runs drives on the controller's clock and moves the machine's axes with them.
`FrontResult`, `compile_front` and `front_end` are importable from this package too,
loaded on first use (the registry, `motionvm.lang`, stays cheap to import).
"""

from __future__ import annotations

import importlib

__all__ = ["FrontResult", "compile_front", "front_end"]


def __getattr__(name: str):
    if name not in __all__:
        raise AttributeError(f"module 'motionvm.lang.pdl' has no attribute '{name}'")
    return getattr(importlib.import_module("motionvm.lang.pdl.front"), name)
