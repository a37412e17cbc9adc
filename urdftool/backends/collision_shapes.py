"""Collision geometry simulators can use: convex hulls, convex decompositions (CoACD), primitives.

:func:`simplify` turns one collision mesh file into what ``convert
--collision hull|decompose|primitives`` writes instead of it, and says how
far its volume is from the mesh's. Results are kept per mesh content and
options in a folder of the user cache (``…/urdftool-collision/<key>/``), so a
second convert of the same robot reads them back instead of recomputing (a
decomposition takes seconds per mesh). Generated files live in folders named
``urdftool-collision…``; exporters recognise them by that name
(:func:`is_generated`) and copy them beside their output.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import tempfile
from dataclasses import asdict, field
from pathlib import Path
from typing import Any

from urdftool.backends import mesh_cache
from urdftool.backends.mesh_shape import object_meshes, shape_facts
from urdftool.backends.meshes import MeshError, content_key, load_trimesh
from urdftool.records import record

GENERATED_DIRNAME = "urdftool-collision"
#: Bump when what is written changes.
_VERSION = 4
_TEMP: list[str] = []


@record
class Primitive:
    """A shape fitted to a mesh, in the mesh's (scaled) frame: ``kind`` box, cylinder, sphere or capsule.

    ``size`` is the box's extents, (radius, length) for a cylinder or a
    capsule along its local z (a capsule's length is that of its cylindrical
    part, between the centres of its end caps), (radius,) for a sphere;
    ``xyz``/``rpy`` place it.
    """

    kind: str
    size: tuple[float, ...]
    xyz: tuple[float, float, float]
    rpy: tuple[float, float, float]


@record
class Simplified:
    """What replaces one collision mesh.

    ``mode`` is what was done (``hull``, ``decompose``, ``primitive``; a mesh
    that needs nothing keeps ``as-is``); ``parts`` are OBJ files (in the
    mesh's unscaled frame, so the URDF ``scale`` still applies) or
    ``primitive`` a fitted shape (already scaled). ``volume`` is the volume of
    the result and ``mesh_volume`` that of the mesh, both scaled (m³).
    """

    mode: str
    parts: tuple[str, ...] = ()
    primitive: Primitive | None = None
    volume: float = 0.0
    mesh_volume: float = 0.0
    note: str = ""
    cached: bool = field(default=False, compare=False)

    @property
    def volume_error(self) -> float:
        """(result − mesh) / mesh: positive where the result adds volume."""
        if self.mesh_volume <= 0:
            return 0.0
        return (self.volume - self.mesh_volume) / self.mesh_volume


def is_generated(path: str) -> bool:
    """A file written by :func:`simplify` (its folder is a ``urdftool-collision`` folder)."""
    return any(part.startswith(GENERATED_DIRNAME) for part in Path(path).parts)


def _root() -> Path:
    base = mesh_cache.cache_root()
    if base is not None:
        return base.parent.parent / GENERATED_DIRNAME
    if not _TEMP:
        _TEMP.append(tempfile.mkdtemp(prefix=f"{GENERATED_DIRNAME}-"))
    return Path(_TEMP[0])


def simplify(
    path: str,
    mode: str,
    scale: tuple[float, float, float] = (1.0, 1.0, 1.0),
    *,
    threshold: float = 0.05,
    max_parts: int = 16,
    tolerance: float = 0.15,
) -> Simplified:
    """Simplify the collision mesh at *path* (``hull``, ``decompose`` or ``primitives``).

    ``decompose`` keeps near-convex meshes (filling 95 % of their hull) as one
    hull; ``primitives`` falls back to the hull when no box, cylinder, sphere
    or capsule is within *tolerance* (relative volume) of the mesh. Raises
    :class:`MeshError`.
    """
    try:
        content = content_key(path)
    except OSError as exc:
        raise MeshError(exc.strerror or str(exc)) from exc
    options = {"v": _VERSION, "mode": mode, "threshold": threshold, "max_parts": max_parts,
               "tolerance": tolerance, "scale": list(scale) if mode == "primitives" else None}
    key = hashlib.sha256(f"{content}{json.dumps(options, sort_keys=True)}".encode()).hexdigest()[:32]
    folder = _root() / key
    recalled = _recall(folder)
    if recalled is not None:
        return recalled
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        result = _compute(path, mode, scale, folder, threshold, max_parts, tolerance)
    with contextlib.suppress(OSError):  # a cache that cannot be written only costs time
        (folder / "result.json").write_text(json.dumps(_to_json(result, folder)), encoding="utf-8")
    return result


def _det(scale: tuple[float, float, float]) -> float:
    return abs(scale[0] * scale[1] * scale[2])


def _compute(path: str, mode: str, scale: tuple[float, float, float], folder: Path,
             threshold: float, max_parts: int, tolerance: float) -> Simplified:
    mesh = load_trimesh(path)
    try:
        hull = mesh.convex_hull
    except Exception as exc:  # qhull: fewer than four distinct points
        raise MeshError(f"no convex hull ({str(exc).splitlines()[0][:80]})") from exc
    det = _det(scale)
    mesh_volume = shape_facts(path).solid_volume * det
    hull_volume = abs(float(hull.volume)) * det
    folder.mkdir(parents=True, exist_ok=True)
    if mode == "primitives":
        fitted = _fit_primitive(mesh, scale, mesh_volume, tolerance)
        if fitted is not None:
            shape, volume = fitted
            return Simplified("primitive", primitive=shape, volume=volume, mesh_volume=mesh_volume)
        note = f"no box, cylinder, sphere or capsule within {tolerance:.0%} of the volume: convex hull"
        return Simplified("hull", (_write(folder, 0, hull),), volume=hull_volume, mesh_volume=mesh_volume,
                          note=note)
    if mode == "decompose" and mesh_volume < 0.95 * hull_volume:
        pieces, by_coacd = _decompose(path, mesh, threshold, max_parts)
        files = tuple(_write(folder, n, piece) for n, piece in enumerate(pieces))
        volume = _union_volume(pieces) * det
        kept = len(pieces) - by_coacd
        note = ", ".join(
            part for part in (f"{kept} convex object(s) of the file kept" if kept else "",
                              f"{by_coacd} part(s) from CoACD (threshold {threshold:g})" if by_coacd else "")
            if part
        )
        return Simplified("decompose", files, volume=volume, mesh_volume=mesh_volume, note=note)
    note = "nearly convex already: one hull" if mode == "decompose" else ""
    return Simplified("hull", (_write(folder, 0, hull),), volume=hull_volume, mesh_volume=mesh_volume,
                      note=note)


def _decompose(path: str, mesh: Any, threshold: float, max_parts: int) -> tuple[list[Any], int]:
    """Convex parts: the mesh's objects or connected pieces that are convex already are kept
    as their hulls (a tray built of slabs stays exactly those slabs); the rest goes through CoACD."""
    pieces = object_meshes(path)
    if len(pieces) <= 1:
        pieces = [p for p in mesh.split(only_watertight=False) if len(p.faces) >= 4]
    if not 1 < len(pieces) <= max_parts:
        parts = _coacd(mesh, threshold, max_parts)
        return parts, len(parts)
    out: list[Any] = []
    by_coacd = 0
    for piece in pieces:
        if _is_convex(piece):
            out.append(piece.convex_hull)
        else:
            made = _coacd(piece, threshold, max(1, max_parts - len(pieces) + 1))
            by_coacd += len(made)
            out.extend(made)
    return out, by_coacd


def _is_convex(piece: Any) -> bool:
    """Every vertex of *piece* lies on its convex hull (within 0.5 % of its size)."""
    import numpy as np

    if len(piece.vertices) > 5000:
        return False
    try:
        hull = piece.convex_hull
    except Exception:  # flat: qhull refuses it
        return False
    normals = hull.face_normals
    offsets = (normals * hull.triangles[:, 0, :]).sum(axis=1)
    heights = piece.vertices @ normals.T - offsets  # <= 0 inside; 0 on a face's plane
    eps = 0.005 * float(np.linalg.norm(piece.extents))
    return bool((heights.max(axis=1) > -eps).all())


def _write(folder: Path, number: int, mesh: Any) -> str:
    target = folder / f"part{number:02d}.obj"
    data = mesh.export(file_type="obj", include_normals=False, include_color=False, include_texture=False)
    target.write_text(data if isinstance(data, str) else data.decode(), encoding="utf-8")
    return str(target)


def _coacd(mesh: Any, threshold: float, max_parts: int) -> list[Any]:
    import coacd
    import trimesh

    coacd.set_log_level("error")
    parts = coacd.run_coacd(
        coacd.Mesh(mesh.vertices, mesh.faces), threshold=threshold, max_convex_hull=max_parts, seed=1
    )
    return [trimesh.Trimesh(vertices, faces).convex_hull for vertices, faces in parts]


def _union_volume(pieces: list[Any]) -> float:
    import trimesh

    if len(pieces) == 1:
        return abs(float(pieces[0].volume))
    try:
        return abs(float(trimesh.boolean.union(pieces, engine="manifold").volume))
    except Exception:  # no boolean engine: the sum over-counts overlaps
        return float(sum(abs(float(p.volume)) for p in pieces))


def _fit_primitive(mesh: Any, scale: tuple[float, float, float], mesh_volume: float,
                   tolerance: float) -> tuple[Primitive, float] | None:
    """The enclosing box, cylinder, sphere or capsule whose volume is nearest the mesh's, if
    within *tolerance*."""
    import numpy as np
    import trimesh

    scaled = mesh.copy()
    scaled.apply_transform(np.diag([*scale, 1.0]))
    if mesh_volume <= 0:
        return None
    candidates: list[tuple[Primitive, float]] = []
    to_origin, extents = trimesh.bounds.oriented_bounds(scaled)
    pose = np.linalg.inv(to_origin)
    candidates.append((Primitive("box", tuple(float(e) for e in extents), *_xyz_rpy(pose)),
                       float(np.prod(extents))))
    try:
        cylinder = trimesh.bounds.minimum_cylinder(scaled)
        radius, height = float(cylinder["radius"]), float(cylinder["height"])
        candidates.append((Primitive("cylinder", (radius, height), *_xyz_rpy(cylinder["transform"])),
                           float(np.pi * radius**2 * height)))
    except Exception:  # a degenerate point set: no cylinder
        pass
    centre, radius = trimesh.nsphere.minimum_nsphere(scaled.vertices)
    candidates.append((Primitive("sphere", (float(radius),), _vec(centre), (0.0, 0.0, 0.0)),
                       float(4 / 3 * np.pi * radius**3)))
    with contextlib.suppress(Exception):  # a flat or degenerate mesh has no hull: no capsule
        candidates.extend(_capsules(scaled.convex_hull))
    best = min(candidates, key=lambda c: abs(c[1] - mesh_volume))
    if abs(best[1] - mesh_volume) / mesh_volume > tolerance:
        return None
    return best


def _capsules(hull: Any) -> list[tuple[Primitive, float]]:
    """The smallest capsule enclosing *hull* along its principal axes (the long one, in practice)."""
    import numpy as np

    best: tuple[Primitive, float] | None = None
    for axis in np.asarray(hull.principal_inertia_vectors, dtype=float):
        axis = axis / np.linalg.norm(axis)
        axis = axis if axis[int(np.argmax(np.abs(axis)))] > 0 else -axis  # one sign, every platform
        fitted = _capsule_along(np.asarray(hull.vertices, dtype=float), axis)
        if fitted is not None and np.isfinite(fitted[1]) and (best is None or fitted[1] < best[1]):
            best = fitted
    return [best] if best is not None else []


def _capsule_along(points: Any, axis: Any) -> tuple[Primitive, float] | None:
    """The smallest capsule with its axis parallel to *axis* enclosing *points*.

    The axis passes through the centre of the smallest circle holding the
    points seen along it; for a radius r, point i at height t_i and distance
    ρ_i from the axis is inside when the segment reaches t_i ± √(r² − ρ_i²),
    which fixes the segment; the radius is searched between the largest ρ and
    the radius at which the segment shrinks to a point (then a sphere fits
    better: no capsule).
    """
    import numpy as np
    import trimesh

    helper = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(axis, helper)
    u /= np.linalg.norm(u)
    v = np.cross(axis, u)
    heights = points @ axis
    planar = np.column_stack([points @ u, points @ v])
    middle, _ = trimesh.nsphere.minimum_nsphere(planar)
    rho = np.linalg.norm(planar - middle, axis=1)

    def ends(r: float) -> tuple[float, float]:
        reach = np.sqrt(np.maximum(r * r - rho * rho, 0.0))
        return float((heights + reach).min()), float((heights - reach).max())

    def volume(r: float) -> float:
        low, high = ends(r)
        return float(np.pi * r * r * max(high - low, 0.0) + 4 / 3 * np.pi * r**3)

    smallest = float(rho.max())
    largest = float(np.hypot((heights.max() - heights.min()) / 2, smallest))
    if not largest > 0:
        return None
    radii = np.linspace(smallest, largest, 65)
    at = int(np.argmin([volume(r) for r in radii]))
    low_r, high_r = float(radii[max(at - 1, 0)]), float(radii[min(at + 1, len(radii) - 1)])
    for _ in range(48):  # golden-section search between the grid neighbours of the best radius
        a, b = low_r + 0.382 * (high_r - low_r), low_r + 0.618 * (high_r - low_r)
        if volume(a) < volume(b):
            high_r = b
        else:
            low_r = a
    radius = (low_r + high_r) / 2
    low, high = ends(radius)
    if high - low <= 1e-6 * radius:
        return None
    centre = (low + high) / 2 * axis + middle[0] * u + middle[1] * v
    pose = np.eye(4)
    pose[:3, :3] = _rotation_onto(axis)
    pose[:3, 3] = centre
    return (Primitive("capsule", (radius, high - low), *_xyz_rpy(pose)), volume(radius))


def _rotation_onto(axis: Any) -> Any:
    """A rotation taking local z onto *axis* (a unit vector)."""
    import trimesh

    return trimesh.geometry.align_vectors([0.0, 0.0, 1.0], axis)[:3, :3]


def _vec(values: Any) -> tuple[float, float, float]:
    return (float(values[0]), float(values[1]), float(values[2]))


def _xyz_rpy(matrix: Any) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    import trimesh

    angles = trimesh.transformations.euler_from_matrix(matrix, "sxyz")
    return _vec(matrix[:3, 3]), _vec(angles)


def _to_json(result: Simplified, folder: Path) -> dict[str, Any]:
    data = asdict(result)
    data["parts"] = [os.path.basename(p) for p in result.parts]
    data.pop("cached", None)
    return data


def _recall(folder: Path) -> Simplified | None:
    try:
        data = json.loads((folder / "result.json").read_text(encoding="utf-8"))
        parts = tuple(str(folder / name) for name in data["parts"])
        if not all(os.path.isfile(p) for p in parts):
            return None
        primitive = data.get("primitive")
        shape = None
        if primitive:
            shape = Primitive(primitive["kind"], tuple(primitive["size"]), _vec(primitive["xyz"]),
                              _vec(primitive["rpy"]))
        return Simplified(data["mode"], parts, shape, float(data["volume"]), float(data["mesh_volume"]),
                          str(data.get("note", "")), cached=True)
    except (OSError, ValueError, KeyError, TypeError):
        return None
