"""The shape of a mesh as a collision engine sees it: hulls, concavity, winding, manifoldness.

What :mod:`urdftool.backends.meshes` measures (size, volume, inertia) is what
a mesh weighs; this module measures what it collides as. Engines that collide
with convex shapes (MuJoCo, PyBullet, Drake's point contact, PhysX) replace a
mesh by its convex hull (PyBullet: one hull per object of an OBJ file), so the
question for a collision mesh is how much of its hull it fills.

Facts are per file content and kept in the persistent mesh cache beside the
mass facts (key ``shape-v1-<sha256>``), so a second check does not read the
file again. Units are metres, after the COLLADA unit and before any URDF scale
(volumes scale by the determinant of the scale, ratios not at all).
"""

from __future__ import annotations

import threading
from dataclasses import asdict
from typing import Any

from urdftool.backends import mesh_cache, mesh_files
from urdftool.backends.meshes import MeshError, consistently_wound, content_key, load_trimesh
from urdftool.records import record

#: Bump when the stored facts change.
_VERSION = "shape-v1"


@record
class ShapeFacts:
    """How a mesh fills its hull, and whether its surface is a clean closed solid.

    ``solid_volume`` is the volume the mesh encloses: its own when it is
    watertight, else the sum of the hulls of its connected pieces or of its OBJ
    objects, whichever is larger (a tray made of open boxes is the volume of
    the boxes), so it never exceeds
    ``hull_volume``. ``object_hull_volume`` sums one hull per object of an OBJ
    file (``objects`` of them; for other formats it equals ``hull_volume``).
    ``nonmanifold_edges`` counts edges shared by more than two faces;
    ``degenerate_faces`` faces of zero area.
    """

    vertices: int
    faces: int
    watertight: bool
    winding_consistent: bool
    nonmanifold_edges: int
    degenerate_faces: int
    solid_volume: float
    hull_volume: float
    hull_vertices: int
    objects: int
    object_hull_volume: float

    @property
    def fill(self) -> float:
        """The fraction of the hull the mesh fills (1 for a convex mesh; 0 for a flat one)."""
        if self.hull_volume <= 0:
            return 1.0
        return min(1.0, self.solid_volume / self.hull_volume)

    def hull_fill(self, per_object: bool) -> float:
        """The fraction of the engine's hull(s) the mesh fills."""
        hull = self.object_hull_volume if per_object else self.hull_volume
        if hull <= 0:
            return 1.0
        return min(1.0, self.solid_volume / hull)


_MEMORY: dict[str, ShapeFacts | MeshError] = {}
_LOCK = threading.Lock()


def shape_facts(path: str) -> ShapeFacts:
    """The shape facts of the mesh at *path*, from memory, the disk cache, or by reading it.

    Raises :class:`MeshError` when the file cannot be read.
    """
    try:
        key = f"{_VERSION}-{content_key(path)}"
    except OSError as exc:
        raise MeshError(exc.strerror or str(exc)) from exc
    with _LOCK:
        known = _MEMORY.get(key)
    if known is None:
        stored = mesh_cache.get(key)
        if stored is not None:
            try:
                known = ShapeFacts(**stored)
            except TypeError:
                known = None
    if known is None:
        try:
            known = measure(path)
            mesh_cache.put(key, asdict(known))
        except MeshError as exc:
            known = exc
    with _LOCK:
        _MEMORY[key] = known
    if isinstance(known, MeshError):
        raise known
    return known


def measure(path: str) -> ShapeFacts:
    """Read *path* and measure its shape (no caching). Raises :class:`MeshError`."""
    import warnings

    with warnings.catch_warnings():
        # trimesh's integrals divide by the zero volume of open or flat pieces
        warnings.simplefilter("ignore", RuntimeWarning)
        return _measure(path)


def _measure(path: str) -> ShapeFacts:
    mesh = load_trimesh(path)
    hull = _hull(mesh)
    hull_volume = abs(float(hull.volume)) if hull is not None else 0.0
    watertight = bool(mesh.is_watertight)
    if watertight:
        solid = abs(float(consistently_wound(mesh).volume))
    objects = object_meshes(path)
    object_hulls = sum(_hull_volume(o) for o in objects) if len(objects) > 1 else hull_volume
    if not watertight:
        pieces = sum(_hull_volume(piece) for piece in mesh.split(only_watertight=False))
        solid = max(pieces, object_hulls if len(objects) > 1 else 0.0)
    return ShapeFacts(
        vertices=len(mesh.vertices),
        faces=len(mesh.faces),
        watertight=watertight,
        winding_consistent=bool(mesh.is_winding_consistent),
        nonmanifold_edges=_nonmanifold_edges(mesh),
        degenerate_faces=int((mesh.area_faces <= 1e-14).sum()),
        solid_volume=min(solid, hull_volume) if hull_volume > 0 else solid,
        hull_volume=hull_volume,
        hull_vertices=len(hull.vertices) if hull is not None else 0,
        objects=max(1, len(objects)),
        object_hull_volume=object_hulls,
    )


def _hull(mesh: Any) -> Any:
    try:
        return mesh.convex_hull
    except Exception:  # qhull refuses flat or degenerate point sets
        return None


def _hull_volume(mesh: Any) -> float:
    hull = _hull(mesh)
    return abs(float(hull.volume)) if hull is not None else 0.0


def _nonmanifold_edges(mesh: Any) -> int:
    import numpy as np

    edges = np.sort(mesh.edges, axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    return int((counts > 2).sum())


def object_meshes(path: str) -> list[Any]:
    """The objects of an OBJ file (``o``/``g`` groups) as meshes; ``[]`` for other formats."""
    if not path.lower().endswith(".obj"):
        return []
    import trimesh

    try:
        scene: Any = mesh_files.load(
            path, force="scene", split_objects=True, split_groups=True, group_material=False
        )
    except Exception:  # the whole-file read succeeded: treat the file as one object
        return []
    return [g for g in scene.geometry.values() if isinstance(g, trimesh.Trimesh) and len(g.faces)]
