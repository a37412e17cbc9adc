"""Mesh files through trimesh: size, volume, centre of mass and inertia, cached per file.

Units: a file's coordinates are taken as metres, after the COLLADA
``<unit meter="…">`` of a ``.dae`` file (which RViz, Gazebo and PyBullet apply);
a URDF ``scale`` multiplies them further. Inertia is for unit density (kg/m³)
about the centre of mass, in the mesh frame; multiply by the density
(mass / volume) for a real body.

Each file is read once per process and its facts are kept per content hash, in
memory and in the persistent cache (:mod:`urdftool.backends.mesh_cache`), so
the same bytes under two names, or in a later run, are not read again. The
facts are stored unscaled; :func:`mesh_info` applies a scale exactly (a scale
is a linear map, so volume, centre and second moments transform in closed
form). :func:`load_many` reads many files in parallel worker processes.
"""

from __future__ import annotations

import contextlib
import hashlib
import logging
import os
import threading
import warnings
from collections.abc import Iterable, Iterator, Mapping
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np
else:  # NumPy loads when a mesh is first read: a structural check never pays for it
    from urdftool.lazy import numpy as np

from urdftool.backends import mesh_cache, mesh_files
from urdftool.backends.collada_trimesh import (
    collada_before_nul,
    collada_declares_entities,
    collada_geometry_only,
    collada_unit,
    lean_collada,
)
from urdftool.model.pose import Matrix, Vec3, vector_norm
from urdftool.records import record
from urdftool.safe_files import check_regular, open_regular


class MeshError(Exception):
    """The mesh file cannot be read (missing, unsupported, or corrupt)."""


@record
class MeshFacts:
    """What a mesh file holds, in metres, before any URDF ``scale``.

    ``volume`` (m³), ``center_mass`` (m) and ``second_moment`` (∫ r rᵀ dV about
    the centre of mass, m⁵) describe the solid: the mesh itself when it is
    closed (watertight), else its convex hull. Bounds are the mesh's own.
    ``unit`` is the COLLADA unit already applied (1 for other formats).
    """

    vertices: int
    faces: int
    watertight: bool
    volume: float
    center_mass: Vec3
    second_moment: tuple[Vec3, Vec3, Vec3]
    bounds_min: Vec3
    bounds_max: Vec3
    unit: float = 1.0

    def to_json(self) -> dict[str, Any]:
        return {
            "vertices": self.vertices,
            "faces": self.faces,
            "watertight": self.watertight,
            "volume": self.volume,
            "center_mass": list(self.center_mass),
            "second_moment": [list(row) for row in self.second_moment],
            "bounds_min": list(self.bounds_min),
            "bounds_max": list(self.bounds_max),
            "unit": self.unit,
        }

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> MeshFacts:
        return cls(
            vertices=int(data["vertices"]),
            faces=int(data["faces"]),
            watertight=bool(data["watertight"]),
            volume=float(data["volume"]),
            center_mass=_vec3(data["center_mass"]),
            second_moment=(
                _vec3(data["second_moment"][0]),
                _vec3(data["second_moment"][1]),
                _vec3(data["second_moment"][2]),
            ),
            bounds_min=_vec3(data["bounds_min"]),
            bounds_max=_vec3(data["bounds_max"]),
            unit=float(data.get("unit", 1.0)),
        )


@record
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
    #: COLLADA unit applied before the scale (1 for other formats)
    unit: float = 1.0

    @property
    def extents(self) -> Vec3:
        lo, hi = self.bounds_min, self.bounds_max
        return (hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2])

    @property
    def diagonal(self) -> float:
        """Length of the bounding box diagonal (m): the mesh's size in one number."""
        return box_diagonal(self.bounds_min, self.bounds_max)


def box_diagonal(lo: Vec3, hi: Vec3) -> float:
    """Length (m) of the diagonal of the box from corner *lo* to corner *hi*."""
    return vector_norm((hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]))


# -- per-process memory ----------------------------------------------------------

#: content hash -> facts, or the error reading those bytes gave
_FACTS: dict[str, MeshFacts | MeshError] = {}
#: (path, size, mtime, inode) -> content hash: each file is hashed once per run. An absolute
#: path is taken as written: the inode tells the file, and normalising cost more than the lookup.
_KEYS: dict[tuple[str, int, int, int], str] = {}
_LOCK = threading.Lock()


