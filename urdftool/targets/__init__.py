"""What each consumer of a URDF does with it: one small table per target (``check --target``).

A *target* is a program that reads URDF files directly: a simulator's own
URDF importer (MuJoCo, PyBullet, Gazebo, gz-sim, Drake, Isaac), a dynamics
library (Pinocchio, KDL) or a planner (MoveIt). Each reads the same file in
its own way: it fills in masses that are missing, fuses links joined by fixed
joints, replaces a concave collision mesh by its convex hull, ignores
``<mimic>``, welds joint types it does not know. The rules of family ``T``
(:mod:`urdftool.rules.targets`) read these tables and say, for the targets a
check was asked about, what each will do with this file.

Every entry names the engine version it was verified on. For MuJoCo, PyBullet,
Pinocchio and Drake the table is re-checked against the installed engine by
``tests/test_targets_engines.py`` and ``tests/test_targets_drake.py`` (each
fixture of ``fixtures/targets/`` is loaded and the predicted mass, body count
or hull is measured); the other entries come from the consumer's
documentation and source at the version named, and docs/targets/<name>.md
says where.

Nothing here imports anything: the tables are data.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import field

from urdftool.records import record

__all__ = [
    "TARGETS",
    "Target",
    "UnknownTarget",
    "parse_targets",
]


@record
class Target:
    """What one consumer does with a URDF file.

    Each field holds the consumer's behaviour in one area, ``None`` where it
    reads the file as URDF means it (nothing to report):

    ``missing_inertial``
        A moving link without ``<inertial>``: ``"one-kg"`` (PyBullet: mass
        1 kg, inertia diag(1, 1, 1)), ``"density"`` (the mass of its collision
        geometry at 1000 kg/m³: MuJoCo, Isaac), ``"zero"`` (kept massless:
        Pinocchio, KDL), ``"dropped"`` (the link and its subtree are left out:
        Gazebo's URDF-to-SDF conversion).
    ``massless_stops``
        A massless link is kept with zero mass and inertia, and a simulation
        stops where that leaves the mass matrix singular (Drake: "mass matrix
        ... is not positive-definite").
    ``floating_root``
        The root link becomes a free body unless it is welded to the world
        (Drake), so it moves like any other link.
    ``fixed_joints``
        ``"fused"`` (the child becomes part of its parent's body: MuJoCo),
        ``"lumped"`` (Gazebo: the child's inertia and shapes move into the
        parent and the link disappears), ``"frames"`` (Pinocchio: the child
        becomes an operational frame, its inertia added to the parent).
    ``hulls_collision_meshes``
        The consumer collides with the convex hull of each collision mesh
        (``"file"``: one hull per file, ``"object"``: one hull per object of an
        OBJ file), so a concave shape (a tray, a bowl, a gripper's palm)
        becomes solid.
    ``mimic``
        ``"ignored"`` (the follower is an independent joint),
        ``"needs-plugin"`` (Gazebo classic: a mimic plugin is needed),
        ``"needs-option"`` (honoured only when asked for), ``"discrete-only"``
        (Drake: a coupler constraint that only a discrete plant with the SAP
        solver honours), or ``None``.
    ``joint_types``
        joint type -> what becomes of it (``"fixed"``: welded, ``"free"``: the
        joint is dropped and its child becomes a free body, or a phrase).
    ``collision_formats``
        Mesh file extensions the consumer reads for collision (``None``: all
        the common ones).
    ``unread_format_fails``
        A collision mesh in another format stops the whole load (Drake's
        parser raises) instead of being dropped.
    ``face_budget``
        Triangles per collision mesh above which collision checking gets slow
        for this consumer (its per-step or per-query cost).
    ``hull_vertex_limit``
        The consumer cooks hulls with at most this many vertices.
    ``root_inertia_ignored``
        The root link's inertia is dropped (KDL).
    ``inertia_from_collision``
        The file's inertia tensor is replaced by one computed from the
        collision shapes' bounding boxes unless the loader is told otherwise
        (PyBullet without ``URDF_USE_INERTIA_FROM_FILE``).
    ``needs_srdf``
        The consumer needs a semantic description (MoveIt).
    ``relative_mesh``
        What becomes of a bare relative mesh path (``meshes/link1.stl``, no
        ``package://`` or ``file://``): ``None`` when the consumer resolves it
        against the URDF file's folder (MuJoCo, PyBullet, Drake: tested),
        otherwise a phrase saying why it does not find the file.
    """

    name: str
    label: str
    verified: str
    engine_tested: bool = False
    missing_inertial: str | None = None
    massless_stops: bool = False
    floating_root: bool = False
    fixed_joints: str | None = None
    hulls_collision_meshes: str | None = None
    mimic: str | None = None
    joint_types: Mapping[str, str] = field(default_factory=dict)
    collision_formats: frozenset[str] | None = None
    unread_format_fails: bool = False
    face_budget: int | None = None
    hull_vertex_limit: int | None = None
    root_inertia_ignored: bool = False
    inertia_from_collision: bool = False
    needs_srdf: bool = False
    relative_mesh: str | None = None
    #: how to keep the consumer from fusing fixed joints, when it can be told
    keep_fixed: str | None = None


_COMMON_MESHES = frozenset({".stl", ".obj", ".dae"})

TARGETS: dict[str, Target] = {
    t.name: t
    for t in (
        Target(
            name="mujoco",
            label="MuJoCo",
            verified="MuJoCo 4.0.0 (URDF import)",
            engine_tested=True,
            missing_inertial="density",
            fixed_joints="fused",
            hulls_collision_meshes="file",
            collision_formats=frozenset({".stl", ".obj", ".msh"}),
            face_budget=200_000,
            keep_fixed='<mujoco><compiler fusestatic="false"/></mujoco> inside <robot>',
        ),
        Target(
            name="pybullet",
            label="PyBullet",
            verified="PyBullet 3.2.7 (loadURDF)",
            engine_tested=True,
            missing_inertial="one-kg",
            hulls_collision_meshes="object",
            mimic="ignored",
            joint_types={"floating": "fixed", "spherical": "fixed"},
            collision_formats=frozenset({".stl", ".obj", ".dae"}),
            face_budget=50_000,
            inertia_from_collision=True,
        ),
        Target(
            name="gazebo",
            label="Gazebo classic",
            verified="Gazebo 11 with SDFormat 9 (URDF-to-SDF conversion)",
            missing_inertial="dropped",
            fixed_joints="lumped",
            mimic="needs-plugin",
            collision_formats=_COMMON_MESHES,
            face_budget=20_000,
            keep_fixed="<gazebo reference=\"JOINT\"><preserveFixedJoint>true</preserveFixedJoint></gazebo>",
            relative_mesh="spawned from robot_description (gazebo_ros spawn_entity), the URDF is a string "
            "with no folder, and Gazebo looks the path up on its resource paths and working directory",
        ),
        Target(
            name="gz-sim",
            label="gz-sim",
            verified="gz-sim 8 (Harmonic) with SDFormat 14 (URDF-to-SDF conversion)",
            missing_inertial="dropped",
            fixed_joints="lumped",
            collision_formats=_COMMON_MESHES,
            face_budget=20_000,
            keep_fixed="<gazebo reference=\"JOINT\"><preserveFixedJoint>true</preserveFixedJoint></gazebo>",
            relative_mesh="spawned from robot_description (ros_gz_sim create -topic), the URDF is a string "
            "with no folder to resolve it against (SDFormat resolves it only for a URDF read from a file)",
        ),
        Target(
            name="drake",
            label="Drake",
            verified="Drake 1.51.1 (multibody::Parser, URDF, into a MultibodyPlant with a SceneGraph)",
            engine_tested=True,
            missing_inertial="zero",
            massless_stops=True,
            floating_root=True,
            hulls_collision_meshes="file",
            mimic="discrete-only",
            joint_types={"floating": "free"},
            collision_formats=frozenset({".obj", ".vtk", ".gltf"}),
            unread_format_fails=True,
            face_budget=20_000,
        ),
        Target(
            name="pinocchio",
            label="Pinocchio",
            verified="Pinocchio 4.1.0 (buildModelFromUrdf)",
            engine_tested=True,
            missing_inertial="zero",
            fixed_joints="frames",
            mimic="needs-option",
            joint_types={"continuous": "two configuration variables (cos θ, sin θ) and one velocity"},
            relative_mesh="buildGeomFromUrdf looks a relative path up in package_dirs only, not beside "
            "the URDF ('Mesh meshes/link1.stl could not be found' unless that folder is one of them)",
        ),
        Target(
            name="kdl",
            label="KDL",
            verified="kdl_parser 2.x (ROS 2 Humble/Jazzy)",
            missing_inertial="zero",
            mimic="ignored",
            joint_types={"floating": "fixed", "planar": "fixed", "spherical": "fixed"},
            root_inertia_ignored=True,
        ),
        Target(
            name="isaac",
            label="Isaac Sim",
            verified="Isaac Sim 4.5 URDF importer (PhysX 5)",
            missing_inertial="density",
            hulls_collision_meshes="file",
            collision_formats=_COMMON_MESHES,
            face_budget=20_000,
            hull_vertex_limit=64,
        ),
        Target(
            name="moveit",
            label="MoveIt",
            verified="MoveIt 2 (Humble/Jazzy) with FCL collision checking",
            collision_formats=_COMMON_MESHES,
            face_budget=5_000,
            needs_srdf=True,
            relative_mesh="geometric_shapes loads meshes through resource_retriever, which takes "
            "package:// and file:// URLs only: RViz shows no mesh, and a collision mesh leaves the link "
            "without that collision shape",
        ),
    )
}


class UnknownTarget(ValueError):
    """A ``--target`` name that is not in :data:`TARGETS`."""


def parse_targets(values: Iterable[str]) -> tuple[Target, ...]:
    """Targets from ``--target`` values (comma-separated, repeatable; ``all`` for every one)."""
    names = [part.strip().lower() for value in values for part in value.split(",") if part.strip()]
    if "all" in names:
        return tuple(TARGETS.values())
    unknown = [n for n in names if n not in TARGETS]
    if unknown:
        known = ", ".join(TARGETS)
        raise UnknownTarget(f"unknown target {', '.join(map(repr, unknown))} (known: {known}, all)")
    return tuple(TARGETS[n] for n in dict.fromkeys(names))
