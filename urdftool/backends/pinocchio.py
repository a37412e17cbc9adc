"""Pinocchio models built from urdftool's typed robot (not from a file).

Because the model comes from :class:`~urdftool.model.Robot`, it works the same
for URDF, xacro and SDF input. Conventions, chosen to match the robot's own
coordinates one to one:

* revolute and continuous joints are ``RevoluteUnaligned`` (one angle, rad;
  continuous joints are not the cos/sin ``RevoluteUnbounded``), prismatic
  joints ``PrismaticUnaligned`` (m), spherical joints ``Spherical``
  (quaternion x, y, z, w), floating joints and the optional free flyer
  ``FreeFlyer`` (x, y, z, then quaternion x, y, z, w);
* planar joints are ``Planar`` (x, y, cos θ, sin θ) in a frame whose z is the
  URDF axis and whose x, y are the in-plane directions e1, e2 of
  :func:`urdftool.model.pose.planar_directions`;
* fixed joints add no joint: the child link becomes a ``BODY`` frame on the
  parent's joint and its inertia is added to that joint's body;
* mimic joints are kept as joints of their own (as MuJoCo carries them, tied by
  an equality): :attr:`PinocchioModel.mimics` lists them, and
  :meth:`PinocchioModel.mimic_projection` gives the map from the independent
  velocities to all of them, for dynamics in reduced coordinates;
* every link is a ``BODY`` frame named after it, placed at the link frame.

Units: m, rad, kg, kg·m²; frames as in URDF.
"""

from __future__ import annotations

from dataclasses import field
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np
else:
    # NumPy is imported on first use: a structural check must not pay for it.
    from urdftool.lazy import numpy as np

from urdftool.model import Inertial, Joint, JointType, KinematicTree, Robot
from urdftool.model.pose import Matrix, planar_directions
from urdftool.records import record

#: Name of the free-flyer joint added with ``free_flyer=True``.
FREE_FLYER = "root_joint"


@record(frozen=False)
class PinocchioModel:
    """A ``pinocchio.Model`` with the names that tie it back to the robot."""

    model: Any
    #: link name -> BODY frame id
    link_frames: dict[str, int] = field(default_factory=dict)
    #: source joint name (or :data:`FREE_FLYER`) -> Pinocchio joint id
    joints: dict[str, int] = field(default_factory=dict)
    #: follower joint -> (leader joint, multiplier, offset): follower = offset + multiplier · leader
    mimics: dict[str, tuple[str, float, float]] = field(default_factory=dict)
    free_flyer: bool = False

    def idx_q(self, joint: str) -> int:
        return int(self.model.joints[self.joints[joint]].idx_q)

    def idx_v(self, joint: str) -> int:
        return int(self.model.joints[self.joints[joint]].idx_v)

    def mimic_projection(self) -> tuple[Matrix, list[int]]:
        """``(G, independent)``: ``v = G @ v[independent]`` for velocities that respect every
        mimic relation (``G`` is nv × len(independent)).

        Chains of mimics compose their multipliers; a follower whose chain loops back
        on itself (a mimic cycle, reported by ``mimic-cycle``) is kept independent.
        """
        nv = int(self.model.nv)
        ultimate = {name: self._ultimate_leader(name) for name in self.mimics if name in self.joints}
        followers = {self.idx_v(name) for name, lead in ultimate.items() if lead is not None}
        independent = [i for i in range(nv) if i not in followers]
        column = {v: c for c, v in enumerate(independent)}
        g = np.zeros((nv, len(independent)))
        for v, c in column.items():
            g[v, c] = 1.0
        for name, lead in ultimate.items():
            if lead is not None:
                leader, gain = lead
                g[self.idx_v(name), column[self.idx_v(leader)]] += gain
        return g, independent

    def _ultimate_leader(self, follower: str) -> tuple[str, float] | None:
        """The independent joint at the end of *follower*'s mimic chain and the product of the
        multipliers along it; ``None`` for a cycle or a leader missing from the model."""
        gain = 1.0
        seen = {follower}
        current = follower
        while current in self.mimics:
            leader, multiplier, _ = self.mimics[current]
            if leader in seen or leader not in self.joints:
                return None
            seen.add(leader)
            gain *= multiplier
            current = leader
        return current, gain


def _se3(transform: Matrix) -> Any:
    import pinocchio as pin

    return pin.SE3(np.array(transform[:3, :3]), np.array(transform[:3, 3]))


