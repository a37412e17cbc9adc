"""The typed robot model that every rule and exporter reads.

Frozen dataclasses with the field names of URDF (``link.inertial.mass``,
``joint.limit.effort``). Units: metres, radians, kilograms, kg·m², newtons,
newton-metres, seconds. Every node keeps the :class:`~urdftool.source.Span`
where it was written; spans take no part in equality.
"""

from __future__ import annotations

import enum
import functools
from collections.abc import Mapping
from dataclasses import field
from typing import TYPE_CHECKING, Any

from urdftool.model.geometry import Geometry
from urdftool.model.pose import IDENTITY, Matrix, Pose, Vec3, rotate_tensor
from urdftool.records import record
from urdftool.source import Span

if TYPE_CHECKING:
    from urdftool.diagnostics import Diagnostic

Inertia3 = tuple[Vec3, Vec3, Vec3]


class JointType(str, enum.Enum):
    """Joint types: URDF's six, plus the extensions that real files use."""

    REVOLUTE = "revolute"
    CONTINUOUS = "continuous"
    PRISMATIC = "prismatic"
    FIXED = "fixed"
    FLOATING = "floating"
    PLANAR = "planar"
    #: Three rotational DOF about a point (SDF ``ball``; PyBullet's URDF ``spherical``).
    SPHERICAL = "spherical"
    #: SDF only.
    UNIVERSAL = "universal"
    REVOLUTE2 = "revolute2"
    SCREW = "screw"
    GEARBOX = "gearbox"

    @property
    def dof(self) -> int:
        return _DOF[self]

    @property
    def is_moving(self) -> bool:
        return self is not JointType.FIXED


_DOF = {
    JointType.REVOLUTE: 1,
    JointType.CONTINUOUS: 1,
    JointType.PRISMATIC: 1,
    JointType.FIXED: 0,
    JointType.FLOATING: 6,
    JointType.PLANAR: 3,
    JointType.SPHERICAL: 3,
    JointType.UNIVERSAL: 2,
    JointType.REVOLUTE2: 2,
    JointType.SCREW: 1,
    JointType.GEARBOX: 1,
}


@record
class Inertial:
    """Mass (kg) and rotational inertia (kg·m²) about the centre of mass.

    ``origin`` places the inertial frame in the link frame: its ``xyz`` is the
    centre of mass and its ``rpy`` the orientation in which ``inertia`` is written.
    """

    mass: float
    inertia: Inertia3
    origin: Pose = IDENTITY
    span: Span | None = field(default=None, compare=False)
    mass_span: Span | None = field(default=None, compare=False)
    inertia_span: Span | None = field(default=None, compare=False)

    @property
    def inertia_matrix(self) -> Matrix:
        """The 3×3 tensor as written, in the inertial frame."""
        import numpy as np

        return np.array(self.inertia, dtype=float)

    @property
    def inertia_in_link_frame(self) -> Matrix:
        """The tensor about the centre of mass, rotated into the link frame."""
        return rotate_tensor(self.inertia_matrix, self.origin.rpy)

    @staticmethod
    def tensor(ixx: float, ixy: float, ixz: float, iyy: float, iyz: float, izz: float) -> Inertia3:
        return ((ixx, ixy, ixz), (ixy, iyy, iyz), (ixz, iyz, izz))


@record
class Material:
    """A named colour (RGBA in 0..1) and/or texture file."""

    name: str | None
    color: tuple[float, float, float, float] | None = None
    texture: str | None = None
    span: Span | None = field(default=None, compare=False)


@record
class Visual:
    geometry: Geometry | None
    origin: Pose = IDENTITY
    name: str | None = None
    material: Material | None = None
    span: Span | None = field(default=None, compare=False)


@record
class Collision:
    geometry: Geometry | None
    origin: Pose = IDENTITY
    name: str | None = None
    span: Span | None = field(default=None, compare=False)


@record
class Limit:
    """Joint limits: position in rad or m, ``effort`` in N·m or N, ``velocity`` in rad/s or m/s.

    ``None`` marks an attribute that was not written.
    """

    lower: float | None = None
    upper: float | None = None
    effort: float | None = None
    velocity: float | None = None
    span: Span | None = field(default=None, compare=False)
    #: where ``lower`` and ``upper`` were written (the attribute in URDF, the element in SDF)
    lower_span: Span | None = field(default=None, compare=False)
    upper_span: Span | None = field(default=None, compare=False)


@record
class Dynamics:
    """Viscous ``damping`` (N·m·s/rad or N·s/m) and Coulomb ``friction`` (N·m or N), and a joint
    spring (SDF ``<spring_stiffness>`` in N·m/rad or N/m, pulling towards ``spring_reference``
    in rad or m; URDF has no spring, so a URDF joint's is 0)."""

    damping: float = 0.0
    friction: float = 0.0
    span: Span | None = field(default=None, compare=False)
    spring_stiffness: float = 0.0
    spring_reference: float = 0.0


@record
class Mimic:
    """This joint follows ``joint``: ``q_self = multiplier * q_joint + offset``."""

    joint: str
    multiplier: float = 1.0
    offset: float = 0.0
    span: Span | None = field(default=None, compare=False)


