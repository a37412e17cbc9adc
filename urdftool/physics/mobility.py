"""How the robot's root meets the world in MJCF: a free joint, a weld, or the world itself.

``--floating-base``:

* ``fixed``: the root body has no joint (welded to the world);
* ``free``: the root body gets a free joint;
* ``auto`` (default): a root link named ``world`` *is* the world (the URDF
  convention for a robot fixed in place); a ``floating`` joint from it gives a
  free joint. Otherwise the base is free when the robot is *mobile* — it has
  wheels (a continuous joint whose child link has a cylinder or sphere, or a
  link or joint named ``*wheel*``), rotors (a moving joint or its link named
  ``*rotor*`` or ``*propeller*``), or legs (at least two kinematic chains of
  two or more moving joints whose tips reach below the root, at the zero
  configuration, by more than a quarter of the robot's size) — and fixed
  otherwise (arms, hands, pan-tilt heads).
"""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
else:  # NumPy loads on first use: importing the rules must not pay for it
    from urdftool.lazy import numpy as np

from urdftool.model import Cylinder, JointType, KinematicTree, Robot, Sphere
from urdftool.records import record

WORLD_LINK = "world"
#: Name of the free joint added to a free root (made unique against the robot's joints).
FREE_JOINT_NAME = "floating_base"


@record
class BasePlan:
    """``kind``: ``"free"``, ``"fixed"`` or ``"world"`` (the root link is the world body)."""

    kind: str
    reason: str
    free_joint: str | None = None


def _free_joint_name(robot: Robot) -> str:
    names = {j.name for j in robot.joints}
    name, n = FREE_JOINT_NAME, 1
    while name in names:
        n += 1
        name = f"{FREE_JOINT_NAME}_{n}"
    return name


def decide_base(robot: Robot, tree: KinematicTree, option: str) -> BasePlan:
    """The base for *option* (``auto`` | ``free`` | ``fixed``), with the reason in words."""
    root = tree.root
    if root == WORLD_LINK:
        return BasePlan("world", "the root link is named 'world'")
    if option == "free":
        return BasePlan("free", "floating-base option free", _free_joint_name(robot))
    if option == "fixed":
        return BasePlan("fixed", "floating-base option fixed")
    reason = mobility(robot, tree)
    if reason:
        return BasePlan("free", f"auto: {reason}", _free_joint_name(robot))
    return BasePlan("fixed", "auto: no wheels or legs")


def mobility(robot: Robot, tree: KinematicTree) -> str | None:
    """Why the robot moves about (``"wheels"``, ``"2 legs"``), or ``None`` when it does not."""
    for joint in tree.joints_in_order:
        link = robot.link(joint.child)
        if link is None:
            continue
        round_shape = any(isinstance(c.geometry, (Cylinder, Sphere)) for c in link.collisions)
        named = "wheel" in joint.name.lower() or "wheel" in link.name.lower()
        if joint.type is JointType.CONTINUOUS and (round_shape or named):
            return "wheels"
        if joint.type.is_moving and any(
            k in f"{joint.name} {link.name}".lower() for k in ("rotor", "propeller")
        ):
            return "rotors"
    legs = _legs(tree)
    return f"{legs} legs" if legs >= 2 else None


def _legs(tree: KinematicTree) -> int:
    """Limbs (told apart by their first moving joint from the root) whose tips, at the end of
    two or more moving joints, hang well below the root at q = 0."""
    poses = tree.forward_kinematics()
    if not poses or tree.root is None:
        return 0
    root = poses[tree.root][:3, 3]
    size = max(float(np.linalg.norm(p[:3, 3] - root)) for p in poses.values())
    if size == 0.0:
        return 0
    limbs: set[str] = set()
    for name in tree.order:
        if tree.children(name):
            continue
        moving = [j for j in tree.path_to_root(name) if j.type.is_moving]
        if len(moving) >= 2 and root[2] - poses[name][2, 3] > 0.25 * size:
            limbs.add(moving[-1].name)
    return len(limbs)


def reroot_massless_base(robot: Robot, tree: KinematicTree) -> Robot:
    """*robot* rooted at the heaviest fixed child of a massless root link (``base_footprint``).

    For engines whose free bases need mass of their own: PyBullet welds a base
    of mass 0 to the world. The fixed joint between the two is reversed (same
    name, inverse origin), so the old root stays in the tree as a massless
    fixed child and every link keeps its place and its frame; the total mass is
    unchanged. Returns *robot* itself when the root has mass or no fixed child
    with mass.
    """
    root = robot.link(tree.root or "")
    if root is None or (root.inertial is not None and root.inertial.mass > 0):
        return robot
    fixed = [j for j in tree.child_joints.get(root.name, []) if j.type is JointType.FIXED]
    masses = {link.name: (link.inertial.mass if link.inertial else 0.0) for link in robot.links}
    if not fixed or max(masses.get(j.child, 0.0) for j in fixed) <= 0:
        return robot
    carrier = max(fixed, key=lambda j: masses.get(j.child, 0.0))
    reversed_joint = dataclasses.replace(
        carrier, parent=carrier.child, child=carrier.parent, origin=carrier.origin.inverse()
    )
    joints = tuple(reversed_joint if joint is carrier else joint for joint in robot.joints)
    new_root = next(link for link in robot.links if link.name == carrier.child)
    links = (new_root, *(link for link in robot.links if link is not new_root))
    return dataclasses.replace(robot, links=links, joints=joints)
