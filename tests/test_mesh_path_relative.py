"""mesh-path-relative (M009): which mesh paths are bare relative paths, when that is worth saying,
and the engines' behaviour the target table claims (MuJoCo, PyBullet and Drake resolve such a path
against the URDF's folder; Pinocchio looks it up in its package_dirs only)."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from tests.conftest import FIXTURES
from urdftool.pipeline.check import CheckOptions, check_file
from urdftool.rules.meshes import is_bare_relative

CUBE = FIXTURES / "rules" / "M004" / "meshes" / "cube.stl"
ROBOT = """<robot name="r">
  <link name="a">
    <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
    <visual><geometry><mesh filename="meshes/link1.stl"/></geometry></visual>
    <collision><geometry><mesh filename="meshes/link1.stl"/></geometry></collision>
  </link>
</robot>
"""


@pytest.mark.parametrize(
    ("filename", "relative"),
    [
        ("meshes/link1.stl", True),
        ("./cf2.dae", True),
        ("../meshes/trunk.dae", True),
        ("link.obj", True),
        ("package://arm/meshes/link1.stl", False),
        ("file:///opt/arm/meshes/link1.stl", False),
        ("model://arm/meshes/link1.stl", False),
        ("https://fuel.gazebosim.org/1.0/x/models/y/1/files/meshes/z.dae", False),
        ("/opt/arm/meshes/link1.stl", False),
        ("C:\\arm\\link1.stl", False),
        ("$(find arm)/meshes/link1.stl", False),
        ("", False),
    ],
)
def test_bare_relative(filename: str, relative: bool) -> None:
    assert is_bare_relative(filename) is relative


def _robot(folder: Path, package: bool) -> Path:
    (folder / "meshes").mkdir(parents=True)
    shutil.copy(CUBE, folder / "meshes" / "link1.stl")
    if package:
        (folder / "package.xml").write_text("<package format='3'><name>arm</name></package>")
    path = folder / "robot.urdf"
    path.write_text(ROBOT)
    return path


def _found(path: Path, *targets: str) -> list[tuple[str, int | None]]:
    options = CheckOptions(select=("M009",), rule_options={"targets": targets} if targets else {})
    return [
        (d.severity.value, d.location.line if d.location else None)
        for report in check_file(str(path), options)
        for d in report.diagnostics
        if d.code == "M009"
    ]


def test_outside_a_ros_package_only_a_failing_target_reports(tmp_path: Path) -> None:
    path = _robot(tmp_path / "sim_model", package=False)
    assert _found(path) == []  # pybullet_data's way of writing a robot
    assert _found(path, "pybullet", "mujoco", "drake") == []
    assert _found(path, "pybullet", "moveit") == [("warning", 4)]
    assert _found(path, "gz-sim") == [("warning", 4)]


def test_inside_a_ros_package_it_is_a_note(tmp_path: Path) -> None:
    path = _robot(tmp_path / "arm_description", package=True)
    assert _found(path) == [("info", 4)]
    assert _found(path, "pinocchio") == [("warning", 4)]


def test_mujoco_and_pybullet_resolve_it_against_the_file(tmp_path: Path) -> None:
    import mujoco
    import pybullet

    path = _robot(tmp_path / "m", package=False)
    assert mujoco.MjModel.from_xml_path(str(path)).nmesh == 1
    client = pybullet.connect(pybullet.DIRECT)
    try:
        body = pybullet.loadURDF(str(path), physicsClientId=client)
        shapes = pybullet.getCollisionShapeData(body, -1, physicsClientId=client)
        assert shapes and shapes[0][4].decode().endswith("meshes/link1.stl")
    finally:
        pybullet.disconnect(client)


def test_pinocchio_looks_in_package_dirs_only(tmp_path: Path) -> None:
    pinocchio = pytest.importorskip("pinocchio")
    path = _robot(tmp_path / "m", package=False)
    with pytest.raises(ValueError, match="could not be found"):
        pinocchio.buildModelsFromUrdf(str(path), package_dirs=[])
    _, collision, _ = pinocchio.buildModelsFromUrdf(str(path), package_dirs=[str(path.parent)])
    assert collision.ngeoms == 1
