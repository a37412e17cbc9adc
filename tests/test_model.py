"""The model's tree view: traversal terminates on any joint graph, FK follows mimic chains."""

from __future__ import annotations

import math

import numpy as np

from urdftool.model import Joint, JointType, KinematicTree, Link, Mimic, Pose, Robot
from urdftool.model.pose import matrix_to_quaternion, matrix_to_rpy, quaternion_to_matrix, rpy_to_matrix


def links(*names: str) -> tuple[Link, ...]:
    return tuple(Link(n) for n in names)


def revolute(name: str, parent: str, child: str, **kw) -> Joint:  # type: ignore[no-untyped-def]
    return Joint(name, JointType.REVOLUTE, parent, child, axis=(0.0, 0.0, 1.0), **kw)


def test_planar_arm_forward_kinematics() -> None:
    robot = Robot(
        "arm",
        links("base", "upper", "fore"),
        (
            revolute("shoulder", "base", "upper"),
            revolute("elbow", "upper", "fore", origin=Pose((1.0, 0.0, 0.0))),
        ),
    )
    poses = KinematicTree.of(robot).forward_kinematics({"shoulder": math.pi / 2, "elbow": math.pi / 2})
    assert np.allclose(poses["fore"][:3, 3], [0.0, 1.0, 0.0])
    assert np.allclose(poses["fore"][:3, :3], rpy_to_matrix((0.0, 0.0, math.pi)))


def test_mimic_chain_is_followed() -> None:
    robot = Robot(
        "gripper",
        links("palm", "a", "b", "c"),
        (
            revolute("driver", "palm", "a"),
            revolute("f1", "palm", "b", mimic=Mimic("driver", 2.0, 0.1)),
            revolute("f2", "palm", "c", mimic=Mimic("f1", -1.0, 0.0)),
        ),
    )
    poses = KinematicTree.of(robot).forward_kinematics({"driver": 0.2})
    angle = -(2.0 * 0.2 + 0.1)
    assert np.allclose(poses["c"][:3, :3], rpy_to_matrix((0.0, 0.0, angle)))


def test_mimic_cycle_terminates() -> None:
    robot = Robot(
        "r",
        links("a", "b", "c"),
        (
            revolute("j1", "a", "b", mimic=Mimic("j2")),
            revolute("j2", "b", "c", mimic=Mimic("j1")),
        ),
    )
    poses = KinematicTree.of(robot).forward_kinematics({"j1": 0.3, "j2": 0.4})
    assert set(poses) == {"a", "b", "c"}


def test_cycles_and_self_loops_terminate_and_are_set_aside() -> None:
    robot = Robot(
        "loop",
        links("a", "b", "c"),
        (
            Joint("ab", JointType.FIXED, "a", "b"),
            Joint("bc", JointType.FIXED, "b", "c"),
            Joint("ca", JointType.FIXED, "c", "a"),
            Joint("self", JointType.FIXED, "b", "b"),
        ),
    )
    tree = KinematicTree.of(robot)
    assert {j.name for j in tree.cycle_joints} == {"ca", "self"}
    assert tree.order == ["a", "b", "c"]
    assert tree.path_to_root("c")[-1].name == "ab"


def test_rotation_conversions_round_trip() -> None:
    rng = np.random.default_rng(1)
    for _ in range(50):
        rpy = tuple(rng.uniform(-3, 3, 3))
        rot = rpy_to_matrix(rpy)  # type: ignore[arg-type]
        assert np.allclose(rpy_to_matrix(matrix_to_rpy(rot)), rot, atol=1e-12)
        assert np.allclose(quaternion_to_matrix(matrix_to_quaternion(rot)), rot, atol=1e-12)
