"""MJCF export: joint mapping, inertia, assets, actuators, equality, keyframe, scene, CLI and API.

Every exported model here is compiled by MuJoCo; equivalence is checked by the
verifier (MuJoCo against Pinocchio) wherever the model has dynamics.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import mujoco
import numpy as np
import pytest
from click.testing import CliRunner
from lxml import etree

import urdftool
from tests.conftest import ERD, FIXTURES, SEEDS
from urdftool.cli import main
from urdftool.export import ExportOptions
from urdftool.export.mjcf import export
from urdftool.export.mjcf_verify import verify
from urdftool.parse import read
from urdftool.parse.packages import PackageResolver

ARM = FIXTURES / "robots" / "two_link_arm.urdf"
BOX = (
    '<inertial><mass value="1"/>'
    '<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>'
)

JOINTS_URDF = f"""<?xml version="1.0"?>
<robot name="joints">
  <link name="base">{BOX}</link>
  <link name="slider">{BOX}</link>
  <link name="planar">{BOX}</link>
  <link name="ball">{BOX}</link>
  <link name="wheel">{BOX}</link>
  <link name="finger">{BOX}</link>
  <link name="tilted">
    <inertial><origin xyz="0.1 0 0" rpy="0.3 -0.2 0.1"/><mass value="2"/>
      <inertia ixx="0.02" ixy="0.001" ixz="0" iyy="0.03" iyz="0" izz="0.04"/></inertial>
  </link>
  <joint name="slide" type="prismatic"><parent link="base"/><child link="slider"/>
    <origin xyz="0 0 0.1" rpy="0 0.5 0"/><axis xyz="1 1 0"/>
    <limit lower="0.2" upper="0.4" effort="50" velocity="1"/><dynamics damping="0.5" friction="0.1"/></joint>
  <joint name="plane" type="planar"><parent link="slider"/><child link="planar"/><axis xyz="0 1 1"/></joint>
  <joint name="sphere" type="spherical"><parent link="planar"/><child link="ball"/>
    <origin xyz="0.2 0 0"/></joint>
  <joint name="spin" type="continuous"><parent link="ball"/><child link="wheel"/><axis xyz="0 0 1"/>
    <limit effort="3" velocity="10"/></joint>
  <joint name="follow" type="revolute"><parent link="wheel"/><child link="finger"/><axis xyz="1 0 0"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/>
    <mimic joint="spin" multiplier="-0.5" offset="0.25"/></joint>
  <joint name="weld" type="fixed"><parent link="finger"/><child link="tilted"/>
    <origin xyz="0 0.1 0" rpy="1 0 0"/></joint>
