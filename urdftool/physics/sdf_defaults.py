"""SDFormat's defaults that other formats lack: the ``<inertial>`` of a link that declares
none, and ``<self_collide>`` (off: no contact between a model's own links unless asked).

libsdformat, gz-sim and Gazebo classic give such a link 1 kg and a unit inertia
(1 kg·m² about each axis of the link frame, centre of mass at the link origin).
The dynamics pass computes with it, and the exports to formats without that
default (MJCF, PyBullet's URDF, URDF) write it out, so the exported robot weighs
what the SDF robot weighs in its own simulator. ``missing-inertial`` still says
the mass is not the author's.

A link welded to the world (a static model's links, and every link joined to
``world`` through fixed joints only) never moves, so its mass acts on nothing a
simulation measures: it is not given the default, and an export writes none for it.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import replace

from urdftool.model import Extension, Inertial, JointType, Link, Robot

#: The link an SDF reader makes for the world a static model or a joint to ``world`` is fixed to.
WORLD = "world"

#: SDFormat's ``<inertial>`` when a link has none: 1 kg, a unit inertia (kg·m²) at the link origin
SDF_DEFAULT_INERTIAL = Inertial(1.0, ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)))


def welded_to_world(robot: Robot) -> set[str]:
    """The links joined to the link ``world`` through fixed joints only (``world`` included)."""
    if robot.link(WORLD) is None:
        return set()
    children: dict[str, list[str]] = {}
    for joint in robot.joints:
        if joint.type is JointType.FIXED:
            children.setdefault(joint.parent, []).append(joint.child)
    welded, stack = {WORLD}, [WORLD]
    while stack:
        for child in children.get(stack.pop(), []):
            if child not in welded:
                welded.add(child)
                stack.append(child)
    return welded


def defaulted_links(robot: Robot) -> list[Link]:
    """The links of an SDF *robot* that take SDFormat's default inertial (none for other formats;
    never ``world``, which is not a body, nor a link welded to it, whose mass acts on nothing)."""
    if robot.format != "sdf":
        return []
    welded = welded_to_world(robot)
    return [link for link in robot.links if link.inertial is None and link.name not in welded]


def sdf_default_inertials(robot: Robot) -> Robot:
    """*robot* with SDFormat's default inertial on every SDF link that has none."""
    defaulted = {link.name for link in defaulted_links(robot)}
    if not defaulted:
        return robot
    links = tuple(replace(link, inertial=SDF_DEFAULT_INERTIAL) if link.name in defaulted else link
                  for link in robot.links)
    return replace(robot, links=links)


def _true(extensions: Iterable[Extension]) -> bool:
    return any(e.tag == "self_collide" and e.element is not None
               and (e.element.text or "").strip().lower() in ("true", "1") for e in extensions)


def sdf_self_colliding(robot: Robot) -> set[str] | None:
    """For an SDF model, the links that collide with the model's other links; ``None`` for other
    formats, where every pair collides.

    SDFormat: two links of a model collide when either link's ``<self_collide>`` is true, or the
    model's is; both default to false, so gz-sim computes no contact inside a model unless asked
    (links joined by a joint never collide).
    """
    if robot.format != "sdf":
        return None
    if _true(robot.extensions):
        return {link.name for link in robot.links}
    return {link.name for link in robot.links if _true(link.extensions)}