def _unit(axis: tuple[float, float, float]) -> np.ndarray:
    a = np.asarray(axis, dtype=float)
    n = float(np.linalg.norm(a))
    return a / n if n > 0 else np.array([1.0, 0.0, 0.0])


def _planar_frame(axis: tuple[float, float, float]) -> Matrix:

    unit = _unit(axis)
    e1, e2 = planar_directions((float(unit[0]), float(unit[1]), float(unit[2])))
    out = np.eye(4)
    out[:3, :3] = np.column_stack([e1, e2, unit])
    return out


def _joint_model(joint: Joint) -> tuple[Any, Matrix]:
    """The Pinocchio joint model and the rotation (4×4) from the URDF joint frame to its frame."""
    import pinocchio as pin

    kind = joint.type
    if kind in (JointType.REVOLUTE, JointType.CONTINUOUS):
        return pin.JointModelRevoluteUnaligned(_unit(joint.axis)), np.eye(4)
    if kind is JointType.PRISMATIC:
        return pin.JointModelPrismaticUnaligned(_unit(joint.axis)), np.eye(4)
    if kind is JointType.FLOATING:
        return pin.JointModelFreeFlyer(), np.eye(4)
    if kind is JointType.SPHERICAL:
        return pin.JointModelSpherical(), np.eye(4)
    if kind is JointType.PLANAR:
        return pin.JointModelPlanar(), _planar_frame(joint.axis)
    raise ValueError(f"joint '{joint.name}': {kind.value} joints have no Pinocchio model here")


def _inertia(inertial: Inertial | None) -> Any:
    import pinocchio as pin

    if inertial is None:
        return pin.Inertia.Zero()
    return pin.Inertia(float(inertial.mass), np.array(inertial.origin.xyz, dtype=float),
                       np.array(inertial.inertia_in_link_frame))


def build_model(robot: Robot, free_flyer: bool = False,
                inertials: dict[str, Inertial | None] | None = None) -> PinocchioModel:
    """A Pinocchio model of *robot*'s kinematic tree (loop closures are not joints).

    *free_flyer* adds a free-flyer joint above the root link. *inertials*
    overrides links' inertials (e.g. after a repair); by default each link's own.
    A root link named ``world`` is the universe itself.
    """
    import pinocchio as pin

    tree = KinematicTree.of(robot)
    model = pin.Model()
    model.name = robot.name or "robot"
    out = PinocchioModel(model, free_flyer=free_flyer)
    own = {link.name: link.inertial for link in robot.links}
    if inertials is not None:
        own.update(inertials)
    #: link -> (joint id carrying it, link frame in that joint's frame)
    placed: dict[str, tuple[int, Matrix]] = {}
    for depth, link, joint in tree.walk():
        if depth == 0:
            jid = 0
            if free_flyer and link.name != "world":
                jid = model.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), FREE_FLYER)
                out.joints[FREE_FLYER] = jid
            placed[link.name] = (jid, np.eye(4))
            _attach(out, link.name, jid, np.eye(4), 0, own.get(link.name))
            continue
        assert joint is not None
        parent_jid, parent_frame = placed[joint.parent]
        at_joint = parent_frame @ joint.origin.matrix
        parent_frame_id = out.link_frames[joint.parent]
        if joint.type is JointType.FIXED:
            placed[link.name] = (parent_jid, at_joint)
            _attach(out, link.name, parent_jid, at_joint, parent_frame_id, own.get(link.name))
            continue
        joint_model, rotation = _joint_model(joint)
        jid = model.addJoint(parent_jid, joint_model, _se3(at_joint @ rotation), joint.name)
        out.joints[joint.name] = jid
        if joint.mimic is not None:
            out.mimics[joint.name] = (joint.mimic.joint, joint.mimic.multiplier, joint.mimic.offset)
        link_in_joint = np.linalg.inv(rotation)
        placed[link.name] = (jid, link_in_joint)
        _attach(out, link.name, jid, link_in_joint, parent_frame_id, own.get(link.name))
    return out


def _attach(out: PinocchioModel, link: str, jid: int, placement: Matrix, previous: int,
            inertial: Inertial | None) -> None:
    model = out.model
    if inertial is not None and inertial.mass != 0.0:
        model.appendBodyToJoint(jid, _inertia(inertial), _se3(placement))
    out.link_frames[link] = model.addBodyFrame(link, jid, _se3(placement), previous)
