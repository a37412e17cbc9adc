"""Joint ranges and seeded random configurations within them.

A configuration is a map from joint name to position, in the robot's own
coordinates (what :meth:`urdftool.model.KinematicTree.forward_kinematics`
reads): a float (rad or m) for one-DOF joints, ``[qw, qx, qy, qz]`` for
spherical joints, ``[x, y, θ]`` for planar joints. Mimic joints are not
sampled: they follow their leader. Floating joints stay at their origin (the
base pose changes neither the mass matrix nor anything a fixed base holds).

Samples are drawn as one array (one row per configuration, one column per
one-DOF joint) so that the dynamics pass stays cheap on large robots; the
rare spherical and planar joints are kept per row beside it. Sampling is
deterministic: the same robot and seed give the same configurations, in the
same order, on every machine.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

from urdftool.model import Joint, JointType, KinematicTree
from urdftool.records import record

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


@record
class Samples:
    """Configurations as an array: row 0 is the zero configuration, then the random ones.

    ``values[row, column]`` is the position (rad or m) of ``joints[column]``;
    ``others[row]`` holds the spherical and planar joints of that row.
    """

    joints: list[Joint]
    values: Any  # ndarray (rows × len(joints))
    others: list[Configuration]

    def __len__(self) -> int:
        return len(self.others)

    def configuration(self, row: int) -> Configuration:
        """Row *row* as a configuration map."""
        out: Configuration = {j.name: float(self.values[row, c]) for c, j in enumerate(self.joints)}
        out.update(self.others[row])
        return out


def sample(tree: KinematicTree, count: int, seed: int = SEED) -> Samples:
    """The zero configuration (every joint at 0 clamped into its range, spherical joints at
    the identity), then *count* configurations drawn uniformly within each range (seeded)."""
    import numpy as np

    joints = sampled_joints(tree)
    one_dof = [j for j in joints if j.dof == 1]
    bounds = np.array([joint_range(j) for j in one_dof], dtype=float).reshape(-1, 2)
    rng = np.random.default_rng(seed)
    unit = rng.uniform(size=(count, len(one_dof)))
    random_rows = bounds[:, 0] + unit * (bounds[:, 1] - bounds[:, 0])
    zero_row = np.clip(0.0, bounds[:, 0], bounds[:, 1])
    values = np.vstack([zero_row, random_rows]) if count else zero_row[None, :]
    multi = [j for j in joints if j.dof != 1]
    others = [_zero_multi(multi)] + [_random_multi(multi, rng) for _ in range(count)]
    return Samples(one_dof, values, others)


def _zero_multi(joints: list[Joint]) -> Configuration:
    out: Configuration = {}
    for joint in joints:
        if joint.type is JointType.SPHERICAL:
            out[joint.name] = [1.0, 0.0, 0.0, 0.0]
        elif joint.type is JointType.PLANAR:
            out[joint.name] = [0.0, 0.0, 0.0]
    return out


def _random_multi(joints: list[Joint], rng: Any) -> Configuration:
    import numpy as np

    out: Configuration = {}
    for joint in joints:
        if joint.type is JointType.SPHERICAL:
            quat = rng.normal(size=4)
            out[joint.name] = [float(v) for v in quat / np.linalg.norm(quat)]
        elif joint.type is JointType.PLANAR:
            x, y = rng.uniform(-UNLIMITED_TRANSLATION, UNLIMITED_TRANSLATION, size=2)
            out[joint.name] = [float(x), float(y), float(rng.uniform(-math.pi, math.pi))]
    return out


def zero_configuration(tree: KinematicTree) -> Configuration:
    """Every joint at 0 clamped into its range; spherical joints at the identity."""
    return sample(tree, 0).configuration(0)


def configurations(tree: KinematicTree, count: int, seed: int = SEED) -> list[Configuration]:
    """The zero configuration, then *count* random ones, as maps."""
    samples = sample(tree, count, seed)
    return [samples.configuration(row) for row in range(len(samples))]


def rounded(configuration: Configuration, digits: int = 4) -> dict[str, float | list[float]]:
    """*configuration* with positions rounded for reports (JSON ``data``)."""
    out: dict[str, float | list[float]] = {}
    for name, value in configuration.items():
        if isinstance(value, Sequence):
            out[name] = [round(float(v), digits) for v in value]
        else:
            out[name] = round(float(value), digits)
    return out
