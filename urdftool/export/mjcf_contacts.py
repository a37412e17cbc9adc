"""Contact excludes: the body pairs MuJoCo must not collide.

Two kinds of ``<contact><exclude>`` are written, both only between bodies that
carry collision geoms:

* **structural**: bodies welded together (a chain of fixed joints makes one
  rigid group in MuJoCo although each link stays its own body), and every body
  of a group with every body of the group one moving joint above it (the
  parent–child pairs of the robot's moving tree). MuJoCo filters a body and
  its direct parent by itself (``filterparent``), but not a grandparent across
  a fixed joint, so a hand welded to the last link of an arm would otherwise
  collide with the forearm it is mounted next to;
* **touching**: pairs whose collision geometry overlaps at the zero
  configuration (the model's ``qpos0``) or at the ``home`` keyframe. MuJoCo
  itself finds them: the file is compiled and its contacts read after
  ``mj_forward``, without stepping. Meshes touching at rest are modelling
  artefacts (coarse hulls around a joint); left in, they push the links apart
  from the first step.
"""

from __future__ import annotations

import itertools
from pathlib import Path

from lxml import etree

from urdftool.export.mjcf_keyframe import compile_in_memory

#: A welded group with more colliding bodies than this gets no pairwise excludes (their number
#: grows as the square: a 5,000-link chain of fixed joints would need 12.5 million).
MAX_GROUP_BODIES = 64

#: Name of the floor geom written by ``--scene`` (never excluded).
FLOOR = "floor"


def _name(body: etree._Element) -> str:
    return "world" if body.tag == "worldbody" else body.get("name", "")


def _collides(body: etree._Element) -> bool:
    return any(g.get("class") == "collision" for g in body.findall("geom"))


def _moves(body: etree._Element) -> bool:
    return body.find("joint") is not None or body.find("freejoint") is not None


def structural_pairs(worldbody: etree._Element) -> list[tuple[str, str]]:
    """Pairs of colliding bodies that are welded together or one moving joint apart."""
    groups: dict[int, list[etree._Element]] = {}
    group_of: dict[int, etree._Element] = {}
    parent_group: dict[int, etree._Element] = {}
    stack: list[tuple[etree._Element, etree._Element]] = [(worldbody, worldbody)]
    while stack:
        body, group = stack.pop()
        group_of[id(body)] = group
        groups.setdefault(id(group), []).append(body)
        for child in body.findall("body"):
            if _moves(child):
                parent_group[id(child)] = group
                stack.append((child, child))
            else:
                stack.append((child, group))
    pairs: list[tuple[str, str]] = []
    seen: set[frozenset[str]] = set()

    def add(a: etree._Element, b: etree._Element) -> None:
        if a is b or not (_collides(a) and _collides(b)):
            return
        key = frozenset((_name(a), _name(b)))
        if key not in seen:
            seen.add(key)
            pairs.append((_name(a), _name(b)))

    for members in groups.values():
        colliding = [m for m in members if _collides(m)]
        if len(colliding) > MAX_GROUP_BODIES:
            continue  # quadratic in the group: MuJoCo's own parent-child filter has to do
        for a, b in itertools.combinations(colliding, 2):
            add(a, b)
    for child_id, above in parent_group.items():
        below = next(m for m in groups[child_id] if id(m) == child_id)
        for a in groups[id(above)]:
            for b in groups[id(below)]:
                add(a, b)
    return pairs


def touching_pairs(root: etree._Element, out_dir: Path | None,
                   files: dict[str, bytes]) -> list[tuple[str, str]]:
    """Pairs of robot bodies whose collision geoms overlap at ``qpos0`` or at each keyframe,
    as MuJoCo computes them; none when MuJoCo is missing or cannot compile the model."""
    model = compile_in_memory(root, out_dir, files)
    if model is None:
        return []
    import mujoco

    data = mujoco.MjData(model)
    found: dict[frozenset[str], tuple[str, str]] = {}
    for keyframe in range(-1, model.nkey):
        if keyframe < 0:
            mujoco.mj_resetData(model, data)
        else:
            mujoco.mj_resetDataKeyframe(model, data, keyframe)
        mujoco.mj_forward(model, data)
        for contact in data.contact[:data.ncon]:
            if contact.dist >= 0:
                continue
            geoms = (int(contact.geom1), int(contact.geom2))
            if any(mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, g) == FLOOR for g in geoms):
                continue
            names = tuple(mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, int(model.geom_bodyid[g]))
                          or "world" for g in geoms)
            found.setdefault(frozenset(names), (names[0], names[1]))
    return sorted(found.values())


def write_excludes(root: etree._Element, worldbody: etree._Element, out_dir: Path | None,
                   files: dict[str, bytes]) -> int:
    """Add ``<contact>`` with the structural and touching excludes after ``<worldbody>``;
    returns how many pairs were found touching."""
    pairs = structural_pairs(worldbody)
    section = etree.Element("contact")
    for a, b in pairs:
        etree.SubElement(section, "exclude", {"body1": a, "body2": b})
    worldbody.addnext(section)
    touching = [p for p in touching_pairs(root, out_dir, files)
                if frozenset(p) not in {frozenset(q) for q in pairs}]
    if touching:
        section.append(etree.Comment(" overlapping at the zero configuration or a keyframe "))
    for a, b in touching:
        etree.SubElement(section, "exclude", {"body1": a, "body2": b})
    if len(section) == 0:
        root.remove(section)
    return len(touching)
