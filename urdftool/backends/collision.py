"""Collision geometry of a robot in Pinocchio and coal (hpp-fcl): overlaps and distances.

A :class:`CollisionScene` places every ``<collision>`` of the robot on the
Pinocchio model of :mod:`urdftool.backends.pinocchio` and answers, for a joint
configuration, which geometry pairs touch and how deep. Shapes:

* boxes, spheres, cylinders, capsules and ellipsoids are coal's own shapes;
* a mesh is taken as its **convex hull** (what MoveIt's FCL checker and most
  simulators do with a concave mesh in practice is close to this; a hull can
  only make a collision more likely, never hide one), scaled by the URDF
  ``scale``; a mesh that cannot be read is left out and listed in
  :attr:`CollisionScene.skipped`;
* planes (SDF) carry no volume and are left out.

Hulls are kept per process by (path, scale). Pinocchio and coal are imported on
first use.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import field
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np
else:
    from urdftool.lazy import numpy as np

from urdftool.backends.meshes import MeshError, load_trimesh, quiet_numerics
from urdftool.backends.pinocchio import PinocchioModel, build_model
from urdftool.model import Box, Capsule, Cylinder, Ellipsoid, Mesh, Robot, Sphere
from urdftool.records import record


def fcl() -> Any:
    """coal, or hpp-fcl (its name before coal 3) with older Pinocchio builds."""
    try:
        import coal
    except ImportError:
        import hppfcl as coal
    return coal


#: (path, scale) -> coal convex hull (or the error reading it)
_HULLS: dict[tuple[str, tuple[float, float, float]], Any] = {}


@record
class Piece:
    """One collision geometry placed on the model: its link, and its index among the link's."""

    link: str
    index: int
    #: the Pinocchio joint (rigid body) it moves with
    body: int


@record(frozen=False)
class CollisionScene:
    """The robot's collision geometries in a Pinocchio ``GeometryModel``."""

    robot: Robot
    pin: PinocchioModel
    geometry: Any
    pieces: list[Piece] = field(default_factory=list)
    #: piece index -> (mesh path, scale) for pieces that are convex hulls of meshes
    meshes: dict[int, tuple[str, tuple[float, float, float]]] = field(default_factory=dict)
    #: (link, what) of geometries left out: unreadable meshes, planes
    skipped: list[tuple[str, str]] = field(default_factory=list)
    _data: Any = None
    _gdata: Any = None
    #: geometry pair (i, j) -> index in the GeometryModel's collision pairs
    _pairs: list[tuple[int, int]] = field(default_factory=list)

    def links(self) -> list[str]:
        """Links with at least one geometry, in model order."""
        return list(dict.fromkeys(p.link for p in self.pieces))

    def use_pairs(self, pairs: Iterable[tuple[int, int]]) -> None:
        """Check only these geometry pairs (indices into :attr:`pieces`)."""
        import pinocchio as pin

        self.geometry.removeAllCollisionPairs()
        self._pairs = []
        for i, j in pairs:
            self.geometry.addCollisionPair(pin.CollisionPair(i, j))
            self._pairs.append((i, j))
        if self._data is None:  # the kinematics' scratch space does not depend on the pairs
            self._data = self.pin.model.createData()
        self._gdata = pin.GeometryData(self.geometry)

    def neutral(self) -> Any:
        import pinocchio as pin

        return pin.neutral(self.pin.model)

    def colliding(self, q: Any) -> list[int]:
        """Indices (into the pairs of :meth:`use_pairs`) of the pairs in contact at *q*."""
        import pinocchio as pin

        pin.computeCollisions(self.pin.model, self._data, self.geometry, self._gdata, q, False)
        results = self._gdata.collisionResults
        return [k for k in range(len(self._pairs)) if results[k].isCollision()]

    def distances(self, q: Any) -> list[float]:
        """Signed distance (m) of every pair of :meth:`use_pairs` at *q*; negative: penetration."""
        import pinocchio as pin

        pin.computeDistances(self.pin.model, self._data, self.geometry, self._gdata, q)
        results = self._gdata.distanceResults  # each attribute read wraps the whole vector again
        return [float(results[k].min_distance) for k in range(len(self._pairs))]

    def placement(self, k: int) -> tuple[Any, Any]:
        """Piece *k*'s rotation (3 × 3) and position (m) in the world frame, as placed by the last
        :meth:`distances` or :meth:`colliding` call."""
        placed = self._gdata.oMg[k]
        return np.asarray(placed.rotation, dtype=float), np.asarray(placed.translation, dtype=float)

    def shape(self, k: int) -> Any:
        """Piece *k*'s coal shape (a mesh's convex hull), in the piece's own frame."""
        return self.geometry.geometryObjects[k].geometry

    def surfaces_meet(self, i: int, j: int) -> bool:
        """Whether pieces *i* and *j* still touch when meshes are their triangles, not their hulls,
        at the placements of the last :meth:`distances` or :meth:`colliding` call. A mesh wholly
        inside another shape does not count (its surface meets nothing)."""
        coal = fcl()

        shapes = [self._exact(k) for k in (i, j)]
        if any(s is None for s in shapes):
            return True
        placed = [self._gdata.oMg[k] for k in (i, j)]
        request, result = coal.CollisionRequest(), coal.CollisionResult()
        transform = getattr(coal, "Transform3s", None) or coal.Transform3f
        transforms = [transform(p.rotation, p.translation) for p in placed]
        return bool(coal.collide(shapes[0], transforms[0], shapes[1], transforms[1], request, result))

    def _exact(self, k: int) -> Any:
        if k not in self.meshes:
            return self.geometry.geometryObjects[k].geometry
        path, scale = self.meshes[k]
        return triangles(path, scale)

    @property
    def pairs(self) -> list[tuple[int, int]]:
        return list(self._pairs)


