"""An independent parser cross-checks urdftool's reading of the corpora.

Pinocchio (urdfdom underneath) and yourdfpy each read the same files; link and
joint counts, joint types, and every link's world pose at random joint
configurations must agree with urdftool's model to 1e-9. Files with structural
errors are excluded: there the parsers legitimately disagree (that is what the
errors are about).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from tests.conftest import ERD, PBD, erd_urdfs, pybullet_robots, relative
from urdftool.diagnostics import Severity
from urdftool.model import JointType, KinematicTree, Robot
from urdftool.parse import read
from urdftool.pipeline.check import CheckOptions, check_file

TOLERANCE = 1e-9
CONFIGURATIONS = 5
SEED = 20261122

ALL = [(p, relative(p, ERD)) for p in erd_urdfs()] + [(p, relative(p, PBD)) for p in pybullet_robots()]

#: Files the other parsers cannot be compared on, and why. test_exclusions_are_exact
#: keeps this list honest: each entry must really have the stated problem.
EXCLUDED = {
    # structural errors: the parsers legitimately read different robots
    "ur_description/urdf/ur3.urdf": "error",
    "bicycle/bike.urdf": "error",
    "biped/biped2d_pybullet.urdf": "error",
    "husky/husky.urdf": "error",
    "quadruped/microtaur/microtaur.urdf": "error",
    "racecar/racecar_differential.urdf": "error",
    # PyBullet's spherical joints: urdfdom and yourdfpy refuse them
    "humanoid/humanoid.urdf": "spherical",
    "spherical_joint_limit.urdf": "spherical",
}

FILES = [(p, n) for p, n in ALL if n not in EXCLUDED]


def _problem(path: str) -> str | None:
    diags = [d for r in check_file(path, CheckOptions(select=("S",))) for d in r.diagnostics]
    if any(d.severity is Severity.ERROR for d in diags):
        return "error"
    if any(d.name == "unknown-joint-type" for d in diags):
        return "spherical"
    return None


@pytest.mark.parametrize(("path", "name"), ALL, ids=[n for _, n in ALL])
def test_exclusions_are_exact(path: str, name: str) -> None:
    assert _problem(path) == EXCLUDED.get(name)


def clean_robot(path: str) -> Robot:
    robot = read(path)[0].robot
    assert robot is not None
    return robot


def random_configuration(robot: Robot, rng: np.random.Generator) -> dict[str, float]:
    q: dict[str, float] = {}
    for joint in robot.joints:
        if joint.type.dof != 1 or joint.mimic is not None:
            continue
        lo, hi = -math.pi, math.pi
        limit = joint.limit
        if (
            joint.type is not JointType.CONTINUOUS
            and limit is not None
            and limit.lower is not None
            and limit.upper is not None
            and limit.lower <= limit.upper
        ):
            lo, hi = limit.lower, limit.upper
        q[joint.name] = float(rng.uniform(lo, hi))
    return q


def full_configuration(robot: Robot, q: dict[str, float]) -> dict[str, float]:
    """*q* plus the positions of mimic joints (which follow their targets)."""
    out = dict(q)
    for joint in robot.joints:
        if joint.mimic is not None and joint.type.dof == 1:
            out[joint.name] = joint.mimic.multiplier * q.get(joint.mimic.joint, 0.0) + joint.mimic.offset
    return out


def urdftool_poses(robot: Robot, q: dict[str, float]) -> dict[str, np.ndarray]:
    tree = KinematicTree.of(robot)
    return tree.forward_kinematics(q)


def _has_multi_dof(robot: Robot) -> bool:
    return any(j.type.dof > 1 for j in robot.joints)


@pytest.mark.parametrize(("path", "name"), FILES, ids=[n for _, n in FILES])
def test_pinocchio_agrees(path: str, name: str) -> None:
    import pinocchio as pin

    robot = clean_robot(path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = pin.buildModelFromUrdf(path)
    data = model.createData()
    bodies = {f.name for f in model.frames if f.type == pin.FrameType.BODY}
    assert bodies == {link.name for link in robot.links}
    moving = {j.name for j in robot.joints if j.type is not JointType.FIXED}
    assert {model.names[i] for i in range(1, model.njoints)} == moving
    for i in range(1, model.njoints):
        joint = robot.joint(model.names[i])
        assert joint is not None
        shortname = model.joints[i].shortname()
        expected = {
            JointType.REVOLUTE: "RevoluteUnaligned|RevoluteUnbounded|JointModelR",
            JointType.CONTINUOUS: "RevoluteUnbounded|RUB",
            JointType.PRISMATIC: "Prismatic|JointModelP",
            JointType.FLOATING: "FreeFlyer",
            JointType.PLANAR: "Planar",
        }[joint.type]
        assert any(tag in shortname for tag in expected.split("|")), (joint.name, joint.type, shortname)
    if _has_multi_dof(robot):
        return  # poses below are for 1-DOF joints; counts and types were compared
    rng = np.random.default_rng(SEED)
    for _ in range(CONFIGURATIONS):
        q = random_configuration(robot, rng)
        full = full_configuration(robot, q)
        qp = pin.neutral(model)
        for i in range(1, model.njoints):
            jname = model.names[i]
            value = full.get(jname, 0.0)
            idx = model.joints[i].idx_q
            if model.joints[i].nq == 2:  # unbounded revolute: (cos, sin)
                qp[idx], qp[idx + 1] = math.cos(value), math.sin(value)
            else:
                qp[idx] = value
        pin.framesForwardKinematics(model, data, qp)
        ours = urdftool_poses(robot, full)
        for f_id, frame in enumerate(model.frames):
            if frame.type != pin.FrameType.BODY:
                continue
            theirs = data.oMf[f_id].homogeneous
            assert np.max(np.abs(ours[frame.name] - theirs)) <= TOLERANCE, frame.name


@pytest.mark.parametrize(("path", "name"), FILES, ids=[n for _, n in FILES])
def test_yourdfpy_agrees(path: str, name: str) -> None:
    import yourdfpy

    robot = clean_robot(path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        theirs = yourdfpy.URDF.load(path, build_scene_graph=True, load_meshes=False,
                                    build_collision_scene_graph=False, load_collision_meshes=False)
    assert set(theirs.link_map) == {link.name for link in robot.links}
    assert set(theirs.joint_map) == {j.name for j in robot.joints}
    for jname, joint in theirs.joint_map.items():
        assert joint.type == robot.joint(jname).type.value
    if _has_multi_dof(robot):
        return
    rng = np.random.default_rng(SEED + 1)
    root = KinematicTree.of(robot).root
    for _ in range(CONFIGURATIONS):
        q = random_configuration(robot, rng)
        cfg = {n: q.get(n, 0.0) for n in theirs.actuated_joint_names}
        theirs.update_cfg(cfg)
        ours = urdftool_poses(robot, full_configuration(robot, q))
        for link in robot.links:
            pose = theirs.get_transform(link.name, root)
            assert np.max(np.abs(ours[link.name] - pose)) <= TOLERANCE, link.name
