"""motionvm: a virtual motion controller for HMPL, PDL and GDL programs."""

__version__ = "0.1.0"
