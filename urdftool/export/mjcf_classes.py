"""Per-joint-group default classes, as MuJoCo Menagerie writes them (``hip``, ``thigh``, ``knee``).

A finished MJCF document is rewritten so that joints that play the same part
on different limbs share a ``<default class>`` holding what they have in
common: the joint's ``axis``, ``range``, ``damping``, ``armature``,
``frictionloss`` and ``actuatorfrcrange``, and their actuators' kind, gains
and ranges. The compiled model is the same number for number (the test
compares ``jnt_range``, ``dof_damping``, ``actuator_gainprm``, ... with and
without classes).

Joints are grouped in two steps:

1. by name pattern: side and index tokens are dropped (``FL_hip_joint``,
   ``RR_hip_joint`` → ``hip``; ``panda_joint1``…``panda_joint7`` → ``panda``;
   ``leg_left_4_joint`` → ``leg``);
2. within a pattern, by settings: the joints' attributes other than name and
   axis must be equal, their actuators of the same kind with equal ranges and
   gains within 1e-6 relative (a gain computed from a left and a right leg's
   inertia differs in the last digits). A set of at least two such joints
   becomes a class; a joint with settings of its own keeps them inline.

A class holds only the attributes every member has with the same text;
anything else (an axis that is mirrored, a gain that differs in the last
digits) stays on each element, so nothing a joint or actuator says changes.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence

from lxml import etree

from urdftool.records import record

#: Name tokens that tell limbs apart: sides, front/rear, and their usual abbreviations.
SIDE_TOKENS = frozenset({
    "l", "r", "left", "right", "lft", "rgt", "front", "rear", "back", "hind", "f", "b", "h",
    "fl", "fr", "rl", "rr", "hl", "hr", "bl", "br", "lf", "rf", "lh", "rh", "lb", "rb",
})
#: Quadruped leg codes (Unitree's ``FL``, ANYmal's ``LF``) by the end of the body they are at.
LEG_ENDS = {**dict.fromkeys(("fl", "fr", "lf", "rf"), "front"),
            **dict.fromkeys(("rl", "rr", "hl", "hr", "lh", "rh", "bl", "br"), "rear")}
#: Tokens that only say "this is a joint".
JOINT_TOKENS = frozenset({"joint", "jnt", "j"})
#: Relative difference under which two computed gains count as the same setting.
GAIN_TOLERANCE = 1e-6
#: Actuator attributes computed from the model (compared with :data:`GAIN_TOLERANCE`).
GAINS = ("kp", "kv", "gear")
#: Attributes never moved into a class.
OWN = frozenset({"name", "joint", "class"})


def _tokens(name: str) -> list[str]:
    return [t for t in re.split(r"[_\-.\s]+", name.lower()) if t]


def name_pattern(name: str) -> str:
    """The joint's role without side or index: ``FL_hip_joint`` → ``hip``, ``panda_joint3`` →
    ``panda``, ``leg_left_4_joint`` → ``leg`` (``joint`` when nothing is left)."""
    kept = []
    for token in _tokens(name):
        token = token.rstrip("0123456789")
        if token and token not in SIDE_TOKENS and token not in JOINT_TOKENS:
            kept.append(token)
    return "_".join(kept) or "joint"


def sideless_name(name: str) -> str:
    """The joint's name without side tokens, keeping indices: ``leg_left_4_joint`` → ``leg_4``."""
    kept = [t for t in _tokens(name) if t not in SIDE_TOKENS and t not in JOINT_TOKENS]
    return "_".join(kept) or "joint"


def _leg_end(name: str) -> str | None:
    """``front`` or ``rear`` for a quadruped leg's joint (``FL_thigh_joint``), else ``None``."""
    ends = {LEG_ENDS[t] for t in _tokens(name) if t in LEG_ENDS}
    return ends.pop() if len(ends) == 1 else None


@record(frozen=False)
class _Member:
    joint: etree._Element
    actuator: etree._Element | None


def _settings(member: _Member) -> tuple[object, ...]:
    """What must agree for two joints to share a class (everything but names, axis and gains)."""
    joint = tuple(sorted((k, v) for k, v in member.joint.attrib.items() if k not in OWN | {"axis"}))
    act = member.actuator
    if act is None:
        return (joint, None)
    fixed = tuple(sorted((k, v) for k, v in act.attrib.items() if k not in OWN and k not in GAINS))
    return (joint, str(act.tag), fixed, tuple(k for k in GAINS if k in act.attrib))


