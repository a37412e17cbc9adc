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
from dataclasses import field
from functools import cached_property
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
else:
    # NumPy is imported on first use: a structural check must not pay for it.
    from urdftool.lazy import numpy as np

from urdftool.backends.pinocchio import FREE_FLYER, PinocchioModel, build_model
from urdftool.facts.dynamics.configurations import Configuration, Samples, sample
from urdftool.model import Joint, JointType, KinematicTree, Robot
from urdftool.model.pose import Matrix
from urdftool.records import record

#: Random configurations sampled besides the zero configuration.
SAMPLES = 16
#: Standard gravity (m/s²), along -z of the root frame.
GRAVITY = 9.81


@record
class Conditioning:
    """The worst-conditioned mass matrix among the samples.

    ``smallest`` and ``largest`` are its extreme eigenvalues (kg·m² for
    revolute joints, kg for prismatic ones); :attr:`light_joint` is the joint
    that moves most along the eigenvector of the smallest one (the direction
    that carries almost no inertia), :attr:`heavy_joint` the same for the largest.
    """

    condition: float
    smallest: float
    largest: float
    configuration: Configuration
    #: index of the sample (0 is the zero configuration)
    sample: int
    #: the reduced mass matrix and the joint behind each of its columns
    matrix: Matrix = field(repr=False, compare=False)
    names: tuple[str, ...] = field(repr=False, compare=False)

    @cached_property
    def _vectors(self) -> Matrix:
        # Eigenvectors only when a rule reports them: on 40-DOF robots they cost
        # more than the rest of the pass.
        return np.linalg.eigh(self.matrix)[1]

    @property
    def light_joint(self) -> str:
        return self.names[int(np.argmax(np.abs(self._vectors[:, 0])))]

    @property
    def heavy_joint(self) -> str:
        return self.names[int(np.argmax(np.abs(self._vectors[:, -1])))]


@record
class GravityLoad:
    """The largest static gravity torque (N·m) or force (N) a joint holds among the samples."""

    joint: Joint
    torque: float
    configuration: Configuration
    sample: int


@record(frozen=False)
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
    #: False when the model was too large for the dense pass (:mod:`.linear`): no conditioning
    dense: bool = True


def analyse(robot: Robot, tree: KinematicTree, floating: bool, base_reason: str,
            samples: int = SAMPLES) -> DynamicsAnalysis:
    """Sample *robot* and compute its conditioning and (fixed base) gravity loads."""
    import pinocchio as pin

    pm = build_model(robot, free_flyer=floating and tree.root != "world")
    data = pm.model.createData()
    g_map, independent = pm.mimic_projection()
    names = _velocity_names(pm)
    column_names = [names[i] for i in independent]
    drawn = sample(tree, samples)
    holds = not floating and not robot.loop_closures and not _has_floating_joint(tree)
    out = DynamicsAnalysis(floating, base_reason, len(independent), len(drawn), None, gravity_computed=holds)
    if not independent:
        return out
    qs = pinocchio_configurations(pm, robot, drawn)
    masses = np.empty((len(drawn), len(independent), len(independent)))
    torques = np.zeros((len(drawn), len(independent)))
    for row, q in enumerate(qs):
        mass = pin.crba(pm.model, data, q)
        mass = np.triu(mass) + np.triu(mass, 1).T  # Pinocchio fills the upper triangle
        masses[row] = g_map.T @ mass @ g_map
        if holds:
            torques[row] = g_map.T @ pin.computeGeneralizedGravity(pm.model, data, q)
    # One batched call: per-matrix LAPACK calls cost more than the algebra on small robots.
    eigenvalues = np.linalg.eigvalsh(masses)
    with np.errstate(divide="ignore", invalid="ignore"):
        conditions = np.where(eigenvalues[:, 0] > 0, eigenvalues[:, -1] / eigenvalues[:, 0], np.inf)
    worst = int(np.argmax(conditions))
    out.conditioning = _conditioning(masses[worst], eigenvalues[worst], column_names,
                                     drawn.configuration(worst), worst)
    if holds:
        out.gravity = _largest_loads(tree, column_names, np.abs(torques), drawn)
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


def pinocchio_configurations(pm: PinocchioModel, robot: Robot, drawn: Samples) -> Matrix:
    """Pinocchio's q for every sample (rows): the free flyer at the origin, mimic joints
    following their leader."""
    import pinocchio as pin

    qs = np.tile(np.array(pin.neutral(pm.model)), (len(drawn), 1))
    columns = [c for c, joint in enumerate(drawn.joints) if joint.name in pm.joints]
    qs[:, [pm.idx_q(drawn.joints[c].name) for c in columns]] = drawn.values[:, columns]
    for row, other in enumerate(drawn.others):
        for name, value in other.items():
            joint = robot.joint(name)
            if name in pm.joints and joint is not None:
                start = pm.idx_q(name)
                coordinates = _pinocchio_coordinates(joint, value)
                qs[row, start:start + len(coordinates)] = coordinates
    mimics = [(pm.idx_q(f), pm.idx_q(leader), m, o) for f, (leader, m, o) in pm.mimics.items()
              if f in pm.joints and leader in pm.joints]
    for _ in mimics:  # one pass per mimic settles chains of joints that mimic mimics
        for follower, leader, multiplier, offset in mimics:
            qs[:, follower] = offset + multiplier * qs[:, leader]
    return qs


def _pinocchio_coordinates(joint: Joint, value: float | Sequence[float]) -> list[float]:
    if joint.type is JointType.SPHERICAL and isinstance(value, Sequence):
        w, x, y, z = value
        return [x, y, z, w]  # Pinocchio stores quaternions (x, y, z, w)
    if joint.type is JointType.PLANAR and isinstance(value, Sequence):
        x, y, theta = value
        return [x, y, float(np.cos(theta)), float(np.sin(theta))]
    return [float(value)] if not isinstance(value, Sequence) else [float(value[0])]


def _conditioning(mass: Matrix, eigenvalues: Matrix, names: list[str], pose: Configuration,
                  sample: int) -> Conditioning:
    smallest, largest = float(eigenvalues[0]), float(eigenvalues[-1])
    condition = largest / smallest if smallest > 0 else float("inf")
    return Conditioning(condition, smallest, largest, pose, sample, mass, tuple(names))


def _largest_loads(tree: KinematicTree, names: list[str], magnitudes: Matrix,
                   drawn: Samples) -> list[GravityLoad]:
    """Per one-DOF joint (in tree order), the sample where its gravity torque is largest."""
    out: list[GravityLoad] = []
    for column, name in enumerate(names):
        joint = tree.robot.joint(name)
        if joint is None or joint.dof != 1:
            continue
        row = int(np.argmax(magnitudes[:, column]))
        out.append(GravityLoad(joint, float(magnitudes[row, column]), drawn.configuration(row), row))
    return out
