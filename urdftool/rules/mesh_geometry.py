"""Geometry judgements behind the meshes-and-geometry rules: sizes, budgets, rigid bodies.

Thresholds live here with the reason for their value; ``docs/meshes.md``
records how they were calibrated on example-robot-data and pybullet_data.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
else:
    # NumPy is imported on first use: a structural check must not pay for it.
    from urdftool.lazy import numpy as np

from urdftool.budgets import DEFAULT_BUDGETS
from urdftool.facts.context import CheckContext
from urdftool.facts.home import home_frames
from urdftool.model import (
    Box,
    Capsule,
    Collision,
    Cylinder,
    Ellipsoid,
    Geometry,
    Joint,
    JointType,
    Link,
    Mesh,
    Sphere,
    Visual,
)
from urdftool.model.tree import KinematicTree

#: Triangles a collision mesh may have before ``collision-mesh-too-complex``, by default (the
#: ``collision-faces`` budget, :mod:`urdftool.budgets`, changes it). Hand-made collision meshes
#: and convex decompositions stay in the hundreds to low thousands; meshes above 10000 are CAD or
#: scan resolution used as-is.
FACE_BUDGET = int(DEFAULT_BUDGETS["collision-faces"])

#: Bounds on a mesh's size relative to the robot's (see :func:`robot_size`) beyond
#: which ``mesh-units-suspect`` fires. On example-robot-data and pybullet_data
#: every mesh lies between 0.011 and 3.3 times its robot's size, so these
#: bounds leave a margin of 3 on both sides, and a 1000-fold mix-up of any of
#: those meshes lands outside them (0.011 × 1000 > 10; 3.3 / 1000 < 1/300).
UNITS_TOO_LARGE = 10.0
UNITS_TOO_SMALL = 1.0 / 300.0


def degenerate_shape(geometry: Geometry | None) -> str | None:
    """What is degenerate about a primitive shape or a mesh scale, in words; ``None`` if nothing."""
    if isinstance(geometry, Mesh):  # the most common shape of all, answered first
        if 0.0 in geometry.scale:
            scale = " ".join(f"{s:g}" for s in geometry.scale)
            return f"mesh '{geometry.filename}' has scale \"{scale}\", which flattens it to nothing"
        return None
    if isinstance(geometry, Box):
        bad = [
            f"{axis}={value:g}"
            for axis, value in zip("xyz", geometry.size, strict=True)
            if not value > 0
        ]
        return f"box has a size that is not positive ({', '.join(bad)} m)" if bad else None
    if isinstance(geometry, Sphere):
        return None if geometry.radius > 0 else f"sphere has radius {geometry.radius:g} m"
    if isinstance(geometry, Cylinder):
        if not (geometry.radius > 0 and geometry.length > 0):
            return f"cylinder has radius {geometry.radius:g} m and length {geometry.length:g} m"
        return None
    if isinstance(geometry, Capsule):
        if not (geometry.radius > 0 and geometry.length >= 0):
            return f"capsule has radius {geometry.radius:g} m and length {geometry.length:g} m"
        return None
    if isinstance(geometry, Ellipsoid):
        if not all(r > 0 for r in geometry.radii):
            return "ellipsoid has radii " + " ".join(f"{r:g}" for r in geometry.radii) + " m"
        return None
    return None


def moving_groups(tree: KinematicTree) -> Iterator[tuple[Joint, list[Link]]]:
    """For each moving joint, the rigid body it moves: its child link first, then the links
    welded to it by fixed joints, depth first."""
    links = {link.name: link for link in tree.robot.links}
    for joint in tree.joints_in_order:
        if joint.type is JointType.FIXED or joint.child not in links:
            continue
        group: list[Link] = []
        stack = [joint.child]
        while stack:
            name = stack.pop()
            group.append(links[name])
            for child_joint in reversed(tree.child_joints.get(name, [])):
                if child_joint.type is JointType.FIXED and child_joint.child in links:
                    stack.append(child_joint.child)
        yield joint, group


#: Primitive shapes smaller than this (m) are contact points or markers, not the robot's size.
_MARKER_SIZE = 1e-3


def robot_size(ctx: CheckContext) -> tuple[float, str] | None:
    """A size for the robot (m) that does not depend on its meshes, and how it was measured.

    The diagonal of the box around its link frames at the zero configuration;
    for a robot whose frames coincide, the median size of its primitive shapes (of those a
    millimetre or more across, when there are any).
    ``None`` when neither exists (a one-link mesh-only model has nothing to compare
    with). Meshes are left out on purpose: a robot whose meshes are all in
    millimetres must not be its own yardstick.
    """
    origins = [origin for _, origin in home_frames(ctx).values()]
    if len(origins) >= 2:
        xs, ys, zs = zip(*origins, strict=True)
        dx, dy, dz = max(xs) - min(xs), max(ys) - min(ys), max(zs) - min(zs)
        spread = math.sqrt(dx * dx + dy * dy + dz * dz)
        if spread > 1e-6:
            return spread, "between its farthest link frames"
    sizes = [size for link in ctx.robot.links for size in _primitive_sizes(link) if size > 0]
    # Drake's YCB objects put 1e-7 m spheres on the box corners as contact points: markers,
    # not the object's size, so shapes under a millimetre count only when nothing is larger.
    sizes = [size for size in sizes if size >= _MARKER_SIZE] or sizes
    if sizes:
        return float(np.median(sizes)), "the median size of its primitive shapes"
    return None


def _primitive_sizes(link: Link) -> Iterator[float]:
    items: tuple[Visual | Collision, ...] = (*link.visuals, *link.collisions)
    for item in items:
        geometry = item.geometry
        if isinstance(geometry, Box):
            yield float(np.linalg.norm(geometry.size))
        elif isinstance(geometry, Sphere):
            yield 2 * math.sqrt(3) * geometry.radius
        elif isinstance(geometry, (Cylinder, Capsule)):
            extra = 2 * geometry.radius if isinstance(geometry, Capsule) else 0.0
            yield math.sqrt(8 * geometry.radius**2 + (geometry.length + extra) ** 2)


def suggested_factor(ratio: float) -> float:
    """The power of ten (preferring 1000 and 1/1000) that brings a size *ratio* back to about 1."""
    exponent = math.log10(ratio)
    thousands = round(exponent / 3) * 3
    k = thousands if thousands != 0 else round(exponent)
    return float(10.0 ** (-k))
