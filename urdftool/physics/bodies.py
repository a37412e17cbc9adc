"""Rigid bodies: links welded together by fixed joints, as simulators merge them.

Gazebo lumps links joined by fixed joints into one body, MuJoCo's URDF import
fuses them (``fusestatic``), Pinocchio and Drake weld them. What a simulator can
or cannot integrate is therefore decided per *rigid body*, not per link: a
massless link fixed to a heavy one is carried by it, a massless link on a
moving joint has nothing to carry it.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from functools import cached_property

from urdftool.model import KinematicTree, Link, Robot
from urdftool.model.pose import IDENTITY, Pose, Vec3, unrotated
from urdftool.physics import vec3
from urdftool.physics.vec3 import Tensor3
from urdftool.records import record

#: MuJoCo's ``mjMINVAL`` (kg, kg·m²): its compiler refuses a moving body whose mass is below it,
#: and takes 1e-15 kg itself (measured with MuJoCo 4.0; PX4's Typhoon sonar weighs exactly that).
#: The mass rules count a mass below it as zero; the fitting rules leave masses at it out too.
MIN_VALUE = 1e-15


@record
class RigidBody:
    """Links welded by fixed joints.

    ``head`` is the link whose parent joint moves (or the root); ``links`` holds
    the head first, then the welded links below it, each with its pose in the
    head's frame.
    """

    head: str
    links: tuple[tuple[Link, Pose], ...]
    #: name of the moving joint above the head, ``None`` for the root body
    joint: str | None

    @property
    def moves(self) -> bool:
        return self.joint is not None

    @cached_property
    def mass(self) -> float:
        """Total mass (kg) of the links that declare one (missing ``<inertial>`` counts 0)."""
        return float(sum(link.inertial.mass for link, _ in self.links if link.inertial))

    @cached_property
    def declared_inertia(self) -> Tensor3:
        """:meth:`composite_inertia` as declared, computed once: several rules weigh one body."""
        return self.composite_inertia()

    def composite_trace(self, replaced: Mapping[str, float] | None = None) -> float:
        """The trace (kg·m²) of :meth:`composite_inertia`, with the traces of *replaced* links'
        tensors (link name -> trace, kg·m²) instead of their declared ones.

        A trace does not depend on the frame a tensor is written in, so each link's own trace
        is summed as written, and the parallel-axis theorem adds 2·m·|d|² for a link whose centre
        of mass is d from the body's: no tensor is rotated or shifted.
        """
        masses = self._mass_points
        total = sum(m for _, m, _, _ in masses)
        if total <= 0:
            return 0.0
        x = sum(m * c[0] for _, m, c, _ in masses) / total
        y = sum(m * c[1] for _, m, c, _ in masses) / total
        z = sum(m * c[2] for _, m, c, _ in masses) / total
        trace = 0.0
        for name, m, c, own in masses:
            if replaced is not None and name in replaced:
                own = replaced[name]
            dx, dy, dz = c[0] - x, c[1] - y, c[2] - z
            trace += own + 2.0 * m * (dx * dx + dy * dy + dz * dz)
        return trace

    @cached_property
    def _mass_points(self) -> list[tuple[str, float, Vec3, float]]:
        """(link name, mass in kg, centre of mass in the head frame, trace of its tensor) of each
        link with a positive mass."""
        return [
            (link.name, inertial.mass, _moved(inertial.origin.xyz, pose), vec3.trace(inertial.inertia))
            for link, pose in self.links
            if (inertial := link.inertial) is not None and inertial.mass > 0
        ]

    def composite_inertia(self, replaced: Mapping[str, Tensor3] | None = None) -> Tensor3:
        """Inertia (kg·m²) of the welded links about their common centre of mass, head frame.

        *replaced* maps link names to a tensor (kg·m², about the link's centre of
        mass, link frame) used instead of the declared one: what the body would
        be with that link's inertia repaired. Computed in floats (:mod:`urdftool.physics.vec3`):
        only the rules weigh a body's inertia.
        """
        parts: list[tuple[float, Vec3, Tensor3]] = []
        for link, pose in self.links:
            if link.inertial is None or link.inertial.mass <= 0:
                continue
            com = _moved(link.inertial.origin.xyz, pose)
            own = (replaced or {}).get(link.name)
            if own is None:
                own = vec3.rotate_tensor(link.inertial.inertia, link.inertial.origin.rpy)
            parts.append((link.inertial.mass, com, vec3.rotate_tensor(own, pose.rpy)))
        total = sum(m for m, _, _ in parts)
        if total <= 0:
            return vec3.ZERO_TENSOR
        center = (
            sum(m * c[0] for m, c, _ in parts) / total,
            sum(m * c[1] for m, c, _ in parts) / total,
            sum(m * c[2] for m, c, _ in parts) / total,
        )
        inertia = vec3.ZERO_TENSOR
        for m, c, t in parts:
            inertia = vec3.added(inertia, vec3.shift_to_point(t, m, vec3.sub(c, center)))
        return inertia


def _moved(point: Vec3, pose: Pose) -> Vec3:
    """*point* (m, link frame) in the head's frame."""
    if unrotated(pose.rpy):
        return vec3.add(point, pose.xyz)
    return vec3.add(vec3.apply(vec3.rotation(pose.rpy), point), pose.xyz)


