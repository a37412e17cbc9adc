"""The robot at its home configuration (every joint at 0): each link frame's world pose.

Several rule families place the robot at home (the mirror-symmetry rules, the
robot's size that judges mesh units, camera frames). The poses are computed
once per check, in plain Python floats: a frame is its rotation's three rows
and its origin. A 4×4 NumPy product costs about a microsecond to dispatch
against tens of nanoseconds for the same arithmetic on floats, and a check
places every link of the robot. The numbers equal those of
:meth:`urdftool.model.KinematicTree.forward_kinematics` to the last digit or
two (the products are summed in another order); the exporters and the
dynamics pass keep using that function.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
else:
    # NumPy is imported on first use: only the rules that need a 4×4 matrix pay for it.
    from urdftool.lazy import numpy as np

from urdftool.facts.context import CheckContext
from urdftool.model import Joint, JointType, Robot
from urdftool.model.pose import Matrix, Vec3, axis_angle_matrix, homogeneous
from urdftool.model.tree import mimic_value
from urdftool.physics import vec3

#: A rotation matrix as its three rows.
Rotation = tuple[Vec3, Vec3, Vec3]
#: A link frame in the world: its rotation and its origin (m), world = rotation · local + origin.
Frame = tuple[Rotation, Vec3]

IDENTITY: Rotation = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
_ORIGIN: Vec3 = (0.0, 0.0, 0.0)


def home_frames(ctx: CheckContext) -> dict[str, Frame]:
    """World frame of every link reachable from a root at q = 0, roots at the identity.

    Mimic joints sit at their offset from their leader's 0, as in
    ``forward_kinematics()``. Shared by every rule of the run: read it, never write into it.
    """
    key = "home-frames"
    if key not in ctx.cache:
        ctx.cache[key] = _frames_at_home(ctx)
    frames: dict[str, Frame] = ctx.cache[key]
    return frames


def home_poses(ctx: CheckContext) -> dict[str, Matrix]:
    """The same frames as 4×4 transforms (m), for the few rules that multiply NumPy matrices.

    Shared by every rule of the run: read it, never write into it.
    """
    key = "home-poses"
    if key not in ctx.cache:
        ctx.cache[key] = {
            name: homogeneous(np.array(rotation), origin)
            for name, (rotation, origin) in home_frames(ctx).items()
        }
    poses: dict[str, Matrix] = ctx.cache[key]
    return poses


def angle_between_frames(a: Rotation, b: Rotation) -> float:
    """The angle (rad) of the rotation from frame *a* to frame *b*, both in one frame: the angle of
    ``a.T @ b``, whose trace is the sum of the two matrices' entrywise products."""
    trace = sum(x * y for row_a, row_b in zip(a, b, strict=True) for x, y in zip(row_a, row_b, strict=True))
    return math.acos(max(-1.0, min(1.0, (trace - 1.0) / 2.0)))


def _frames_at_home(ctx: CheckContext) -> dict[str, Frame]:
    robot, tree = ctx.robot, ctx.tree
    frames: dict[str, Frame] = {}
    # the tree's depth-first order (shared with other rules), each link after its parent; a
    # root is a link without a parent joint
    for name in tree.order:
        joint = tree.parent_joint.get(name)
        if joint is None:
            frames[name] = (IDENTITY, _ORIGIN)
            continue
        rotation, (ox, oy, oz) = frames[joint.parent]
        # the joint frame: its origin turned with the parent's frame (written out: this runs
        # once per joint, and a function call costs as much as the arithmetic)
        (a, b, c), (d, e, f), (g, h, i) = rotation
        x, y, z = joint.origin.xyz
        origin = (ox + (a * x + b * y + c * z), oy + (d * x + e * y + f * z), oz + (g * x + h * y + i * z))
        if joint.origin.rpy != _ORIGIN:  # most joints sit at rpy="0 0 0"
            rotation = vec3.product(rotation, vec3.rotation(joint.origin.rpy))
        if joint.mimic is not None:  # only a mimic joint is away from its 0 at home
            moved = _motion_at_home(joint, robot)
            if moved is not None:
                turn, slide = moved
                step = vec3.apply(rotation, slide)
                origin = (origin[0] + step[0], origin[1] + step[1], origin[2] + step[2])
                rotation = vec3.product(rotation, turn)
        frames[name] = (rotation, origin)
    return frames


def _motion_at_home(joint: Joint, robot: Robot) -> tuple[Rotation, Vec3] | None:
    """The joint's motion at q = 0 (a rotation and a translation in the joint frame), ``None``
    when it is the identity: every joint but a one-axis mimic whose offset moves it."""
    if joint.mimic is None or joint.type.dof != 1:
        return None
    value = mimic_value(joint, {}, robot)
    if value == 0.0:
        return None
    x, y, z = joint.axis
    norm = math.sqrt(x * x + y * y + z * z)
    unit = (x / norm, y / norm, z / norm) if norm > 0 else (1.0, 0.0, 0.0)
    if joint.type in (JointType.REVOLUTE, JointType.CONTINUOUS):
        (a, b, c), (d, e, f), (g, h, i) = axis_angle_matrix(unit, value).tolist()
        return ((a, b, c), (d, e, f), (g, h, i)), _ORIGIN
    if joint.type is JointType.PRISMATIC:
        return IDENTITY, (unit[0] * value, unit[1] * value, unit[2] * value)
    return None
