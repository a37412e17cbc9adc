"""Per-joint-group default classes in the MJCF export (docs/mjcf.md, "Default classes"): joints of
the same role on different limbs share a class when their settings agree, and MuJoCo compiles the
same model with and without the classes."""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pytest
from lxml import etree

from tests.conftest import ERD
from urdftool.export import ExportOptions, mjcf
from urdftool.export.mjcf_classes import name_pattern, sideless_name
from urdftool.parse import read
from urdftool.pipeline.check import CheckOptions
from urdftool.pipeline.load import load_one

#: What a class may change in the compiled model: every joint, DOF and actuator parameter.
COMPILED = (
    "jnt_type", "jnt_axis", "jnt_range", "jnt_limited", "jnt_actfrcrange", "jnt_actfrclimited",
    "jnt_stiffness", "jnt_pos", "dof_damping", "dof_armature", "dof_frictionloss",
    "actuator_trntype", "actuator_trnid", "actuator_gear", "actuator_gaintype", "actuator_gainprm",
    "actuator_biastype", "actuator_biasprm", "actuator_dyntype", "actuator_dynprm",
    "actuator_ctrlrange", "actuator_ctrllimited", "actuator_forcerange", "actuator_forcelimited",
    "qpos0", "key_qpos", "key_ctrl", "body_mass", "body_inertia", "geom_rgba", "geom_group",
)


@pytest.mark.parametrize(("joint", "pattern"), [
    ("FL_hip_joint", "hip"), ("RR_calf_joint", "calf"), ("LF_HAA", "haa"), ("HR_KFE", "kfe"),
    ("panda_joint3", "panda"), ("panda_finger_joint2", "panda_finger"), ("leg_left_4_joint", "leg"),
    ("arm_right_7_joint", "arm"), ("l_hip_pitch", "hip_pitch"), ("joint1", "joint"),
])
def test_name_pattern_drops_sides_and_indices(joint: str, pattern: str) -> None:
    assert name_pattern(joint) == pattern


def test_sideless_name_keeps_the_index() -> None:
    assert sideless_name("leg_left_4_joint") == sideless_name("leg_right_4_joint") == "leg_4"


def _leg(side: str, y: float, lower: float, damping: float) -> str:
    box = ('<inertial><mass value="1"/>'
           '<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>')
    return (
        f'<link name="{side}_thigh">{box}</link><link name="{side}_shin">{box}</link>'
        f'<joint name="{side}_hip_joint" type="revolute"><parent link="base"/><child link="{side}_thigh"/>'
        f'<origin xyz="0 {y} 0"/><axis xyz="0 1 0"/>'
        '<limit lower="-1" upper="1" effort="20" velocity="1"/><dynamics damping="0.5"/></joint>'
        f'<joint name="{side}_knee_joint" type="revolute">'
        f'<parent link="{side}_thigh"/><child link="{side}_shin"/>'
        f'<origin xyz="0 0 -0.3"/><axis xyz="0 1 0"/>'
        f'<limit lower="{lower}" upper="2" effort="30" velocity="1"/><dynamics damping="{damping}"/></joint>'
    )


def _biped(tmp_path: Path):  # type: ignore[no-untyped-def]
    box = ('<inertial><mass value="5"/>'
           '<inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>')
    text = (f'<robot name="biped"><link name="base">{box}</link>'
            + _leg("left", 0.1, 0.0, 0.2) + _leg("right", -0.1, 0.0, 0.2)
            # a third knee with a range of its own keeps its settings inline
            + _leg("rear", 0.0, -0.5, 0.2).replace("rear_hip_joint", "tail_joint")
            + "</robot>")
    (tmp_path / "biped.urdf").write_text(text)
    robot = read(tmp_path / "biped.urdf")[0].robot
    assert robot is not None
    return robot