#: Composes a parent pose with a child's (:meth:`Pose.compose`, or :func:`urdftool.physics.vec3.compose`).
Compose = Callable[[Pose, Pose], Pose]


def rigid_bodies(tree: KinematicTree, compose: Compose = Pose.compose) -> list[RigidBody]:
    """Every rigid body of the tree, heads in depth-first order from the roots.

    *compose* places each welded link in its head's frame: NumPy's products by default (what
    the exporters write), :func:`urdftool.physics.vec3.compose` for a check's rules.
    """
    links = {link.name: link for link in tree.robot.links}
    bodies: list[RigidBody] = []
    for _, link, joint in tree.walk():
        if joint is not None and not joint.type.is_moving:
            continue
        members = _welded(tree, links, link, compose)
        bodies.append(RigidBody(link.name, members, joint.name if joint is not None else None))
    return bodies


def _welded(
    tree: KinematicTree, links: dict[str, Link], head: Link, compose: Compose
) -> tuple[tuple[Link, Pose], ...]:
    """*head* and the links welded below it by fixed joints, with poses in head's frame."""
    out: list[tuple[Link, Pose]] = []
    stack: list[tuple[Link, Pose]] = [(head, IDENTITY)]
    while stack:  # the tree view has no cycles, so this ends
        link, pose = stack.pop()
        out.append((link, pose))
        for joint in reversed(tree.child_joints.get(link.name, [])):
            child = links.get(joint.child)
            if child is not None and not joint.type.is_moving:
                stack.append((child, compose(pose, joint.origin)))
    return tuple(out)


def body_of(bodies: list[RigidBody]) -> dict[str, RigidBody]:
    """Link name -> the rigid body it belongs to."""
    return {link.name: body for body in bodies for link, _ in body.links}


@record
class MassRole:
    """Why a link needs mass, and how bad it is when it has none.

    ``severity`` is ``"error"`` when nothing carries the link (it heads a
    moving body without mass), ``"warning"`` when it collides but is welded to
    a body with mass.
    """

    why: str
    severity: str
    joint: str | None
    carrier: str | None
    carrier_mass: float | None


def mass_role(link: Link, body: RigidBody | None) -> MassRole | None:
    """Whether the massless *link* needs mass, given the rigid *body* it belongs to.

    ``None`` when it is fine without: a link of a massless root body (the
    world, a footprint, a static object in PyBullet's convention), or a link
    without collision geometry welded to a body that has mass.
    """
    if body is None:
        return None
    collides = any(c.geometry is not None for c in link.collisions)
    if body.moves and body.mass < MIN_VALUE and (link.name == body.head or collides):
        return MassRole(
            f"moves with joint '{body.joint}' and nothing welded to it has mass",
            "error",
            body.joint,
            None,
            None,
        )
    if collides and body.mass >= MIN_VALUE:
        carrier = heaviest(body)
        return MassRole(
            f"has collision geometry; it is welded to '{carrier}' ({body.mass:.3g} kg in all), "
            "which carries it without its weight",
            "warning",
            body.joint,
            carrier,
            body.mass,
        )
    return None


def heaviest(body: RigidBody) -> str:
    """Name of the heaviest link of *body* (the one that carries the others)."""
    return max(body.links, key=lambda item: item[0].inertial.mass if item[0].inertial else 0.0)[
        0
    ].name


def kinematics_only(robot: Robot) -> bool:
    """True for a kinematic model: it has a moving joint and no link carries an ``<inertial>``.

    MoveIt, RViz and IK packages (ROS-Industrial support packages, many
    ``*_description`` packages) ship such models on purpose; urdfdom, yourdfpy
    and Pinocchio accept them. They cannot be simulated as they are.
    """
    return any(joint.type.is_moving for joint in robot.joints) and all(
        link.inertial is None for link in robot.links
    )
