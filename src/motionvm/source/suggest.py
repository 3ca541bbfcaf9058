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
    if found:
        return by_lower[found[0]]
    return _fewest_edits(lower, by_lower)


def _fewest_edits(lower: str, by_lower: dict[str, str]) -> str | None:
    """For short names, where one typo moves difflib's ratio a long way (`cout` is 0.57
    from `cnt`): the candidate with the same first letter within `_allowed` edits
    (insert, delete, replace, swap two neighbours), the fewest first."""
    if len(lower) < 3:
        return None
    best, best_d = None, None
    for low, c in by_lower.items():
        if low[:1] != lower[:1] or abs(len(low) - len(lower)) > 2:
            continue
        limit = _allowed(max(len(low), len(lower)))
        d = edit_distance(lower, low, limit)
        if d <= limit and (best_d is None or d < best_d):
            best, best_d = c, d
    return best


def _allowed(length: int) -> int:
    """Edits a name of `length` characters may be away from a suggestion."""
    return 1 if length <= 3 else 2 if length <= 8 else 3


def edit_distance(a: str, b: str, limit: int) -> int:
    """Optimal string alignment distance of `a` and `b` (Damerau-Levenshtein without
    repeated edits of one substring); any value > `limit` once it is certain."""
    if abs(len(a) - len(b)) > limit:
        return limit + 1
    prev2: list[int] = []
    prev = list(range(len(b) + 1))
    for i in range(1, len(a) + 1):
        cur = [i] + [0] * len(b)
        for j in range(1, len(b) + 1):
            cost = 0 if a[i - 1] == b[j - 1] else 1
            cur[j] = min(prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + cost)
            if i > 1 and j > 1 and a[i - 1] == b[j - 2] and a[i - 2] == b[j - 1]:
                cur[j] = min(cur[j], prev2[j - 2] + 1)
        if min(cur) > limit:
            return limit + 1
        prev2, prev = prev, cur
    return prev[-1]


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
