"""Mass properties of shapes at uniform density: volume, centroid, inertia, bounds.

Everything here is *per unit density*: a :class:`SolidProperties` of volume V
(m³) has the inertia (kg·m² per kg/m³) a solid of density 1 kg/m³ would have.
Multiply by ``mass / volume`` to get a body of a given mass.

Frames: a shape's properties are first computed in the shape's own frame
(cylinders and capsules along local z, centred at the origin, as in URDF), then
moved into the link frame with the ``<origin>`` of its ``<visual>`` or
``<collision>`` and summed with the others: the inertia of several shapes is
the sum of each one's inertia shifted to their common centroid (parallel-axis
theorem). Overlapping shapes count twice; URDF gives no way to tell.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
else:
    # NumPy is imported on first use: a structural check must not pay for it.
    from urdftool.lazy import numpy as np

from urdftool.backends.meshes import MeshError, mesh_info
from urdftool.model.geometry import Box, Capsule, Cylinder, Ellipsoid, Geometry, Mesh, Sphere
from urdftool.model.pose import Matrix, Pose, identity_exact, rotate_tensor, unrotated
from urdftool.physics.inertia import (
    box_inertia,
    capsule_inertia,
    cylinder_inertia,
    ellipsoid_inertia,
    shift_to_point,
    sphere_inertia,
)
from urdftool.records import record


@record
class SolidProperties:
    """A solid of density 1 kg/m³: volume (m³), centroid (m), inertia about the centroid, bounds.

    ``center``, ``inertia`` and the bounds are in one frame (the shape's own
    frame, or the link frame after :func:`place`). ``label`` names the shape in
    the robot's terms ("0.1 m box", "mesh wheel.stl").
    """

    volume: float
    center: Matrix
    inertia: Matrix
    bounds_min: Matrix
    bounds_max: Matrix
    label: str
    #: meshes that are not closed are measured by their convex hull
    approximate: bool = False

    def inertia_for_mass(self, mass: float) -> Matrix:
        """The inertia (kg·m²) about the centroid of a uniform solid of *mass* (kg)."""
        return self.inertia * (mass / self.volume)


def _fmt(value: float) -> str:
    return f"{value:.3g}"


def _solid(volume: float, inertia: Matrix, half: Sequence[float], label: str) -> SolidProperties:
    if volume < sys.float_info.min:
        # a subnormal volume (a box 4.9e-324 m deep) is no volume: mass / volume would overflow and
        # its inertia's eigenvalues do not converge (fixtures/fuzz-regressions/denormal_box_size.sdf)
        volume = 0.0
    lo = -np.asarray(half, dtype=float)
    return SolidProperties(volume, np.zeros(3), np.asarray(inertia, dtype=float), lo, -lo, label)


def shape_properties(geometry: Geometry) -> SolidProperties | None:
    """The unit-density properties of a primitive shape in its own frame.

    ``None`` for shapes without a volume (planes, non-positive sizes) and for
    meshes (see :func:`mesh_properties`).
    """
    if isinstance(geometry, Box):
        x, y, z = geometry.size
        if min(x, y, z) <= 0:
            return None
        size = (x, y, z)
        label = f"{_fmt(x)} m box" if x == y == z else f"{_fmt(x)}×{_fmt(y)}×{_fmt(z)} m box"
        return _solid(x * y * z, box_inertia(x * y * z, size), (x / 2, y / 2, z / 2), label)
    if isinstance(geometry, Cylinder):
        r, h = geometry.radius, geometry.length
        if r <= 0 or h <= 0:
            return None
        volume = math.pi * r * r * h
        label = f"cylinder r={_fmt(r)} m l={_fmt(h)} m"
        return _solid(volume, cylinder_inertia(volume, r, h), (r, r, h / 2), label)
    if isinstance(geometry, Sphere):
        r = geometry.radius
        if r <= 0:
            return None
        volume = 4.0 / 3.0 * math.pi * r**3
        return _solid(volume, sphere_inertia(volume, r), (r, r, r), f"sphere r={_fmt(r)} m")
    if isinstance(geometry, Capsule):
        r, h = geometry.radius, geometry.length
        if r <= 0 or h < 0:
            return None
        volume = math.pi * r * r * h + 4.0 / 3.0 * math.pi * r**3
        label = f"capsule r={_fmt(r)} m l={_fmt(h)} m"
        return _solid(volume, capsule_inertia(volume, r, h), (r, r, h / 2 + r), label)
    if isinstance(geometry, Ellipsoid):
        a, b, c = geometry.radii
        if min(a, b, c) <= 0:
            return None
        volume = 4.0 / 3.0 * math.pi * a * b * c
        label = f"ellipsoid {_fmt(a)}×{_fmt(b)}×{_fmt(c)} m"
        return _solid(volume, ellipsoid_inertia(volume, (a, b, c)), (a, b, c), label)
    return None


def mesh_properties(mesh: Mesh) -> SolidProperties | None:
    """The unit-density properties of a mesh file (after ``scale``), in the mesh frame.

    A closed (watertight) mesh is measured as the solid it encloses; an open one
    by its convex hull, which is exact for convex parts and over-estimates
    volume and inertia for concave ones. ``None`` when the mesh does not resolve,
    cannot be read, or encloses no volume.
    """
    if mesh.resolved is None:
        return None

    try:
        info = mesh_info(mesh.resolved, mesh.scale)
    except MeshError:
        return None
    if not info.volume > 0 or not all(map(math.isfinite, np.ravel(info.inertia_unit_density).tolist())):
        return None
    name = mesh.filename.rsplit("/", 1)[-1]
    return SolidProperties(
        info.volume,
        np.asarray(info.center_mass, dtype=float),
        np.asarray(info.inertia_unit_density, dtype=float),
        np.asarray(info.bounds_min, dtype=float),
        np.asarray(info.bounds_max, dtype=float),
        f"mesh {name}",
        approximate=not info.watertight,
    )


def geometry_properties(geometry: Geometry | None) -> SolidProperties | None:
    """Unit-density properties of any geometry in its own frame, or ``None`` when it has none."""
    if geometry is None:
        return None
    if isinstance(geometry, Mesh):
        return mesh_properties(geometry)
    return shape_properties(geometry)


def place(solid: SolidProperties, origin: Pose) -> SolidProperties:
    """*solid* moved by *origin* (the shape frame in the link frame)."""
    if _unrotated(solid, origin):
        return _shifted(solid, origin.xyz)
    rotation = origin.rotation
    xyz = np.asarray(origin.xyz, dtype=float)
    center = rotation @ solid.center + xyz
    inertia = rotation @ solid.inertia @ rotation.T
    corners = _corners(solid.bounds_min, solid.bounds_max) @ rotation.T + xyz
    return SolidProperties(
        solid.volume,
        center,
        inertia,
        corners.min(axis=0),
        corners.max(axis=0),
        solid.label,
        solid.approximate,
    )


def _corners(lo: Matrix, hi: Matrix) -> Matrix:
    (x0, y0, z0), (x1, y1, z1) = lo.tolist(), hi.tolist()
    return np.array([[x, y, z] for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)])


def _unrotated(solid: SolidProperties, origin: Pose) -> bool:
    """Whether :func:`place` may skip its products with the rotation: they would give back the
    same numbers, sign of zero included (:func:`~urdftool.model.pose.unrotated`). The offset is
    added to each product (±0 + +0 is +0 both ways) and the inertia's products to nothing, so
    neither may hold a -0."""
    if not unrotated(origin.rpy):
        return False
    return identity_exact(
        (*origin.xyz, *solid.inertia.ravel().tolist(), *solid.center.tolist(),
         *solid.bounds_min.tolist(), *solid.bounds_max.tolist())
    )


def _shifted(solid: SolidProperties, xyz: tuple[float, float, float]) -> SolidProperties:
    """:func:`place` without rotation (see :func:`_unrotated`): the same numbers, three products
    fewer. The bounds' corners are not enumerated: adding an offset keeps the order of numbers."""
    offset = np.asarray(xyz, dtype=float)
    lo, hi = solid.bounds_min, solid.bounds_max
    return SolidProperties(
        solid.volume,
        solid.center + offset,
        solid.inertia.copy(),
        np.minimum(lo, hi) + offset,
        np.maximum(lo, hi) + offset,
        solid.label,
        solid.approximate,
    )


def combine(solids: Iterable[SolidProperties]) -> SolidProperties | None:
    """One solid made of several (same frame, same density); ``None`` when there are none."""
    parts = [s for s in solids if s.volume > 0]
    if not parts:
        return None
    if len(parts) == 1:
        return parts[0]
    volume = sum(p.volume for p in parts)
    center = sum((p.volume * p.center for p in parts), np.zeros(3)) / volume
    inertia = sum(
        (shift_to_point(p.inertia, p.volume, p.center - center) for p in parts), np.zeros((3, 3))
    )
    label = " + ".join(p.label for p in parts[:3]) + (
        f" + {len(parts) - 3} more" if len(parts) > 3 else ""
    )
    return SolidProperties(
        volume,
        center,
        inertia,
        np.min([p.bounds_min for p in parts], axis=0),
        np.max([p.bounds_max for p in parts], axis=0),
        label,
        any(p.approximate for p in parts),
    )


def rotate_into(tensor: Matrix, frame: Pose) -> Matrix:
    """A tensor written in the link frame, expressed in *frame* (given in the link frame)."""
    return rotate_tensor(tensor, frame.rpy, inverse=True)
