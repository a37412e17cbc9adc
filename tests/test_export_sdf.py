"""URDF → SDF export: every tree-shaped model in example-robot-data round-trips exactly."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import urdftool
from tests.conftest import ERD, FIXTURES, erd_urdfs
from urdftool.cli import main
from urdftool.model import KinematicTree, Robot
from urdftool.parse import read


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
    for seed in (0, 1, 2):
        q = _configuration(source, tree, seed)
        q_back = {name_by_child[source.joint(n).child]: v for n, v in q.items()}
        poses, poses_back = tree.forward_kinematics(q), tree_back.forward_kinematics(q_back)
        assert set(poses) == set(poses_back)
        for link, pose in poses.items():
            np.testing.assert_allclose(poses_back[link], pose, atol=1e-9, rtol=0, err_msg=link)
    for link in source.links:
        other = back.link(link.name)
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
