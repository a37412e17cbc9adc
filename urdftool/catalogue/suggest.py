"""Did-you-mean suggestions for misspelt names."""

from __future__ import annotations

import functools
from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING

from urdftool.lazy import LazyModule

if TYPE_CHECKING:
    import difflib
else:  # imported when a name is misspelt, not by every reader that might suggest one
    difflib = LazyModule("difflib")


def closest(word: str, candidates: Iterable[str], cutoff: float = 0.6) -> str | None:
    """The candidate closest to *word*, or ``None`` when nothing is within *cutoff* (difflib's
    similarity ratio, 0 to 1)."""
    if isinstance(candidates, frozenset) and len(candidates) <= _VOCABULARY:
        # A fixed vocabulary (an element's attributes, its children): the same misspelling on
        # every joint of a CAD export is looked up once.
        return _closest_in_vocabulary(word, candidates, cutoff)
    return _closest(word, candidates, cutoff)


#: Largest set of names taken for a fixed vocabulary, whose answers are kept (a robot's own
#: names can run to thousands, and are not kept).
_VOCABULARY = 64


@functools.lru_cache(maxsize=1024)
def _closest_in_vocabulary(word: str, candidates: frozenset[str], cutoff: float) -> str | None:
    return _closest(word, candidates, cutoff)


def _closest(word: str, candidates: Iterable[str], cutoff: float) -> str | None:
    # difflib.get_close_matches(word, sorted(set(candidates)), n=1, cutoff=cutoff), the same
    # answer (the highest ratio, ties to the later name) without its exact ratio for every name:
    # quick_ratio bounds the exact ratio from above, so the names are tried best bound first and
    # the search stops at the first bound below the best ratio found. Matters for a misspelt name
    # among a large robot's thousand links.
    # Both bounds are computed here as difflib computes them (real_quick_ratio: the shorter
    # length; quick_ratio: the letters in common, counted with multiplicity), the same floats,
    # without a matcher per name: str.count over the word's distinct letters, in C.
    # A letter the word holds once is in common when the name has it at all: one set
    # intersection for those (most of a name's letters), a count only for the repeated ones.
    # A name that could hold every repeated letter as often as the word does and still has too
    # few letters in common (most names of a robot) is dropped before those letters are counted.
    letters = tuple(dict.fromkeys(word))
    once = frozenset(letter for letter in letters if word.count(letter) == 1)
    repeated = tuple(letter for letter in letters if letter not in once)
    counts = tuple(word.count(letter) for letter in repeated)
    most = sum(counts)  # the repeated letters a name can have in common with the word, at most
    size = len(word)
    bounded: list[tuple[float, str]] = []
    # a set of names is searched as it is (the order does not matter: the bounds are sorted)
    for candidate in candidates if isinstance(candidates, (set, frozenset)) else set(candidates):
        length = len(candidate) + size
        # _ratio(min(len(candidate), size), length), written out: this runs for every name.
        if not length or 2.0 * min(len(candidate), size) / length >= cutoff:
            single = len(once.intersection(candidate))
            if _ratio(single + most, length) < cutoff:
                continue
            common = single + sum(map(min, map(candidate.count, repeated), counts))
            bound = _ratio(common, length)
            if bound >= cutoff:
                bounded.append((bound, candidate))
    if not bounded:
        return None
    matcher = difflib.SequenceMatcher()
    matcher.set_seq2(word)
    best: tuple[float, str] | None = None
    for bound, candidate in sorted(bounded, reverse=True):
        if best is not None and bound < best[0]:
            break
        matcher.set_seq1(candidate)
        score = matcher.ratio()
        if score >= cutoff and (best is None or (score, candidate) > best):
            best = (score, candidate)
    return best[1] if best is not None else None


def _ratio(matches: int, length: int) -> float:
    """difflib's ``_calculate_ratio``."""
    return 2.0 * matches / length if length else 1.0


def did_you_mean(word: str, candidates: Iterable[str]) -> str:
    """``"; did you mean 'x'?"`` or the empty string."""
    match = closest(word, candidates)
    return f"; did you mean '{match}'?" if match else ""


def suggester(candidates: Iterable[str]) -> Callable[[str], str]:
    """:func:`did_you_mean` against one set of names, each word answered once: a model that
    misspells one name in several places (four ``<gazebo>`` blocks of one caster, a link in many
    SRDF entries) pays for one search among its names, not one per place."""
    names = set(candidates)
    answers: dict[str, str] = {}

    def suggest(word: str) -> str:
        answer = answers.get(word)
        if answer is None:
            answer = answers[word] = did_you_mean(word, names)
        return answer

    return suggest
