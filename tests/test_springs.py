"""SDF joint springs (`<spring_stiffness>`, `<spring_reference>`) reach every export that can hold
them: MJCF joint `stiffness`/`springref` (checked in MuJoCo), SDF, and the Gazebo extension of a
URDF export; a spring on the joint that closes a loop is reported as dropped in MJCF."""

from __future__ import annotations

from pathlib import Path

import mujoco
from lxml import etree

import urdftool
from tests.conftest import FIXTURES
from urdftool.export import ExportOptions
from urdftool.export.mjcf import export

PENDULUM = FIXTURES / "robots" / "spring_pendulum.sdf"


def test_the_spring_is_read_from_sdf() -> None:
    joint = urdftool.load(PENDULUM).joint("hinge")
    assert joint is not None and joint.dynamics is not None
    assert (joint.dynamics.spring_stiffness, joint.dynamics.spring_reference) == (10.0, 0.3)


def test_mujoco_pulls_the_joint_to_the_spring_reference() -> None:
    model = mujoco.MjModel.from_xml_string(urdftool.to_mjcf(PENDULUM))
    hinge = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, "hinge")
    assert model.jnt_stiffness[hinge] == 10.0
    assert model.qpos_spring[model.jnt_qposadr[hinge]] == 0.3
    data = mujoco.MjData(model)
    for _ in range(round(5.0 / model.opt.timestep)):  # 5 s: the damped spring settles
        mujoco.mj_step(model, data)
    assert abs(data.qpos[model.jnt_qposadr[hinge]] - 0.3) < 1e-3


def test_sdf_and_urdf_exports_keep_the_spring(tmp_path: Path) -> None:
    sdf = etree.fromstring(urdftool.to_sdf(PENDULUM).encode())
    dynamics = sdf.find(".//joint[@name='hinge']/axis/dynamics")
    assert dynamics is not None
    assert (dynamics.findtext("spring_stiffness"), dynamics.findtext("spring_reference")) == ("10", "0.3")
    again = tmp_path / "again.sdf"
    again.write_text(urdftool.to_sdf(PENDULUM))
    joint = urdftool.load(again).joint("hinge")
    assert joint is not None and joint.dynamics is not None and joint.dynamics.spring_stiffness == 10.0
    urdf = etree.fromstring(urdftool.to_urdf(PENDULUM).encode())
    block = urdf.find("gazebo[@reference='hinge']")
    assert block is not None  # sdformat's URDF reader turns these back into the SDF spring
    assert (block.findtext("springStiffness"), block.findtext("springReference")) == ("10", "0.3")


def test_a_spring_on_a_loop_cut_is_reported_as_dropped(tmp_path: Path) -> None:
    text = (FIXTURES / "robots" / "four_bar.sdf").read_text().replace(
        """      <parent>coupler</parent>
      <child>rocker</child>
      <axis><xyz>0 1 0</xyz></axis>""",
        """      <parent>coupler</parent>
      <child>rocker</child>
      <axis><xyz>0 1 0</xyz><dynamics><spring_stiffness>4</spring_stiffness></dynamics></axis>""")
    path = tmp_path / "four_bar_spring.sdf"
    path.write_text(text)
    report = urdftool.check(path)  # a plain check converts nothing
    assert not [d for d in report.diagnostics if d.code == "C001"]
    result = export(urdftool.load(path), tmp_path / "out.xml", ExportOptions())
    dropped = [d for d in result.diagnostics if d.code == "C001" and "spring" in d.message]
    assert len(dropped) == 1 and "coupler_to_rocker" in dropped[0].message
    assert dropped[0].location is not None and dropped[0].location.line is not None


def test_the_pybullet_export_says_pybullet_has_no_spring(tmp_path: Path) -> None:
    from urdftool.export.pybullet import export as export_pybullet

    result = export_pybullet(urdftool.load(PENDULUM), tmp_path / "robot.urdf", ExportOptions())
    dropped = [d for d in result.diagnostics if d.code == "C001" and "spring" in d.message]
    assert len(dropped) == 1 and "'hinge'" in dropped[0].message and dropped[0].severity.value == "warning"
