"""Did-you-mean suggestions for misspelt names."""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING

from urdftool.lazy import LazyModule

if TYPE_CHECKING:
    import difflib
else:  # imported when a name is misspelt, not by every reader that might suggest one
    difflib = LazyModule("difflib")


def closest(word: str, candidates: Iterable[str], cutoff: float = 0.6) -> str | None:
    """The candidate closest to *word*, or ``None`` when nothing is within *cutoff* (difflib's
    similarity ratio, 0 to 1)."""
    # difflib.get_close_matches(word, sorted(set(candidates)), n=1, cutoff=cutoff), the same
    # answer (the highest ratio, ties to the later name) without its exact ratio for every name:
    # each quicker ratio bounds the exact one from above, so a name whose bound is below the best
    # ratio so far cannot win. Matters for a misspelt name among a large robot's thousand links.
    matcher = difflib.SequenceMatcher()
    matcher.set_seq2(word)
    best: tuple[float, str] | None = None
    for candidate in set(candidates):
        floor = cutoff if best is None else max(cutoff, best[0])
        matcher.set_seq1(candidate)
        if matcher.real_quick_ratio() < floor or matcher.quick_ratio() < floor:
            continue
        score = matcher.ratio()
        if score >= cutoff and (best is None or (score, candidate) > best):
            best = (score, candidate)
    return best[1] if best is not None else None


def did_you_mean(word: str, candidates: Iterable[str]) -> str:
    """``"; did you mean 'x'?"`` or the empty string."""
    match = closest(word, candidates)
    return f"; did you mean '{match}'?" if match else ""