def count_geometries(robot: Robot) -> int:
    return sum(len(link.collisions) for link in robot.links)


def build_scene(robot: Robot, mesh_paths: Mapping[int, str | None]) -> CollisionScene:
    """The scene of *robot*; *mesh_paths* maps ``id(mesh)`` to the resolved file (or ``None``)."""
    import pinocchio as pin

    model = build_model(robot)
    scene = CollisionScene(robot, model, pin.GeometryModel())
    for link in robot.links:
        frame_id = model.link_frames.get(link.name)
        if frame_id is None:
            continue
        frame = model.model.frames[frame_id]
        for index, collision in enumerate(link.collisions):
            shape = _shape(collision.geometry, mesh_paths)
            if isinstance(shape, str):
                scene.skipped.append((link.name, shape))
                continue
            placement = frame.placement * _se3(collision.origin.matrix)
            if isinstance(collision.geometry, Mesh):
                scale = tuple(float(v) for v in collision.geometry.scale)
                scene.meshes[len(scene.pieces)] = (str(mesh_paths[id(collision.geometry)]),
                                                   (scale[0], scale[1], scale[2]))
            body = int(frame.parentJoint)
            scene.geometry.addGeometryObject(pin.GeometryObject(f"{link.name}#{index}", body, frame_id,
                                                                placement, shape))
            scene.pieces.append(Piece(link.name, index, int(frame.parentJoint)))
    return scene


def _se3(matrix: Any) -> Any:
    import pinocchio as pin

    m = np.asarray(matrix, dtype=float)
    return pin.SE3(m[:3, :3].copy(), m[:3, 3].copy())


