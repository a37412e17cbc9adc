"""Left/right names: which names of a robot may be each other's mirror.

One token swapped between ``left``/``right`` (``left_knee``, ``arm_left_2_joint``,
``panda_leftfinger``), ``l``/``r`` (``l_elbow``, ``hip_r``) or the side letter of a leg code
(``FL``/``FR``, ``RL``/``RR``, ``LF``/``RF``, ``LH``/``RH``). The symmetry rules
(:mod:`urdftool.rules.intent_symmetry`) judge the pairs found here; the names alone decide
nothing about the robot.
"""

from __future__ import annotations

import re
from collections.abc import Sequence

_TOKENS = re.compile(r"([_\-.]+)")
_WORDS = {
    "left": "right",
    "right": "left",
    "Left": "Right",
    "Right": "Left",
    "LEFT": "RIGHT",
    "RIGHT": "LEFT",
}
_LETTERS = {"l": "r", "r": "l", "L": "R", "R": "L"}
#: Every side marker holds one of these letters; a token without any has no other side.
_SIDE_LETTERS = frozenset(_LETTERS)


def mirror_names(name: str, swaps: dict[str, list[str]] | None = None) -> list[str]:
    """Names that *name* would have on the other side: every side marker swapped, then one at a time.

    *swaps*: each token's :func:`_swap_token`, kept across the names of one robot (their
    tokens repeat: ``joint``, ``link``, ``left``).
    """
    if _SIDE_LETTERS.isdisjoint(name):  # no token of it has a side marker
        return []
    parts = _TOKENS.split(name)  # tokens at the even places, separators between them
    memo = {} if swaps is None else swaps
    sided: list[tuple[int, list[str]]] = []  # each token with a side marker: its place, its swaps
    for i in range(0, len(parts), 2):
        part = parts[i]
        found = memo.get(part)
        if found is None:
            found = memo[part] = _swap_token(part)
        if found:
            sided.append((i, found))
    if not sided:  # letters of "link" or "roll", no side marker: most names of a robot
        return []
    if len(sided) == 1:  # one marker (``FL_hip``, ``left_knee``): every swap is a one-at-a-time swap
        i, found = sided[0]
        head, tail = "".join(parts[:i]), "".join(parts[i + 1 :])
        each = [head + swapped + tail for swapped in found]
        # the name with every marker swapped comes first, as below: here it is the first swap
        return [each[0], *each] if found[0] != parts[i] else each
    out: list[str] = []
    every = parts.copy()
    for i, found in sided:
        every[i] = found[0]
    if every != parts:
        out.append("".join(every))
    for i, found in sided:
        for swapped in found:
            out.append("".join((*parts[:i], swapped, *parts[i + 1 :])))
    return out


#: Deletes every letter that a side marker's swap can change (:func:`_swap_token` replaces the
#: words and letters of ``_WORDS`` and ``_LETTERS`` only, and keeps every other character in order).
_WITHOUT_SIDE_LETTERS = str.maketrans("", "", "".join(sorted({*"".join(_WORDS), *_LETTERS})))

_WORD_LETTER = re.compile(r"^(.*)(left|right|Left|Right)([LR])$")


def _swap_token(token: str) -> list[str]:
    if _SIDE_LETTERS.isdisjoint(token):  # most tokens of a robot's names: "joint", "2", "base"
        return []
    out = []
    both = _WORD_LETTER.match(token)  # minitaur's ``leftL``: the leg's side and the motor's
    if both:
        out.append(both[1] + _WORDS[both[2]] + _LETTERS[both[3]])
    for word, other in _WORDS.items():
        if word in token:
            out.append(token.replace(word, other))
    if token in _LETTERS:
        out.append(_LETTERS[token])
    if len(token) == 2:
        a, b = token[0], token[1]
        if a.upper() in "FHBMR" and b in _LETTERS:
            out.append(a + _LETTERS[b])
        elif a in _LETTERS and b.upper() in "FHBM":
            out.append(_LETTERS[a] + b)
    return out


def pairs(names: Sequence[str], swaps: dict[str, list[str]] | None = None) -> list[tuple[str, str]]:
    """Every pair of *names* that may be each other's mirror, each pair once, in file order.

    A name can have more than one candidate (``r_gripper_l_finger`` against
    ``l_gripper_r_finger`` and ``r_gripper_r_finger``); :func:`settled` keeps
    the candidate that mirrors. *swaps*: as for :func:`mirror_names`.
    """
    known = set(names)
    # A name's mirrors differ from it only in the letters of the side markers: a name alone
    # with its other letters cannot have one, and most names of a robot are alone.
    rest = {name: name.translate(_WITHOUT_SIDE_LETTERS) for name in known}
    alike: dict[str, int] = {}
    for letters in rest.values():
        alike[letters] = alike.get(letters, 0) + 1
    seen: set[tuple[str, str]] = set()  # each pair once, its two names in sorted order
    out: list[tuple[str, str]] = []
    # A name's mirrors are among its look-alikes: a name already paired with every other
    # look-alike has nothing left to find (the second name of most pairs).
    partners: dict[str, int] = {}
    swaps = {} if swaps is None else swaps
    for name in names:
        others = alike[rest[name]] - 1
        if others == 0 or partners.get(name, 0) == others:
            continue
        for other in mirror_names(name, swaps):
            if other not in known or other == name:
                continue
            key = (name, other) if name < other else (other, name)
            if key not in seen:
                seen.add(key)
                out.append((name, other))
                partners[name] = partners.get(name, 0) + 1
                partners[other] = partners.get(other, 0) + 1
    return out
