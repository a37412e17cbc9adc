"""The mesh-format support table (urdftool.backends.mesh_formats) holds in the installed engines.

``mesh-format-unsupported`` names engines that cannot read a file; these tests
load the fixture meshes in real MuJoCo and PyBullet so the claims stay true
when the engines are upgraded.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.conftest import FIXTURES
from urdftool.backends.mesh_formats import engines_refusing, sniff

MESHES = FIXTURES / "rules" / "M004" / "meshes"
CASES = ["cube.stl", "ascii.stl", "cube.obj", "cube.dae"]


def mujoco_reads(path: Path) -> bool:
    import mujoco

    xml = (
        f'<mujoco><asset><mesh name="m" file="{path}"/></asset><worldbody><body>'
        '<freejoint/><geom type="mesh" mesh="m"/></body></worldbody></mujoco>'
    )
    try:
        mujoco.MjModel.from_xml_string(xml)
    except ValueError:
        return False
    return True


def pybullet_reads(path: Path, tmp_path: Path) -> bool:
    """True when PyBullet builds a collision shape of the right size from the mesh."""
    import pybullet

    urdf = tmp_path / f"probe_{path.stem}_{path.suffix[1:]}.urdf"  # PyBullet caches files by name
    urdf.write_text(
        '<robot name="probe"><link name="body"><inertial><mass value="1"/>'
        '<inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>'
        f'<collision><geometry><mesh filename="{path}"/></geometry></collision></link></robot>'
    )
    client = pybullet.connect(pybullet.DIRECT)
    try:
        body = pybullet.loadURDF(str(urdf), physicsClientId=client)
        shapes = pybullet.getCollisionShapeData(body, -1, physicsClientId=client)
        low, high = pybullet.getAABB(body, -1, physicsClientId=client)
    except pybullet.error:
        return False
    finally:
        pybullet.disconnect(client)
    return bool(shapes) and high[0] - low[0] > 0.09  # the cube is 0.1 m wide


@pytest.mark.parametrize("name", CASES)
def test_mujoco_support_matches_the_table(name: str) -> None:
    path = MESHES / name
    assert mujoco_reads(path) == ("mujoco" not in engines_refusing(sniff(str(path))))


@pytest.mark.parametrize("name", CASES)
def test_pybullet_support_matches_the_table(name: str, tmp_path: Path) -> None:
    path = MESHES / name
    assert pybullet_reads(path, tmp_path) == ("pybullet" not in engines_refusing(sniff(str(path))))
