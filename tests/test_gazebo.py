"""Gazebo extension rules on small robots written here: plugin spellings and exceptions."""

from __future__ import annotations

from pathlib import Path

import pytest

from urdftool.pipeline.check import CheckOptions, check_file

INERTIAL = (
    '<inertial><mass value="1"/>'
    '<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>'
)


def wheel(name: str, x: float, y: float, radius: float = 0.1) -> str:
    return (
        f'<link name="{name}">{INERTIAL}<collision><origin rpy="1.5708 0 0"/><geometry>'
        f'<cylinder radius="{radius}" length="0.04"/></geometry></collision></link>'
        f'<joint name="{name}_joint" type="continuous"><parent link="base"/><child link="{name}"/>'
        f'<origin xyz="{x} {y} 0"/><axis xyz="0 1 0"/></joint>'
    )


def robot(tmp_path: Path, body: str) -> list:
    path = tmp_path / "robot.urdf"
    path.write_text(f'<robot name="rover"><link name="base">{INERTIAL}</link>{body}</robot>')
    return [d for r in check_file(str(path), CheckOptions(select=("G",))) for d in r.diagnostics]


def test_ros2_diff_drive_with_two_wheel_pairs_checks_each_pair(tmp_path: Path) -> None:
    body = (
        wheel("fl", 0.2, 0.2)
        + wheel("fr", 0.2, -0.2)
        + wheel("rl", -0.2, 0.25)
        + wheel("rr", -0.2, -0.25)
        + '<gazebo><plugin name="dd" filename="libgazebo_ros_diff_drive.so">'
        + "<num_wheel_pairs>2</num_wheel_pairs>"
        "<left_joint>fl_joint</left_joint><right_joint>fr_joint</right_joint>"
        "<left_joint>rl_joint</left_joint><right_joint>rr_joint</right_joint>"
        "<wheel_separation>0.4</wheel_separation><wheel_separation>0.4</wheel_separation>"
        "<wheel_diameter>0.2</wheel_diameter><wheel_diameter>0.2</wheel_diameter></plugin></gazebo>"
    )
    found = [d for d in robot(tmp_path, body) if d.code == "G004"]
    assert [round(d.data["measured_m"], 3) for d in found] == [0.5]  # only the rear pair is off


def test_skid_steer_compares_with_the_mean_of_both_axles(tmp_path: Path) -> None:
    body = (
        wheel("lf", 0.2, 0.2)
        + wheel("rf", 0.2, -0.2)
        + wheel("lr", -0.2, 0.2)
        + wheel("rr", -0.2, -0.2)
        + '<gazebo><plugin name="skid" filename="libgazebo_ros_skid_steer_drive.so">'
        "<leftFrontJoint>lf_joint</leftFrontJoint><rightFrontJoint>rf_joint</rightFrontJoint>"
        "<leftRearJoint>lr_joint</leftRearJoint><rightRearJoint>rr_joint</rightRearJoint>"
        "<wheelSeparation>0.4</wheelSeparation><wheelDiameter>0.25</wheelDiameter></plugin></gazebo>"
    )
    found = [d for d in robot(tmp_path, body) if d.code == "G004"]
    assert len(found) == 1 and "diameter" in found[0].message
    assert found[0].data["measured_m"] == pytest.approx(0.2)


def test_plugin_may_name_joints_that_gazebo_blocks_define(tmp_path: Path) -> None:
    body = (
        '<gazebo><joint name="world_hinge" type="revolute">'
        "<parent>world</parent><child>base</child></joint>"
        '<plugin name="jsp" filename="libgazebo_ros_joint_state_publisher.so">'
        "<jointName>world_hinge</jointName></plugin></gazebo>"
    )
    assert [d for d in robot(tmp_path, body) if d.code == "G003"] == []


def test_unexpanded_substitutions_are_left_to_the_syntax_rules(tmp_path: Path) -> None:
    body = (
        '<gazebo><plugin name="jsp" filename="libgazebo_ros_joint_state_publisher.so">'
        "<jointName>${prefix}joint</jointName></plugin></gazebo>"
    )
    assert [d for d in robot(tmp_path, body) if d.code == "G003"] == []


def test_pose_in_a_link_is_a_warning_with_its_value(tmp_path: Path) -> None:
    found = robot(tmp_path, '<link name="arm"><pose>0 0 1 0 0 0</pose></link>')
    assert [d.code for d in found] == ["G005"]
    assert found[0].severity.value == "warning" and "0 0 1" in found[0].message


@pytest.mark.parametrize("block, severity", [
    # schunk_description's lwa4p: a colour and Gazebo's defaults; only the colour is lost
    ("<gravity>true</gravity><self_collide>false</self_collide><material value='Schunk/Blue'/>", "warning"),
    ("<material>Gazebo/FlatBlack</material>", "warning"),  # champ_velodyne's hokuyo_frame
    # anything else is lost behaviour: a link that should float, collide, carry a sensor
    ("<gravity>false</gravity><material>Gazebo/Red</material>", "error"),
    ("<self_collide>true</self_collide>", "error"),
    ("<mu1>0.2</mu1>", "error"),
    ("<sensor type='ray' name='laser'/>", "error"),
    ("", "error"),
])
def test_a_stale_reference_that_only_sets_a_colour_is_a_warning(tmp_path: Path, block: str,
                                                               severity: str) -> None:
    found = robot(tmp_path, f'<link name="base_link"/><gazebo reference="hokuyo_frame">{block}</gazebo>')
    assert [(d.code, d.severity.value) for d in found if d.code == "G001"] == [("G001", severity)]
