"""Whether the rigid-body dynamics of a model mean anything, and how its base meets the world.

The dynamics pass runs on models whose links are physically possible. A
negative mass, or a tensor that is not positive definite or breaks A + B ≥ C,
belongs to no real body: mass matrices and gravity torques computed from it
are numbers without a robot behind them, and the inertia rules have already
reported the cause at the ``<inertial>``. Massless or point-mass links are not
invalid in that sense (they are what ``mass-matrix-singular`` is about).
"""

from __future__ import annotations

from urdftool.model import Joint, JointType, KinematicTree, Link, Robot
from urdftool.physics.inertia import MIN_MOMENT, assess
from urdftool.physics.mobility import decide_base
from urdftool.records import record

#: Joint types the Pinocchio backend builds (the others have no model there).
PINOCCHIO_JOINT_TYPES = frozenset({
    JointType.REVOLUTE, JointType.CONTINUOUS, JointType.PRISMATIC, JointType.FIXED,
    JointType.FLOATING, JointType.SPHERICAL, JointType.PLANAR,
})


@record
class NotCovered:
    """Why the dynamics pass does not run on a model: a sentence, and the links or joints behind it."""

    reason: str
    elements: tuple[str, ...] = ()


def invalid_inertia(link: Link) -> str | None:
    """Why *link*'s inertial belongs to no real body, or ``None`` (mass ≥ 0, tensor zero or valid)."""
    inertial = link.inertial
    if inertial is None:
        return None
    if inertial.mass < 0:
        return "negative mass"
    tensor = inertial.inertia_matrix
    if inertial.mass == 0.0 or not tensor.any():
        return None  # a massless frame or a point mass: Pinocchio takes both
    verdict = assess(tensor, abs_tol=MIN_MOMENT)
    if not verdict.positive_definite:
        return "inertia not positive definite"
    if verdict.triangle_violation is not None:
        return "inertia breaks A + B >= C"
    return None


def not_covered(robot: Robot, tree: KinematicTree) -> NotCovered | None:
    """Why the dynamics of *robot* cannot be computed meaningfully, or ``None`` when they can."""
    invalid = [(link.name, why) for link in robot.links if (why := invalid_inertia(link))]
    if invalid:
        listed = ", ".join(f"'{name}' ({why})" for name, why in invalid[:3])
        more = f" and {len(invalid) - 3} more" if len(invalid) > 3 else ""
        return NotCovered(f"physically invalid inertia on link {listed}{more}",
                          tuple(name for name, _ in invalid))
    if len(tree.roots) > 1:
        return NotCovered(f"the robot has {len(tree.roots)} roots; the dynamics need one tree",
                          tuple(tree.roots))
    cycle = mimic_cycle(robot)
    if cycle:
        return NotCovered("mimic joints follow each other in a cycle (" + " → ".join(cycle) + ")", cycle)
    unsupported = [j for j in tree.joints_in_order if j.type not in PINOCCHIO_JOINT_TYPES]
    if unsupported:
        names = ", ".join(f"'{j.name}' ({j.type.value})" for j in unsupported[:3])
        return NotCovered(f"joint {names} has no rigid-body model here", tuple(j.name for j in unsupported))
    return None


def mimic_cycle(robot: Robot) -> tuple[str, ...]:
    """The first cycle of joints mimicking each other (a joint may mimic itself), or ``()``."""
    for joint in robot.joints:
        chain = [joint.name]
        current: Joint | None = joint
        while current is not None and current.mimic is not None:
            if current.mimic.joint in chain:
                return (*chain[chain.index(current.mimic.joint):], current.mimic.joint)
            chain.append(current.mimic.joint)
            current = robot.joint(current.mimic.joint)
    return ()


def floating_base(robot: Robot, tree: KinematicTree) -> tuple[bool, str]:
    """Whether the robot moves about (free-flyer root), and why, as the MJCF export decides it.

    A root named ``world`` or a robot without wheels or legs is fixed to the
    world; wheels, legs or a ``floating`` joint at the root make it mobile.
    """
    if tree.root == "world":
        children = tree.child_joints.get("world", [])
        if any(j.type is JointType.FLOATING for j in children):
            return True, "a floating joint from 'world'"
    plan = decide_base(robot, tree, "auto")
    return plan.kind == "free", plan.reason
