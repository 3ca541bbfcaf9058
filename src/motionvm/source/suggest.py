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


def ranked(name: str, candidates: Iterable[str], n: int = 3, cutoff: float = 0.6) -> list[str]:
    """Up to `n` candidates like `name`, the closest first: compared case-insensitively
    (`movabs` is nearer `MoveAbs` than `abs`), an exact case-insensitive match first;
    ties keep the candidates' order."""
    lower = name.lower()
    scored = []
    for i, c in enumerate(candidates):
        low = c.lower()
        score = 2.0 if low == lower else difflib.SequenceMatcher(None, lower, low).ratio()
        if score >= cutoff:
            scored.append((-score, i, c))
    return [c for _, _, c in sorted(scored)[:n]]
