"""URDF → SDF export: every tree-shaped model in example-robot-data round-trips exactly."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import urdftool
from tests.conftest import ERD, FIXTURES, erd_urdfs
from urdftool.cli import main
from urdftool.export import ExportOptions, export_model
from urdftool.model import KinematicTree, Pose, Robot
from urdftool.parse import read
from urdftool.pipeline.convert import convert_robot


def _tree_shaped(path: str) -> bool:
    robot = read(path)[0].robot
    if robot is None:
        return False
    tree = KinematicTree.of(robot)
    return len(tree.roots) == 1 and not tree.cycle_joints


TREES = [p for p in erd_urdfs() if _tree_shaped(p)]


def _configuration(robot: Robot, tree: KinematicTree, seed: int) -> dict[str, float]:
    """Random positions (rad or m) for every 1-DOF joint.

    Mimic joints follow their target as in the source.
    """
    rng = np.random.default_rng(seed)
    q = {j.name: float(rng.uniform(-1.5, 1.5)) for j in tree.joints_in_order if j.dof == 1}
    for joint in tree.joints_in_order:
        if joint.mimic is not None:
            target = q.get(joint.mimic.joint, 0.0) if robot.joint(joint.mimic.joint) else 0.0
            q[joint.name] = joint.mimic.multiplier * target + joint.mimic.offset
    return q


def test_corpus_has_tree_shaped_models() -> None:
    assert len(TREES) >= 60


@pytest.mark.parametrize("path", TREES, ids=lambda p: str(Path(p).relative_to(ERD)))
def test_urdf_to_sdf_round_trip(path: str, tmp_path: Path) -> None:
    source = read(path)[0].robot
    out = tmp_path / "model.sdf"
    text = urdftool.to_sdf(source, out)
    assert out.read_text() == text
    back = read(str(out))[0].robot
    assert back is not None and not back.diagnostics, [d.message for d in back.diagnostics][:3]
    tree, tree_back = KinematicTree.of(source), KinematicTree.of(back)
    # a joint renamed for SDF's single namespace is found by its child link
    name_by_child = {j.child: j.name for j in back.joints}
    # massless links on fixed joints come back as SDF frames (urdftool/export/sdf_frames.py)
    frames = {e.attributes["name"]: e.attributes for e in back.extensions if e.tag == "frame"}
    for seed in (0, 1, 2):
        q = _configuration(source, tree, seed)
        q_back = {name_by_child[source.joint(n).child]: v for n, v in q.items() if source.joint(n).child
                  not in frames}
        poses, poses_back = tree.forward_kinematics(q), tree_back.forward_kinematics(q_back)
        assert set(poses) == set(poses_back) | set(frames)
        # a massless root comes back as a frame: the SDF tree's root is the link under it, so
        # poses are compared relative to a link both trees have
        ref = tree_back.roots[0]
        inv, inv_back = np.linalg.inv(poses[ref]), np.linalg.inv(poses_back[ref])
        for link, pose in poses.items():
            if link in frames:
                attached = frames[link]
                in_link = Pose(tuple(map(float, attached["xyz"].split())),  # type: ignore[arg-type]
                               tuple(map(float, attached["rpy"].split())))  # type: ignore[arg-type]
                got = poses_back[attached["attached_to"]] @ in_link.matrix
            else:
                got = poses_back[link]
            np.testing.assert_allclose(inv_back @ got, inv @ pose, atol=1e-9, rtol=0, err_msg=link)
    for link in source.links:
        other = back.link(link.name)
        if link.name in frames:
            assert other is None and (link.inertial is None or link.inertial.mass == 0)
            continue
        assert other is not None
        if link.inertial is None:
            assert other.inertial is None
            continue
        assert other.inertial.mass == link.inertial.mass
        np.testing.assert_allclose(other.inertial.inertia_in_link_frame, link.inertial.inertia_in_link_frame,
                                   atol=1e-12)
        np.testing.assert_allclose(other.inertial.origin.xyz, link.inertial.origin.xyz, atol=1e-12)


def test_sdf_export_is_byte_identical_on_rerun() -> None:
    path = FIXTURES / "robots" / "two_link_arm.urdf"
    assert urdftool.to_sdf(path) == urdftool.to_sdf(path)


def test_cli_convert_urdf_to_sdf_and_check(tmp_path: Path) -> None:
    source = str(FIXTURES / "robots" / "two_link_arm.urdf")
    out = tmp_path / "arm.sdf"
    result = CliRunner().invoke(main, ["convert", source, "-o", str(out)])
    assert result.exit_code == 0, result.output
    assert out.read_text().startswith("<?xml")
    result = CliRunner().invoke(main, ["convert", source, "-o", str(out), "--check"])
    assert result.exit_code == 0, result.output


def test_gazebo_blocks_are_mapped_or_reported(tmp_path: Path) -> None:
    urdf = tmp_path / "bot.urdf"
    urdf.write_text(
        '<robot name="bot"><link name="base"><inertial><mass value="1"/>'
        '<inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>'
        '<collision><geometry><box size="1 1 1"/></geometry></collision></link>\n'
        '<gazebo reference="base"><mu1>0.8</mu1><selfCollide>true</selfCollide><foo>1</foo></gazebo>\n'
        '<gazebo><plugin name="drive" filename="libdrive.so"/></gazebo>\n'
        '<transmission name="t"/>\n</robot>\n'
    )
    from urdftool.export import ExportOptions, export_model

    result = export_model(read(str(urdf))[0].robot, "sdf", tmp_path / "bot.sdf", ExportOptions())
    text = result.files["bot.sdf"].decode()
    assert "<mu>0.8</mu>" in text and "<self_collide>true</self_collide>" in text
    assert '<plugin name="drive" filename="libdrive.so"/>' in text and "urdftool-src" not in text
    dropped = {(d.code, d.location.line) for d in result.diagnostics}
    assert ("C001", 2) in dropped and ("C001", 4) in dropped  # <foo> and the transmission


def test_gazebo_contact_settings_reach_every_collision(tmp_path: Path) -> None:
    """kp, kd, minDepth, maxVel, fdir1, maxContacts and laserRetro go where libsdformat's URDF
    reader puts them; none is reported as dropped (new-user report of 2026-11-26, problem 5)."""
    from lxml import etree

    robot = read(str(FIXTURES / "newuser" / "gazebo_friction_arm.urdf"))[0].robot
    result = export_model(robot, "sdf", tmp_path / "arm.sdf", ExportOptions())
    model = etree.fromstring(result.files["arm.sdf"]).find("model")
    collision = model.find("link[@name='link_7']/collision")
    assert collision.findtext("surface/friction/ode/mu") == "0.2"
    assert collision.findtext("surface/friction/ode/mu2") == "0.3"
    assert collision.findtext("surface/contact/ode/kp") == "1000000.0"
    assert collision.findtext("surface/contact/ode/kd") == "1.0"
    dropped = [d.element for d in result.diagnostics]
    assert not [e for e in dropped if e and ("/kp" in e or "/kd" in e or "/mu" in e)], dropped
    (tmp_path / "arm.sdf").write_bytes(result.files["arm.sdf"])
    back = read(str(tmp_path / "arm.sdf"))[0]
    assert back.robot is not None and not back.diagnostics


FRAMES = FIXTURES / "newuser" / "massless_sensor_frames.urdf"


def test_massless_links_on_fixed_joints_become_frames_and_weigh_nothing_in_drake(tmp_path: Path) -> None:
    """Drake reads the SDF export with SDFormat's rules (libsdformat): the base_footprint root, the
    lidar's scan frame, a mount and a flange become <frame>s (no 1 kg each); the link a plugin looks
    up stays a link,
    with its 1 kg reported (new-user report of 2026-11-26, problem 1)."""
    pytest.importorskip("pydrake")
    from pydrake.multibody.parsing import Parser
    from pydrake.multibody.plant import MultibodyPlant

    source = read(str(FRAMES))[0].robot
    assert source is not None
    out = tmp_path / "rover.sdf"
    urdftool.to_sdf(source, out)
    plant = MultibodyPlant(0.0)
    Parser(plant).AddModels(str(out))
    plant.Finalize()
    context = plant.CreateDefaultContext()
    declared = sum(link.inertial.mass for link in source.links if link.inertial is not None)
    assert plant.CalcTotalMass(context) == pytest.approx(declared + 1.0)  # imu_link, reported
    poses = KinematicTree.of(source).forward_kinematics({})
    base = plant.GetFrameByName("base_footprint").CalcPoseInWorld(context).inverse()
    for name, carrier in (("base_footprint", "base_link"), ("laser", "lidar_link"), ("mount", "base_link"),
                          ("flange", "base_link")):
        frame = plant.GetFrameByName(name)
        assert frame.body().name() == carrier
        np.testing.assert_allclose((base @ frame.CalcPoseInWorld(context)).GetAsMatrix4(),
                                   poses[name], atol=1e-12)
    tool = base @ plant.GetBodyByName("tool").EvalPoseInWorld(context)
    np.testing.assert_allclose(tool.GetAsMatrix4(), poses["tool"], atol=1e-12)


def test_frames_carry_their_visuals_and_sensors_into_the_link(tmp_path: Path) -> None:
    from lxml import etree

    source = read(str(FRAMES))[0].robot
    assert source is not None
    text = urdftool.to_sdf(source)
    model = etree.fromstring(text.encode()).find("model")
    assert model is not None
    assert [f.get("name") for f in model.iter("frame")] == ["base_footprint", "laser", "mount", "flange"]
    assert model.find("link[@name='base_link']/visual[@name='mount_visual']") is not None
    sensor = model.find("link[@name='lidar_link']/sensor")
    assert sensor is not None and sensor.findtext("pose").split()[:3] == ["-0.01", "0", "0.031"]
    assert model.find("joint[@name='tool_joint']/parent").text == "base_link"
    assert model.find("link[@name='tool']/pose").get("relative_to") == "flange"
    assert model.find("joint[@name='lidar_to_laser']") is None
    conversion_findings = convert_robot(source, "sdf", tmp_path / "r.sdf", ExportOptions()).diagnostics
    kept = [d for d in conversion_findings if d.code == "C001"]
    assert [d.element for d in kept] == ["link[imu_link]"] and "plugin 'imu_plugin'" in kept[0].message
