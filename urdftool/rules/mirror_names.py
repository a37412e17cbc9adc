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
    parts = _TOKENS.split(name)
    memo = {} if swaps is None else swaps
    tokens: list[list[str]] = []
    sided: list[int] = []  # where the parts with a side marker are
    for i in range(0, len(parts), 2):
        part = parts[i]
        found = memo.get(part)
        if found is None:
            found = memo[part] = _swap_token(part)
        tokens.append(found)
        if found:
            sided.append(i)
    if not sided:  # letters of "link" or "roll", no side marker: most names of a robot
        return []
    if len(sided) == 1:  # one marker (``FL_hip``, ``left_knee``): the same list, built directly
        i = sided[0]
        head, tail = "".join(parts[:i]), "".join(parts[i + 1 :])
        first = [head + tokens[i // 2][0] + tail] if tokens[i // 2][0] != parts[i] else []
        return first + [head + swapped + tail for swapped in tokens[i // 2]]
    out: list[str] = []
    every = [(tokens[i // 2] or [p])[0] if i % 2 == 0 else p for i, p in enumerate(parts)]
    if every != parts:
        out.append("".join(every))
    for i in range(0, len(parts), 2):
        for swapped in tokens[i // 2]:
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
    seen: set[frozenset[str]] = set()
    out: list[tuple[str, str]] = []
    swaps = {} if swaps is None else swaps
    for name in names:
        if alike[rest[name]] < 2:
            continue
        for other in mirror_names(name, swaps):
            if other not in known or other == name:
                continue
            key = frozenset((name, other))
            if key not in seen:
                seen.add(key)
                out.append((name, other))
    return out
