"""Collision geometry as volume: points filling a geometry, and which points lie inside another.

A penetration depth says how far two shapes must move apart, which near a
joint grows with the angle even when only the two links' ends overlap. The
share of one geometry's volume inside another says how much of a link has
gone *into* the other, and is what ``range-passes-through-parent`` (N305)
judges.

Geometries are those of :class:`~urdftool.backends.collision.CollisionScene`,
as solids (:func:`solid`): boxes, spheres, cylinders, capsules and ellipsoids
exactly; a mesh as its own triangles when they close a volume (watertight,
tested with trimesh's ray casts), not as its convex hull, because the hull of
a clevis fills the gap the next link turns in and would report that link as
buried in its parent. For the same reason a closed mesh that is its own
convex hull is marked an ``envelope``: the caller cannot tell the part inside
it from the space its notches leave. A mesh that is not watertight has no
inside: its solid is ``None`` and the caller cannot judge the pair. Points are a regular grid
in the geometry's own frame, clipped to the solid, so their count is
proportional to its volume.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np
else:
    from urdftool.lazy import numpy as np

from urdftool.backends.collision import CollisionScene
from urdftool.backends.meshes import MeshError, load_trimesh, quiet_numerics
from urdftool.records import record

#: A closed mesh whose volume is at least this share of its convex hull's is an envelope (:class:`Solid`).
ENVELOPE = 0.99

#: (path, scale) -> the watertight mesh scaled, or None (unreadable or open)
_MESHES: dict[tuple[str, tuple[float, float, float]], Any] = {}


@record
class Solid:
    """One collision geometry as a volume, in its own frame: a coal primitive or a closed mesh."""

    shape: Any
    mesh: Any
    #: bounding box corners (m) in the geometry's frame
    lower: Any
    upper: Any
    #: a mesh that is its own convex hull (volume within :data:`ENVELOPE` of the hull's): most
    #: often the hull of a part with notches, which it fills; never true for a primitive
    envelope: bool = False

    def contains(self, points: Any) -> Any:
        """Which of *points* (n × 3, m, in the geometry's frame) lie inside (a boolean mask)."""
        p = np.asarray(points, dtype=float).reshape(-1, 3)
        found = np.zeros(len(p), dtype=bool)
        near = np.all((p >= self.lower) & (p <= self.upper), axis=1)
        if near.any():
            found[near] = self._contains(p[near])
        return found

    def fill(self, spacing: float) -> Any:
        """Points (n × 3, m) on a grid of *spacing* m that lie inside; the box's centre when the
        grid misses the solid (a part thinner than the spacing)."""
        axes = [np.arange(lo + spacing / 2, hi, spacing) if hi - lo > spacing else np.array([(lo + hi) / 2])
                for lo, hi in zip(self.lower, self.upper, strict=True)]
        grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
        points = grid[self.contains(grid)]
        return points if len(points) else ((self.lower + self.upper) / 2).reshape(1, 3)

    @property
    def box_volume(self) -> float:
        return float(np.prod(np.maximum(self.upper - self.lower, 0.0)))

    def _contains(self, p: Any) -> Any:
        if self.mesh is not None:
            with quiet_numerics():
                return np.asarray(self.mesh.contains(p), dtype=bool)
        shape, name = self.shape, type(self.shape).__name__
        if name == "Box":
            return np.all(np.abs(p) <= np.asarray(shape.halfSide, dtype=float), axis=1)
        if name == "Sphere":
            return np.einsum("ij,ij->i", p, p) <= float(shape.radius) ** 2
        if name == "Cylinder":
            radial = p[:, 0] ** 2 + p[:, 1] ** 2
            return (radial <= float(shape.radius) ** 2) & (np.abs(p[:, 2]) <= float(shape.halfLength))
        if name == "Capsule":
            axis = np.zeros_like(p)
            axis[:, 2] = np.clip(p[:, 2], -float(shape.halfLength), float(shape.halfLength))
            gap = p - axis
            return np.einsum("ij,ij->i", gap, gap) <= float(shape.radius) ** 2
        if name == "Ellipsoid":
            return np.sum((p / np.asarray(shape.radii, dtype=float)) ** 2, axis=1) <= 1.0
        return np.zeros(len(p), dtype=bool)


def solid(scene: CollisionScene, k: int) -> Solid | None:
    """Piece *k* of *scene* as a solid, or ``None`` for a mesh that does not close a volume."""
    if k in scene.meshes:
        mesh = _closed_mesh(*scene.meshes[k])
        if mesh is None:
            return None
        lower, upper = (np.asarray(v, dtype=float) for v in mesh.bounds)
        with quiet_numerics():
            envelope = bool(mesh.volume >= ENVELOPE * mesh.convex_hull.volume)
        return Solid(None, mesh, lower, upper, envelope)
    shape = scene.shape(k)
    shape.computeLocalAABB()
    box = shape.aabb_local
    return Solid(shape, None, np.asarray(box.min_, dtype=float), np.asarray(box.max_, dtype=float))


def _closed_mesh(path: str, scale: tuple[float, float, float]) -> Any:
    key = (path, scale)
    if key not in _MESHES:
        try:
            with quiet_numerics():
                mesh = load_trimesh(path).copy()
                mesh.apply_scale(np.asarray(scale, dtype=float))
                _MESHES[key] = mesh if mesh.is_watertight and len(mesh.faces) else None
        except MeshError:
            _MESHES[key] = None
    return _MESHES[key]
