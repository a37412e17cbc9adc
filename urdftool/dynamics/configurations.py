"""Joint ranges and seeded random configurations within them.

A configuration is a map from joint name to position, in the robot's own
coordinates (what :meth:`urdftool.model.KinematicTree.forward_kinematics`
reads): a float (rad or m) for one-DOF joints, ``[qw, qx, qy, qz]`` for
spherical joints, ``[x, y, θ]`` for planar joints. Mimic joints are not
sampled: they follow their leader. Floating joints stay at their origin (the
base pose changes neither the mass matrix nor anything a fixed base holds).

Sampling is deterministic: the same robot and seed give the same
configurations, in the same order, on every machine.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence

from urdftool.model import Joint, JointType, KinematicTree

#: Seed of every sampled configuration set: reruns give the same numbers.
SEED = 20240607
#: Range (m) sampled for prismatic joints without usable limits.
UNLIMITED_TRANSLATION = 0.1

Position = float | list[float]
Configuration = dict[str, Position]


def joint_range(joint: Joint) -> tuple[float, float] | None:
    """Where a one-DOF joint may be (rad or m): its limits when usable, else a full turn
    (or :data:`UNLIMITED_TRANSLATION` either way for prismatic joints). ``None`` for
    other joint types."""
    if joint.type.dof != 1:
        return None
    limit = joint.limit
    if joint.type is not JointType.CONTINUOUS and limit is not None and limit.lower is not None \
            and limit.upper is not None and limit.lower <= limit.upper:
        return (limit.lower, limit.upper)
    if joint.type is JointType.PRISMATIC:
        return (-UNLIMITED_TRANSLATION, UNLIMITED_TRANSLATION)
    return (-math.pi, math.pi)


def sampled_joints(tree: KinematicTree) -> list[Joint]:
    """The joints a configuration sets: tree joints that move and follow no other joint."""
    return [j for j in tree.joints_in_order
            if j.type.is_moving and j.mimic is None and j.type is not JointType.FLOATING]


def zero_configuration(tree: KinematicTree) -> Configuration:
    """Every joint at 0, clamped into its range (a joint whose range excludes 0 sits at
    the nearer limit); spherical joints at the identity."""
    out: Configuration = {}
    for joint in sampled_joints(tree):
        bounds = joint_range(joint)
        if bounds is not None:
            out[joint.name] = min(max(0.0, bounds[0]), bounds[1])
        elif joint.type is JointType.SPHERICAL:
            out[joint.name] = [1.0, 0.0, 0.0, 0.0]
        elif joint.type is JointType.PLANAR:
            out[joint.name] = [0.0, 0.0, 0.0]
    return out


def random_configurations(tree: KinematicTree, count: int, seed: int = SEED) -> Iterator[Configuration]:
    """*count* configurations drawn uniformly within each joint's range (seeded)."""
    import numpy as np

    rng = np.random.default_rng(seed)
    joints = sampled_joints(tree)
    for _ in range(count):
        out: Configuration = {}
        for joint in joints:
            bounds = joint_range(joint)
            if bounds is not None:
                out[joint.name] = float(rng.uniform(bounds[0], bounds[1]))
            elif joint.type is JointType.SPHERICAL:
                quat = rng.normal(size=4)
                out[joint.name] = [float(v) for v in quat / np.linalg.norm(quat)]
            elif joint.type is JointType.PLANAR:
                x, y = rng.uniform(-UNLIMITED_TRANSLATION, UNLIMITED_TRANSLATION, size=2)
                out[joint.name] = [float(x), float(y), float(rng.uniform(-math.pi, math.pi))]
        yield out


def configurations(tree: KinematicTree, count: int, seed: int = SEED) -> list[Configuration]:
    """The zero configuration, then *count* random ones."""
    return [zero_configuration(tree), *random_configurations(tree, count, seed)]


def rounded(configuration: Configuration, digits: int = 4) -> dict[str, float | list[float]]:
    """*configuration* with positions rounded for reports (JSON ``data``)."""
    out: dict[str, float | list[float]] = {}
    for name, value in configuration.items():
        if isinstance(value, Sequence):
            out[name] = [round(float(v), digits) for v in value]
        else:
            out[name] = round(float(value), digits)
    return out
