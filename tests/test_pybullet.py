"""The PyBullet-ready URDF export, checked by loading every output in PyBullet (DIRECT)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from click.testing import CliRunner

import urdftool
from tests.conftest import SEEDS
from urdftool.backends.pybullet import PyBulletLoad, engine_messages, import_pybullet
from urdftool.cli import main
from urdftool.export import ExportOptions, export_model, verify_model
from urdftool.export.pybullet_meshes import dominant_colour

INERTIA = '<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>'
LINK = '<link name="{name}"><inertial><mass value="1"/>' + INERTIA + "</inertial></link>"


def robot_file(tmp_path: Path, body: str, name: str = "in.urdf") -> Path:
    path = tmp_path / "src" / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(f'<?xml version="1.0"?>\n<robot name="toy">\n{body}\n</robot>\n')
    return path


def revolute(name: str, parent: str, child: str, extra: str = "") -> str:
    return (
        f'<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="0 0 0.5" rpy="0.1 0.2 0.3"/><axis xyz="0 1 0"/>'
        f'<limit lower="-1" upper="1" effort="5" velocity="2"/>{extra}</joint>'
    )


def convert(*args: str) -> tuple[int, str]:
    result = CliRunner().invoke(main, ["convert", *args, "--to", "pybullet"])
    return result.exit_code, result.output


def test_arm_converts_loads_and_verifies(tmp_path: Path) -> None:
    src = robot_file(
        tmp_path,
        LINK.format(name="base") + LINK.format(name="arm") + revolute("shoulder", "base", "arm"),
    )
    out = tmp_path / "out" / "toy.urdf"
    code, output = convert(str(src), "-o", str(out), "--verify")
    assert code == 0, output
    assert "link world position (m)" in output
    text = out.read_text()
    assert "URDF_USE_INERTIA_FROM_FILE" in text and "../src/in.urdf" in text
    with PyBulletLoad(str(out)) as loaded:
        assert loaded.body is not None and loaded.messages == []


def test_missing_inertial_on_moving_link_is_refused_then_repaired(tmp_path: Path) -> None:
    body = (
        LINK.format(name="base") + '<link name="arm"><collision><geometry><box size="0.1 0.1 0.4"/>'
        "</geometry></collision></link>" + revolute("shoulder", "base", "arm")
    )
    src = robot_file(tmp_path, body)
    out = tmp_path / "out" / "toy.urdf"
    code, output = convert(str(src), "-o", str(out))
    assert (
        code == 1 and "inertia-not-exportable" in output and "in.urdf:3:131:" in output
    )  # <link name="arm">
    assert not out.exists()
    code, output = convert(str(src), "-o", str(out), "--repair-inertia", "--verify")
    assert code == 0, output
    assert "inertia-repaired" in output


def test_massless_fixed_link_is_written_with_zero_mass(tmp_path: Path) -> None:
    body = (
        LINK.format(name="base")
        + LINK.format(name="arm")
        + '<link name="tool"/>'
        + revolute("shoulder", "base", "arm")
        + '<joint name="flange" type="fixed"><parent link="arm"/><child link="tool"/></joint>'
    )
    src = robot_file(tmp_path, body)
    out = tmp_path / "toy.urdf"
    assert convert(str(src), "-o", str(out), "--verify")[0] == 0
    with PyBulletLoad(str(out)) as loaded:
        masses = {link.name: link.mass for link in loaded.links()}
    assert masses == {"base": 1.0, "arm": 1.0, "tool": 0.0}  # PyBullet alone would give 'tool' 1 kg


def test_invalid_tensor_is_refused_at_its_line(tmp_path: Path) -> None:
    bad = (
        '<link name="arm"><inertial><mass value="1"/>'
        '<inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.3"/></inertial></link>'
    )
    src = robot_file(tmp_path, LINK.format(name="base") + bad + revolute("shoulder", "base", "arm"))
    result = export_model(urdftool.load(src), "pybullet", tmp_path / "o.urdf", ExportOptions())
    assert result.failed and not result.files
    (error,) = [d for d in result.diagnostics if d.name == "inertia-not-exportable"]
    line = src.read_text().splitlines()[2]
    column = line.index("<inertial>", line.index('name="arm"')) + 1
    assert error.location is not None and (error.location.line, error.location.column) == (
        3,
        column,
    )


def test_non_unit_axis_is_normalised(tmp_path: Path) -> None:
    body = (
        LINK.format(name="base")
        + LINK.format(name="slider")
        + '<joint name="slide" type="prismatic"><parent link="base"/><child link="slider"/>'
        '<axis xyz="0 0 2"/><limit lower="0" upper="1" effort="5" velocity="1"/></joint>'
    )
    out = tmp_path / "toy.urdf"
    code, output = convert(str(robot_file(tmp_path, body)), "-o", str(out), "--verify")
    assert code == 0, output
    assert '<axis xyz="0 0 1"/>' in out.read_text()


def test_floating_joint_is_refused(tmp_path: Path) -> None:
    body = (
        LINK.format(name="world_link")
        + LINK.format(name="body")
        + '<joint name="free" type="floating"><parent link="world_link"/><child link="body"/></joint>'
    )
    code, output = convert(str(robot_file(tmp_path, body)), "-o", str(tmp_path / "o.urdf"))
    assert code == 1 and "floating" in output and "useFixedBase" in output


def test_mimic_is_reported_with_a_gear_recipe_that_works(tmp_path: Path) -> None:
    body = (
        LINK.format(name="base")
        + LINK.format(name="a")
        + LINK.format(name="b")
        + revolute("ja", "base", "a")
        + revolute("jb", "base", "b", '<mimic joint="ja" multiplier="0.5"/>')
    )
    src = robot_file(tmp_path, body)
    out = tmp_path / "toy.urdf"
    result = export_model(urdftool.load(src), "pybullet", out, ExportOptions())
    (mimic,) = [d for d in result.diagnostics if d.name == "conversion-dropped"]
    assert mimic.help and "JOINT_GEAR" in mimic.help and "gearRatio=-0.5" in mimic.help
    out.write_bytes(result.files["toy.urdf"])
    assert verify_model(urdftool.load(src), "pybullet", out, ExportOptions()).ok
    p = import_pybullet()
    client = p.connect(p.DIRECT)
    try:
        robot = p.loadURDF(str(out), flags=p.URDF_USE_INERTIA_FROM_FILE, physicsClientId=client)
        p.setGravity(0, 0, 0, physicsClientId=client)
        # The recipe: a = index of the mimic joint, b = index of the joint it follows.
        gear = p.createConstraint(
            robot,
            1,
            robot,
            0,
            jointType=p.JOINT_GEAR,
            jointAxis=[0, 0, 1],
            parentFramePosition=[0, 0, 0],
            childFramePosition=[0, 0, 0],
            physicsClientId=client,
        )
        p.changeConstraint(gear, gearRatio=-0.5, maxForce=100, physicsClientId=client)
        p.setJointMotorControl2(robot, 1, p.VELOCITY_CONTROL, force=0, physicsClientId=client)
        p.setJointMotorControl2(
            robot, 0, p.VELOCITY_CONTROL, targetVelocity=1, force=5, physicsClientId=client
        )
        for _ in range(240):
            p.stepSimulation(physicsClientId=client)
        target = p.getJointState(robot, 0, physicsClientId=client)[0]
        follower = p.getJointState(robot, 1, physicsClientId=client)[0]
    finally:
        p.disconnect(physicsClientId=client)
    assert target > 0.5 and follower == pytest.approx(0.5 * target, rel=1e-2)


def test_verify_fails_on_a_file_that_differs_from_the_source(tmp_path: Path) -> None:
    src = robot_file(
        tmp_path,
        LINK.format(name="base") + LINK.format(name="arm") + revolute("shoulder", "base", "arm"),
    )
    out = tmp_path / "toy.urdf"
    assert convert(str(src), "-o", str(out))[0] == 0
    out.write_text(out.read_text().replace('<axis xyz="0 1 0"/>', '<axis xyz="1 0 0"/>'))
    outcome = verify_model(urdftool.load(src), "pybullet", out, ExportOptions())
    assert not outcome.ok
    failed = {d.element for d in outcome.diagnostics}
    assert "joint[shoulder]" in failed
    assert all(d.name == "engine-rejected" and d.location is not None for d in outcome.diagnostics)


def test_pybullet_warnings_are_captured_from_c(tmp_path: Path) -> None:
    bad = (
        '<link name="arm"><inertial><mass value="1"/>'
        '<inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.3"/></inertial></link>'
    )
    path = robot_file(
        tmp_path, LINK.format(name="base") + bad + revolute("shoulder", "base", "arm")
    )
    with PyBulletLoad(str(path)) as loaded:
        assert loaded.body is not None
        assert any("Bad inertia tensor" in m and "arm" in m for m in loaded.messages)


def test_engine_messages_split_markers() -> None:
    text = (
        "b3Warning[a.cpp,1]:\nNo inertial data for link, using mass=1b3Warning[a.cpp,1]:\nwheel\n"
        "Warning: joint unsupported, creating a fixed joint instead.\n"
    )
    assert engine_messages(text) == [
        "No inertial data for link, using mass=1",
        "wheel",
        "Warning: joint unsupported, creating a fixed joint instead.",
    ]


def test_reruns_are_byte_identical_and_check_detects_staleness(tmp_path: Path) -> None:
    src = SEEDS / "gazebo_ros_demos" / "rrbot_description" / "urdf" / "rrbot.xacro"
    out = tmp_path / "rrbot.urdf"
    assert convert(str(src), "-o", str(out))[0] == 0
    before = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()}
    assert convert(str(src), "-o", str(out))[0] == 0
    assert {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()} == before
    assert convert(str(src), "-o", str(out), "--check")[0] == 0
    asset = next(p for p in before if p.suffix == ".obj")
    asset.write_bytes(b"# edited\n")
    assert convert(str(src), "-o", str(out), "--check")[0] == 1


@pytest.mark.parametrize(
    "seed",
    [
        "go_chase_it/my_robot/urdf/my_robot.xacro",
        "gazebo_ros_demos/rrbot_description/urdf/rrbot.xacro",
    ],
)
def test_seed_lidar_dae_is_loaded_as_coloured_obj(seed: str, tmp_path: Path) -> None:
    src = SEEDS / seed
    out = tmp_path / "robot.urdf"
    code, output = convert(str(src), "-o", str(out), "--verify")
    assert code == 0, output
    dae = next(SEEDS.glob(f"{seed.split('/')[0]}/**/hokuyo.dae"))
    colour = dominant_colour(str(dae))
    assert colour is not None
    with PyBulletLoad(str(out)) as loaded:
        assert loaded.body is not None and loaded.messages == []
        p, client = loaded._p, loaded._client
        shapes = p.getVisualShapeData(loaded.body, physicsClientId=client)
    lidar = [s for s in shapes if s[4].decode().endswith(".obj") and "hokuyo" in s[4].decode()]
    assert lidar, "the Hokuyo mesh is loaded"
    assert all(math.isclose(a, b, abs_tol=1e-6) for a, b in zip(lidar[0][7], colour, strict=True))


def test_copy_assets_puts_every_mesh_beside_out(tmp_path: Path) -> None:
    src = SEEDS / "gazebo_ros_demos" / "rrbot_description" / "urdf" / "rrbot.xacro"
    out = tmp_path / "rrbot.urdf"
    assert convert(str(src), "-o", str(out), "--copy-assets", "--verify")[0] == 0
    text = out.read_text()
    assert "package://" not in text and 'filename="assets/' in text


def test_python_api_flavor(tmp_path: Path) -> None:
    src = robot_file(
        tmp_path,
        LINK.format(name="base") + LINK.format(name="arm") + revolute("shoulder", "base", "arm"),
    )
    out = tmp_path / "api.urdf"
    text = urdftool.api.to_urdf(src, out, flavor="pybullet")
    assert out.read_text() == text and "URDF_USE_INERTIA_FROM_FILE" in text
    with pytest.raises(ValueError):
        urdftool.api.to_urdf(src, flavor="bullet")