def _gains_agree(a: _Member, b: _Member) -> bool:
    if a.actuator is None or b.actuator is None:
        return True
    for key in GAINS:
        x, y = a.actuator.get(key), b.actuator.get(key)
        if x is None or y is None or x == y:
            continue
        try:
            fx, fy = float(x), float(y)
        except ValueError:  # a vector (gear): equal text only
            return False
        if not math.isclose(fx, fy, rel_tol=GAIN_TOLERANCE, abs_tol=0.0):
            return False
    return True


def _subsets(members: Sequence[_Member]) -> list[list[_Member]]:
    """Members split into sets of equal settings, in document order; singletons dropped."""
    sets: list[list[_Member]] = []
    for member in members:
        key = _settings(member)
        for group in sets:
            if _settings(group[0]) == key and all(_gains_agree(m, member) for m in group):
                group.append(member)
                break
        else:
            sets.append([member])
    return [s for s in sets if len(s) >= 2]


def _common(elements: Sequence[etree._Element]) -> dict[str, str]:
    """Attributes every element has with the same text (names and joint references excepted)."""
    first = elements[0]
    return {k: v for k, v in first.attrib.items()
            if k not in OWN and all(e.get(k) == v for e in elements[1:])}


def _class_names(pattern: str, subsets: list[list[_Member]], taken: set[str]) -> list[str]:
    names = []
    for number, subset in enumerate(subsets, start=1):
        sideless = {sideless_name(m.joint.get("name", "")) for m in subset}
        if len(subsets) == 1:
            name = pattern
        elif len(sideless) == 1 and sideless != {pattern}:
            name = sideless.pop()
        elif len(ends := {_leg_end(m.joint.get("name", "")) for m in subset}) == 1 and None not in ends:
            name = f"{pattern}_{ends.pop()}"
        else:
            name = f"{pattern}_{number}"
        base, n = name, 1
        while name in taken:
            n += 1
            name = f"{base}_{n}"
        taken.add(name)
        names.append(name)
    return names


def write_joint_classes(root: etree._Element, reserved: Sequence[str] = ()) -> list[str]:
    """Group the joints of the MJCF document *root* into default classes (module docstring);
    returns the class names added, in document order. *reserved*: class names already used."""
    default = root.find("default")
    worldbody = root.find("worldbody")
    if default is None or worldbody is None:
        return []
    actuators: dict[str, etree._Element] = {}
    section = root.find("actuator")
    counts: dict[str, int] = {}
    for act in section if section is not None else ():
        if isinstance(act.tag, str) and act.get("joint"):
            counts[act.get("joint", "")] = counts.get(act.get("joint", ""), 0) + 1
            actuators[act.get("joint", "")] = act
    by_pattern: dict[str, list[_Member]] = {}
    for joint in worldbody.iter("joint"):
        name = joint.get("name", "")
        if counts.get(name, 0) > 1:  # two actuators on one joint: left as written
            continue
        by_pattern.setdefault(name_pattern(name), []).append(_Member(joint, actuators.get(name)))
    taken = set(reserved) | {"main"}
    added = []
    for pattern, members in by_pattern.items():
        subsets = _subsets(members)
        for name, subset in zip(_class_names(pattern, subsets, taken), subsets, strict=True):
            _apply(default, name, subset)
            added.append(name)
    return added


def _apply(default: etree._Element, name: str, subset: list[_Member]) -> None:
    """Write class *name* with what *subset* shares and strip it from each member."""
    holder = etree.SubElement(default, "default", {"class": name})
    parts: list[tuple[str, list[etree._Element]]] = [("joint", [m.joint for m in subset])]
    acts = [m.actuator for m in subset if m.actuator is not None]
    if len(acts) == len(subset):
        parts.append((str(acts[0].tag), acts))
    for tag, elements in parts:
        shared = _common(elements)
        etree.SubElement(holder, tag, shared)
        for element in elements:
            for key in shared:
                del element.attrib[key]
            _set_class_after_name(element, name)


def _set_class_after_name(element: etree._Element, name: str) -> None:
    """``class`` right after ``name`` (and ``joint``), as Menagerie writes it."""
    items = list(element.attrib.items())
    element.attrib.clear()
    head = [(k, v) for k, v in items if k in ("name", "joint")]
    tail = [(k, v) for k, v in items if k not in ("name", "joint")]
    for key, value in [*head, ("class", name), *tail]:
        element.set(key, value)