@record
class SafetyController:
    k_velocity: float
    k_position: float = 0.0
    soft_lower_limit: float = 0.0
    soft_upper_limit: float = 0.0
    span: Span | None = field(default=None, compare=False)


@record
class Calibration:
    rising: float | None = None
    falling: float | None = None
    span: Span | None = field(default=None, compare=False)


@record
class Link:
    name: str
    inertial: Inertial | None = None
    visuals: tuple[Visual, ...] = ()
    collisions: tuple[Collision, ...] = ()
    span: Span | None = field(default=None, compare=False)
    #: child elements kept as written: SDF-isms (``<pose>``), PyBullet ``<contact>``
    extensions: tuple[Extension, ...] = field(default=(), compare=False)


@record
class Joint:
    """A joint: the child link's frame is ``origin`` in the parent link's frame at q = 0.

    ``axis`` is a unit-or-not vector in the joint frame as written (default x).
    """

    name: str
    type: JointType
    parent: str
    child: str
    origin: Pose = IDENTITY
    axis: Vec3 = (1.0, 0.0, 0.0)
    limit: Limit | None = None
    dynamics: Dynamics | None = None
    mimic: Mimic | None = None
    safety_controller: SafetyController | None = None
    calibration: Calibration | None = None
    span: Span | None = field(default=None, compare=False)
    axis_span: Span | None = field(default=None, compare=False)
    #: universal and revolute2 joints: the second axis (in the joint frame at q = 0; it turns
    #: with the first) and its limit
    axis2: Vec3 | None = None
    limit2: Limit | None = None
    #: child elements kept as written (namespaced or SDF-only elements)
    extensions: tuple[Extension, ...] = field(default=(), compare=False)

    @property
    def dof(self) -> int:
        return self.type.dof


@record
class Extension:
    """An element kept as written for rules and exporters: ``<gazebo>``,
    ``<transmission>``, ``<ros2_control>`` or anything unknown at the top level.

    ``element`` is the lxml element (its descendants carry source positions,
    read them with :func:`urdftool.parse.locate.span_of`).
    """

    tag: str
    attributes: Mapping[str, str]
    element: Any = field(compare=False, repr=False)
    span: Span | None = field(default=None, compare=False)


@record
class LoopClosure:
    """A joint cut from a closed chain to make the rest a tree (SDF).

    ``parent_anchor`` and ``child_anchor`` are the joint frame in each body's frame.
    """

    joint: Joint
    parent_anchor: Pose
    child_anchor: Pose


@record
class Robot:
    """A robot as read from one file.

    ``diagnostics`` are the problems found while reading it (syntax, numbers,
    unknown elements); rules add the rest.
    """

    name: str | None
    links: tuple[Link, ...] = ()
    joints: tuple[Joint, ...] = ()
    materials: tuple[Material, ...] = ()
    extensions: tuple[Extension, ...] = ()
    loop_closures: tuple[LoopClosure, ...] = ()
    path: str = ""
    format: str = "urdf"
    span: Span | None = field(default=None, compare=False)
    diagnostics: tuple[Diagnostic, ...] = field(default=(), compare=False)
    #: Joint name -> value (rad or m) of a named home configuration, when known.
    home: Mapping[str, float] | None = field(default=None, compare=False)
    #: Root link -> its pose in the model frame, for formats where a model may hold several
    #: roots: SDF's free bodies (links no joint holds), which simulators give a free joint each.
    root_poses: Mapping[str, Pose] | None = field(default=None, compare=False)
    #: The ``<plugin>`` elements of the SDF world, kept on the world's first model: systems such
    #: as gz-sim's Sensors belong to the world, and a rule reads them once per world.
    world_plugins: tuple[Any, ...] = field(default=(), compare=False, repr=False)
    #: The ``<world>`` element (lxml) the model is in, on every model of an SDF world, for rules
    #: that ask what the world loads (which gz-sim systems run); ``None`` for a model read alone.
    world: Any = field(default=None, compare=False, repr=False)
    #: Where an SDF model is marked ``<static>true</static>`` (its ``<static>``, else the model: an
    #: include made it static); ``None`` for a model that moves.
    static_span: Span | None = field(default=None, compare=False)

    def link(self, name: str) -> Link | None:
        """The first link of that name (as urdfdom keeps the first of a duplicate), in O(1)."""
        return self._links_by_name.get(name)

    def joint(self, name: str) -> Joint | None:
        """The first joint of that name, in O(1)."""
        return self._joints_by_name.get(name)

    # Lookups by name are asked once per joint by many rules: an index built on first use keeps
    # them constant-time on models of thousands of links (the robot is frozen, so it never goes stale).
    @functools.cached_property
    def _links_by_name(self) -> dict[str, Link]:
        index: dict[str, Link] = {}
        for link in self.links:
            index.setdefault(link.name, link)
        return index

    @functools.cached_property
    def _joints_by_name(self) -> dict[str, Joint]:
        index: dict[str, Joint] = {}
        for joint in self.joints:
            index.setdefault(joint.name, joint)
        return index

    @property
    def total_mass(self) -> float:
        """Sum of link masses (kg); links without ``<inertial>`` count as 0."""
        return float(sum(link.inertial.mass for link in self.links if link.inertial))

    def extensions_named(self, tag: str) -> tuple[Extension, ...]:
        return tuple(ext for ext in self.extensions if ext.tag == tag)
