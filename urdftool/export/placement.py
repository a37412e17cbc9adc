"""Where a free robot starts above the floor: its lowest collision point at a configuration.

With ``--scene`` a free robot is placed so that the lowest point of its
collision geometry is :data:`CLEARANCE` (1 mm) above the floor (z = 0), at the
start pose. The point is computed from the geometry, not by simulating: the
link poses come from forward kinematics at the configuration (joint values
for the home pose, zero elsewhere; mimic joints follow), and each collision
shape gives its lowest point in closed form (box corners; a sphere's centre
minus its radius; cylinders and capsules from their axis' tilt) or, for
meshes, from the vertices of the convex hull, which is the shape MuJoCo and
PyBullet collide with. Meshes that cannot be read are left out (the exporter
reports them).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping

import numpy as np

from urdftool.backends.meshes import MeshError, load_trimesh
from urdftool.model import Box, Capsule, Cylinder, Ellipsoid, Geometry, KinematicTree, Mesh, Robot, Sphere
from urdftool.model.pose import Matrix

#: Gap (m) between the lowest collision point and the floor at the start.
CLEARANCE = 0.001


@functools.lru_cache(maxsize=256)
def _hull_vertices(path: str) -> np.ndarray | None:
    try:
        mesh = load_trimesh(path)
    except (MeshError, OSError, ValueError):
        return None
    try:
        return np.asarray(mesh.convex_hull.vertices, dtype=float)
    except Exception:  # qhull fails on flat or degenerate meshes: use every vertex
        return np.asarray(mesh.vertices, dtype=float)


def lowest_point(geometry: Geometry | None, pose: Matrix) -> float | None:
    """The lowest world z of *geometry* placed at *pose* (4×4), ``None`` when unknown."""
    rot, centre = pose[:3, :3], pose[:3, 3]
    if isinstance(geometry, Box):
        half = np.asarray(geometry.size, dtype=float) / 2
        return float(centre[2] - np.abs(rot[2, :]) @ half)
    if isinstance(geometry, Sphere):
        return float(centre[2] - geometry.radius)
    if isinstance(geometry, Ellipsoid):
        radii = np.asarray(geometry.radii, dtype=float)
        return float(centre[2] - math.sqrt(float(np.sum((rot[2, :] * radii) ** 2))))
    if isinstance(geometry, (Cylinder, Capsule)):
        tilt = abs(float(rot[2, 2]))  # |cos| of the axis against the vertical
        half_length = geometry.length / 2
        if isinstance(geometry, Capsule):
            return float(centre[2] - tilt * half_length - geometry.radius)
        return float(centre[2] - tilt * half_length
                     - geometry.radius * math.sqrt(max(0.0, 1 - tilt * tilt)))
    if isinstance(geometry, Mesh) and geometry.resolved:
        vertices = _hull_vertices(geometry.resolved)
        if vertices is None or len(vertices) == 0:
            return None
        scaled = vertices * np.asarray(geometry.scale, dtype=float)
        return float(np.min(scaled @ rot[2, :] + centre[2]))
    return None


def bounding_radius(geometry: Geometry | None) -> float:
    """The radius (m) of a sphere about *geometry*'s origin that holds it (0 when unknown)."""
    if isinstance(geometry, Box):
        return float(np.linalg.norm(np.asarray(geometry.size, dtype=float) / 2))
    if isinstance(geometry, Sphere):
        return float(geometry.radius)
    if isinstance(geometry, Ellipsoid):
        return float(max(geometry.radii))
    if isinstance(geometry, Capsule):
        return float(geometry.length / 2 + geometry.radius)
    if isinstance(geometry, Cylinder):
        return float(math.hypot(geometry.length / 2, geometry.radius))
    if isinstance(geometry, Mesh) and geometry.resolved:
        vertices = _hull_vertices(geometry.resolved)
        if vertices is not None and len(vertices):
            return float(np.max(np.linalg.norm(vertices * np.asarray(geometry.scale, dtype=float), axis=1)))
    return 0.0


def lowest_collision_point(robot: Robot, tree: KinematicTree, q: Mapping[str, float],
                           base: Matrix | None = None) -> float | None:
    """The lowest world z of the robot's collision geometry at joint values *q*."""
    poses = tree.forward_kinematics(dict(q), base=base)
    lowest: float | None = None
    for link in robot.links:
        frame = poses.get(link.name)
        if frame is None:
            continue
        for collision in link.collisions:
            z = lowest_point(collision.geometry, frame @ collision.origin.matrix)
            if z is not None and (lowest is None or z < lowest):
                lowest = z
    return lowest


def floor_lift(robot: Robot, tree: KinematicTree, q: Mapping[str, float],
               base: Matrix | None = None) -> float:
    """How far to raise the robot (m) so its lowest collision point is :data:`CLEARANCE` above z = 0
    (0 for a robot without collision geometry)."""
    lowest = lowest_collision_point(robot, tree, q, base)
    return 0.0 if lowest is None else CLEARANCE - lowest
