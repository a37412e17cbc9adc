"""Mesh files through trimesh: size, volume, centre of mass and inertia, cached per file.

Units: the file's coordinates times ``scale`` are taken as metres. Inertia is
for unit density (kg/m³) about the centre of mass, in the mesh frame; multiply
by the density (mass / volume) for a real body.
"""

from __future__ import annotations

import hashlib
import threading
from dataclasses import dataclass

import numpy as np

from urdftool.model.pose import Matrix, Vec3


class MeshError(Exception):
    """The mesh file cannot be read (missing, unsupported, or corrupt)."""


@dataclass(frozen=True)
class MeshInfo:
    """What urdftool needs to know about a mesh, after scaling (m, m³, kg·m² per kg/m³)."""

    path: str
    vertices: int
    faces: int
    watertight: bool
    volume: float
    center_mass: Vec3
    inertia_unit_density: Matrix
    bounds_min: Vec3
    bounds_max: Vec3

    @property
    def extents(self) -> Vec3:
        lo, hi = self.bounds_min, self.bounds_max
        return (hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2])


_CACHE: dict[tuple[str, Vec3], MeshInfo] = {}
_LOCK = threading.Lock()


def content_key(path: str) -> str:
    """SHA-256 of the file's bytes (the cache key: the same mesh under two names loads once)."""
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def load_trimesh(path: str):  # type: ignore[no-untyped-def]
    """The file as one ``trimesh.Trimesh`` (scenes are concatenated)."""
    import trimesh

    try:
        loaded = trimesh.load(path, force="mesh", process=True)
    except Exception as exc:  # trimesh raises many kinds for bad files
        raise MeshError(f"{type(exc).__name__}: {exc}") from exc
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0:
        raise MeshError("no triangles in file")
    return loaded


def mesh_info(path: str, scale: Vec3 = (1.0, 1.0, 1.0)) -> MeshInfo:
    """Properties of the mesh at *path* scaled by *scale*. Raises :class:`MeshError`."""
    try:
        key = (content_key(path), tuple(scale))
    except OSError as exc:
        raise MeshError(str(exc)) from exc
    with _LOCK:
        if key in _CACHE:
            return _CACHE[key]
    mesh = load_trimesh(path)
    mesh.apply_scale(np.asarray(scale, dtype=float))
    volume = float(abs(mesh.volume)) if mesh.is_watertight else float(abs(mesh.convex_hull.volume))
    solid = mesh if mesh.is_watertight else mesh.convex_hull
    inertia = np.asarray(solid.moment_inertia, dtype=float)
    if solid.volume < 0:
        inertia = -inertia
    com = solid.center_mass
    lo, hi = mesh.bounds
    info = MeshInfo(
        path=path,
        vertices=len(mesh.vertices),
        faces=len(mesh.faces),
        watertight=bool(mesh.is_watertight),
        volume=volume,
        center_mass=(float(com[0]), float(com[1]), float(com[2])),
        inertia_unit_density=inertia,
        bounds_min=(float(lo[0]), float(lo[1]), float(lo[2])),
        bounds_max=(float(hi[0]), float(hi[1]), float(hi[2])),
    )
    with _LOCK:
        _CACHE[key] = info
    return info
