"""The loss reports of the exporters say what is really lost: the Gazebo friction the MJCF export
writes as geom friction is not listed as dropped (new-user report of 2026-11-26, problem 5)."""

from __future__ import annotations

from pathlib import Path

import mujoco
import pytest

from tests.conftest import FIXTURES
from urdftool.export import ExportOptions
from urdftool.export.mjcf import export
from urdftool.parse import read

ARM = FIXTURES / "newuser" / "gazebo_friction_arm.urdf"


def _mjcf(tmp_path: Path) -> tuple[mujoco.MjModel, list[str]]:
    robot = read(ARM)[0].robot
    assert robot is not None
    out = tmp_path / "arm.xml"
    result = export(robot, out, ExportOptions())
    out.write_bytes(result.files[out.name])
    dropped = [d.data["element"] for d in result.diagnostics if d.code == "C001"]
    return mujoco.MjModel.from_xml_path(str(out)), dropped


def test_friction_written_to_the_geoms_is_not_reported_as_dropped(tmp_path: Path) -> None:
    model, dropped = _mjcf(tmp_path)
    base = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "link_0")
    geoms = [i for i in range(model.ngeom) if model.geom_bodyid[i] == base and model.geom_group[i] == 3]
    assert geoms and all(model.geom_friction[i][0] == pytest.approx(0.2) for i in geoms)
    assert "gazebo[link_0]/mu1" not in dropped and "gazebo[link_0]/mu2" not in dropped
    # link_7's mu1 (0.2, the smaller) is written; its mu2 (0.3) is what isotropic friction loses
    assert "gazebo[link_7]/mu1" not in dropped and "gazebo[link_7]/mu2" in dropped


def test_what_mjcf_cannot_carry_is_still_reported(tmp_path: Path) -> None:
    _model, dropped = _mjcf(tmp_path)
    for element in ("gazebo[joint_7]/provideFeedback", "gazebo/plugin", "gazebo[link_0]/material",
                    "gazebo[link_7]/kp", "gazebo[link_7]/kd"):
        assert element in dropped, dropped


def test_friction_of_a_block_naming_no_link_is_reported(tmp_path: Path) -> None:
    source = tmp_path / "r.urdf"
    source.write_text(
        '<robot name="r"><link name="a"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" '
        'ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial><collision><geometry><sphere radius="0.1"/>'
        '</geometry></collision></link><gazebo reference="b"><mu1>0.8</mu1></gazebo>'
        '<gazebo reference="a"><mu1>high</mu1></gazebo></robot>')
    robot = read(source)[0].robot
    assert robot is not None
    result = export(robot, tmp_path / "r.xml", ExportOptions())
    dropped = [d.data["element"] for d in result.diagnostics if d.code == "C001"]
    assert dropped == ["gazebo[b]/mu1", "gazebo[a]/mu1"]
