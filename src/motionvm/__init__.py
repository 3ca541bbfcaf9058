"""motionvm: a virtual motion controller for HMPL, PDL and GDL programs."""

from motionvm import compiled_build

__version__ = "0.1.0"

compiled_build.choose()  # the motion cycle: compiled or pure Python, before its import
