"""Fixed joints fused for PyBullet: exact composite inertia, fused frames kept, loaded in PyBullet."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import urdftool
from tests.conftest import ERD
from urdftool.backends.pybullet import PyBulletLoad
from urdftool.cli import main
from urdftool.export import ExportOptions, export_model
from urdftool.export.pybullet_fuse import fuse_fixed, read_fused_frames
from urdftool.model import KinematicTree
from urdftool.physics.bodies import rigid_bodies

BOX = '<inertia ixx="{a}" ixy="{ab}" ixz="0" iyy="{b}" iyz="{bc}" izz="{c}"/>'


def _link(name: str, mass: float, com: str, moments: tuple[float, float, float], rpy: str = "0 0 0") -> str:
    a, b, c = moments
    inertia = BOX.format(a=a, b=b, c=c, ab=min(a, b) / 10, bc=min(b, c) / 5)
    return (
        f'<link name="{name}"><inertial><origin xyz="{com}" rpy="{rpy}"/><mass value="{mass}"/>{inertia}'
        f'</inertial><visual><origin xyz="0.01 0 0" rpy="0 0.3 0"/><geometry><box size="0.1 0.05 0.02"/>'
        f'</geometry></visual><collision><origin xyz="0 0.02 0" rpy="0.2 0 0"/><geometry>'
        f'<sphere radius="0.03"/></geometry></collision></link>'
    )


def _fixed(name: str, parent: str, child: str, xyz: str, rpy: str) -> str:
    return (
        f'<joint name="{name}" type="fixed"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="{xyz}" rpy="{rpy}"/></joint>'
    )


#: A base with a welded sensor chain (two fixed joints deep, one of them massless), an arm
#: on a revolute joint carrying a welded tool, and a finger hanging from the tool.
TOY = (
    '<?xml version="1.0"?>\n<robot name="toy">'
    + _link("base", 2.0, "0.01 0.02 0.03", (0.02, 0.03, 0.04), "0.1 0.2 0.3")
    + '<link name="mount"/>'
    + _link("camera", 0.3, "0.02 0 0", (0.001, 0.002, 0.0025), "0 0.4 0")
    + _link("arm", 1.0, "0 0 0.2", (0.01, 0.011, 0.005))
    + _link("tool", 0.5, "0 0.01 0.05", (0.002, 0.003, 0.0035), "0.3 0 0.1")
    + _link("finger", 0.1, "0 0 0.02", (0.0002, 0.0003, 0.00035))
    + _fixed("mount_joint", "base", "mount", "0.1 0 0.2", "0 0 1.2")
    + _fixed("camera_joint", "mount", "camera", "0 0.05 0.01", "0.5 -0.2 0.1")
    + '<joint name="shoulder" type="revolute"><parent link="base"/><child link="arm"/>'
    '<origin xyz="0 0 0.1" rpy="0 0 0.4"/><axis xyz="0 1 0"/>'
    '<limit lower="-1" upper="1" effort="10" velocity="1"/></joint>'
    + _fixed("flange", "arm", "tool", "0 0 0.4", "0.7 0.1 -0.3")
    + '<joint name="grip" type="prismatic"><parent link="tool"/><child link="finger"/>'
    '<origin xyz="0.01 0 0.1" rpy="0 0.2 0"/><axis xyz="1 0 0"/>'
    '<limit lower="0" upper="0.04" effort="5" velocity="0.1"/></joint>'
    "</robot>\n"
)


def _toy(tmp_path: Path) -> Path:
    path = tmp_path / "src" / "toy.urdf"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(TOY)
    return path


def test_fused_inertia_is_the_rigid_body_composite_and_frames_keep_their_pose(tmp_path: Path) -> None:
    robot = urdftool.load(_toy(tmp_path))
    fusion = fuse_fixed(robot)
    assert {(f.link, f.into) for f in fusion.frames} == {
        ("mount", "base"), ("camera", "base"), ("tool", "arm")}
    fused = {link.name: link for link in fusion.robot.links}
    assert set(fused) == {"base", "arm", "finger"}
    assert fusion.robot.total_mass == pytest.approx(robot.total_mass, rel=1e-12)
    # The composite inertia equals the rigid-body composite urdftool's rules use (independent code).
    tree = KinematicTree.of(robot)
    for body in rigid_bodies(tree):
        link = fused[body.head]
        assert link.inertial is not None
        assert link.inertial.mass == pytest.approx(body.mass, rel=1e-12)
        assert np.allclose(link.inertial.inertia_in_link_frame, body.composite_inertia(), rtol=0, atol=1e-15)
    # Visuals and collisions ride along, each re-posed into the kept link's frame.
    assert len(fused["base"].visuals) == 2 and len(fused["arm"].collisions) == 2
    # The finger now hangs from the arm, at the same place; every fused frame keeps its pose.
    source, merged = tree.forward_kinematics({"shoulder": 0.3}), KinematicTree.of(fusion.robot)
    after = merged.forward_kinematics({"shoulder": 0.3})
    assert np.allclose(after["finger"], source["finger"], atol=1e-12)
    for frame in fusion.frames:
        assert np.allclose(after[frame.into] @ frame.pose.matrix, source[frame.link], atol=1e-12)


def test_fuse_fixed_flag_writes_the_frames_and_verifies_in_pybullet(tmp_path: Path) -> None:
    src = _toy(tmp_path)
    out = tmp_path / "out" / "toy.urdf"
    result = CliRunner().invoke(
        main, ["convert", str(src), "-o", str(out), "--to", "pybullet", "--fuse-fixed", "--verify"])
    assert result.exit_code == 0, result.output
    assert "info[C001 conversion-dropped] fuse fixed joints: 3 links" in result.output
    assert "link world position (m)" in result.output  # the fused frames are among those compared
    text = out.read_text()
    assert "fuse fixed joints" in text
    frames = read_fused_frames(text)
    assert set(frames) == {"mount", "camera", "tool"}
    robot = urdftool.load(src)
    poses = KinematicTree.of(robot).forward_kinematics()
    for name, (into, pose) in frames.items():
        relative = np.linalg.inv(poses[into]) @ poses[name]
        assert np.allclose(pose.matrix, relative, rtol=0, atol=1e-12)
    with PyBulletLoad(str(out)) as loaded:
        assert loaded.body is not None and loaded.messages == []
        assert {link.name for link in loaded.links()} == {"base", "arm", "finger"}


def test_without_the_flag_a_small_robot_is_not_fused(tmp_path: Path) -> None:
    result = export_model(urdftool.load(_toy(tmp_path)), "pybullet", tmp_path / "o.urdf", ExportOptions())
    text = result.files["o.urdf"].decode()
    assert "fused frames" not in text and '<link name="camera">' in text


def test_odd_link_names_survive_the_frames_comment(tmp_path: Path) -> None:
    src = _toy(tmp_path)
    src.write_text(src.read_text().replace('"camera"', '"cam--era%"'))
    out = tmp_path / "o.urdf"
    result = export_model(urdftool.load(src), "pybullet", out, ExportOptions(fuse_fixed=True))
    assert not result.failed
    assert set(read_fused_frames(result.files["o.urdf"].decode())) == {"mount", "cam--era%", "tool"}


TIAGO_DUAL = "tiago_description/robots/tiago_dual.urdf"


@pytest.mark.slow  # loads and converts a 129-joint robot with its meshes (~5 s)
def test_tiago_dual_is_fused_automatically_and_keeps_mass_and_frames(tmp_path: Path) -> None:
    """129 joints: too many for PyBullet to report, so the fixed ones are fused (a warning says so)."""
    assert ERD is not None
    src = ERD / TIAGO_DUAL
    out = tmp_path / "robot.urdf"
    result = CliRunner().invoke(main, ["convert", str(src), "-o", str(out), "--to", "pybullet", "--verify"])
    assert result.exit_code == 0, result.output
    assert "warning[C001 conversion-dropped] the robot has 129 joints" in result.output
    robot = urdftool.load(src)
    tree = KinematicTree.of(robot)
    frames = read_fused_frames(out.read_text())
    # base_footprint (massless root) is re-rooted below base_link first, then fused into it
    fixed = {j.child for j in robot.joints if j.type.value == "fixed"}
    assert set(frames) == fixed - {"base_link"} | {"base_footprint"} and len(frames) == 28
    poses = tree.forward_kinematics()
    for name, (into, pose) in frames.items():
        relative = np.linalg.inv(poses[into]) @ poses[name]
        assert np.allclose(pose.matrix, relative, rtol=0, atol=1e-9), name
    with PyBulletLoad(str(out)) as loaded:
        assert loaded.body is not None and loaded.messages == []
        links = loaded.links()
        assert len(links) == 102  # the base and 101 joints: PyBullet reports every state
        total = sum(link.mass for link in links)
        frames_world = loaded.link_frames({})
    assert total == pytest.approx(robot.total_mass, rel=1e-9, abs=0)
    # In PyBullet too, each fused frame (placed from its link) sits where the source puts it.
    root = frames_world["base_link"]
    for name, (into, pose) in frames.items():
        built = np.linalg.inv(root) @ frames_world[into] @ pose.matrix
        expected = np.linalg.inv(poses["base_link"]) @ poses[name]
        assert np.allclose(built, expected, rtol=0, atol=1e-6), name


def test_a_massless_world_root_stays_massless_and_fixed(tmp_path: Path) -> None:
    """Fusing the arm's base into a massless ``world`` root would give PyBullet a base with mass,
    which floats: the root keeps its fixed children as links."""
    src = _toy(tmp_path)
    src.write_text(src.read_text().replace(
        '<link name="mount"/>',
        '<link name="mount"/><link name="world"/><joint name="bolt" type="fixed"><parent link="world"/>'
        '<child link="base"/><origin xyz="0 0 0.3"/></joint>'))
    out = tmp_path / "o.urdf"
    result = export_model(urdftool.load(src), "pybullet", out, ExportOptions(fuse_fixed=True))
    assert not result.failed
    text = result.files["o.urdf"].decode()
    assert "base: fixed to the world" in text
    assert set(read_fused_frames(text)) == {"mount", "camera", "tool"}  # into base and arm, not world
    out.write_bytes(text.encode())
    with PyBulletLoad(str(out)) as loaded:
        masses = {link.name: link.mass for link in loaded.links()}
    assert masses["world"] == 0 and masses["base"] > 0
