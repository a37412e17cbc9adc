"""The wheel geometry a drive plugin should declare, measured on the robot.

Gazebo's differential and skid-steer drive plugins turn velocity commands into
wheel speeds, and wheel speeds into odometry, with the *declared* wheel
separation and diameter. The robot's joints and wheel shapes fix the true
values; this module measures them at the zero configuration:

* wheel separation: the distance between the left and right wheel centres
  along the wheel axle (the left joint's axis), where a wheel's centre is its
  first collision shape's centre (or the joint frame for a wheel without one);
* wheel diameter: the largest of the wheel's collision shapes across the axle
  (cylinder or sphere: twice the radius; mesh: its bounding box across the
  axle), since the outermost one touches the ground; visual shapes when the
  wheel has no collision.
"""

from __future__ import annotations

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
from urdftool.records import record

#: Relative difference between declared and measured values that is reported.
#: Wheel positions in real models agree with their plugins to a few millimetres;
#: 5% separates a rounded value (0.287 written as 0.29) from a wrong one.
TOLERANCE = 0.05


@record
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
    shapes = _wheel_shapes(link) if link is not None else []
    diameter = None
    if shapes:
        centre = (frame @ shapes[0].origin.matrix)[:3, 3]
        # the outermost shape is the one on the ground: Leo Rover's wheel collides as a wide
        # 57 mm cylinder and a narrow 62.5 mm tread, and rolls on the tread
        sizes = [_diameter(shape, (frame @ shape.origin.matrix)[:3, :3].T @ axle) for shape in shapes]
        diameter = max((d for d in sizes if d is not None), default=None)
    return Wheel(joint, centre, axle, diameter)


def _wheel_shapes(link: Link) -> list[Collision | Visual]:
    """The link's round shapes and meshes: its collisions, or its visuals when it has none."""
    for items in (link.collisions, link.visuals):
        found: list[Collision | Visual] = [
            item for item in items if isinstance(item.geometry, (Cylinder, Sphere, Capsule, Mesh))
        ]
        if found:
            return found
    return []


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