def content_key(path: str, status: os.stat_result | None = None) -> str:
    """SHA-256 of the file's bytes (the cache key: the same mesh under two names loads once).
    *status*: its ``os.stat``, when the caller has it. Raises ``OSError`` when it cannot be read."""
    stat = os.stat(path) if status is None else status
    where = path if os.path.isabs(path) else os.path.abspath(path)
    memo = (where, stat.st_size, stat.st_mtime_ns, stat.st_ino)
    with _LOCK:
        if memo in _KEYS:
            return _KEYS[memo]
    digest = hashlib.sha256()
    with open_regular(path, "mesh") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    key = digest.hexdigest()
    with _LOCK:
        _KEYS[memo] = key
    return key


def _remember(key: str, result: MeshFacts | MeshError, store: bool) -> None:
    with _LOCK:
        _FACTS[key] = result
    if store:
        value = {"error": str(result)} if isinstance(result, MeshError) else result.to_json()
        mesh_cache.put(key, value)


def _recall(key: str) -> MeshFacts | MeshError | None:
    with _LOCK:
        if key in _FACTS:
            return _FACTS[key]
    stored = mesh_cache.get(key)
    if stored is None:
        return None
    try:
        result: MeshFacts | MeshError = (
            MeshError(str(stored["error"])) if "error" in stored else MeshFacts.from_json(stored)
        )
    except (KeyError, TypeError, ValueError, IndexError):
        return None  # an entry from a broken write: compute it again
    _remember(key, result, store=False)
    return result


# -- reading one file --------------------------------------------------------------

def _quiet_trimesh_log() -> None:
    """Give trimesh's logger a handler of its own, so its warnings (and the tracebacks it logs
    for files it cannot read, which urdftool reports as findings) do not fall through to
    Python's last-resort handler on stderr. An application that configures logging still
    sees them through its own handlers."""
    logger = logging.getLogger("trimesh")
    if not any(isinstance(h, logging.NullHandler) for h in logger.handlers):
        logger.addHandler(logging.NullHandler())


def load_trimesh(path: str, lean: bool = True):  # type: ignore[no-untyped-def]
    """The file as one ``trimesh.Trimesh`` in metres.

    Scenes are concatenated and COLLADA units applied. A ``.dae`` file is read
    with the lean reader of :mod:`urdftool.backends.collada` when it handles
    the file (*lean*), else with trimesh (pycollada); both give the same mesh.
    """
    import trimesh

    _quiet_trimesh_log()

    try:
        check_regular(path, "mesh")  # trimesh opens the file itself: no devices, no FIFOs
    except OSError as exc:
        raise MeshError(exc.strerror or str(exc)) from exc
    if collada_declares_entities(path):
        raise MeshError("the COLLADA file declares XML entities, which urdftool refuses to expand")
    loaded = lean_collada(path) if lean and path.lower().endswith(".dae") else None
    if loaded is None:
        try:
            loaded = mesh_files.load(path, force="mesh", process=True)
        except Exception as exc:  # trimesh raises many kinds for bad files
            loaded = collada_before_nul(path)
            if loaded is None:
                raise MeshError(f"{type(exc).__name__}: {exc}".strip().rstrip(":")) from exc
    if (
        not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0
    ) and path.lower().endswith(".dae"):
        loaded = collada_geometry_only(path)
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0:
        raise MeshError("the file holds no triangles")
    unit = collada_unit(path)
    if unit != 1.0:
        loaded.apply_scale(unit)
    return loaded


def read_facts(path: str, lean: bool = True) -> MeshFacts:
    """Read *path* with trimesh and measure it (no caching). Raises :class:`MeshError`.

    *lean* reads COLLADA files with the lean reader where it can (see :func:`load_trimesh`).
    """
    mesh = load_trimesh(path, lean)
    with quiet_numerics():
        return _measure(path, mesh)


@contextlib.contextmanager
def quiet_numerics() -> Iterator[None]:
    """Silence NumPy's floating-point RuntimeWarnings inside trimesh: a flat or empty mesh has
    zero volume and trimesh divides by it while measuring; callers handle the result, and the
    warning would only litter the user's terminal."""
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore", RuntimeWarning)
        yield