</robot>
"""


def load_text(tmp_path: Path, text: str, name: str = "robot.urdf") -> urdftool.Robot:
    path = tmp_path / name
    path.write_text(text)
    robot = read(path)[0].robot
    assert robot is not None
    return robot


def write(result, out: Path) -> None:  # type: ignore[no-untyped-def]
    assert not result.failed, [d.message for d in result.diagnostics]
    for rel, data in result.files.items():
        (out.parent / rel).parent.mkdir(parents=True, exist_ok=True)
        (out.parent / rel).write_bytes(data)


def exported(robot, tmp_path: Path, **options) -> tuple[Path, etree._Element]:  # type: ignore[no-untyped-def]
    out = tmp_path / "out" / "robot.xml"
    write(export(robot, out, ExportOptions(**options)), out)
    return out, etree.parse(str(out)).getroot()


def test_every_joint_type_maps_and_verifies(tmp_path: Path) -> None:
    robot = load_text(tmp_path, JOINTS_URDF)
    out, root = exported(robot, tmp_path)
    joints = {j.get("name"): j for j in root.iter("joint") if j.getparent().tag == "body"}
    assert joints["slide"].get("type") == "slide" and joints["slide"].get("range") == "0.2 0.4"
    assert joints["slide"].get("damping") == "0.5" and joints["slide"].get("frictionloss") == "0.1"
    assert [joints[f"plane_{s}"].get("type") for s in ("x", "y", "rot")] == ["slide", "slide", "hinge"]
    assert joints["sphere"].get("type") == "ball"
    assert joints["spin"].get("type") == "hinge" and joints["spin"].get("range") is None
    assert joints["spin"].get("actuatorfrcrange") == "-3 3"
    assert root.find(".//body[@name='tilted']").find("joint") is None  # fixed: a body, no joint
    verdict = verify(robot, out, ExportOptions())
    assert verdict.ok, verdict.rows
    assert [row[0] for row in verdict.rows][1:] == [
        "link positions (m), 20 configurations", "link orientations (rad)",
        "total mass (relative)", "joint-space mass matrix (relative)"]


def test_mimic_polynomial_in_mujocos_direction(tmp_path: Path) -> None:
    robot = load_text(tmp_path, JOINTS_URDF)
    out, root = exported(robot, tmp_path)
    equality = root.find("equality/joint")
    assert (equality.get("joint1"), equality.get("joint2")) == ("follow", "spin")
    assert equality.get("polycoef") == "0.25 -0.5 0 0 0"
    model = mujoco.MjModel.from_xml_path(str(out))
    key = model.key_qpos[0]
    follow = model.jnt_qposadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, "follow")]
    assert key[follow] == pytest.approx(0.25)  # offset + multiplier * 0


def test_home_keyframe_clamped_into_limits(tmp_path: Path) -> None:
    robot = load_text(tmp_path, JOINTS_URDF)
    out, root = exported(robot, tmp_path)
    model = mujoco.MjModel.from_xml_path(str(out))
    slide = model.jnt_qposadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, "slide")]
    assert model.key_qpos[0][slide] == 0.2
    assert root.find("keyframe/key").get("name") == "home"


def test_inertial_rotation_is_honoured(tmp_path: Path) -> None:
    robot = load_text(tmp_path, JOINTS_URDF)
    out, root = exported(robot, tmp_path)
    inertial = root.find(".//body[@name='tilted']/inertial")
    assert inertial.get("fullinertia") is not None and inertial.get("quat") is None
    model = mujoco.MjModel.from_xml_path(str(out))
    body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "tilted")
    link = robot.link("tilted")
    assert link is not None and link.inertial is not None
    rot = np.zeros(9)
    mujoco.mju_quat2Mat(rot, model.body_iquat[body])
    rot = rot.reshape(3, 3)
    np.testing.assert_allclose(rot @ np.diag(model.body_inertia[body]) @ rot.T,
                               link.inertial.inertia_in_link_frame, atol=1e-15)


def test_output_is_byte_identical_on_reruns(tmp_path: Path) -> None:
    robot = load_text(tmp_path, JOINTS_URDF)
    first = export(robot, tmp_path / "a.xml", ExportOptions(actuators="position", scene=True))
    second = export(robot, tmp_path / "a.xml", ExportOptions(actuators="position", scene=True))
    assert first.files == second.files


def test_floating_base_auto_free_fixed(tmp_path: Path) -> None:
    arm = read(ARM)[0].robot
    _, root = exported(arm, tmp_path)
    assert root.find(".//freejoint") is None
    _, root = exported(arm, tmp_path, floating_base="free")
    assert root.find("worldbody/body/freejoint").get("name") == "floating_base"
    assert ERD is not None
    solo = read(ERD / "solo_description" / "robots" / "solo12.urdf")[0].robot
    _, root = exported(solo, tmp_path)
    assert root.find("worldbody/body/freejoint") is not None
    assert "4 legs" in root[0].text
    _, root = exported(solo, tmp_path, floating_base="fixed")
    assert root.find(".//freejoint") is None


def test_actuators_motor_and_position(tmp_path: Path) -> None:
    robot = load_text(tmp_path, JOINTS_URDF)
    out, root = exported(robot, tmp_path, actuators="motor")
    motors = {m.get("joint"): m for m in root.iter("motor")}
    assert set(motors) == {"slide", "spin"}  # the mimic follower has no actuator
    assert motors["spin"].get("ctrlrange") == "-3 3"
    out, root = exported(robot, tmp_path, actuators="position")
    position = {p.get("joint"): p for p in root.iter("position")}
    kp, kv = float(position["slide"].get("kp")), float(position["slide"].get("kv"))
    moved = kv**2 / (4 * kp)  # critically damped: kv = 2 sqrt(kp I)
    assert moved * (2 * np.pi * 10) ** 2 <= kp * (1 + 1e-9)
    assert kv >= kp * 0.002  # stable at the 2 ms step with the damping integrated implicitly
    assert float(position["slide"].get("kv")) > 0 and position["slide"].get("ctrlrange") == "0.2 0.4"
    mujoco.MjModel.from_xml_path(str(out))


def test_mesh_assets_named_by_content_and_deduplicated(tmp_path: Path) -> None:
    dae = FIXTURES / "rules" / "C004" / "good_mesh.dae"
    for folder in ("visual", "collision", "copy"):
        (tmp_path / folder).mkdir()
    shutil.copy(dae, tmp_path / "visual" / "x.dae")
    shutil.copy(dae, tmp_path / "copy" / "x.dae")
    # a different mesh under the same file name
    (tmp_path / "collision" / "x.dae").write_text(dae.read_text().replace("0.05", "0.07"))
    link = (
        f'<link name="base">{BOX}'
        '<visual><geometry><mesh filename="visual/x.dae"/></geometry></visual>'
        '<visual><geometry><mesh filename="copy/x.dae"/></geometry></visual>'
        '<collision><geometry><mesh filename="collision/x.dae" scale="2 2 2"/></geometry></collision></link>'
    )
    robot = load_text(tmp_path, f'<robot name="m">{link}</robot>')
    out, root = exported(robot, tmp_path)
    meshes = root.findall("asset/mesh")
    assert len(meshes) == 2 and meshes[1].get("scale") == "2 2 2"
    assert len({m.get("file") for m in meshes}) == 2
    assert all(m.get("file").startswith("assets/") and (out.parent / m.get("file")).is_file() for m in meshes)
    geoms = root.findall(".//geom")
    assert geoms[0].get("mesh") == geoms[1].get("mesh") != geoms[2].get("mesh")
    model = mujoco.MjModel.from_xml_path(str(out))
    assert model.nmesh == 2
    visual = [g for g in geoms if g.get("class") == "visual"]
    assert all(g.get("class") == "visual" for g in visual)


def test_visual_and_collision_groups(tmp_path: Path) -> None:
    out, _root = exported(read(ARM)[0].robot, tmp_path)
    model = mujoco.MjModel.from_xml_path(str(out))
    visual = [i for i in range(model.ngeom) if model.geom_group[i] == 2]
    collision = [i for i in range(model.ngeom) if model.geom_group[i] == 3]
    assert visual and collision
    assert all(model.geom_contype[i] == 0 and model.geom_conaffinity[i] == 0 for i in visual)
    assert all(model.geom_contype[i] == 1 for i in collision)
    assert tuple(model.geom_rgba[visual[0]]) == pytest.approx((0.2, 0.3, 0.8, 1.0))


@pytest.mark.parametrize("xacro", ["hyundai_ngv/m_robot_description/urdf/m_robot.xacro",
                                   "go_chase_it/my_robot/urdf/my_robot.xacro"])
def test_seed_robots_keep_sensor_links_with_scene(xacro: str, tmp_path: Path) -> None:
    loaded = read(SEEDS / xacro, None, PackageResolver.create(None, [str(SEEDS)]))[0]
    robot = loaded.robot
    assert robot is not None
    out = tmp_path / "robot.xml"
    result = export(robot, out, ExportOptions(scene=True, repair_inertia=True))
    write(result, out)
    model = mujoco.MjModel.from_xml_path(str(out))
    repaired = {d.data["link"]: d.data["after"]["mass"] for d in result.diagnostics if d.code == "C002"}
    sensors = [link for link in robot.links if any(k in link.name for k in ("camera", "laser", "hokuyo"))]
    assert sensors
    for link in sensors:
        body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, link.name)
        assert body > 0, f"{link.name} lost its body"
        source = link.inertial.mass if link.inertial else 0.0
        assert model.body_mass[body] == pytest.approx(repaired.get(link.name, source))
    assert mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "floor") >= 0
    dropped = [d for d in result.diagnostics if d.code == "C001"]
    assert any("plugin" in d.message for d in dropped) and all(d.location for d in dropped)
    for mesh in (m for m in range(model.nmesh)):
        assert model.mesh_vertnum[mesh] > 0
    assert verify(robot, out, ExportOptions(scene=True, repair_inertia=True)).ok


def test_loop_closures_become_equalities_at_their_anchors(tmp_path: Path) -> None:
    assert ERD is not None
    robot = read(ERD / "cassie_description" / "robots" / "cassie_v2.sdf")[0].robot
    assert robot is not None and robot.loop_closures
    out, root = exported(robot, tmp_path)
    model = mujoco.MjModel.from_xml_path(str(out))
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    connects = root.findall("equality/connect")
    assert connects
    for connect in connects:
        a = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, connect.get("site1"))
        b = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, connect.get("site2"))
        # the loop is closed at the model's zero configuration: both anchors coincide
        assert np.linalg.norm(data.site_xpos[a] - data.site_xpos[b]) < 1e-6


def test_to_mjcf_api(tmp_path: Path) -> None:
    text = urdftool.to_mjcf(ARM)
    assert text.startswith("<mujoco") and not list(tmp_path.iterdir())
    out = tmp_path / "arm.xml"
    assert urdftool.to_mjcf(ARM, out, actuators="motor") == out.read_text()
    with pytest.raises(urdftool.ConversionRefused) as refused:
        urdftool.to_mjcf(FIXTURES / "rules" / "C003" / "bad.urdf")
    assert {d.code for d in refused.value.diagnostics if d.severity.value == "error"} == {"C003"}
    assert "<mujoco" in urdftool.to_mjcf(FIXTURES / "rules" / "C003" / "bad.urdf", repair_inertia=True)


def test_cli_convert_verify_and_check(tmp_path: Path) -> None:
    runner = CliRunner()
    out = tmp_path / "arm.xml"
    result = runner.invoke(main, ["convert", str(ARM), "-o", str(out), "--verify"])
    assert result.exit_code == 0, result.output
    assert "joint-space mass matrix" in result.output and "FAIL" not in result.output
    fresh = runner.invoke(main, ["convert", str(ARM), "-o", str(out), "--check"])
    assert fresh.exit_code == 0 and f"{out}: up to date" in fresh.output
    out.write_text(out.read_text().replace("damping", "armature"))
    stale = runner.invoke(main, ["convert", str(ARM), "-o", str(out), "--check"])
    assert stale.exit_code == 1 and "stale (differs from what would be written)" in stale.output
    out.unlink()
    gone = runner.invoke(main, ["convert", str(ARM), "-o", str(out), "--check"])
    assert gone.exit_code == 1 and f"{out}: missing" in gone.output
    refused = runner.invoke(main, ["convert", str(FIXTURES / "rules" / "C003" / "bad.urdf"), "-o",
                                   str(tmp_path / "bad.xml")])
    assert refused.exit_code == 1 and "C003" in refused.output and not (tmp_path / "bad.xml").exists()


def test_verify_catches_a_different_robot(tmp_path: Path) -> None:
    robot = read(ARM)[0].robot
    out, _ = exported(robot, tmp_path)
    out.write_text(out.read_text().replace('mass="1"', 'mass="1.5"', 1))
    verdict = verify(robot, out, ExportOptions())
    failed = {row[0] for row in verdict.rows if not row[3]}
    assert not verdict.ok and "total mass (relative)" in failed
    assert "joint-space mass matrix (relative)" in failed
    assert all(d.code == "C005" for d in verdict.diagnostics)


def test_gazebo_friction_reaches_the_collision_geoms(tmp_path: Path) -> None:
    """`<gazebo reference><mu1>/<mu2>` become MuJoCo's sliding friction on that link's collision
    geoms: the smaller of the two, at most MU_MAX (learning_ros's mobot writes 100000)."""
    robot = read(SEEDS / "learning_ros" / "mobot_urdf" / "urdf" / "mobot_w_lidar.urdf")[0].robot
    assert robot is not None
    out, _root = exported(robot, tmp_path)
    model = mujoco.MjModel.from_xml_path(str(out))
    wheel = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "left_wheel")
    geoms = [i for i in range(model.ngeom) if model.geom_bodyid[i] == wheel and model.geom_group[i] == 3]
    assert geoms and all(model.geom_friction[i][0] == pytest.approx(3.0) for i in geoms)
    base = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, robot.links[0].name)
    others = [i for i in range(model.ngeom) if model.geom_bodyid[i] == base and model.geom_group[i] == 3]
    assert all(model.geom_friction[i][0] == pytest.approx(1.0) for i in others)  # MuJoCo's default
    source = tmp_path / "pair.urdf"
    source.write_text(
        '<robot name="r"><link name="a"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" '
        'ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial><collision><geometry><sphere radius="0.1"/>'
        '</geometry></collision></link><gazebo reference="a"><mu1>0.8</mu1><mu2 value="0.6"/></gazebo>'
        '</robot>')
    out, _root = exported(read(source)[0].robot, tmp_path / "pair")
    model = mujoco.MjModel.from_xml_path(str(out))
    assert model.geom_friction[0][0] == pytest.approx(0.6)


def test_scene_for_a_fixed_robot_without_collision_geometry(tmp_path: Path) -> None:
    """The floor of a fixed robot with nothing to collide stays at z = 0 (it raised TypeError)."""
    robot = load_text(tmp_path, f'<robot name="ghost"><link name="base">{BOX}<visual><geometry>'
                                '<box size="0.1 0.1 0.1"/></geometry></visual></link></robot>')
    out, root = exported(robot, tmp_path, scene=True)
    floor = root.find("worldbody/geom[@name='floor']")
    assert floor is not None and floor.get("pos") is None
    mujoco.MjModel.from_xml_path(str(out))
