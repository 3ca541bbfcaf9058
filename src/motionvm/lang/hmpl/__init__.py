"""HMPL, HIWIN's C-like motion language: preprocessor, parser, checker, lowering to
Python generators, and its run side (`rtapi.py`, the built-ins in `lib/`)."""