def _measure(path: str, mesh: Any) -> MeshFacts:
    watertight = bool(mesh.is_watertight)
    solid = consistently_wound(mesh) if watertight else _convex_hull(mesh)
    lo, hi = mesh.bounds
    if solid is None or not abs(float(solid.volume)) > 0:
        # Flat or empty: no solid to measure (a plane, a single triangle).
        volume, center, second = 0.0, (lo + hi) / 2.0, np.zeros((3, 3))
    else:
        volume = float(solid.volume)
        inertia = np.asarray(solid.moment_inertia, dtype=float)
        if volume < 0:  # inward-facing triangles: trimesh's integrals come out negated
            volume, inertia = -volume, -inertia
        center = np.asarray(solid.center_mass, dtype=float)
        # I = tr(C)·E − C for the second moment C, so C = tr(I)/2·E − I.
        second = np.trace(inertia) / 2.0 * np.eye(3) - inertia
    return MeshFacts(
        vertices=len(mesh.vertices),
        faces=len(mesh.faces),
        watertight=watertight,
        volume=volume,
        center_mass=_vec3(center),
        second_moment=(_vec3(second[0]), _vec3(second[1]), _vec3(second[2])),
        bounds_min=_vec3(lo),
        bounds_max=_vec3(hi),
        unit=collada_unit(path),
    )


def consistently_wound(mesh: Any) -> Any:
    """*mesh*, or a copy whose triangles all face one way when some were written reversed.

    A closed surface with some triangles reversed (CAD exports write them) encloses the same
    solid, but their signed volumes cancel in trimesh's integrals: a 0.2 m box measured 0 m³
    and was called flat, while MuJoCo reads it as the 8-litre box it is. ``fix_winding`` makes
    the triangles agree (the result may face inward; callers take the absolute volume).
    """
    if mesh.is_winding_consistent:
        return mesh
    import trimesh

    fixed = mesh.copy()
    trimesh.repair.fix_winding(fixed)
    return fixed


def _convex_hull(mesh: Any) -> Any:
    try:
        return mesh.convex_hull
    except Exception:  # qhull refuses flat or degenerate point sets
        return None


def _read_for_pool(path: str) -> tuple[str, MeshFacts | str]:
    """Worker-process entry: facts, or the error message (exceptions pickle poorly)."""
    try:
        return path, read_facts(path)
    except MeshError as exc:
        return path, str(exc)
    except Exception as exc:  # a trimesh bug on odd input must not stop the run
        return path, f"{type(exc).__name__}: {exc}"


# -- public entry points -------------------------------------------------------------


def facts_for(path: str, status: os.stat_result | None = None) -> MeshFacts:
    """The facts of the mesh at *path*, from memory, the disk cache, or by reading it;
    *status*: its ``os.stat``, when the caller has it.

    Raises :class:`MeshError`.
    """
    try:
        key = content_key(path, status)
    except OSError as exc:
        raise MeshError(exc.strerror or str(exc)) from exc
    result = _recall(key)
    if result is None:
        try:
            result = read_facts(path)
        except MeshError as exc:
            result = exc
        _remember(key, result, store=True)
    if isinstance(result, MeshError):
        raise result
    return result


def load_many(
    paths: Iterable[str], jobs: int | None = None, statuses: Mapping[str, os.stat_result | None] | None = None
) -> dict[str, MeshFacts | MeshError]:
    """Facts for every path (or its error), reading uncached files in parallel.

    *jobs* caps the worker processes (default: one per available core, at most
    8). Inside a worker process of ``check -j`` files are read in-process, since
    the run is parallel already. *statuses*: each path's ``os.stat``, when the caller has it.
    """
    out: dict[str, MeshFacts | MeshError] = {}
    todo: dict[str, list[str]] = {}  # content hash -> paths with those bytes
    statuses = statuses or {}
    for path in dict.fromkeys(paths):
        try:
            key = content_key(path, statuses.get(path))
        except OSError as exc:
            out[path] = MeshError(exc.strerror or str(exc))
            continue
        known = _recall(key)
        if known is not None:
            out[path] = known
        else:
            todo.setdefault(key, []).append(path)
    if todo:
        for key, result in _read_all(todo, jobs).items():
            _remember(key, result, store=True)
            for path in todo[key]:
                out[path] = result
    return out


