"""``--verify`` for PyBullet: load OUT headless and compare what PyBullet built with the source.

Compared, per link: mass (kg), principal moments (kg·m²), centre of mass (m)
and the whole tensor in the link frame (which checks the inertial frame's
orientation even where PyBullet re-diagonalised it); per joint: type, unit
axis and limits; and the world pose of every URDF link frame (m, rad) at the
zero configuration and at random ones, against urdftool's forward kinematics.
Expected inertia is what the export wrote (the source's, or repaired with
``--repair-inertia``). Any warning PyBullet prints while loading fails.

PyBullet places bodies at their centre of mass; link frames are read back
explicitly (see :mod:`urdftool.backends.pybullet`).
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Mapping
from dataclasses import field
from pathlib import Path

import numpy as np

from urdftool.backends.pybullet import EngineJoint, EngineLink, PyBulletLoad
from urdftool.catalogue.conversion import EngineRejected
from urdftool.diagnostics import Diagnostic
from urdftool.export import ExportOptions, VerifyResult
from urdftool.export.pybullet import plan_export
from urdftool.export.pybullet_fuse import frame_matrices, read_fused_frames
from urdftool.export.pybullet_inertia import plan_inertia
from urdftool.model import Inertial, Joint, JointType, KinematicTree, Link, Robot
from urdftool.model.pose import Matrix
from urdftool.model.tree import mimic_value
from urdftool.physics.inertia import principal_moments
from urdftool.records import record
from urdftool.source import Span

#: PyBullet computes in floating point after its own diagonalisation: 1e-6 (relative for inertia).
TOLERANCE = 1e-6
#: Random joint configurations compared besides the zero configuration.
CONFIGURATIONS = 8
EXPECTED_TYPES = {
    JointType.REVOLUTE: "revolute",
    JointType.CONTINUOUS: "revolute",
    JointType.PRISMATIC: "prismatic",
    JointType.FIXED: "fixed",
    JointType.SPHERICAL: "spherical",
    JointType.PLANAR: "planar",
}


@record(frozen=False)
class Worst:
    """The largest error of one quantity and where in the source it occurred."""

    quantity: str
    tolerance: float = TOLERANCE
    error: float = 0.0
    element: str | None = None
    span: Span | None = None

    def see(self, error: float, element: str, span: Span | None) -> None:
        if not error <= self.error:  # NaN counts as worst
            self.error, self.element, self.span = error, element, span

    @property
    def passed(self) -> bool:
        return self.error <= self.tolerance


@record(frozen=False)
class Comparison:
    robot: Robot
    rows: list[Worst] = field(default_factory=list)

    def row(self, quantity: str, tolerance: float = TOLERANCE) -> Worst:
        worst = Worst(quantity, tolerance)
        self.rows.append(worst)
        return worst


def verify_pybullet(
    robot: Robot, out: Path, options: ExportOptions | None = None, unfused: Robot | None = None
) -> VerifyResult:
    """Load *out* in PyBullet with ``URDF_USE_INERTIA_FROM_FILE`` and compare it with *robot*.

    With fixed joints fused, *robot* is the fused robot (inertia and joints are compared with
    it) and *unfused* the robot before fusing: every one of its link frames is compared, the
    fused ones placed by the poses listed in *out*'s comment.
    """
    options = options or ExportOptions()
    tree = KinematicTree.of(robot)
    frames = frame_matrices(read_fused_frames(Path(out).read_text(encoding="utf-8", errors="replace")))
    expected = plan_inertia(robot, tree, options.repair_inertia, options.floating_base).inertials
    with PyBulletLoad(str(out)) as loaded:
        diagnostics = [_engine_message(robot, message) for message in loaded.messages]
        if loaded.body is None:
            diagnostics.append(
                EngineRejected.diagnostic(
                    f"PyBullet refused {out.name}: {loaded.error}", robot.span, element="robot"
                )
            )
            return VerifyResult(False, [], diagnostics)
        comparison = Comparison(robot)
        compare_inertia(comparison, expected, loaded.links())
        compare_joints(comparison, loaded.joints(), loaded.links())
        compare_poses(comparison, KinematicTree.of(unfused) if unfused else tree, loaded, frames)
    rows = [(w.quantity, w.error, w.tolerance, w.passed) for w in comparison.rows]
    for worst in comparison.rows:
        if not worst.passed:
            diagnostics.append(
                EngineRejected.diagnostic(
                    f"{worst.element}: {worst.quantity} differs in PyBullet by {worst.error:.3g} "
                    f"(tolerance {worst.tolerance:g})",
                    worst.span,
                    element=worst.element,
                    data={
                        "quantity": worst.quantity,
                        "error": worst.error,
                        "tolerance": worst.tolerance,
                    },
                )
            )
    return VerifyResult(not diagnostics, rows, diagnostics)


def _engine_message(robot: Robot, message: str) -> Diagnostic:
    """A PyBullet warning, located at the link or joint it names (else the robot)."""
    items: tuple[Link | Joint, ...] = (*robot.links, *robot.joints)
    for item in items:
        if re.search(rf"(?<![\w-]){re.escape(item.name)}(?![\w-])", message):
            kind = "link" if item in robot.links else "joint"
            return EngineRejected.diagnostic(
                f"PyBullet: {message}",
                item.span,
                element=f"{kind}[{item.name}]",
                data={"engine": "pybullet", "message": message},
            )
    return EngineRejected.diagnostic(
        f"PyBullet: {message}",
        robot.span,
        element="robot",
        data={"engine": "pybullet", "message": message},
    )


def compare_inertia(
    comparison: Comparison, expected: Mapping[str, Inertial], engine: Iterable[EngineLink]
) -> None:
    """Mass, principal moments, centre of mass and link-frame tensor of every link."""
    mass = comparison.row("link mass (relative)")
    moments = comparison.row("principal moments (relative to trace)")
    com = comparison.row("centre of mass in link frame (m)")
    tensor = comparison.row("inertia in link frame (relative to trace)")
    found = {link.name: link for link in engine}
    for link in comparison.robot.links:
        where, span = f"link[{link.name}]", link.span
        built = found.get(link.name)
        if built is None:
            mass.see(math.inf, where, span)
            continue
        source = expected[link.name]
        # relative to the source's numbers; absolute (kg, kg·m²) where the source has none, where
        # a ratio would print the rounding of a zero as 1e+12
        mass.see(abs(built.mass - source.mass) / (max(abs(source.mass), 1e-12) if source.mass else 1.0),
                 where, span)
        source_tensor = source.inertia_in_link_frame
        trace = float(np.trace(source_tensor))
        scale = max(trace, 1e-12) if trace > 0 else 1.0
        source_moments, _ = principal_moments(source_tensor)
        built_moments = np.sort(np.asarray(built.inertia_diagonal))
        moments.see(float(np.max(np.abs(built_moments - source_moments))) / scale, where, span)
        com.see(
            float(np.linalg.norm(built.inertial_frame[:3, 3] - np.asarray(source.origin.xyz))),
            where,
            span,
        )
        rotation = built.inertial_frame[:3, :3]
        built_tensor = rotation @ np.diag(built.inertia_diagonal) @ rotation.T
        tensor.see(float(np.max(np.abs(built_tensor - source_tensor))) / scale, where, span)


def compare_joints(
    comparison: Comparison, engine: Iterable[EngineJoint], links: Iterable[EngineLink]
) -> None:
    """Type, unit axis and limits of every joint (limits that the source writes)."""
    frames = {link.name: link.inertial_frame for link in links}
    types = comparison.row("joint types (mismatches)", 0.0)
    axes = comparison.row("joint axes (unit vectors)")
    limits = comparison.row("joint limits (rad, m, N·m, N, rad/s, m/s)")
    found = {joint.name: joint for joint in engine}
    for joint in comparison.robot.joints:
        where, span = f"joint[{joint.name}]", joint.span
        built = found.get(joint.name)
        if built is None or built.type != EXPECTED_TYPES.get(joint.type):
            types.see(types.error + 1, where, span)
            continue
        if built.dof == 1:
            # PyBullet keeps the axis in the child's inertial frame; bring it to the link frame.
            axis = (
                frames[joint.child][:3, :3] @ np.asarray(built.axis)
                if joint.child in frames
                else np.zeros(3)
            )
            axes.see(float(np.max(np.abs(axis - _unit(joint)))), where, span)
        limits.see(_limit_error(joint, built), where, span)


def _unit(joint: Joint) -> Matrix:
    axis = np.asarray(joint.axis, dtype=float)
    unit: Matrix = axis / np.linalg.norm(axis)
    return unit


def _limit_error(joint: Joint, built: EngineJoint) -> float:
    limit = joint.limit
    if limit is None or joint.type not in (
        JointType.REVOLUTE,
        JointType.PRISMATIC,
        JointType.CONTINUOUS,
    ):
        return 0.0
    pairs = [(limit.effort, built.effort), (limit.velocity, built.velocity)]
    # Without both bounds PyBullet leaves a joint unlimited (urdfdom reads 0, 0): nothing to compare.
    if (
        joint.type is not JointType.CONTINUOUS
        and limit.lower is not None
        and limit.upper is not None
    ):
        pairs += [(limit.lower, built.lower), (limit.upper, built.upper)]
    return max((abs(a - b) for a, b in pairs if a is not None), default=0.0)


def compare_poses(
    comparison: Comparison,
    tree: KinematicTree,
    loaded: PyBulletLoad,
    fused: Mapping[str, tuple[str, Matrix]] | None = None,
) -> None:
    """World pose of every link frame, relative to the base, at zero and random configurations;
    a *fused* frame (name -> link it was fused into, its pose there) is placed from that link."""
    position = comparison.row("link world position (m)")
    orientation = comparison.row("link world orientation (rad)")
    index = {joint.name: joint.index for joint in loaded.joints()}
    spans = {link.name: link.span for link in tree.robot.links}
    for q in configurations(tree):
        source = tree.forward_kinematics(q)
        engine_q = {
            index[name]: value for name, value in _with_mimics(tree, q).items() if name in index
        }
        built = loaded.link_frames(engine_q)
        for name, (into, pose) in (fused or {}).items():
            if into in built and name not in built:
                built[name] = built[into] @ pose
        root = tree.root
        if root is None or root not in built:
            return
        base = np.linalg.inv(built[root])
        for name, pose in source.items():
            where = f"link[{name}]"
            if name not in built:
                position.see(math.inf, where, spans.get(name))
                continue
            relative = base @ built[name]
            position.see(
                float(np.linalg.norm(relative[:3, 3] - pose[:3, 3])), where, spans.get(name)
            )
            orientation.see(_angle(pose[:3, :3].T @ relative[:3, :3]), where, spans.get(name))


def _angle(rotation: Matrix) -> float:
    """The rotation angle (rad) of a 3×3 rotation matrix."""
    cosine = (float(np.trace(rotation)) - 1.0) / 2.0
    sine = (
        float(
            np.linalg.norm(
                [
                    rotation[2, 1] - rotation[1, 2],
                    rotation[0, 2] - rotation[2, 0],
                    rotation[1, 0] - rotation[0, 1],
                ]
            )
        )
        / 2.0
    )
    return math.atan2(sine, cosine)


def configurations(tree: KinematicTree, count: int = CONFIGURATIONS) -> list[dict[str, float]]:
    """The zero configuration, then *count* random ones within the limits (seeded: reproducible).

    Continuous and unlimited revolute joints range over ±π, unlimited prismatic ones ±0.5 m;
    mimic joints are left to follow their target.
    """
    rng = np.random.default_rng(0)
    movable = [j for j in tree.joints_in_order if j.dof == 1 and j.mimic is None]
    out: list[dict[str, float]] = [{}]
    for _ in range(count):
        out.append({joint.name: float(rng.uniform(*_range(joint))) for joint in movable})
    return out


def _range(joint: Joint) -> tuple[float, float]:
    limit = joint.limit
    if (
        joint.type is not JointType.CONTINUOUS
        and limit is not None
        and limit.lower is not None
        and limit.upper is not None
        and limit.lower < limit.upper
    ):
        return limit.lower, limit.upper
    return (-0.5, 0.5) if joint.type is JointType.PRISMATIC else (-math.pi, math.pi)


def _with_mimics(tree: KinematicTree, q: Mapping[str, float]) -> dict[str, float]:
    """*q* with every 1-DOF mimic joint set to what it follows (PyBullet does not enforce ``<mimic>``)."""
    values = dict(q)
    for joint in tree.joints_in_order:
        if joint.mimic is not None and joint.dof == 1:
            values[joint.name] = mimic_value(joint, q, tree.robot)
    return values


def verify(robot: Robot, out: Path, options: ExportOptions) -> VerifyResult:
    """Load *out* in PyBullet (DIRECT) and compare it with the robot the export wrote
    (*robot*, re-rooted and fused as :func:`~urdftool.export.pybullet.plan_export` plans it)."""
    plan = plan_export(robot, options)
    unfused = plan.unfused if plan.fusion.frames else None
    return verify_pybullet(plan.robot, Path(out), options, unfused)
