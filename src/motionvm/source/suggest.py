"""'Did you mean ...?' suggestions for misspelt names."""

from __future__ import annotations

import difflib
from collections.abc import Iterable


def closest(name: str, candidates: Iterable[str]) -> str | None:
    """The candidate the user most likely meant, or None; an exact case-insensitive match wins."""
    pool = list(candidates)
    lower = name.lower()
    for c in pool:
        if c.lower() == lower and c != name:
            return c
    found = difflib.get_close_matches(name, pool, n=1, cutoff=0.75)
    if found:
        return found[0]
    by_lower = {c.lower(): c for c in pool}
    found = difflib.get_close_matches(lower, list(by_lower), n=1, cutoff=0.75)
    return by_lower[found[0]] if found else None


def did_you_mean(name: str, candidates: Iterable[str]) -> str:
    """' (did you mean 'X'?)' or ''."""
    c = closest(name, candidates)
    return f" (did you mean '{c}'?)" if c else ""
