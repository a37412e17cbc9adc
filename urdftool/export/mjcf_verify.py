"""The proof of equivalence: MuJoCo's compiled model against Pinocchio built from the source.

At ``CONFIGURATIONS`` random configurations within the joint limits (seeded,
so reruns agree) it compares the world pose of every link's body (m, rad),
the total mass (kg) and the joint-space mass matrix. The two engines order
and parameterise joints differently, so the map is explicit: MuJoCo joints are
found by name; quaternions are (w, x, y, z) in MuJoCo and (x, y, z, w) in
Pinocchio; a MuJoCo free joint's linear velocity is in the world frame and
Pinocchio's in the body frame, as are a planar joint's in-plane velocities, so
the mass matrices are compared as ``M_pin = Tᵀ M_mj T`` with ``v_mj = T v_pin``.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from urdftool.backends.mujoco import (
    EngineError,
    compile_model,
    name_to_id,
    positions_and_mass_matrix,
    total_mass,
)
from urdftool.backends.pinocchio import FREE_FLYER, build_model
from urdftool.catalogue.conversion import EngineRejected
from urdftool.diagnostics import Diagnostic
from urdftool.export import ExportOptions, VerifyResult
from urdftool.export.mjcf import plan_inertia
from urdftool.model import Collision, Joint, JointType, KinematicTree, Mesh, Robot, Visual
from urdftool.model.pose import Matrix, matrix_to_quaternion, quaternion_to_matrix
from urdftool.model.tree import mimic_value
from urdftool.physics.mobility import decide_base
from urdftool.records import record

CONFIGURATIONS = 20
#: Pose tolerance (m and rad) and relative tolerance for mass and mass matrix.
TOLERANCE = 1e-9
#: Range (m) sampled for prismatic joints without limits and free-joint positions.
UNLIMITED_TRANSLATION = 1.0


@record
class JointMap:
    """One source joint: where it lives in MuJoCo (qpos/dof addresses) and in Pinocchio."""

    joint: Joint | None  # None for the added free flyer
    kind: str  # "one", "free", "ball", "planar"
    mj_qpos: tuple[int, ...]
    mj_dof: tuple[int, ...]
    pin_q: int
    pin_v: int
    #: joint placement in its parent (4×4) for free joints written as URDF floating joints
    origin: Matrix


def _random_quaternion(rng: np.random.Generator) -> np.ndarray:
    q = rng.normal(size=4)
    unit: np.ndarray = q / np.linalg.norm(q)
    return unit  # (w, x, y, z)


def _bounds(joint: Joint) -> tuple[float, float]:
    limit = joint.limit
    if joint.type is JointType.REVOLUTE and limit and limit.lower is not None and limit.upper is not None \
            and limit.lower < limit.upper:
        return (limit.lower, limit.upper)
    if joint.type is JointType.PRISMATIC:
        if limit and limit.lower is not None and limit.upper is not None and limit.lower < limit.upper:
            return (limit.lower, limit.upper)
        return (-UNLIMITED_TRANSLATION, UNLIMITED_TRANSLATION)
    return (-math.pi, math.pi)


def build_maps(
    robot: Robot, tree: KinematicTree, mj: Any, pin: Any, free_joint: str | None
) -> list[JointMap]:
    """The joint map; raises ``KeyError`` naming a joint MuJoCo does not have."""

    def addresses(name: str) -> tuple[int, int]:
        jid = name_to_id(mj, "joint", name)
        if jid < 0:
            raise KeyError(name)
        return int(mj.jnt_qposadr[jid]), int(mj.jnt_dofadr[jid])

    maps: list[JointMap] = []
    if free_joint is not None:
        q, v = addresses(free_joint)
        maps.append(JointMap(None, "free", tuple(range(q, q + 7)), tuple(range(v, v + 6)),
                             pin.idx_q(FREE_FLYER), pin.idx_v(FREE_FLYER), np.eye(4)))
    for joint in tree.joints_in_order:
        if not joint.type.is_moving:
            continue
        if joint.type is JointType.PLANAR:
            parts = [addresses(f"{joint.name}_{s}") for s in ("x", "y", "rot")]
            maps.append(JointMap(joint, "planar", tuple(p[0] for p in parts), tuple(p[1] for p in parts),
                                 pin.idx_q(joint.name), pin.idx_v(joint.name), np.eye(4)))
            continue
        q, v = addresses(joint.name)
        kind = {JointType.FLOATING: "free", JointType.SPHERICAL: "ball"}.get(joint.type, "one")
        nq, nv = {"free": (7, 6), "ball": (4, 3), "one": (1, 1)}[kind]
        maps.append(JointMap(joint, kind, tuple(range(q, q + nq)), tuple(range(v, v + nv)),
                             pin.idx_q(joint.name), pin.idx_v(joint.name), joint.origin.matrix))
    return maps


def _sample(maps: list[JointMap], robot: Robot, rng: np.random.Generator) -> dict[int, Any]:
    """A random value per map entry (index -> float or array), mimic followers following."""
    values: dict[int, Any] = {}
    for i, m in enumerate(maps):
        if m.kind in ("free", "ball"):
            pos = rng.uniform(-UNLIMITED_TRANSLATION, UNLIMITED_TRANSLATION, 3)
            values[i] = (pos, _random_quaternion(rng))
        elif m.kind == "planar":
            values[i] = rng.uniform([-1.0, -1.0, -math.pi], [1.0, 1.0, math.pi])
        else:
            assert m.joint is not None
            values[i] = float(rng.uniform(*_bounds(m.joint)))
    by_name = {m.joint.name: float(values[i]) for i, m in enumerate(maps)
               if m.joint is not None and m.kind == "one"}
    for i, m in enumerate(maps):
        if m.joint is not None and m.joint.mimic is not None and m.kind == "one":
            values[i] = mimic_value(m.joint, by_name, robot)
    return values


def _configure(maps: list[JointMap], values: dict[int, Any], nq_mj: int, nq_pin: int, nv_mj: int,
               nv_pin: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """MuJoCo qpos, Pinocchio q, and T with v_mj = T v_pin."""
    qmj = np.zeros(nq_mj)
    qpin = np.zeros(nq_pin)
    t = np.zeros((nv_mj, nv_pin))
    for i, m in enumerate(maps):
        value = values[i]
        if m.kind == "one":
            qmj[m.mj_qpos[0]] = value
            qpin[m.pin_q] = value
            t[m.mj_dof[0], m.pin_v] = 1.0
        elif m.kind == "ball":
            w, x, y, z = value[1]
            qmj[list(m.mj_qpos)] = (w, x, y, z)
            qpin[m.pin_q:m.pin_q + 4] = (x, y, z, w)
            t[np.ix_(m.mj_dof, range(m.pin_v, m.pin_v + 3))] = np.eye(3)
        elif m.kind == "free":
            pos, (w, x, y, z) = value
            qpin[m.pin_q:m.pin_q + 7] = (*pos, x, y, z, w)
            motion = np.eye(4)
            motion[:3, :3] = quaternion_to_matrix((w, x, y, z))
            motion[:3, 3] = pos
            world = m.origin @ motion  # MuJoCo's free joint holds the body's world pose

            qmj[list(m.mj_qpos)] = (*world[:3, 3], *matrix_to_quaternion(world[:3, :3]))
            t[np.ix_(m.mj_dof[:3], range(m.pin_v, m.pin_v + 3))] = world[:3, :3]
            t[np.ix_(m.mj_dof[3:], range(m.pin_v + 3, m.pin_v + 6))] = np.eye(3)
        else:  # planar: x, y in the plane, then the angle
            x, y, theta = value
            qmj[list(m.mj_qpos)] = (x, y, theta)
            qpin[m.pin_q:m.pin_q + 4] = (x, y, math.cos(theta), math.sin(theta))
            c, s = math.cos(theta), math.sin(theta)
            t[np.ix_(m.mj_dof[:2], range(m.pin_v, m.pin_v + 2))] = [[c, -s], [s, c]]
            t[m.mj_dof[2], m.pin_v + 2] = 1.0
    return qmj, qpin, t


def _relative(error: float, reference: float) -> float:
    """*error* relative to *reference*; the absolute error when the reference is 0 (a model
    without mass, or a mass matrix of zeros), where a ratio would only measure the rounding."""
    return error / reference if reference > 0 else error


def _rotation_error(a: Matrix, b: Matrix) -> float:
    """Angle (rad) of a⁻¹b, accurate for tiny angles."""
    r = a.T @ b
    skew = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]])
    return float(math.atan2(np.linalg.norm(skew) / 2.0, (np.trace(r) - 1.0) / 2.0))


@record(frozen=False)
class Errors:
    position: float = 0.0
    rotation: float = 0.0
    matrix: float = 0.0
    worst_link: str | None = None


def _compare(robot: Robot, mj: Any, pin: Any, maps: list[JointMap], configurations: int,
             seed: int) -> Iterator[tuple[str, float, float]]:
    """Per configuration: (worst link, position error, rotation error, mass-matrix error) streamed."""
    import pinocchio

    rng = np.random.default_rng(seed)
    pdata = pin.model.createData()
    bodies = {link.name: name_to_id(mj, "body", link.name) for link in robot.links}
    for _ in range(configurations):
        values = _sample(maps, robot, rng)
        qmj, qpin, t = _configure(maps, values, mj.nq, pin.model.nq, mj.nv, pin.model.nv)
        data, m_mj = positions_and_mass_matrix(mj, qmj)
        # armature (rotor inertia from transmissions and gearboxes) is added on purpose and
        # reported where it is written; the comparison is of the rigid bodies
        m_mj = m_mj - np.diag(np.asarray(mj.dof_armature, dtype=float))
        pinocchio.framesForwardKinematics(pin.model, pdata, qpin)
        m_pin = np.triu(pinocchio.crba(pin.model, pdata, qpin))
        m_pin = m_pin + np.triu(m_pin, 1).T
        for name, body in bodies.items():
            placement = pdata.oMf[pin.link_frames[name]]
            if body < 0:
                pos, rot = np.zeros(3), np.eye(3)  # the world link is the world body
            else:
                pos, rot = data.xpos[body], data.xmat[body].reshape(3, 3)
            yield (
                name,
                float(np.linalg.norm(pos - placement.translation)),
                _rotation_error(rot, placement.rotation),
            )
        diff = m_pin - t.T @ m_mj @ t
        yield "", -1.0, _relative(float(np.max(np.abs(diff))) if diff.size else 0.0,
                                  float(np.max(np.abs(m_pin))) if m_pin.size else 0.0)


def verify_mjcf(robot: Robot, out: Path, options: ExportOptions, configurations: int = CONFIGURATIONS,
                seed: int = 0) -> VerifyResult:
    """Compile *out* and compare it with the source robot (see the module docstring)."""

    tree = KinematicTree.of(robot)
    base = decide_base(robot, tree, options.floating_base)
    try:
        mj = compile_model(out)
    except EngineError as exc:
        return VerifyResult(False, [], [_engine_error(robot, exc, out)])
    inertials = plan_inertia(robot, tree, base, options.repair_inertia).inertials
    pin = build_model(robot, free_flyer=base.kind == "free", inertials=dict(inertials))
    try:
        maps = build_maps(robot, tree, mj, pin, base.free_joint if base.kind == "free" else None)
    except KeyError as exc:
        return VerifyResult(False, [], [EngineRejected.diagnostic(
            f"MuJoCo model has no joint '{exc.args[0]}'", robot.span)])
    errors = Errors()
    worst = -1.0
    for name, position, other in _compare(robot, mj, pin, maps, configurations, seed):
        if position < 0:
            errors.matrix = max(errors.matrix, other)
            continue
        errors.position = max(errors.position, position)
        errors.rotation = max(errors.rotation, other)
        if max(position, other) > worst:
            worst, errors.worst_link = max(position, other), name
    pin_mass = float(sum(inertia.mass for inertia in pin.model.inertias))
    mass_error = _relative(abs(total_mass(mj) - pin_mass), pin_mass)
    # a source without mass (a static model) is compared in kg: a relative error has no scale
    mass_row = "total mass (relative)" if pin_mass > 0 else "total mass (kg; the source has none)"
    dof_error = float(abs(mj.nv - pin.model.nv))
    rows = [
        ("degrees of freedom (MuJoCo - Pinocchio)", dof_error, 0.0, dof_error == 0.0),
        (f"link positions (m), {configurations} configurations", errors.position, TOLERANCE,
         errors.position <= TOLERANCE),
        ("link orientations (rad)", errors.rotation, TOLERANCE, errors.rotation <= TOLERANCE),
        (mass_row, mass_error, TOLERANCE, mass_error <= TOLERANCE),
        ("joint-space mass matrix (relative)", errors.matrix, TOLERANCE, errors.matrix <= TOLERANCE),
    ]
    diagnostics = [_mismatch(robot, row, errors.worst_link) for row in rows if not row[3]]
    return VerifyResult(all(row[3] for row in rows), rows, diagnostics)


def _mismatch(robot: Robot, row: tuple[str, float, float, bool], link: str | None) -> Diagnostic:
    name, error, tolerance, _ = row
    span = robot.span
    if "link" in name and link is not None and robot.link(link) is not None:
        span = robot.link(link).span or span  # type: ignore[union-attr]
    return EngineRejected.diagnostic(
        f"MuJoCo and the source differ: {name}: {error:.3g} > {tolerance:.3g}"
        + (f" (worst at link '{link}')" if "link" in name and link else ""),
        span, data={"quantity": name, "error": error, "tolerance": tolerance})


def _engine_error(robot: Robot, exc: Any, out: Path) -> Diagnostic:
    """MuJoCo's compile error at the link, joint or mesh of the source it names."""
    span = robot.span
    if exc.element:
        node = robot.link(exc.element) or robot.joint(exc.element)
        if node is not None and node.span is not None:
            span = node.span
        else:
            span = _mesh_span(robot, exc.element, out) or span
    return EngineRejected.diagnostic(f"MuJoCo refused the export: {exc.message}", span,
                                     data={"element": exc.element, "line": exc.line})


def _mesh_span(robot: Robot, mesh_name: str, out: Path):  # type: ignore[no-untyped-def]
    """The source ``<mesh>`` behind MJCF mesh asset *mesh_name*: the first mesh geometry, in the
    link whose body uses the asset, whose file has the asset's stem."""
    from lxml import etree

    try:
        document = etree.parse(str(out))
    except (OSError, etree.XMLSyntaxError):
        return None
    for geom in document.iter("geom"):
        if geom.get("mesh") != mesh_name:
            continue
        body = geom.getparent()
        link = robot.link(body.get("name", "")) if body is not None else None
        elements: tuple[Visual | Collision, ...] = (*link.visuals, *link.collisions) if link else ()
        for element in elements:
            geometry = element.geometry
            if isinstance(geometry, Mesh) and mesh_name.startswith(
                Path(geometry.filename).name.split(".")[0]
            ):
                return geometry.span or element.span
    return None


def verify(robot: Robot, out: Path, options: ExportOptions) -> VerifyResult:
    """Compile *out* with MuJoCo and compare it with Pinocchio built from *robot*."""
    return verify_mjcf(robot, Path(out), options)
