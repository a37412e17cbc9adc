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
import os
import sys
from collections.abc import Iterable

from urdftool.backends.meshes import MeshError, MeshFacts, facts_for
from urdftool.model.geometry import Box, Capsule, Cylinder, Ellipsoid, Geometry, Mesh, Sphere
from urdftool.model.pose import Pose, Vec3, unrotated
from urdftool.physics import vec3
from urdftool.physics.inertia import (
    box_moments,
    capsule_moments,
    cylinder_moments,
    ellipsoid_moments,
    sphere_moments,
)
from urdftool.physics.vec3 import Tensor3
from urdftool.records import record


@record
class SolidProperties:
    """A solid of density 1 kg/m³: volume (m³), centroid (m), inertia about the centroid, bounds.

    ``center``, ``inertia`` and the bounds are in one frame (the shape's own
    frame, or the link frame after :func:`place`), as Python floats (a tensor is
    its three rows: :mod:`urdftool.physics.vec3`); ``bounds_min`` ≤ ``bounds_max``
    on each axis. ``label`` names the shape in the robot's terms ("0.1 m box",
    "mesh wheel.stl").
    """

    volume: float
    center: Vec3
    inertia: Tensor3
    bounds_min: Vec3
    bounds_max: Vec3
    label: str
    #: meshes that are not closed are measured by their convex hull
    approximate: bool = False

    def inertia_for_mass(self, mass: float) -> Tensor3:
        """The inertia (kg·m²) about the centroid of a uniform solid of *mass* (kg)."""
        return vec3.scaled(self.inertia, mass / self.volume)


def _fmt(value: float) -> str:
    return f"{value:.3g}"


_ORIGIN: Vec3 = (0.0, 0.0, 0.0)


def _solid(volume: float, moments: Vec3, half: Vec3, label: str) -> SolidProperties:
    """A primitive centred in its own frame, with principal *moments* (per unit density) on its
    axes and bounds ±*half* (m)."""
    if volume < sys.float_info.min:
        # a subnormal volume (a box 4.9e-324 m deep) is no volume: mass / volume would overflow and
        # its inertia's eigenvalues do not converge (fixtures/fuzz-regressions/denormal_box_size.sdf)
        volume = 0.0
    ixx, iyy, izz = moments
    inertia = ((ixx, 0.0, 0.0), (0.0, iyy, 0.0), (0.0, 0.0, izz))
    return SolidProperties(volume, _ORIGIN, inertia, (-half[0], -half[1], -half[2]), half, label)


def shape_properties(geometry: Geometry) -> SolidProperties | None:
    """The unit-density properties of a primitive shape in its own frame.

    ``None`` for shapes without a volume (planes, non-positive sizes) and for
    meshes (see :func:`mesh_properties`).
    """
    if isinstance(geometry, Box):
        x, y, z = geometry.size
        if min(x, y, z) <= 0:
            return None
        label = f"{_fmt(x)} m box" if x == y == z else f"{_fmt(x)}×{_fmt(y)}×{_fmt(z)} m box"
        return _solid(x * y * z, box_moments(x * y * z, (x, y, z)), (x / 2, y / 2, z / 2), label)
    if isinstance(geometry, Cylinder):
        r, h = geometry.radius, geometry.length
        if r <= 0 or h <= 0:
            return None
        volume = math.pi * r * r * h
        label = f"cylinder r={_fmt(r)} m l={_fmt(h)} m"
        return _solid(volume, cylinder_moments(volume, r, h), (r, r, h / 2), label)
    if isinstance(geometry, Sphere):
        r = geometry.radius
        if r <= 0:
            return None
        volume = 4.0 / 3.0 * math.pi * r**3
        return _solid(volume, sphere_moments(volume, r), (r, r, r), f"sphere r={_fmt(r)} m")
    if isinstance(geometry, Capsule):
        r, h = geometry.radius, geometry.length
        if r <= 0 or h < 0:
            return None
        volume = math.pi * r * r * h + 4.0 / 3.0 * math.pi * r**3
        label = f"capsule r={_fmt(r)} m l={_fmt(h)} m"
        return _solid(volume, capsule_moments(volume, r, h), (r, r, h / 2 + r), label)
    if isinstance(geometry, Ellipsoid):
        a, b, c = geometry.radii
        if min(a, b, c) <= 0:
            return None
        volume = 4.0 / 3.0 * math.pi * a * b * c
        label = f"ellipsoid {_fmt(a)}×{_fmt(b)}×{_fmt(c)} m"
        return _solid(volume, ellipsoid_moments(volume, (a, b, c)), (a, b, c), label)
    return None


def mesh_properties(mesh: Mesh, status: os.stat_result | None = None) -> SolidProperties | None:
    """The unit-density properties of a mesh file (after ``scale``), in the mesh frame; *status*:
    the file's ``os.stat``, when the caller has it.

    A closed (watertight) mesh is measured as the solid it encloses; an open one
    by its convex hull, which is exact for convex parts and over-estimates
    volume and inertia for concave ones. ``None`` when the mesh does not resolve,
    cannot be read, or encloses no volume.
    """
    if mesh.resolved is None:
        return None
    try:
        facts = facts_for(mesh.resolved, status)
    except MeshError:
        return None
    return _scaled_mesh(facts, mesh.scale, f"mesh {mesh.filename.rsplit('/', 1)[-1]}")


