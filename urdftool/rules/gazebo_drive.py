"""The wheel geometry a drive plugin should declare, measured on the robot.

Gazebo's differential and skid-steer drive plugins turn velocity commands into
wheel speeds, and wheel speeds into odometry, with the *declared* wheel
separation and diameter. The robot's joints and wheel shapes fix the true
values; this module measures them at the zero configuration:

* wheel separation: the distance between the left and right wheel centres
  along the wheel axle (the left joint's axis), where a wheel's centre is its
  first collision shape's centre (or the joint frame for a wheel without one);
* wheel diameter: the wheel's collision shape across the axle (cylinder or
  sphere: twice the radius; mesh: its bounding box across the axle).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
else:
    # NumPy is imported on first use: a structural check must not pay for it.
    from urdftool.lazy import numpy as np

from urdftool.facts.context import CheckContext
from urdftool.facts.meshes import mesh_extents
from urdftool.model import Capsule, Collision, Cylinder, Joint, Link, Mesh, Sphere, Visual
from urdftool.model.pose import Matrix

#: Relative difference between declared and measured values that is reported.
#: Wheel positions in real models agree with their plugins to a few millimetres;
#: 5% separates a rounded value (0.287 written as 0.29) from a wrong one.
TOLERANCE = 0.05


@dataclass(frozen=True)
class Wheel:
    """A wheel at the zero configuration in the world (root) frame: centre (m) and axle."""

    joint: Joint
    centre: Matrix
    axle: Matrix
    diameter: float | None


def measure_wheel(ctx: CheckContext, joint_name: str, poses: dict[str, Matrix]) -> Wheel | None:
    """The wheel driven by *joint_name*, or ``None`` when the joint or its links are missing."""
    joint = ctx.robot.joint(joint_name)
    if joint is None or joint.parent not in poses:
        return None
    frame = poses[joint.parent] @ joint.origin.matrix
    axis = np.asarray(joint.axis, dtype=float)
    norm = float(np.linalg.norm(axis))
    axle = frame[:3, :3] @ (axis / norm if norm > 0 else np.array([1.0, 0.0, 0.0]))
    centre = frame[:3, 3]
    link = ctx.robot.link(joint.child)
    shape = _wheel_shape(link) if link is not None else None
    diameter = None
    if shape is not None:
        placed = frame @ shape.origin.matrix
        centre = placed[:3, 3]
        diameter = _diameter(shape, placed[:3, :3].T @ axle)
    return Wheel(joint, centre, axle, diameter)


def _wheel_shape(link: Link) -> Collision | Visual | None:
    items: tuple[Collision | Visual, ...] = (*link.collisions, *link.visuals)
    for item in items:
        if isinstance(item.geometry, (Cylinder, Sphere, Capsule, Mesh)):
            return item
    return None


def _diameter(shape: Collision | Visual, axle_in_shape: Matrix) -> float | None:
    """The shape's size across the axle (m); *axle_in_shape* is the axle in the shape frame."""
    geometry = shape.geometry
    if isinstance(geometry, (Cylinder, Sphere, Capsule)):
        return 2.0 * geometry.radius
    if isinstance(geometry, Mesh) and geometry.resolved:
        extents = mesh_extents(geometry.resolved, geometry.scale)
        if extents is None:
            return None
        across = [i for i in range(3) if abs(axle_in_shape[i]) < 0.7]
        return float(max(extents[i] for i in across)) if across else None
    return None


def separation(left: Wheel, right: Wheel) -> float:
    """Distance between the wheel centres along the left wheel's axle (m)."""
    return float(abs(np.dot(left.centre - right.centre, left.axle)))


def differs(declared: float, measured: float) -> bool:
    """True when *declared* is off by more than :data:`TOLERANCE` of *measured*."""
    return measured > 0 and abs(declared - measured) > TOLERANCE * measured
