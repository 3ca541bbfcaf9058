"""Holding off Python's cyclic garbage collector while a compiler builds its trees.

A compile makes hundreds of thousands of tokens, syntax nodes and Python `ast` nodes that
form no reference cycles; with the collector on, it walks all of them again and again as
they pile up (about 40 % of a PDL compile's time). While held, nothing is collected; at
the end the survivors (the program keeps its trees) go straight to the oldest generation:
`freeze` then `unfreeze` splices the generation lists in O(1).
"""

from __future__ import annotations

import gc
from collections.abc import Iterator
from contextlib import contextmanager


@contextmanager
def gc_held(promote: bool = True) -> Iterator[None]:
    """No cyclic collection inside the block (the collector's state restored after).
    `promote`: what survives the block goes to the oldest generation (a compile, whose
    program lives on); False leaves it young, to be collected as usual (a front end's
    pass whose tokens and trees are soon dropped: the language server parses a file at
    every edit, and promoting those would keep their garbage until a full collection)."""
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_enabled:
            if promote:
                gc.freeze()
                gc.unfreeze()
            gc.enable()
