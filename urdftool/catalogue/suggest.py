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
    matches = difflib.get_close_matches(word, sorted(set(candidates)), n=1, cutoff=cutoff)
    return matches[0] if matches else None


def did_you_mean(word: str, candidates: Iterable[str]) -> str:
    """``"; did you mean 'x'?"`` or the empty string."""
    match = closest(word, candidates)
    return f"; did you mean '{match}'?" if match else ""
