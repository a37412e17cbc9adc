"""SDF universal joints: two hinges in MJCF, two revolute joints and a massless link in URDF,
each moving the child exactly as the source's joint does."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import urdftool
from urdftool.model import JointType, KinematicTree

INERTIAL = ("<inertial><mass>1</mass><inertia><ixx>0.01</ixx><iyy>0.01</iyy><izz>0.01</izz></inertia>"
            "</inertial>")
CARDAN = f"""<sdf version="1.7"><model name="u">
  <link name="base">{INERTIAL}</link>
  <link name="tip"><pose>0.1 0 0.5 0 0.3 0</pose>{INERTIAL}</link>
  <joint name="fix" type="fixed"><parent>world</parent><child>base</child></joint>
  <joint name="cardan" type="universal"><parent>base</parent><child>tip</child>
    <axis><xyz>1 0 0</xyz><limit><lower>-1</lower><upper>1</upper></limit></axis>
    <axis2><xyz>0 1 0</xyz><limit><lower>-0.5</lower><upper>0.5</upper></limit></axis2></joint>
</model></sdf>
"""
ANGLES = [(0.0, 0.0), (0.4, 0.0), (0.0, -0.3), (0.7, 0.45), (-0.9, -0.2)]


@pytest.fixture
def source(tmp_path: Path) -> Path:
    path = tmp_path / "cardan.sdf"
    path.write_text(CARDAN)
    return path


def _tip(robot: urdftool.Robot, q: dict[str, object]) -> np.ndarray:
    return KinematicTree.of(robot).forward_kinematics(q)["tip"]


def test_the_sdf_reader_keeps_both_axes(source: Path) -> None:
    joint = urdftool.load(source).joint("cardan")
    assert joint is not None and joint.type is JointType.UNIVERSAL and joint.axis2 is not None
    assert joint.limit2 is not None and joint.limit2.upper == 0.5


def test_mjcf_two_hinges_move_the_tip_as_the_universal_joint_does(source: Path, tmp_path: Path) -> None:
    import mujoco

    robot = urdftool.load(source)
    out = tmp_path / "cardan.xml"
    urdftool.to_mjcf(source, out)
    model = mujoco.MjModel.from_xml_path(str(out))
    data = mujoco.MjData(model)
    first, second = (model.joint(f"cardan_{i}") for i in (1, 2))
    assert model.jnt_range[first.id].tolist() == [-1.0, 1.0]
    assert model.jnt_range[second.id].tolist() == [-0.5, 0.5]
    base, tip = model.body("base").id, model.body("tip").id
    for a, b in ANGLES:
        data.qpos[model.jnt_qposadr[first.id]], data.qpos[model.jnt_qposadr[second.id]] = a, b
        mujoco.mj_kinematics(model, data)
        world_base = np.eye(4)
        world_base[:3, :3], world_base[:3, 3] = data.xmat[base].reshape(3, 3), data.xpos[base]
        world_tip = np.eye(4)
        world_tip[:3, :3], world_tip[:3, 3] = data.xmat[tip].reshape(3, 3), data.xpos[tip]
        source_poses = KinematicTree.of(robot).forward_kinematics({"cardan": (a, b)})
        relative_source = np.linalg.inv(source_poses["base"]) @ source_poses["tip"]
        relative_mujoco = np.linalg.inv(world_base) @ world_tip
        np.testing.assert_allclose(relative_mujoco, relative_source, atol=1e-12)


def test_urdf_two_revolute_joints_move_the_tip_as_the_universal_joint_does(source: Path,
                                                                          tmp_path: Path) -> None:
    robot = urdftool.load(source)
    out = tmp_path / "cardan.urdf"
    urdftool.to_urdf(source, out)
    back = urdftool.load(out)
    assert back.link("cardan_cross") is not None and back.link("cardan_cross").inertial is None
    for a, b in ANGLES:
        np.testing.assert_allclose(_tip(back, {"cardan_1": a, "cardan_2": b}),
                                   _tip(robot, {"cardan": (a, b)}), atol=1e-12)
    assert not urdftool.check(out, select=["S", "J"]).errors
