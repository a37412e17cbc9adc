"""An SDF model's ``<self_collide>`` reaches MJCF: measured in MuJoCo.

SDFormat: two links of a model collide only when either link's ``<self_collide>`` (or the
model's) is true; the default is false. MuJoCo collides every pair of bodies not joined by a
joint. The fixture is hand-written: a thick fixed base, a turret on a vertical shoulder and a
horizontal forearm on a horizontal elbow, 0.2 m above the base's top. Released, the forearm
falls: where the forearm and the base collide it lands on the base (about 35°), where they do
not it swings through the base (past 80°).
"""

from __future__ import annotations

import math
from pathlib import Path

import mujoco
import pytest

import urdftool

_INERTIA = "<ixx>0.001</ixx><iyy>0.001</iyy><izz>0.001</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz>"


def _link(name: str, pose: str, box: str = "", box_pose: str = "0 0 0 0 0 0", extra: str = "") -> str:
    collision = (f"<collision name='c'><pose>{box_pose}</pose><geometry><box><size>{box}</size></box>"
                 "</geometry></collision>") if box else ""
    return (f"<link name='{name}'><pose>{pose}</pose>{extra}<inertial><pose>{box_pose}</pose>"
            f"<mass>0.5</mass><inertia>{_INERTIA}</inertia></inertial>{collision}</link>")


def folded_arm(model_flag: str = "", forearm_flag: str = "") -> str:
    """The arm, with optional ``<self_collide>`` text for the model and for the forearm."""
    model_self = f"<self_collide>{model_flag}</self_collide>" if model_flag else ""
    fore_self = f"<self_collide>{forearm_flag}</self_collide>" if forearm_flag else ""
    limit = "<limit><lower>-2</lower><upper>2</upper></limit>"
    return f"""<?xml version="1.0"?>
<sdf version="1.9">
  <model name="folded_arm">
    {model_self}
    {_link("base", "0 0 -0.15 0 0 0", "0.6 0.6 0.4")}
    <joint name="shoulder" type="revolute">
      <parent>base</parent><child>turret</child><axis><xyz>0 0 1</xyz>{limit}</axis>
    </joint>
    {_link("turret", "0 0 0.25 0 0 0")}
    <joint name="elbow" type="revolute">
      <parent>turret</parent><child>forearm</child><axis><xyz>0 1 0</xyz>{limit}</axis>
    </joint>
    {_link("forearm", "0 0 0.25 0 0 0", "0.3 0.05 0.05", "0.2 0 0 0 0 0", fore_self)}
  </model>
</sdf>
"""


def _largest_fall(tmp_path: Path, text: str, name: str = "arm.sdf") -> float:
    """The largest elbow angle (degrees) over 1.5 s of the exported model, released at rest."""
    source = tmp_path / name
    source.write_text(text)
    model = mujoco.MjModel.from_xml_string(urdftool.to_mjcf(source, scene=True, floating_base="fixed"))
    data = mujoco.MjData(model)
    elbow = model.jnt_qposadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, "elbow")]
    largest = 0.0
    while data.time < 1.5:
        mujoco.mj_step(model, data)
        largest = max(largest, math.degrees(data.qpos[elbow]))
    return largest


def test_sdf_links_without_self_collide_pass_through_each_other(tmp_path: Path) -> None:
    assert _largest_fall(tmp_path, folded_arm()) > 80.0


@pytest.mark.parametrize(("model_flag", "forearm_flag"), [("", "true"), ("true", ""), ("1", "")])
def test_self_collide_on_the_model_or_a_link_lands_the_forearm_on_the_base(
        tmp_path: Path, model_flag: str, forearm_flag: str) -> None:
    assert _largest_fall(tmp_path, folded_arm(model_flag, forearm_flag)) < 45.0


def test_urdf_links_collide_as_in_gazebo(tmp_path: Path) -> None:
    """URDF has no such switch: every pair not joined by a joint collides."""
    inertial = ('<inertial><mass value="0.5"/><inertia ixx="0.001" iyy="0.001" izz="0.001" ixy="0" '
                'ixz="0" iyz="0"/></inertial>')
    limit = '<limit lower="-2" upper="2" effort="1" velocity="1"/>'
    urdf = f"""<robot name="folded_arm">
  <link name="base">{inertial}<collision><geometry><box size="0.6 0.6 0.4"/></geometry></collision></link>
  <link name="turret">{inertial}</link>
  <link name="forearm">{inertial.replace("<mass", '<origin xyz="0.2 0 0"/><mass')}
    <collision><origin xyz="0.2 0 0"/><geometry><box size="0.3 0.05 0.05"/></geometry></collision></link>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="turret"/>
    <origin xyz="0 0 0.4"/><axis xyz="0 0 1"/>{limit}</joint>
  <joint name="elbow" type="revolute"><parent link="turret"/><child link="forearm"/>
    <axis xyz="0 1 0"/>{limit}</joint>
</robot>"""
    assert _largest_fall(tmp_path, urdf, "arm.urdf") < 45.0
