"""The smoke simulation's set-up, shared by both engines: options, base, start pose, neighbours.

* The base: a robot that moves about (wheels, legs, a floating joint at the
  root; the MJCF export's rule) is dropped onto a ground plane at z = 0 from
  :data:`DROP_CLEARANCE` above its lowest collision point; any other robot is
  bolted to the world at its root, with no ground (nothing to stand on, and
  nothing for a base plate that reaches below z = 0 to collide with).
* The start pose: the robot's home configuration when it has one, else every
  joint at 0 clamped into its limits (the zero configuration of the dynamics pass).
* Neighbours: links that touch by construction are not a penetration: two
  links of one rigid body (welded by fixed joints) and two bodies joined by a
  joint.
"""

from __future__ import annotations

from dataclasses import field
from typing import Any

from urdftool.facts.dynamics.configurations import zero_configuration
from urdftool.facts.dynamics.coverage import floating_base
from urdftool.facts.simulation.options import DURATION as DURATION
from urdftool.facts.simulation.options import ENGINES as ENGINES
from urdftool.facts.simulation.options import SimOptions as SimOptions
from urdftool.model import Joint, JointType, KinematicTree, Robot
from urdftool.physics.bodies import body_of, rigid_bodies
from urdftool.records import record

#: Height (m) of the lowest collision point above the ground when a mobile robot is dropped.
DROP_CLEARANCE = 0.002
#: Natural frequency (rad/s) of the ``--hold`` PD controller at every joint: slow enough
#: for an explicit controller at either engine's default step (ω·dt ≤ 0.1).
HOLD_FREQUENCY = 25.0
#: Overlaps (m) up to this depth at the first step are contact, not penetration.
PENETRATION_TOLERANCE = 0.001
#: Standard gravity (m/s²) in both engines.
GRAVITY = 9.81


@record(frozen=False)
class Scene:
    """One robot made ready to simulate."""

    robot: Robot
    tree: KinematicTree
    floating: bool
    base_reason: str
    #: one-DOF joint -> start position (rad or m); mimic joints follow their leader
    start: dict[str, float]
    #: link pairs that touch by construction
    neighbours: set[frozenset[str]] = field(default_factory=set)
    #: the largest distance (m) between two link frames at the start, at least 0.1 m
    size: float = 0.1

    @property
    def energy_scale(self) -> float:
        """Total mass × g × size (J): the energy it takes to lift the robot by its own size."""
        return max(self.robot.total_mass, 1e-6) * GRAVITY * self.size

    @property
    def limited_joints(self) -> list[Joint]:
        """One-DOF joints with usable position limits (continuous joints have none)."""
        out = []
        for joint in self.tree.joints_in_order:
            limit = joint.limit
            if joint.type in (JointType.REVOLUTE, JointType.PRISMATIC) and limit is not None \
                    and limit.lower is not None and limit.upper is not None and limit.lower < limit.upper:
                out.append(joint)
        return out

    def touching(self, link_a: str, link_b: str) -> bool:
        return link_a == link_b or frozenset((link_a, link_b)) in self.neighbours


def prepare(robot: Robot) -> Scene:
    """The base, start pose and neighbour pairs of *robot*."""
    tree = KinematicTree.of(robot)
    floating, reason = floating_base(robot, tree)
    start = start_pose(robot, tree)
    return Scene(robot, tree, floating, reason, start, neighbour_pairs(tree), _size(tree, start))


def _size(tree: KinematicTree, start: dict[str, float]) -> float:
    """The largest distance (m) between two link frames in the start pose (at least 0.1 m)."""
    import numpy as np

    origins = np.array([pose[:3, 3] for pose in tree.forward_kinematics(dict(start)).values()])
    if len(origins) < 2:
        return 0.1
    extent = float(np.linalg.norm(origins.max(axis=0) - origins.min(axis=0)))
    return max(extent, 0.1)


def start_pose(robot: Robot, tree: KinematicTree) -> dict[str, float]:
    """Home when the robot has one (clamped into the limits), else the zero configuration."""
    start = {name: value for name, value in zero_configuration(tree).items() if isinstance(value, float)}
    for name, value in (robot.home or {}).items():
        joint = robot.joint(name)
        if name in start and joint is not None:
            low, high = _bounds(joint)
            start[name] = min(max(float(value), low), high)
    for joint in tree.joints_in_order:
        mimic = joint.mimic
        if mimic is not None and joint.dof == 1:
            start[joint.name] = mimic.offset + mimic.multiplier * start.get(mimic.joint, 0.0)
    return start


def _bounds(joint: Joint) -> tuple[float, float]:
    limit = joint.limit
    if joint.type is not JointType.CONTINUOUS and limit and limit.lower is not None \
            and limit.upper is not None and limit.lower <= limit.upper:
        return limit.lower, limit.upper
    return -float("inf"), float("inf")


def neighbour_pairs(tree: KinematicTree) -> set[frozenset[str]]:
    """Pairs of links in one rigid body, or in two bodies joined by a moving joint."""
    bodies = rigid_bodies(tree)
    owner = body_of(bodies)
    members = {body.head: [link.name for link, _ in body.links] for body in bodies}
    pairs: set[frozenset[str]] = set()
    for names in members.values():
        pairs.update(frozenset((a, b)) for a in names for b in names if a != b)
    for body in bodies:
        joint = tree.parent_joint.get(body.head)
        if joint is None or joint.parent not in owner:
            continue
        parent = members[owner[joint.parent].head]
        pairs.update(frozenset((a, b)) for a in parent for b in members[body.head])
    return pairs


class HoldController:
    """``--hold``: PD at the start pose with ``kp = Mᵢᵢ ω²`` and ``kd = 2 Mᵢᵢ ω`` (critically
    damped for the joint's own inertia), torques (N·m or N) clipped at the effort limit."""

    def __init__(self, target: Any, inertia: Any, effort: Any, omega: float = HOLD_FREQUENCY):
        self.target, self.effort = target, effort
        self.kp, self.kd = inertia * omega**2, 2.0 * inertia * omega

    @classmethod
    def at(cls, target: Any, inertia: Any, joints: list[Joint]) -> HoldController:
        """The controller for *joints* at *target* (rad or m), given the diagonal of M."""
        import numpy as np

        effort = np.array([j.limit.effort if j.limit and j.limit.effort and j.limit.effort > 0
                           else np.inf for j in joints])
        return cls(np.asarray(target, dtype=float), np.maximum(np.asarray(inertia, dtype=float), 1e-9),
                   effort)

    def torques(self, positions: Any, velocities: Any) -> Any:
        import numpy as np

        raw = self.kp * (self.target - np.asarray(positions)) - self.kd * np.asarray(velocities)
        return np.clip(raw, -self.effort, self.effort)