def _shape(geometry: object, mesh_paths: Mapping[int, str | None]) -> Any:
    """A coal shape, or a sentence saying why there is none."""
    coal = fcl()

    if isinstance(geometry, Box):
        return coal.Box(*(float(v) for v in geometry.size))
    if isinstance(geometry, Sphere):
        return coal.Sphere(float(geometry.radius))
    if isinstance(geometry, Cylinder):
        return coal.Cylinder(float(geometry.radius), float(geometry.length))
    if isinstance(geometry, Capsule):
        return coal.Capsule(float(geometry.radius), float(geometry.length))
    if isinstance(geometry, Ellipsoid):
        return coal.Ellipsoid(*(float(v) for v in geometry.radii))
    if isinstance(geometry, Mesh):
        path = mesh_paths.get(id(geometry))
        if path is None:
            return f"mesh '{geometry.filename}' not found"
        scale = tuple(float(v) for v in geometry.scale)
        hull = convex_hull(path, (scale[0], scale[1], scale[2]))
        return hull if not isinstance(hull, MeshError) else f"mesh '{geometry.filename}': {hull}"
    return f"{type(geometry).__name__.lower()} has no volume"


def convex_hull(path: str, scale: tuple[float, float, float]) -> Any:
    """The coal convex hull of the mesh at *path*, scaled, or the :class:`MeshError`."""
    key = (path, scale)
    if key not in _HULLS:
        _HULLS[key] = _read_hull(path, scale)
    return _HULLS[key]


def _read_hull(path: str, scale: tuple[float, float, float]) -> Any:
    coal = fcl()

    try:
        with quiet_numerics():
            mesh = load_trimesh(path)
            hull = mesh.convex_hull
    except MeshError as exc:
        return exc
    except Exception as exc:  # qhull refuses flat point sets, trimesh odd files
        return MeshError(f"no convex hull: {type(exc).__name__}")
    vertices = np.asarray(hull.vertices, dtype=float) * np.asarray(scale, dtype=float)
    faces = np.asarray(hull.faces, dtype=np.int64)
    if len(faces) < 4:
        return MeshError("no convex hull: the mesh is flat")
    bvh = coal.BVHModelOBBRSS()
    bvh.beginModel(len(faces), len(vertices))
    bvh.addVertices(vertices)
    bvh.addTriangles(faces)
    bvh.endModel()
    try:
        bvh.buildConvexRepresentation(False)
    except RuntimeError as exc:  # coal caps a hull vertex's neighbours ("Too many neighbors")
        return MeshError(f"no convex hull: coal refused it ({str(exc).strip().splitlines()[-1]})")
    return bvh.convex


#: (path, scale) -> coal triangle mesh (or ``None`` when unreadable)
_TRIANGLES: dict[tuple[str, tuple[float, float, float]], Any] = {}


def triangles(path: str, scale: tuple[float, float, float]) -> Any:
    """The mesh at *path* as a coal triangle mesh (BVH), scaled; ``None`` when unreadable."""
    coal = fcl()

    key = (path, scale)
    if key not in _TRIANGLES:
        try:
            mesh = load_trimesh(path)
        except MeshError:
            _TRIANGLES[key] = None
            return None
        bvh = coal.BVHModelOBBRSS()
        vertices = np.asarray(mesh.vertices, dtype=float) * np.asarray(scale, dtype=float)
        bvh.beginModel(len(mesh.faces), len(vertices))
        bvh.addVertices(vertices)
        bvh.addTriangles(np.asarray(mesh.faces, dtype=np.int64))
        bvh.endModel()
        _TRIANGLES[key] = bvh
    return _TRIANGLES[key]


def sample_counts(scene: CollisionScene, configurations: Iterable[Any], groups: list[int],
                  progress: Callable[[int], None] | None = None) -> tuple[list[int], int]:
    """In how many of *configurations* each group of pairs is in contact (pair ``k`` of
    :meth:`CollisionScene.use_pairs` belongs to group ``groups[k]``; a group counts once per
    configuration), and how many configurations were checked."""
    counts = [0] * (max(groups) + 1 if groups else 0)
    done = 0
    for q in configurations:
        for g in {groups[k] for k in scene.colliding(q)}:
            counts[g] += 1
        done += 1
        if progress is not None:
            progress(1)
    return counts, done
