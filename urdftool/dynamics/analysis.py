"""Mass matrix conditioning and static gravity torques, computed with Pinocchio.

The model comes from :func:`urdftool.backends.pinocchio.build_model` (the same
one the MJCF export is verified against), with a free-flyer root for robots
that move about. At the zero configuration and :data:`SAMPLES` seeded random
configurations within the joint limits it computes:

* the joint-space mass matrix M(q) (composite rigid-body algorithm), reduced to
  the independent joints when some joints mimic others (``Gᵀ M G``), its
  eigenvalues and 2-norm condition number; the worst sample is kept;
* for a robot fixed to the world, the generalized gravity vector g(q): the
  torque (N·m) or force (N) each joint must exert to hold the pose at rest,
  with gravity 9.81 m/s² along -z of the root frame. For a joint that others
  mimic, its motor holds them too (``Gᵀ g``).

Loop closures (SDF) are not joints of the tree: the mass matrix is the
spanning tree's, and gravity torques of a fixed robot with loops are not
computed (the closing joint carries part of the load, which the tree does not
know). Units: kg, kg·m² (and kg·m for the coupling terms of a free flyer).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from urdftool.backends.pinocchio import FREE_FLYER, PinocchioModel, build_model
from urdftool.dynamics.configurations import Configuration, configurations
from urdftool.model import Joint, JointType, KinematicTree, Robot
from urdftool.model.pose import Matrix

#: Random configurations sampled besides the zero configuration.
SAMPLES = 16
#: Standard gravity (m/s²), along -z of the root frame.
GRAVITY = 9.81


@dataclass(frozen=True)
class Conditioning:
    """The worst-conditioned mass matrix among the samples.

    ``smallest`` and ``largest`` are its extreme eigenvalues (kg·m² for
    revolute joints, kg for prismatic ones); ``light_joint`` is the joint that
    moves most along the eigenvector of the smallest one (the direction that
    carries almost no inertia), ``heavy_joint`` the same for the largest.
    """

    condition: float
    smallest: float
    largest: float
    light_joint: str
    heavy_joint: str
    configuration: Configuration
    #: index of the sample (0 is the zero configuration)
    sample: int


@dataclass(frozen=True)
class GravityLoad:
    """The largest static gravity torque (N·m) or force (N) a joint holds among the samples."""

    joint: Joint
    torque: float
    configuration: Configuration
    sample: int


@dataclass
class DynamicsAnalysis:
    """What the dynamics pass found on one robot."""

    floating: bool
    base_reason: str
    dof: int
    samples: int
    conditioning: Conditioning | None
    #: one entry per one-DOF independent joint, for fixed-base robots without loops
    gravity: list[GravityLoad] = field(default_factory=list)
    gravity_computed: bool = False


def analyse(robot: Robot, tree: KinematicTree, floating: bool, base_reason: str,
            samples: int = SAMPLES) -> DynamicsAnalysis:
    """Sample *robot* and compute its conditioning and (fixed base) gravity loads."""
    import pinocchio as pin

    pm = build_model(robot, free_flyer=floating and tree.root != "world")
    data = pm.model.createData()
    g_map, independent = pm.mimic_projection()
    names = _velocity_names(pm)
    column_names = [names[i] for i in independent]
    poses = configurations(tree, samples)
    holds = not floating and not robot.loop_closures and not _has_floating_joint(tree)
    out = DynamicsAnalysis(floating, base_reason, len(independent), len(poses), None, gravity_computed=holds)
    if not independent:
        return out
    worst: Conditioning | None = None
    loads: dict[str, GravityLoad] = {}
    for index, pose in enumerate(poses):
        q = pinocchio_configuration(pm, robot, pose)
        mass = pin.crba(pm.model, data, q)
        mass = np.triu(mass) + np.triu(mass, 1).T  # Pinocchio fills the upper triangle
        reduced = g_map.T @ mass @ g_map
        current = _conditioning(reduced, column_names, pose, index)
        if worst is None or current.condition > worst.condition:
            worst = current
        if holds:
            torques = g_map.T @ pin.computeGeneralizedGravity(pm.model, data, q)
            _keep_largest(loads, tree, column_names, torques, pose, index)
    out.conditioning = worst
    out.gravity = [loads[j.name] for j in tree.joints_in_order if j.name in loads]
    return out


def _has_floating_joint(tree: KinematicTree) -> bool:
    return any(j.type is JointType.FLOATING for j in tree.joints_in_order)


def _velocity_names(pm: PinocchioModel) -> list[str]:
    """The source joint name behind each velocity index (the free flyer is the base)."""
    names = [""] * int(pm.model.nv)
    for name, jid in pm.joints.items():
        joint = pm.model.joints[jid]
        label = "the floating base" if name == FREE_FLYER else name
        for k in range(int(joint.nv)):
            names[int(joint.idx_v) + k] = label
    return names


def pinocchio_configuration(pm: PinocchioModel, robot: Robot, pose: Configuration) -> Matrix:
    """Pinocchio's q for *pose*: the free flyer at the origin, mimic joints following their leader."""
    import pinocchio as pin

    q = np.array(pin.neutral(pm.model))
    for name, value in pose.items():
        if name not in pm.joints:
            continue
        start = pm.idx_q(name)
        joint = robot.joint(name)
        assert joint is not None
        q[start:start + _nq(joint)] = _pinocchio_coordinates(joint, value)
    for follower, (leader, multiplier, offset) in pm.mimics.items():
        if follower in pm.joints and leader in pm.joints:
            q[pm.idx_q(follower)] = offset + multiplier * q[pm.idx_q(leader)]
    return q


def _nq(joint: Joint) -> int:
    return {JointType.SPHERICAL: 4, JointType.PLANAR: 4}.get(joint.type, 1)


def _pinocchio_coordinates(joint: Joint, value: float | Sequence[float]) -> list[float]:
    if joint.type is JointType.SPHERICAL and isinstance(value, Sequence):
        w, x, y, z = value
        return [x, y, z, w]  # Pinocchio stores quaternions (x, y, z, w)
    if joint.type is JointType.PLANAR and isinstance(value, Sequence):
        x, y, theta = value
        return [x, y, float(np.cos(theta)), float(np.sin(theta))]
    return [float(value)] if not isinstance(value, Sequence) else [float(value[0])]


def _conditioning(mass: Matrix, names: list[str], pose: Configuration, sample: int) -> Conditioning:
    eigenvalues, vectors = np.linalg.eigh(mass)
    smallest, largest = float(eigenvalues[0]), float(eigenvalues[-1])
    condition = largest / smallest if smallest > 0 else float("inf")
    return Conditioning(condition, smallest, largest, names[int(np.argmax(np.abs(vectors[:, 0])))],
                        names[int(np.argmax(np.abs(vectors[:, -1])))], pose, sample)


def _keep_largest(loads: dict[str, GravityLoad], tree: KinematicTree, names: list[str], torques: Any,
                  pose: Configuration, sample: int) -> None:
    """Record, per one-DOF joint, the sample where its gravity torque is largest."""
    seen: set[str] = set()
    for name, torque in zip(names, np.asarray(torques, dtype=float)):
        joint = tree.robot.joint(name)
        if joint is None or joint.dof != 1 or name in seen:
            continue
        seen.add(name)
        magnitude = abs(float(torque))
        if name not in loads or magnitude > loads[name].torque:
            loads[name] = GravityLoad(joint, magnitude, pose, sample)