def _scaled_mesh(facts: MeshFacts, scale: Vec3, label: str) -> SolidProperties | None:
    """*facts* under a URDF ``scale``: :func:`urdftool.backends.meshes.scaled_info`'s volume,
    centre, inertia and bounds, in floats (the mesh survey and the exporters keep that one)."""
    second = facts.second_moment
    volume, center = facts.volume, facts.center_mass
    lo, hi = facts.bounds_min, facts.bounds_max
    (a, b, c), (d, e, f), (g, h, i) = second
    if tuple(scale) != _UNIT:  # most meshes are not scaled: x × 1.0 is x, the products are skipped
        sx, sy, sz = scale
        det = abs(sx * sy * sz)
        # det·S·C·S
        a, b, c = det * (sx * a * sx), det * (sx * b * sy), det * (sx * c * sz)
        d, e, f = det * (sy * d * sx), det * (sy * e * sy), det * (sy * f * sz)
        g, h, i = det * (sz * g * sx), det * (sz * h * sy), det * (sz * i * sz)
        volume = volume * det
        center = (center[0] * sx, center[1] * sy, center[2] * sz)
        lo, hi = (lo[0] * sx, lo[1] * sy, lo[2] * sz), (hi[0] * sx, hi[1] * sy, hi[2] * sz)
    if not volume > 0:
        return None
    # the unit-density inertia is tr(C)·E − C
    total = a + e + i
    # (0.0 - b: a product of zero stays +0, as NumPy's tr(C)·E − C writes it)
    inertia = ((total - a, 0.0 - b, 0.0 - c), (0.0 - d, total - e, 0.0 - f), (0.0 - g, 0.0 - h, total - i))
    if not all(map(math.isfinite, (*inertia[0], *inertia[1], *inertia[2]))):
        return None
    return SolidProperties(
        volume,
        (float(center[0]), float(center[1]), float(center[2])),
        inertia,
        (min(lo[0], hi[0]), min(lo[1], hi[1]), min(lo[2], hi[2])),
        (max(lo[0], hi[0]), max(lo[1], hi[1]), max(lo[2], hi[2])),
        label,
        approximate=not facts.watertight,
    )


_UNIT = (1.0, 1.0, 1.0)


def geometry_properties(geometry: Geometry | None) -> SolidProperties | None:
    """Unit-density properties of any geometry in its own frame, or ``None`` when it has none."""
    if geometry is None:
        return None
    if isinstance(geometry, Mesh):
        return mesh_properties(geometry)
    return shape_properties(geometry)


def place(solid: SolidProperties, origin: Pose) -> SolidProperties:
    """*solid* moved by *origin* (the shape frame in the link frame)."""
    xyz = origin.xyz
    lo, hi = solid.bounds_min, solid.bounds_max
    if unrotated(origin.rpy):
        if xyz == _ORIGIN:  # most shapes sit at the link's origin
            return solid
        return SolidProperties(
            solid.volume, vec3.add(solid.center, xyz), solid.inertia, vec3.add(lo, xyz), vec3.add(hi, xyz),
            solid.label, solid.approximate,
        )
    turn = vec3.rotation(origin.rpy)
    # The rotated box's bounds: along each axis, the sum of each term's smaller (larger) end
    # is the smallest (largest) of the eight corners.
    low, high = [], []
    for (r0, r1, r2), offset in zip(turn, xyz, strict=True):
        x0, x1, y0, y1, z0, z1 = r0 * lo[0], r0 * hi[0], r1 * lo[1], r1 * hi[1], r2 * lo[2], r2 * hi[2]
        low.append((x0 if x0 < x1 else x1) + (y0 if y0 < y1 else y1) + (z0 if z0 < z1 else z1) + offset)
        high.append((x1 if x0 < x1 else x0) + (y1 if y0 < y1 else y0) + (z1 if z0 < z1 else z0) + offset)
    return SolidProperties(
        solid.volume,
        vec3.add(vec3.apply(turn, solid.center), xyz),
        vec3.product(vec3.product(turn, solid.inertia), vec3.transpose(turn)),
        (low[0], low[1], low[2]),
        (high[0], high[1], high[2]),
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
    center = (
        sum(p.volume * p.center[0] for p in parts) / volume,
        sum(p.volume * p.center[1] for p in parts) / volume,
        sum(p.volume * p.center[2] for p in parts) / volume,
    )
    inertia = vec3.ZERO_TENSOR
    for p in parts:
        inertia = vec3.added(inertia, vec3.shift_to_point(p.inertia, p.volume, vec3.sub(p.center, center)))
    label = " + ".join(p.label for p in parts[:3]) + (
        f" + {len(parts) - 3} more" if len(parts) > 3 else ""
    )
    return SolidProperties(
        volume,
        center,
        inertia,
        (min(p.bounds_min[0] for p in parts), min(p.bounds_min[1] for p in parts),
         min(p.bounds_min[2] for p in parts)),
        (max(p.bounds_max[0] for p in parts), max(p.bounds_max[1] for p in parts),
         max(p.bounds_max[2] for p in parts)),
        label,
        any(p.approximate for p in parts),
    )


def rotate_into(tensor: Tensor3, frame: Pose) -> Tensor3:
    """A tensor written in the link frame, expressed in *frame* (given in the link frame)."""
    return vec3.rotate_tensor(tensor, frame.rpy, inverse=True)