def _workers(jobs: int | None, files: int) -> int:
    import multiprocessing

    if multiprocessing.parent_process() is not None:
        return 1
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        cores = os.cpu_count() or 1
    return max(1, min(jobs or cores, cores, 8, files))


def _read_all(todo: dict[str, list[str]], jobs: int | None) -> dict[str, MeshFacts | MeshError]:
    """Read one path per content hash, biggest files first so the workers finish together."""
    first = {key: paths[0] for key, paths in todo.items()}
    order = sorted(first, key=lambda k: -_size(first[k]))
    workers = _workers(jobs, len(order))
    results: dict[str, MeshFacts | MeshError] = {}
    if workers <= 1:
        for key in order:
            _, value = _read_for_pool(first[key])
            results[key] = MeshError(value) if isinstance(value, str) else value
        return results
    by_path = {first[key]: key for key in order}
    for path, value in _pool(workers).map(_read_for_pool, [first[k] for k in order], chunksize=1):
        results[by_path[path]] = MeshError(value) if isinstance(value, str) else value
    return results


_POOL: Any = None


def _pool(workers: int) -> Any:
    """One worker pool for the whole run: a check of many robots starts its workers once."""
    global _POOL
    if _POOL is None or _POOL._max_workers < workers:
        import atexit
        from concurrent.futures import ProcessPoolExecutor

        import trimesh  # noqa: F401  (imported once here, inherited by forked workers)

        if _POOL is not None:
            _POOL.shutdown()
        _POOL = ProcessPoolExecutor(max_workers=workers)
        atexit.register(_POOL.shutdown)
    return _POOL


def _size(path: str) -> int:
    try:
        return os.path.getsize(path)
    except OSError:
        return 0


def scaled_info(path: str, facts: MeshFacts, scale: Vec3 = (1.0, 1.0, 1.0)) -> MeshInfo:
    """*facts* under a URDF ``scale`` (a diagonal linear map S), exactly.

    Volume scales by |det S|, the centre by S, the second moment C by
    |det S|·S·C·S, and the unit-density inertia is tr(C)·E − C.
    """
    second, det, center = np.asarray(facts.second_moment, dtype=float), 1.0, _vec3(facts.center_mass)
    if tuple(scale) != _UNIT:  # most meshes are not scaled: x × 1.0 is x, the products are skipped
        s = np.asarray(scale, dtype=float)
        det = float(abs(np.prod(s)))
        second = det * (s[:, None] * second * s[None, :])
        center = _vec3(np.asarray(facts.center_mass) * s)
    bounds_min, bounds_max = scaled_bounds(facts, scale)
    return MeshInfo(path=path, vertices=facts.vertices, faces=facts.faces, watertight=facts.watertight,
                    volume=facts.volume * det, center_mass=center,
                    inertia_unit_density=np.trace(second) * np.eye(3) - second,
                    bounds_min=bounds_min, bounds_max=bounds_max, unit=facts.unit)


def scaled_bounds(facts: MeshFacts, scale: Vec3 = (1.0, 1.0, 1.0)) -> tuple[Vec3, Vec3]:
    """The bounds (m) of :func:`scaled_info`, alone: what a size check needs, without the inertia."""
    if tuple(scale) == _UNIT:
        ends = np.array([facts.bounds_min, facts.bounds_max], dtype=float)  # see scaled_info
    else:
        s = np.asarray(scale, dtype=float)
        ends = np.array([np.asarray(facts.bounds_min) * s, np.asarray(facts.bounds_max) * s])
    return _vec3(ends.min(axis=0)), _vec3(ends.max(axis=0))


_UNIT = (1.0, 1.0, 1.0)


def mesh_info(path: str, scale: Vec3 = (1.0, 1.0, 1.0)) -> MeshInfo:
    """Properties of the mesh at *path* scaled by *scale*. Raises :class:`MeshError`."""
    return scaled_info(path, facts_for(path), scale)


def _vec3(values: Any) -> Vec3:
    return (float(values[0]), float(values[1]), float(values[2]))