def _export(robot, out: Path, classes: bool, **options):  # type: ignore[no-untyped-def]
    """Export and compile; without *classes*, as the exporter wrote before them."""
    with pytest.MonkeyPatch.context() as patch:
        if not classes:
            patch.setattr(mjcf, "write_joint_classes", lambda *args, **kwargs: [])
        result = mjcf.export(robot, out, ExportOptions(**options))
    for name, data in result.files.items():
        (out.parent / name).parent.mkdir(parents=True, exist_ok=True)
        (out.parent / name).write_bytes(data)
    return mujoco.MjModel.from_xml_path(str(out)), etree.parse(str(out)).getroot()


def _same_model(a: mujoco.MjModel, b: mujoco.MjModel) -> None:
    for name in COMPILED:
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert [a.joint(i).name for i in range(a.njnt)] == [b.joint(i).name for i in range(b.njnt)]


def _classes(root: etree._Element) -> dict[str, etree._Element]:
    return {d.get("class"): d for d in root.findall("default/default")}


def test_mirrored_joints_share_a_class_and_a_unique_one_stays_inline(tmp_path: Path) -> None:
    robot = _biped(tmp_path)
    with_classes, root = _export(robot, tmp_path / "a" / "robot.xml", True, actuators="position")
    without, _ = _export(robot, tmp_path / "b" / "robot.xml", False, actuators="position")
    _same_model(with_classes, without)
    classes = _classes(root)
    assert list(classes) == ["visual", "collision", "hip", "knee"]
    hip = classes["hip"].find("joint")
    assert hip is not None and hip.attrib == {
        "type": "hinge", "axis": "0 1 0", "range": "-1 1", "damping": "0.5", "actuatorfrcrange": "-20 20"}
    joints = {j.get("name"): j for j in root.iter("joint")}
    assert joints["left_hip_joint"].attrib == {"name": "left_hip_joint", "class": "hip"}
    assert joints["right_knee_joint"].get("class") == "knee"
    assert joints["rear_knee_joint"].get("class") is None
    assert joints["rear_knee_joint"].get("range") == "-0.5 2"
    actuators = {a.get("name"): a for a in root.find("actuator")}
    assert actuators["left_hip_joint"].get("class") == "hip"
    assert actuators["rear_knee_joint"].get("class") is None


CASES = [
    ("talos_data/robots/talos_reduced.urdf", "auto",
     ["arm", "gripper", "leg_2", "leg_3", "leg_4", "leg_5", "leg_6"]),
    ("cassie_description/robots/cassie.sdf", "auto",
     ["roll_ip", "yaw_ip", "pitch_ip", "pitch_rod", "achilles_spring", "knee_ip", "crank_rod",
      "foot_ip", "shin_spring"]),
    ("go2_description/urdf/go2.urdf", "auto", ["hip", "thigh_front", "thigh_rear", "calf"]),
    ("go2_description/urdf/go2.urdf", "none", ["hip", "thigh_front", "thigh_rear", "calf"]),
    ("solo_description/robots/solo12.urdf", "auto", ["haa_1", "haa_2", "hfe", "kfe"]),
    ("panda_description/urdf/panda.urdf", "auto", []),
    ("panda_description/urdf/panda.urdf", "none", ["panda_1", "panda_2", "panda_finger"]),
]


@pytest.mark.parametrize(("rel", "actuators", "expected"), CASES)
def test_classes_compile_to_the_same_model(tmp_path: Path, rel: str, actuators: str,
                                           expected: list[str]) -> None:
    assert ERD is not None
    robot = load_one(str(ERD / rel), CheckOptions()).robot
    assert robot is not None
    # Cassie's foot reference links break A + B >= C (docs/mjcf.md, "Standing")
    options = {"scene": True, "actuators": actuators, "repair_inertia": rel.endswith(".sdf")}
    with_classes, root = _export(robot, tmp_path / "a" / "robot.xml", True, **options)
    without, _ = _export(robot, tmp_path / "b" / "robot.xml", False, **options)
    _same_model(with_classes, without)
    assert list(_classes(root))[2:] == expected
