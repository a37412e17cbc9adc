"""Static gravity torques in linear time and memory, for models too large for the dense pass.

Pinocchio's ``Data`` grows about as DOF³ in memory (68 MB at 100 joints, 1.7 GB
at 300, measured), and the mass-matrix pass factorises dense DOF×DOF matrices.
Above :data:`DENSE_DOF` moving joints the dynamics pass therefore computes
only what needs no dense matrix: the static gravity load of every joint of a
fixed-base robot, from one bottom-up sweep per configuration. For the joint
whose child link is ``c``, with the links below it (its subtree ``S``) of mass
``m_k`` and world centre of mass ``p_k``, the torque (N·m) a revolute joint
holds is ``|a · Σ_k (p_k − o) × (m_k g)|`` and the force (N) a prismatic joint
holds is ``|a · Σ_k m_k g|``, with ``a`` the joint axis and ``o`` its origin in
the world frame and ``g`` = 9.81 m/s² along −z of the root frame. The
subtree sums ``Σ m_k`` and ``Σ m_k p_k`` accumulate from the leaves up, so a
configuration costs O(links). Mass-matrix conditioning is not computed
(``dynamics-not-checked`` says so).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
else:
    from urdftool.lazy import numpy as np

from urdftool.facts.dynamics.analysis import GRAVITY, DynamicsAnalysis, GravityLoad
from urdftool.facts.dynamics.configurations import sample
from urdftool.model import JointType, KinematicTree, Robot

#: Moving joints from which the dense Pinocchio pass is replaced by this one, by default (the
#: ``dynamics-dof`` budget, :mod:`urdftool.budgets`, changes it).
DENSE_DOF = 120


def moving_dof(tree: KinematicTree) -> int:
    return sum(joint.dof for joint in tree.joints_in_order if joint.type is not JointType.FIXED)


def gravity_loads(robot: Robot, tree: KinematicTree, floating: bool, base_reason: str,
                  samples: int) -> DynamicsAnalysis:
    """The largest static gravity load of each one-DOF joint over the zero and *samples* configurations."""
    dof = moving_dof(tree)
    holds = not floating and not robot.loop_closures and all(
        j.type is not JointType.FLOATING for j in tree.joints_in_order)
    out = DynamicsAnalysis(floating, base_reason, dof, 0, None, gravity_computed=holds, dense=False)
    if not holds:
        return out
    drawn = sample(tree, samples)
    out.samples = len(drawn)
    one_dof = [j for j in tree.joints_in_order
               if j.type in (JointType.REVOLUTE, JointType.CONTINUOUS, JointType.PRISMATIC)]
    leaders = {j.name: j for j in one_dof if j.mimic is None}
    best: dict[str, tuple[float, int]] = {}
    masses = {link.name: (link.inertial.mass if link.inertial else 0.0) for link in robot.links}
    links = {link.name: link for link in robot.links}
    weight = np.array([0.0, 0.0, -GRAVITY])
    for row in range(len(drawn)):
        poses = tree.forward_kinematics(drawn.configuration(row))
        mass_below: dict[str, float] = {}
        moment_below: dict[str, np.ndarray] = {}
        for name in reversed(tree.order):  # leaves first
            link = links.get(name)
            pose = poses.get(name)
            m = masses.get(name, 0.0)
            com = np.zeros(3)
            if link is not None and link.inertial is not None and pose is not None:
                com = pose[:3, :3] @ np.asarray(link.inertial.origin.xyz, dtype=float) + pose[:3, 3]
            total, moment = m, m * com
            for joint in tree.child_joints.get(name, []):
                total += mass_below.get(joint.child, 0.0)
                moment = moment + moment_below.get(joint.child, np.zeros(3))
            mass_below[name], moment_below[name] = total, moment
        torques: dict[str, float] = {}
        for joint in one_dof:
            frame = poses.get(joint.child)
            if frame is None:
                continue
            axis = frame[:3, :3] @ np.asarray(joint.axis, dtype=float)
            below, moment = mass_below.get(joint.child, 0.0), moment_below.get(joint.child, np.zeros(3))
            if joint.type is JointType.PRISMATIC:
                load = float(axis @ (below * weight))
            else:
                load = float(axis @ np.cross(moment - below * frame[:3, 3], weight))
            leader = joint
            if joint.mimic is not None and joint.mimic.joint in leaders:
                leader, load = leaders[joint.mimic.joint], load * joint.mimic.multiplier
            torques[leader.name] = torques.get(leader.name, 0.0) + load
        for name, load in torques.items():
            if abs(load) > best.get(name, (-1.0, 0))[0]:
                best[name] = (abs(load), row)
    rows = {row: drawn.configuration(row) for row in {row for _, row in best.values()}}  # each built once
    out.gravity = [GravityLoad(leaders[name], value, rows[row], row)
                   for name, (value, row) in best.items() if name in leaders]
    return out
